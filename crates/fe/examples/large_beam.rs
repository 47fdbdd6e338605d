//! Preprocessing time of large built-in beam models, for the memory and time figures of the
//! sparse beam route (issue 25 item 3). Run under `/usr/bin/time -v` for the peak RSS:
//!
//! - `large_beam cantilever E`: a 3D steel cantilever (1 m, 10 × 10 mm) of E elements, the
//!   tip's six DOFs as static modes, 6 normal modes;
//! - `large_beam grillage G`: a 3D steel grillage of G × G square cells of 0.1 m (one
//!   element per member, 10 × 10 mm), clamped at one corner, the opposite corner's six DOFs
//!   as static modes, 6 normal modes: 6 (G + 1)² DOFs.
//!
//! `cargo run --release -p flexmbd-fe --example large_beam -- grillage 199`

use std::time::Instant;

use flexmbd_core::Dim;
use flexmbd_fe::frame::{FrameNode, Member};
use flexmbd_fe::{BeamBodySpec, Dof, Material, NodeDof, ReferenceFrame, Section};

fn steel() -> Material {
    Material {
        young_modulus: 2.1e11,
        density: 7850.0,
        poisson_ratio: Some(0.3),
        shear_modulus: None,
    }
}

fn cantilever(elements: usize) -> Result<BeamBodySpec, Box<dyn std::error::Error>> {
    let text = format!(
        "(dim: Spatial, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)),
          section: Rectangle(width: 0.01, height: 0.01),
          geometry: (points: [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], elements_per_segment: {elements}),
          frame: Clamped(node: 0),
          boundary: [(node: {elements}, dof: Ux), (node: {elements}, dof: Uy), (node: {elements}, dof: Uz),
                     (node: {elements}, dof: Rx), (node: {elements}, dof: Ry), (node: {elements}, dof: Rz)],
          normal_modes: 6)"
    );
    Ok(BeamBodySpec::from_ron_str(&text, "cantilever")?)
}

fn grillage(g: usize) -> BeamBodySpec {
    let name = |i: usize, j: usize| format!("n{i}_{j}");
    let mut nodes = Vec::new();
    let mut members = Vec::new();
    for j in 0..=g {
        for i in 0..=g {
            nodes.push(FrameNode {
                name: name(i, j),
                position: vec![0.1 * i as f64, 0.1 * j as f64, 0.0],
            });
            let member = |to: String| Member {
                from: name(i, j),
                to,
                elements: None,
                section: None,
                orientation: None,
            };
            if i < g {
                members.push(member(name(i + 1, j)));
            }
            if j < g {
                members.push(member(name(i, j + 1)));
            }
        }
    }
    let section = Section::Rectangle {
        width: 0.01,
        height: 0.01,
    };
    let mut spec = BeamBodySpec::frame(Dim::Spatial, steel(), section, nodes, members);
    spec.frame = ReferenceFrame::Clamped { node: 0 };
    let corner = (g + 1) * (g + 1) - 1;
    spec.boundary = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]
        .into_iter()
        .map(|dof| NodeDof { node: corner, dof })
        .collect();
    spec.normal_modes = 6;
    spec
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: large_beam cantilever ELEMENTS | grillage CELLS";
    let kind = args.next().ok_or(usage)?;
    let size: usize = args.next().ok_or(usage)?.parse()?;
    let spec = match kind.as_str() {
        "cantilever" => cantilever(size)?,
        "grillage" => grillage(size),
        _ => return Err(usage.into()),
    };
    let start = Instant::now();
    let body = flexmbd_fe::reduce(&spec)?;
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "{kind} {size}: {} FE DOFs, preprocessing {seconds:.3} s; normal modes {:.6?} Hz",
        body.inventory.n_fe_dofs, body.inventory.normal_frequencies_hz
    );
    Ok(())
}
