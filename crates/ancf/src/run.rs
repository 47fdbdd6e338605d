//! The spin-up run (docs/methods.md §7.3, docs/scenes.md §5): build the cable, start from static
//! equilibrium when gravity is present (§5.4 item 4), integrate with ALI3-P (§5) and
//! record the tip displacement in the frame turning with θ(t) at a fixed interval.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use flexmbd_core::{InvalidValue, Observe};
use flexmbd_integrators::{Ali3p, Ali3pSettings, IntegratorError, Stats};

use crate::cable::{Cable, StaticError, StaticReport};
use crate::spec::{CableSpec, validate_run};

/// Why a spin-up run failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AncfError {
    /// A bad input value.
    #[error(transparent)]
    Invalid(#[from] InvalidValue),
    /// The static start failed.
    #[error(transparent)]
    Static(#[from] StaticError),
    /// The integrator stopped.
    #[error(transparent)]
    Integrator(#[from] IntegratorError),
    /// The stop flag was set ([`run_spin_up_or_stop`]); the run ended between steps.
    #[error("interrupted at t = {t} s")]
    Interrupted {
        /// The time reached.
        t: f64,
    },
}

/// Output of [`run_spin_up`]: tip displacements in the turning frame at the output times.
#[derive(Clone, Debug, PartialEq)]
pub struct History {
    /// Output times (s), t = 0 included.
    pub t: Vec<f64>,
    /// Tip displacement (d_x axial, d_y horizontal, d_z vertical; d_z = 0 in 2D) (m).
    pub tip: Vec<[f64; 3]>,
    /// Total energy ½q̇ᵀMq̇ + U − Q_gᵀq (J).
    pub energy: Vec<f64>,
    /// Integrator counters.
    pub stats: Stats,
    /// Wall-clock seconds of the time loop (static start and set-up excluded).
    pub cpu_seconds: f64,
    /// The static start, when gravity was present.
    pub static_start: Option<StaticReport>,
}

impl History {
    /// Smallest value of tip component `k` over the run.
    pub fn min(&self, k: usize) -> f64 {
        self.tip.iter().map(|d| d[k]).fold(f64::INFINITY, f64::min)
    }
    /// Largest value of tip component `k` over the run.
    pub fn max(&self, k: usize) -> f64 {
        self.tip
            .iter()
            .map(|d| d[k])
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// max over t of |self − other| for tip component `k` (same output times).
    pub fn max_difference(&self, other: &History, k: usize) -> f64 {
        self.tip
            .iter()
            .zip(&other.tip)
            .map(|(a, b)| (a[k] - b[k]).abs())
            .fold(0.0, f64::max)
    }
}

/// Run the spin-up of `spec` with step `h` for `duration` seconds, recording every
/// `output_interval` (rounded to a whole number of steps), with the default ALI3-P
/// settings of docs/methods.md §5.
pub fn run_spin_up(
    spec: &CableSpec,
    h: f64,
    duration: f64,
    output_interval: f64,
) -> Result<History, AncfError> {
    let never = AtomicBool::new(false);
    run_spin_up_or_stop(spec, h, duration, output_interval, &never)
}

/// [`run_spin_up`] that ends between two steps once `stop` is set
/// ([`AncfError::Interrupted`]), as a sweep's runs do on Ctrl-C.
pub fn run_spin_up_or_stop(
    spec: &CableSpec,
    h: f64,
    duration: f64,
    output_interval: f64,
    stop: &AtomicBool,
) -> Result<History, AncfError> {
    let settings = Ali3pSettings {
        step: h,
        ..Default::default()
    };
    spin_up(spec, settings, duration, output_interval, stop)
}

/// [`run_spin_up`] with explicit integrator settings.
pub fn run_spin_up_with(
    spec: &CableSpec,
    settings: Ali3pSettings,
    duration: f64,
    output_interval: f64,
) -> Result<History, AncfError> {
    spin_up(
        spec,
        settings,
        duration,
        output_interval,
        &AtomicBool::new(false),
    )
}

fn spin_up(
    spec: &CableSpec,
    settings: Ali3pSettings,
    duration: f64,
    output_interval: f64,
    stop: &AtomicBool,
) -> Result<History, AncfError> {
    validate_run(settings.step, duration, output_interval)?;
    let mut cable = Cable::new(spec)?;
    let static_start = if spec.gravity.iter().any(|&g| g != 0.0) {
        Some(cable.solve_static(0.0, 10)?)
    } else {
        None
    };
    let hist = cable_history(&mut cable, settings, duration, output_interval, stop)?;
    Ok(History {
        static_start,
        ..hist
    })
}

/// Integrate `cable` from its initial positions ([`Cable::initial_positions`]) at rest for
/// `duration` seconds, recording every `output_interval` (rounded to a whole number of
/// steps); no static start (`static_start` is `None`).
pub fn run_cable(
    cable: &mut Cable,
    settings: Ali3pSettings,
    duration: f64,
    output_interval: f64,
) -> Result<History, AncfError> {
    cable_history(
        cable,
        settings,
        duration,
        output_interval,
        &AtomicBool::new(false),
    )
}

fn cable_history(
    cable: &mut Cable,
    settings: Ali3pSettings,
    duration: f64,
    output_interval: f64,
    stop: &AtomicBool,
) -> Result<History, AncfError> {
    let h = settings.step;
    validate_run(h, duration, output_interval)?;
    let mut s = Ali3p::new(cable, 0.0, settings)?;
    let steps = (duration / h).round() as usize;
    let every = ((output_interval / h).round() as usize).max(1);
    let cap = steps / every + 1;
    let mut hist = History {
        t: Vec::with_capacity(cap),
        tip: Vec::with_capacity(cap),
        energy: Vec::with_capacity(cap),
        stats: Stats::default(),
        cpu_seconds: 0.0,
        static_start: None,
    };
    let mut sens = vec![0.0; cable.sensor_names().len()];
    let d = cable.dim_components();
    let mut record = |s: &Ali3p, cable: &mut Cable, hist: &mut History| {
        cable.sensors(s.state(), &mut sens);
        let mut tip = [0.0; 3];
        tip[..d].copy_from_slice(&sens[..d]);
        hist.t.push(s.t);
        hist.tip.push(tip);
        hist.energy.push(sens[d]);
    };
    record(&s, cable, &mut hist);
    let t0 = Instant::now();
    for k in 1..=steps {
        if stop.load(Ordering::Relaxed) {
            return Err(AncfError::Interrupted { t: s.t });
        }
        s.step(cable)?;
        if k % every == 0 {
            record(&s, cable, &mut hist);
        }
    }
    hist.cpu_seconds = t0.elapsed().as_secs_f64();
    hist.stats = s.stats.clone();
    Ok(hist)
}
