//! The weights of every flexible body's inertia terms over a pilot run, and the terms
//! chosen by them (issue 31 item 2; `flexmbd terms`; docs/design.md "Inertia terms by
//! weight").
//!
//! The **pilot** is the scene itself with every term kept, in relative coordinates with
//! shape integrals (the route that can drop terms; the motion does not depend on the route),
//! run to the scene's duration or a shorter one. At each output instant (every step without
//! `solver.output_interval`; t = 0 included) each flexible body's motion — frame, modal
//! coordinates, their rates and accelerations, read from the integrator's state — is handed
//! to a [`WeightMeter`], which evaluates `F = M̄Ż − Q̄_v` for every choice of terms and
//! weighs what each group of terms adds, in the body's kinetic-energy norms
//! ([`flexmbd_body::weights`]). The weights are a property of the motion, so one pilot
//! serves every threshold: [`BodyWeights::choose`].

use flexmbd_body::InertiaMethod;
use flexmbd_body::InertiaTerms;
use flexmbd_body::weights::{MotionSample, WeightMeter, WeightTable};
use flexmbd_core::{BodyMotion, InvalidValue};
use flexmbd_model::{FormulationKind, Scene};

use crate::{Error, Simulation};

/// One flexible body's weights.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyWeights {
    /// The body's name in the prepared scene (a substructured beam's pieces have their own).
    pub body: String,
    /// Its modal coordinates.
    pub modes: usize,
    /// The weights of its terms over the pilot.
    pub table: WeightTable,
}

impl BodyWeights {
    /// The cheapest terms whose dropped groups weigh at most `threshold`
    /// ([`WeightTable::choose`]); a threshold outside (0, 1) is refused by name.
    pub fn choose(&self, threshold: f64) -> Result<InertiaTerms, Error> {
        self.table.choose(threshold).map_err(Error::Input)
    }
}

/// The pilot's scene: `scene` with every term kept, relative, shape integrals, run for
/// `duration` (the scene's when `None`).
fn pilot_scene(scene: &Scene, duration: Option<f64>) -> Result<Scene, Error> {
    let mut pilot = scene.clone();
    if let Some(d) = duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(Error::Input(InvalidValue::new(
                "duration",
                d,
                "the pilot's duration must be a positive number of seconds",
            )));
        }
        pilot.solver.duration = pilot.solver.duration.min(d);
    }
    pilot.solver.formulation = FormulationKind::Relative;
    pilot.solver.inertia = InertiaMethod::ShapeIntegrals;
    for b in &mut pilot.bodies {
        b.inertia_terms = InertiaTerms::FULL;
    }
    Ok(pilot)
}

/// Weigh the inertia terms of every flexible body of `scene` over its pilot run (module
/// doc), to `duration` when given (at most the scene's). A scene without a flexible body,
/// or whose flexible bodies cannot drop terms (FS0), is refused by name; a pilot that fails
/// is the step's error.
pub fn weigh_terms(scene: &Scene, duration: Option<f64>) -> Result<Vec<BodyWeights>, Error> {
    let pilot = pilot_scene(scene, duration)?;
    let mut sim = Simulation::new(&pilot)?;
    let mut meters = Vec::new();
    for (k, pb) in sim.prepared().bodies().iter().enumerate() {
        if !pb.flexible || pb.body.n_modes() == 0 {
            continue;
        }
        let name = sim.prepared().scene().bodies[pb.index].name.clone();
        let meter = WeightMeter::new(&pb.body, &format!("bodies[{name}]")).map_err(Error::Input)?;
        meters.push((k, name, pb.body.n_modes(), meter));
    }
    if meters.is_empty() {
        return Err(Error::Input(InvalidValue::new(
            "scene",
            &scene.name,
            "the scene has no flexible body with modes: rigid bodies have no inertia terms to \
             weigh (a beam runs flexible with --set bodies.NAME.flexible=true)",
        )));
    }
    let h = pilot.solver.step;
    let steps = (pilot.solver.duration / h).round() as usize;
    let every = pilot
        .solver
        .output_interval
        .map_or(1, |dt| ((dt / h).round() as usize).max(1));
    let mut motions: Vec<BodyMotion> = Vec::new();
    let mut sample = |sim: &mut Simulation,
                      meters: &mut Vec<(usize, String, usize, WeightMeter)>| {
        let reported = sim.body_motions(&mut motions);
        debug_assert!(reported, "the relative formulation reports body motions");
        for (k, _, _, meter) in meters.iter_mut() {
            let m = &motions[*k];
            let f = &m.frame;
            meter.add(&MotionSample {
                state: flexmbd_body::BodyState::from_origin_velocity(
                    f.origin,
                    f.rotation,
                    f.angular_velocity,
                    f.velocity,
                    &m.modes,
                    &m.mode_rates,
                ),
                origin_acceleration: f.acceleration,
                angular_acceleration: f.angular_acceleration,
                mode_accelerations: &m.mode_accelerations,
            });
        }
    };
    sample(&mut sim, &mut meters);
    for k in 1..=steps {
        sim.step()?;
        if k % every == 0 || k == steps {
            sample(&mut sim, &mut meters);
        }
    }
    Ok(meters
        .into_iter()
        .map(|(_, body, modes, meter)| BodyWeights {
            body,
            modes,
            table: meter.table(),
        })
        .collect())
}

/// `scene` with each weighed body's terms set to its choice at `threshold` (bodies of
/// `weights` the scene does not name, a substructured beam's pieces, are left as they are),
/// and the choices made.
pub fn apply_choice(
    scene: &Scene,
    weights: &[BodyWeights],
    threshold: f64,
) -> Result<(Scene, Vec<(String, InertiaTerms)>), Error> {
    let mut out = scene.clone();
    let mut chosen = Vec::new();
    for w in weights {
        let terms = w.choose(threshold)?;
        if let Some(b) = out.bodies.iter_mut().find(|b| b.name == w.body) {
            b.inertia_terms = terms;
            chosen.push((w.body.clone(), terms));
        }
    }
    Ok((out, chosen))
}
