//! Shared builders for the physics tests.
#![allow(dead_code)]

use flexmbd_core::Dim;
use flexmbd_fe::{
    BeamBodySpec, Damping, Geometry, Material, ModeSelection, NodeDof, ReferenceFrame, Section,
};

pub const E: f64 = 2.1e11;
pub const RHO: f64 = 7850.0;
pub const NU: f64 = 0.3;

pub fn steel() -> Material {
    Material {
        young_modulus: E,
        density: RHO,
        poisson_ratio: Some(NU),
        shear_modulus: None,
    }
}

/// A beam spec on a polyline (2D points get z ignored).
pub fn beam(
    dim: Dim,
    section: Section,
    points: &[[f64; 3]],
    n_el: usize,
    frame: ReferenceFrame,
    boundary: Vec<NodeDof>,
    normal_modes: usize,
) -> BeamBodySpec {
    let pts = points
        .iter()
        .map(|p| match dim {
            Dim::Planar => vec![p[0], p[1]],
            Dim::Spatial => p.to_vec(),
        })
        .collect();
    BeamBodySpec {
        dim,
        material: steel(),
        section,
        geometry: Geometry {
            points: pts,
            elements_per_segment: n_el,
            orientation: None,
            nodes: Vec::new(),
            members: Vec::new(),
        },
        frame,
        reference: Default::default(),
        boundary,
        normal_modes,
        axial_modes: 0,
        mode_selection: ModeSelection::LowestFrequency,
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        damping: Damping::None,
        origin: "test spec".to_string(),
    }
}

/// Straight beam of length 1 m along x, clamped at node 0.
pub fn cantilever(dim: Dim, section: Section, n_el: usize, normal_modes: usize) -> BeamBodySpec {
    beam(
        dim,
        section,
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        n_el,
        ReferenceFrame::Clamped { node: 0 },
        vec![],
        normal_modes,
    )
}

pub fn square10() -> Section {
    Section::Rectangle {
        width: 0.01,
        height: 0.01,
    }
}

/// 10 mm along y, 20 mm along z: I_z = 1.667e-9, I_y = 6.667e-9.
pub fn rect10x20() -> Section {
    Section::Rectangle {
        width: 0.01,
        height: 0.02,
    }
}

/// Euler–Bernoulli ω = (βL)² √(EI/(ρA L⁴)) in Hz.
pub fn eb_hz(beta_l: f64, ei: f64, rho_a: f64, l: f64) -> f64 {
    beta_l * beta_l * (ei / (rho_a * l.powi(4))).sqrt() / (2.0 * std::f64::consts::PI)
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The largest relative difference |a_k − b_k| / a_k of two lists of ω² (a: the reference).
pub fn worst_relative_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / x)
        .fold(0.0, f64::max)
}

pub const CANTILEVER_BL: [f64; 3] = [1.875_104_07, 4.694_091_13, 7.854_757_44];
pub const FREE_FREE_BL: [f64; 3] = [4.730_040_74, 7.853_204_62, 10.995_607_8];
