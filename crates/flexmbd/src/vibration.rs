//! The linearised free vibration of a scene about its static equilibrium (`flexmbd
//! eigen`): the numerics are `flexmbd_integrators::linearise` (docs/methods.md §5.5); this
//! module finds the equilibrium ([`crate::equilibrium()`]), runs them, and says which sensors
//! and coordinates each mode moves most.
//!
//! **Contributions.** A mode's shape δq (complex, n) moves sensor i by |S_i δq|, S = ∂s/∂q
//! the sensors' sensitivities at the equilibrium by central differences (step
//! 6·10⁻⁶ max(1, |q_j|), as the tangents). Each list is normalised by its largest entry (1
//! for the sensor the mode moves most); sensors of different units are compared by their
//! SI values, so a reader compares like with like.

use flexmbd_core::CompiledScene;
use flexmbd_integrators::linearise::{Mode, ModeKind, RELATIVE_STEP, linearise};
use flexmbd_model::Scene;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::Error;
use crate::equilibrium::{Equilibrium, Named, element_forces, sensors_at, solve};

/// Contributions listed per mode: those at least this fraction of the largest.
pub const CONTRIBUTION_FLOOR: f64 = 1e-3;

/// One mode of a scene's free vibration.
#[derive(Clone, Debug, Serialize)]
pub struct ModeReport {
    /// 1-based, in order of frequency.
    pub index: usize,
    /// Undamped frequency |s|/2π (Hz).
    pub frequency_hz: f64,
    /// Damped frequency Im s/2π (Hz); 0 for a mode that does not oscillate.
    pub damped_frequency_hz: f64,
    /// Damping ratio ζ = −Re s/|s|.
    pub damping_ratio: f64,
    /// `oscillatory`, `zero` (a free rigid-body motion), `overdamped` or `unstable`.
    pub kind: String,
    /// Eigenvalue s = (Re, Im) (1/s).
    pub eigenvalue: [f64; 2],
    /// The sensors it moves, by normalised amplitude |S_i δq| (largest 1), largest first,
    /// those below [`CONTRIBUTION_FLOOR`] left out.
    pub sensors: Vec<Named>,
    /// The coordinates it moves (`q3`), by normalised |δq_j|, as the sensors.
    pub coordinates: Vec<Named>,
}

/// The linearised free vibration of a scene (module documentation).
#[derive(Clone, Debug, Serialize)]
pub struct Vibration {
    /// The equilibrium it is linearised about.
    pub equilibrium: Equilibrium,
    /// Degrees of freedom: the motions the constraints allow.
    pub dof: usize,
    /// The modes, by frequency.
    pub modes: Vec<ModeReport>,
}

/// Sensitivities S = ∂s/∂q (sensors × n) at (t = 0, q, q̇ = 0) by central differences.
fn sensitivities(f: &mut dyn CompiledScene, q: &DVector<f64>) -> DMatrix<f64> {
    let (ns, n) = (f.sensor_names().len(), q.len());
    let mut s = DMatrix::zeros(ns, n);
    let mut qp = q.clone();
    for j in 0..n {
        let d = RELATIVE_STEP * q[j].abs().max(1.0);
        qp[j] = q[j] + d;
        let plus = sensors_at(f, &qp);
        qp[j] = q[j] - d;
        let minus = sensors_at(f, &qp);
        qp[j] = q[j];
        for i in 0..ns {
            s[(i, j)] = (plus[i] - minus[i]) / (2.0 * d);
        }
    }
    s
}

/// `amplitudes` named by `name`, normalised by the largest, largest first, the small left
/// out.
fn ranked(amplitudes: &[f64], name: impl Fn(usize) -> String) -> Vec<Named> {
    let big = amplitudes.iter().copied().fold(0.0, f64::max);
    if big.is_nan() || big <= 0.0 || !big.is_finite() {
        return Vec::new();
    }
    let mut v: Vec<Named> = amplitudes
        .iter()
        .enumerate()
        .filter(|(_, a)| **a >= CONTRIBUTION_FLOOR * big)
        .map(|(i, a)| Named {
            name: name(i),
            value: a / big,
        })
        .collect();
    v.sort_by(|a, b| b.value.total_cmp(&a.value));
    v
}

/// The report of mode `index` (1-based) of shape `mode.shape`, S the sensitivities.
fn report(index: usize, mode: &Mode, s: &DMatrix<f64>, sensor_names: &[String]) -> ModeReport {
    let sensor_amp: Vec<f64> = (0..s.nrows())
        .map(|i| {
            let (re, im) = mode
                .shape
                .iter()
                .enumerate()
                .fold((0.0, 0.0), |(re, im), (j, (a, b))| {
                    (re + s[(i, j)] * a, im + s[(i, j)] * b)
                });
            f64::hypot(re, im)
        })
        .collect();
    let coord_amp: Vec<f64> = mode.shape.iter().map(|(a, b)| a.hypot(*b)).collect();
    ModeReport {
        index,
        frequency_hz: mode.frequency_hz,
        damped_frequency_hz: mode.damped_frequency_hz,
        damping_ratio: mode.damping_ratio,
        kind: match mode.kind {
            ModeKind::Oscillatory => "oscillatory",
            ModeKind::Zero => "zero",
            ModeKind::Overdamped => "overdamped",
            ModeKind::Unstable => "unstable",
        }
        .into(),
        eigenvalue: [mode.eigenvalue.0, mode.eigenvalue.1],
        sensors: ranked(&sensor_amp, |i| sensor_names[i].clone()),
        coordinates: ranked(&coord_amp, |j| format!("q{j}")),
    }
}

impl Vibration {
    /// A table for a reader: the equilibrium's solve, then one line per mode (index,
    /// frequency, damped frequency, damping ratio, kind, the sensors it moves most).
    pub fn to_text(&self) -> String {
        let e = &self.equilibrium;
        let mut s = format!(
            "{}: linearised free vibration about the static equilibrium, {} formulation — {} coordinates, {} constraints, {} degrees of freedom\n",
            e.scene, e.formulation, e.n_coordinates, e.n_constraints, self.dof
        );
        s += &format!(
            "{:>4}  {:>14}  {:>14}  {:>10}  {:<11}  dominant sensors (normalised amplitude)\n",
            "mode", "frequency Hz", "damped Hz", "damping", "kind"
        );
        for m in &self.modes {
            let dominant: Vec<String> = m
                .sensors
                .iter()
                .take(3)
                .map(|n| format!("{} {:.2}", n.name, n.value))
                .collect();
            s += &format!(
                "{:>4}  {:>14.6}  {:>14.6}  {:>10.6}  {:<11}  {}\n",
                m.index,
                m.frequency_hz,
                m.damped_frequency_hz,
                m.damping_ratio,
                m.kind,
                dominant.join(", ")
            );
        }
        s
    }

    /// The undamped frequencies (Hz) of the modes of `kind` (`"oscillatory"`, …), in order.
    pub fn frequencies(&self, kind: &str) -> Vec<f64> {
        self.modes
            .iter()
            .filter(|m| m.kind == kind)
            .map(|m| m.frequency_hz)
            .collect()
    }
}

/// The linearised free vibration of `scene` about its static equilibrium at t = 0, in the
/// formulation its solver block names (module documentation). `scene` should be validated
/// (as [`Scene::load`] does).
pub fn vibration(scene: &Scene) -> Result<Vibration, Error> {
    let (mut f, solution) = solve(scene)?;
    let mut equilibrium = Equilibrium::of(scene, f.as_mut(), &solution);
    equilibrium.forces = element_forces(scene, &solution.q)?;
    let lin = linearise(f.as_mut(), 0.0, &solution.q, &solution.lambda)?;
    let modes = lin.modes()?;
    let s = sensitivities(f.as_mut(), &solution.q);
    let names = f.sensor_names().to_vec();
    Ok(Vibration {
        equilibrium,
        dof: lin.dof(),
        modes: modes
            .iter()
            .enumerate()
            .map(|(k, m)| report(k + 1, m, &s, &names))
            .collect(),
    })
}
