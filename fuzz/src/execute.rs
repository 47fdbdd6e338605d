//! One execution: load, validate, start and step a mutated scene in one formulation, and
//! the class of its outcome. Runs inside the worker (see [`crate::worker`]); the classes
//! that only the supervisor can see (hang, abort, oom, crash) are named here too.

use flexmbd::model::{FormulationKind, ModelError, Scene};
use flexmbd::{Error, Simulation};

/// The name under which a mutant is loaded (errors name it as their file).
pub const ORIGIN: &str = "mutant.ron";

/// How an execution ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Class {
    /// Refused at load, validation or compilation with a proper message.
    Refused,
    /// A step (or the start: statics, consistent initial conditions) failed cleanly.
    Failed,
    /// Ran its steps with finite sensors and state.
    Ok,
    /// Defect: a refusal or failure whose message is empty or does not name its field.
    BadMessage,
    /// Defect: a sensor or the state is NaN or infinite while every step reported success.
    OkNonFinite,
    /// Defect: a panic (caught in the worker).
    Panic,
    /// Defect: over the wall-clock cap (the worker was killed).
    Hang,
    /// Defect: the worker aborted on an allocation failure under the memory cap.
    Oom,
    /// Defect: the worker aborted for another reason.
    Abort,
    /// Defect: the worker died otherwise (a signal such as SIGSEGV, or an exit).
    Crash,
}

/// Every class, in report order.
pub const CLASSES: [Class; 10] = [
    Class::Refused,
    Class::Failed,
    Class::Ok,
    Class::BadMessage,
    Class::OkNonFinite,
    Class::Panic,
    Class::Hang,
    Class::Oom,
    Class::Abort,
    Class::Crash,
];

impl Class {
    /// Its name in outcome lines, summaries and reproducer file names.
    pub fn name(self) -> &'static str {
        match self {
            Class::Refused => "refused",
            Class::Failed => "failed",
            Class::Ok => "ok",
            Class::BadMessage => "bad_message",
            Class::OkNonFinite => "ok_non_finite",
            Class::Panic => "panic",
            Class::Hang => "hang",
            Class::Oom => "oom",
            Class::Abort => "abort",
            Class::Crash => "crash",
        }
    }

    /// The class named `name`.
    pub fn from_name(name: &str) -> Option<Class> {
        CLASSES.into_iter().find(|c| c.name() == name)
    }

    /// Whether this outcome is a defect of flexmbd.
    pub fn is_defect(self) -> bool {
        !matches!(self, Class::Refused | Class::Failed | Class::Ok)
    }
}

/// An outcome: its class and a one-line detail (the message, the panic and its location).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The class.
    pub class: Class,
    /// One line.
    pub detail: String,
}

impl Outcome {
    /// An outcome with its detail folded onto one line.
    pub fn new(class: Class, detail: impl AsRef<str>) -> Outcome {
        let detail = detail.as_ref().replace(['\n', '\r', '\t'], " ");
        Outcome { class, detail }
    }
}

/// The formulation's name in files and messages.
pub fn formulation_name(f: FormulationKind) -> &'static str {
    match f {
        FormulationKind::Absolute => "absolute",
        FormulationKind::Relative => "relative",
    }
}

/// The formulation named `name` (as [`formulation_name`] writes it).
pub fn formulation_from_name(name: &str) -> Option<FormulationKind> {
    match name.to_ascii_lowercase().as_str() {
        "absolute" => Some(FormulationKind::Absolute),
        "relative" => Some(FormulationKind::Relative),
        _ => None,
    }
}

/// Load `text` as a scene, run it in `formulation` (overriding `solver.formulation`),
/// validate it, start a [`Simulation`] (the duration as written: validation and start see
/// what a user's run would), then take at most `max_steps` steps, checking the sensors
/// and the state after the start and after each step. Panics propagate (the worker
/// catches them).
pub fn execute(text: &str, formulation: FormulationKind, max_steps: usize) -> Outcome {
    let mut scene = match Scene::from_ron_str(text, ORIGIN) {
        Ok(scene) => scene,
        Err(e) => return refusal(&e),
    };
    scene.solver.formulation = formulation;
    if let Err(e) = scene.validate() {
        return refusal(&e);
    }
    if let Some(outcome) = beyond_size_cap(&scene) {
        return outcome;
    }
    let mut sim = match Simulation::new(&scene) {
        Ok(sim) => sim,
        Err(Error::Model(e)) => return refusal(&e),
        Err(e @ (Error::Fe(_) | Error::Io(_))) => return checked(Class::Refused, &e.to_string()),
        Err(e) => return checked(Class::Failed, &format!("start: {e}")),
    };
    let mut sensors = vec![0.0; sim.sensor_names().len()];
    if let Some(bad) = non_finite(&mut sim, &mut sensors) {
        return Outcome::new(Class::OkNonFinite, format!("after the start: {bad}"));
    }
    let h = sim.step_size();
    let mut steps = 0;
    while steps < max_steps && sim.time() + 0.5 * h <= scene.solver.duration {
        if let Err(e) = sim.step() {
            return checked(Class::Failed, &e.to_string());
        }
        steps += 1;
        if let Some(bad) = non_finite(&mut sim, &mut sensors) {
            return Outcome::new(Class::OkNonFinite, format!("step {steps}: {bad}"));
        }
    }
    Outcome::new(Class::Ok, format!("{steps} steps to t = {}", sim.time()))
}

/// The largest built-in beam a mutant is reduced with: the dense route's former limit,
/// for which the wall-clock cap was sized. Beams up to the library's limit (10⁶ FE DOFs on
/// the sparse route, about 3 kB per DOF and a minute) are valid input but would turn a
/// mutated element count (`100000`) into a hang or an out-of-memory of the campaign's
/// worker, not a defect; their reduction is tested in `crates/fe/tests/sparse_beam.rs`.
pub const MAX_BEAM_FE_DOFS: usize = 2_400;

/// A mutant with a beam larger than [`MAX_BEAM_FE_DOFS`], counted as refused (by the
/// campaign, not by flexmbd) without reducing it.
fn beyond_size_cap(scene: &Scene) -> Option<Outcome> {
    scene.bodies.iter().find_map(|b| match &b.model {
        flexmbd::model::BodyModel::Beam(spec) if spec.n_fe_dofs() > MAX_BEAM_FE_DOFS => {
            Some(Outcome::new(
                Class::Refused,
                format!(
                    "bodies[{}]: {} FE DOFs, above the campaign's cap of {MAX_BEAM_FE_DOFS} (not run)",
                    b.name,
                    spec.n_fe_dofs()
                ),
            ))
        }
        _ => None,
    })
}

/// The first non-finite sensor, coordinate or velocity at the current state, named.
fn non_finite(sim: &mut Simulation, sensors: &mut [f64]) -> Option<String> {
    sim.read_sensors(sensors);
    if let Some(i) = sensors.iter().position(|v| !v.is_finite()) {
        return Some(format!(
            "sensor `{}` = {}",
            sim.sensor_names()[i],
            sensors[i]
        ));
    }
    let state = sim.integrator();
    if let Some(i) = state.q.iter().position(|v| !v.is_finite()) {
        return Some(format!("q[{i}] = {}", state.q[i]));
    }
    if let Some(i) = state.qd.iter().position(|v| !v.is_finite()) {
        return Some(format!("qd[{i}] = {}", state.qd[i]));
    }
    None
}

/// A refusal by the model: its message must be non-empty and, for a refused value or a
/// missing name, must name the field.
fn refusal(e: &ModelError) -> Outcome {
    let message = e.to_string();
    let field = match e {
        ModelError::Invalid { error, .. } => Some(error.field.as_str()),
        ModelError::Missing { item, .. } => Some(item.as_str()),
        _ => None,
    };
    match field {
        Some(f) if f.trim().is_empty() => {
            Outcome::new(Class::BadMessage, format!("names no field: {message}"))
        }
        Some(f) if !message.contains(f) => Outcome::new(
            Class::BadMessage,
            format!("does not show field `{f}`: {message}"),
        ),
        _ => checked(Class::Refused, &message),
    }
}

/// `class` with `message`, or a bad message when it is empty.
fn checked(class: Class, message: &str) -> Outcome {
    if message.trim().is_empty() {
        Outcome::new(
            Class::BadMessage,
            format!("{} with an empty message", class.name()),
        )
    } else {
        Outcome::new(class, message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::corpus::{default_models_dir, load_corpus};

    fn pendulum() -> String {
        std::fs::read_to_string(default_models_dir().join("flexible_pendulum.ron")).unwrap()
    }

    /// In this process, whose working directory is not `models/`: the scenes with an
    /// imported body, whose export is named relative to the scene, are run by a worker
    /// started there (`tests/supervisor.rs`).
    #[test]
    fn every_scene_of_the_corpus_runs_ok_in_both_formulations() {
        let (corpus, _) = load_corpus(&default_models_dir()).unwrap();
        let self_contained = corpus.iter().filter(|s| !s.text.contains("Imported("));
        for seed in self_contained {
            for f in [FormulationKind::Absolute, FormulationKind::Relative] {
                let o = execute(&seed.text, f, 2);
                assert_eq!(
                    o.class,
                    Class::Ok,
                    "{} {f:?}: {}",
                    seed.path.display(),
                    o.detail
                );
            }
        }
    }

    #[test]
    fn a_syntax_error_is_refused_with_its_position() {
        let o = execute("(name: \"x\",", FormulationKind::Absolute, 2);
        assert_eq!(o.class, Class::Refused, "{}", o.detail);
        assert!(o.detail.starts_with("mutant.ron:1:"), "{}", o.detail);
    }

    #[test]
    fn a_negative_step_is_refused_naming_solver_step() {
        let text = pendulum().replace("step: 1e-3", "step: -1e-3");
        assert_ne!(
            text,
            pendulum(),
            "the seed's step literal changed; update the test"
        );
        let o = execute(&text, FormulationKind::Relative, 2);
        assert_eq!(o.class, Class::Refused, "{}", o.detail);
        assert!(o.detail.contains("solver.step"), "{}", o.detail);
    }

    #[test]
    fn the_steps_stop_at_the_cap_or_at_the_duration_whichever_comes_first() {
        let o = execute(&pendulum(), FormulationKind::Absolute, 3);
        assert_eq!(o, Outcome::new(Class::Ok, "3 steps to t = 0.003"));
        let short = pendulum().replace("duration: 10.0", "duration: 0.002");
        assert_ne!(
            short,
            pendulum(),
            "the seed's duration changed; update the test"
        );
        let o = execute(&short, FormulationKind::Relative, 3);
        assert_eq!(o, Outcome::new(Class::Ok, "2 steps to t = 0.002"));
    }

    #[test]
    fn class_names_round_trip() {
        for c in CLASSES {
            assert_eq!(Class::from_name(c.name()), Some(c));
        }
    }
}
