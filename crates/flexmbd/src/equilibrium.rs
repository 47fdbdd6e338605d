//! The static equilibrium of a scene as a result of its own (`flexmbd equilibrium`): every
//! coordinate, the constraint multipliers, the sensors, the force elements' forces and the
//! joints' reactions there, and how the solve went.
//!
//! The solve is `flexmbd_integrators::statics::solve_static` at t = 0 with q̇ = 0, the one a
//! run with `solver.initial_state: StaticEquilibrium` starts from (docs/methods.md §5.4 item
//! 4); this module only compiles the scene, solves and reads the result.
//!
//! Each force element's force at the equilibrium — a spring–damper's or link's tension
//! (its damper carries nothing at rest) and length, a tyre's normal force and deflection — is
//! read by `ElementForce` probes, sensors added to a copy of the scene for this purpose only
//! (sensors do not enter the dynamics, so the copy's equilibrium is the scene's): the same
//! compiled force elements that load the equilibrium compute what is reported.
//!
//! Each joint's and scene constraint's reaction — the force and moment it exerts on its body2
//! at body2's marker, ground components — comes from every body's balance at the equilibrium,
//! the same route in every formulation ([`reactions`]: the module documentation says how,
//! and why not from λ).
//!
//! The multipliers λ are those of Q − Φ_qᵀλ = 0: the constraint forces on the coordinates
//! are −Φ_qᵀλ, one multiplier per constraint equation in the formulation's order (the
//! equations are the formulation's, not the joints': a revolute joint in natural coordinates
//! is several equations, in relative coordinates none unless it closes a loop).

use flexmbd_core::{CompiledScene, State};
use flexmbd_integrators::{StaticCounters, StaticSettings, StaticSolution, solve_static};
use flexmbd_model::{ElementQuantity, Force, FormulationKind, Scene, Sensor, SensorKind};
use nalgebra::DVector;
use serde::Serialize;

use crate::Error;

pub mod reactions;

use reactions::ReactionProbes;
pub use reactions::{JointReaction, Reactions};

/// A named value (a sensor at the equilibrium).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Named {
    /// The name.
    pub name: String,
    /// The value (SI units).
    pub value: f64,
}

/// A force element at the equilibrium.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ElementForce {
    /// The element's name.
    pub name: String,
    /// Its type: `SpringDamper`, `Link` or `Tyre`.
    pub kind: &'static str,
    /// The length its law is evaluated at (m): a spring–damper's or a link's length l (the
    /// distance of its markers, or a·(r₂ − r₁) along a body-fixed axis); a tyre's deflection
    /// δ = R − (z_W − h) (negative: off the road).
    pub length: f64,
    /// A spring–damper's free length l₀ (m); `None` for the other elements.
    pub free_length: Option<f64>,
    /// Its force (N): the tension (positive pulling the ends together; the damper carries
    /// nothing at rest), a tyre's normal force (≥ 0).
    pub force: f64,
}

/// The static equilibrium of a scene (module documentation).
#[derive(Clone, Debug, Serialize)]
pub struct Equilibrium {
    /// The scene's name.
    pub scene: String,
    /// `absolute` or `relative`.
    pub formulation: String,
    /// Coordinates n.
    pub n_coordinates: usize,
    /// Constraint equations m (redundant ones included).
    pub n_constraints: usize,
    /// The coordinates q at the equilibrium (n).
    pub coordinates: Vec<f64>,
    /// The constraint multipliers λ (m): the constraint forces are −Φ_qᵀλ.
    pub multipliers: Vec<f64>,
    /// The sensors at the equilibrium, in the scene's order.
    pub sensors: Vec<Named>,
    /// Each force element's state at the equilibrium, in the scene's order.
    pub forces: Vec<ElementForce>,
    /// The joints' and scene constraints' reactions (`None` when not computed: in the
    /// equilibrium of `flexmbd eigen`, for a scene without joints or constraints, when the
    /// stiffening rewrite changes the bodies or their modes — substructuring, FNL2, FS0 —
    /// and if the balance equations are not finite).
    pub reactions: Option<Reactions>,
    /// True when the scene has joints or constraints but their reactions were not computed
    /// (`reactions` says when).
    pub reactions_skipped: bool,
    /// How the static solve went (flattened into the JSON object).
    #[serde(flatten)]
    pub solve: StaticCounters,
}

/// The name of a scene's formulation.
pub(crate) fn formulation_name(scene: &Scene) -> &'static str {
    match scene.solver.formulation {
        FormulationKind::Absolute => "absolute",
        FormulationKind::Relative => "relative",
    }
}

/// Compile `scene` (validated, as [`Scene::load`] leaves it) and find its static
/// equilibrium at t = 0: the compiled formulation and the solution.
pub(crate) fn solve(scene: &Scene) -> Result<(Box<dyn CompiledScene>, StaticSolution), Error> {
    let mut f = crate::simulation::compile(scene)?;
    let solution = solve_static(f.as_mut(), 0.0, &StaticSettings::default())?;
    Ok((f, solution))
}

/// The sensors of `f` at (t = 0, q, q̇ = 0).
pub(crate) fn sensors_at(f: &mut dyn CompiledScene, q: &DVector<f64>) -> Vec<f64> {
    let mut out = vec![0.0; f.sensor_names().len()];
    let qd = DVector::zeros(q.len());
    f.sensors(State::new(0.0, q, &qd), &mut out);
    out
}

impl Equilibrium {
    /// The report of `solution`, a static equilibrium of `f` compiled from `scene`.
    pub(crate) fn of(scene: &Scene, f: &mut dyn CompiledScene, solution: &StaticSolution) -> Self {
        let values = sensors_at(f, &solution.q);
        Equilibrium {
            scene: scene.name.clone(),
            formulation: formulation_name(scene).into(),
            n_coordinates: f.n_coordinates(),
            n_constraints: f.n_constraints(),
            coordinates: solution.q.iter().copied().collect(),
            multipliers: solution.lambda.iter().copied().collect(),
            sensors: f
                .sensor_names()
                .iter()
                .zip(values)
                .map(|(name, value)| Named {
                    name: name.clone(),
                    value,
                })
                .collect(),
            forces: Vec::new(),
            reactions: None,
            reactions_skipped: false,
            solve: solution.counters,
        }
    }

    /// The value of the sensor `name`, if the scene has one.
    pub fn sensor(&self, name: &str) -> Option<f64> {
        self.sensors
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.value)
    }

    /// A table for a reader: the solve, the sensors, the coordinates and the multipliers.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "{}: static equilibrium, {} formulation — {} coordinates, {} constraints\n  {} Newton iterations, {} load steps, residual {:.3e}, max |Φ| {:.3e}\n",
            self.scene,
            self.formulation,
            self.n_coordinates,
            self.n_constraints,
            self.solve.iterations,
            self.solve.load_steps,
            self.solve.residual,
            self.solve.phi
        );
        s += "sensors:\n";
        for n in &self.sensors {
            s += &format!("  {:<24} {:>16.9e}\n", n.name, n.value);
        }
        if !self.forces.is_empty() {
            s += "force elements (tension positive):\n";
            for e in &self.forces {
                s += &match (e.kind, e.free_length) {
                    ("Tyre", _) => format!(
                        "  {:<24} {:>16.9e} N   normal force, deflection {:.9e} m\n",
                        e.name, e.force, e.length
                    ),
                    (_, Some(free)) => format!(
                        "  {:<24} {:>16.9e} N   length {:.9e} m, free length {:.9e} m\n",
                        e.name, e.force, e.length, free
                    ),
                    (_, None) => format!(
                        "  {:<24} {:>16.9e} N   length {:.9e} m\n",
                        e.name, e.force, e.length
                    ),
                };
            }
        }
        match &self.reactions {
            Some(r) => s += &r.to_text(),
            None if self.reactions_skipped => {
                s += "joint reactions: not computed (the stiffening rewrite changes the bodies or their modes, or the balance is not finite)\n"
            }
            None => {}
        }
        s += "coordinates q:\n";
        for (i, v) in self.coordinates.iter().enumerate() {
            s += &format!("  q{i:<23} {v:>16.9e}\n");
        }
        s += "multipliers λ (constraint forces −Φ_qᵀλ):\n";
        for (i, v) in self.multipliers.iter().enumerate() {
            s += &format!("  λ{i:<23} {v:>16.9e}\n");
        }
        s
    }
}

/// The static equilibrium of `scene` at t = 0 in the formulation its solver block names
/// (module documentation). `scene` should be validated (as [`Scene::load`] does).
pub fn equilibrium(scene: &Scene) -> Result<Equilibrium, Error> {
    let (mut f, solution) = solve(scene)?;
    let mut e = Equilibrium::of(scene, f.as_mut(), &solution);
    (e.forces, e.reactions) = probe(scene, &solution.q, true)?;
    e.reactions_skipped =
        e.reactions.is_none() && !(scene.joints.is_empty() && scene.constraints.is_empty());
    Ok(e)
}

/// Every force element's state at the positions `q` of `scene` (module documentation).
pub(crate) fn element_forces(scene: &Scene, q: &DVector<f64>) -> Result<Vec<ElementForce>, Error> {
    Ok(probe(scene, q, false)?.0)
}

/// Every force element's state and, with `with_reactions`, the joints' reactions at the
/// positions `q` of `scene`, read by one compiled copy of the scene with probe sensors.
fn probe(
    scene: &Scene,
    q: &DVector<f64>,
    with_reactions: bool,
) -> Result<(Vec<ElementForce>, Option<Reactions>), Error> {
    let prepared = if with_reactions && !(scene.joints.is_empty() && scene.constraints.is_empty()) {
        Some(crate::pilot::prepared_scene(
            scene,
            &crate::simulation::NO_STOP,
        )?)
    } else {
        None
    };
    let reaction_probes = prepared
        .as_ref()
        .filter(|_| with_reactions)
        .and_then(|p| ReactionProbes::new(scene, p));
    if scene.forces.is_empty() && reaction_probes.is_none() {
        return Ok((Vec::new(), None));
    }
    let mut probed = scene.clone();
    let first = probed.sensors.len();
    probed.sensors.extend(element_probes(scene));
    let first_reaction = probed.sensors.len();
    if let Some(r) = &reaction_probes {
        probed.sensors.extend_from_slice(r.sensors());
    }
    let mut f = crate::simulation::compile(&probed)?;
    let values = sensors_at(f.as_mut(), q);
    let forces = element_states(scene, &values[first..first_reaction])?;
    let reactions = match (&prepared, &reaction_probes) {
        (Some(p), Some(r)) => reactions::reactions(p, r, &values[first_reaction..])?,
        _ => None,
    };
    Ok((forces, reactions))
}

/// The probe sensors of every force element's tension and length.
fn element_probes(scene: &Scene) -> Vec<Sensor> {
    let mut sensors = Vec::with_capacity(2 * scene.forces.len());
    for (i, force) in scene.forces.iter().enumerate() {
        for (quantity, what) in [
            (ElementQuantity::Force, "force"),
            (ElementQuantity::Length, "length"),
        ] {
            sensors.push(Sensor {
                name: format!("__force{i}_{what}"),
                kind: SensorKind::ElementForce {
                    force: force.name().to_string(),
                    quantity,
                },
                displacement: false,
            });
        }
    }
    sensors
}

/// Every force element's state from the values of its probes ([`element_probes`]).
fn element_states(scene: &Scene, probes: &[f64]) -> Result<Vec<ElementForce>, Error> {
    scene
        .forces
        .iter()
        .enumerate()
        .map(|(i, force)| {
            let free_length = match force {
                Force::SpringDamper { .. } => {
                    let [(b1, m1), (b2, m2)] = force.ends();
                    let undeformed = |b: &str, m: &str| {
                        scene.undeformed_position(b, m, None).unwrap_or_default()
                    };
                    Some(force.spring_free_length(
                        &scene.name,
                        &undeformed(b1, m1),
                        &undeformed(b2, m2),
                    )?)
                }
                Force::Link { .. } | Force::Tyre { .. } | Force::Load { .. } => None,
            };
            Ok(ElementForce {
                name: force.name().to_string(),
                kind: force.kind_name(),
                length: probes[2 * i + 1],
                free_length,
                force: probes[2 * i],
            })
        })
        .collect()
}
