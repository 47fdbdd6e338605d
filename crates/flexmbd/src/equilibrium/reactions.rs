//! The reactions of the joints and scene constraints at a static equilibrium, found the
//! same way in every formulation: from each body's balance of forces and moments.
//!
//! At rest every body is in equilibrium under what is applied to it — gravity m g at its
//! (deformed) centre of mass, the force elements' forces at their markers (a tyre's normal
//! force at its wheel centre; a link along a body-fixed axis also at its auxiliary axis
//! marker, which makes its moment on body1) — and the reactions of the joints and
//! constraints that touch it. A flexible body's elastic forces are internal to it and do not
//! enter its balance; only the external forces at their deformed points do. The unknowns
//! are each joint's reaction components along its constrained directions, at body2's
//! marker P2, in ground components (body1 feels the opposite wrench at the same point):
//!
//! | joint | forces | moments |
//! |---|---|---|
//! | Revolute | 3 (planar 2) | 2 ⊥ the axis (planar none) |
//! | Spherical | 3 | — |
//! | Universal | 3 | 1, along arm1 × arm2 |
//! | Prismatic | 2 ⊥ the axis (planar 1) | 3 (planar 1) |
//! | Cylindrical | 2 ⊥ the axis | 2 ⊥ the axis |
//! | Rigid | 3 (planar 2) | 3 (planar 1) |
//! | Free | — | — |
//!
//! A driven joint carries one more: the moment about its axis (revolute) or the force along
//! it (prismatic). A `Distance` constraint is one tension f along n = (r_P2 − r_P1)/|…|
//! (body2 feels −f n), a `PointInPlane` one force f n on P2 along the plane's normal. The
//! balance equations — 6 per moving body (planar 3: x, y and the moment about z), moments
//! about the body frame's origin — are solved for the unknowns by least squares with the
//! minimum norm (an SVD): redundant constraints make the reactions non-unique, and the
//! result then says so (`redundant`) and gives the minimum-norm set. The balance left
//! after the solve (`residual_force`, `residual_moment`) is the static solve's own
//! residual seen body by body.
//!
//! The kinematics come from sensors read at the equilibrium (`ReactionProbes`), so the
//! route is the same in every formulation: per body its three Cardan angles (its rotation
//! A = R A(0)), one marker's position in the ground and in the body's own frame (its origin
//! r0 = r_P − A p_P), a flexible body's modal coordinates y (its first moment m̄(y)) and
//! the ground positions of its markers (on nodes: deformed). The force elements are the
//! compiled ones of `flexmbd_model::force_elements`, evaluated over the markers' positions
//! as coordinates: the generalised force on a marker's three coordinates is the force on
//! that marker.
//!
//! Not computed for a substructured scene (`--stiffening substructuring:N`: its bodies are
//! not the scene's) nor when the stiffening rewrite changes a flexible body's modes (FNL2's
//! complete axial basis, FS0 without axial modes: modal coordinates the scene's sensors do
//! not name).

use flexmbd_core::{Dim, SystemTerms};
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::interface_force::{MarkerPoints, start_position};
use flexmbd_model::{
    Axis, Constraint, JointKind, MarkerId, PreparedScene, Scene, Sensor, SensorKind,
};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::Serialize;

/// The reaction of one joint or scene constraint at the equilibrium.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointReaction {
    /// The joint's (or constraint's) name.
    pub name: String,
    /// Its type: `Revolute`, …, `Free`, `Distance`, `PointInPlane`.
    pub kind: &'static str,
    /// The body it acts on (its `body2`).
    pub body: String,
    /// The force it exerts on body2 (N, ground components).
    pub force: [f64; 3],
    /// The moment it exerts on body2 about body2's marker (N·m, ground components).
    pub moment: [f64; 3],
    /// A `Distance` constraint's tension (N, positive pulling the markers together), a
    /// `PointInPlane` constraint's normal force on P2 along the normal (N); `None` for the
    /// joints.
    pub scalar: Option<f64>,
}

/// The joints' and constraints' reactions at an equilibrium (module documentation).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Reactions {
    /// Every joint then every scene constraint, in the scene's order.
    pub joints: Vec<JointReaction>,
    /// Balance equations (6 per moving body; planar 3).
    pub equations: usize,
    /// Reaction components solved for.
    pub unknowns: usize,
    /// The rank of the balance equations in the unknowns.
    pub rank: usize,
    /// Whether the constraints are redundant (rank < unknowns): the reactions are then not
    /// unique, and these are the minimum-norm ones.
    pub redundant: bool,
    /// The largest force left unbalanced on a body after the solve (N).
    pub residual_force: f64,
    /// The largest moment left unbalanced on a body after the solve (N·m).
    pub residual_moment: f64,
}

impl Reactions {
    /// A table for a reader: each reaction's force and moment on its body2, and how the
    /// balance was solved.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "joint reactions on body2 at its marker (ground components; force N, moment N·m):\n  {} balance equations, {} unknowns, rank {}; unbalanced after the solve: {:.3e} N, {:.3e} N·m\n",
            self.equations, self.unknowns, self.rank, self.residual_force, self.residual_moment
        );
        if self.redundant {
            s += "  redundant constraints: the reactions are not unique; these are the minimum-norm ones\n";
        }
        for r in &self.joints {
            let [fx, fy, fz] = r.force;
            let [mx, my, mz] = r.moment;
            s += &format!(
                "  {:<24} {:<12} on {:<16} F ({fx:>14.6e} {fy:>14.6e} {fz:>14.6e})  M ({mx:>14.6e} {my:>14.6e} {mz:>14.6e})",
                r.name, r.kind, r.body
            );
            if let Some(v) = r.scalar {
                let what = if r.kind == "Distance" {
                    "tension"
                } else {
                    "normal force"
                };
                s += &format!("  {what} {v:.9e} N");
            }
            s += "\n";
        }
        s
    }
}

const PREFIX: &str = "__reaction";

/// The sensors the reactions read at the equilibrium, and where their values land.
pub(crate) struct ReactionProbes {
    sensors: Vec<Sensor>,
    /// Per body: the index of its first sensor, `None` for a body with no markers (no joint,
    /// force or constraint touches it).
    first: Vec<Option<usize>>,
    /// Position components per marker: 2 in a planar scene (z = 0), 3 in space.
    components: usize,
}

fn position_sensor(
    name: String,
    body: &str,
    marker: &str,
    axis: Axis,
    frame: Option<&str>,
) -> Sensor {
    Sensor {
        name,
        kind: SensorKind::Position {
            body: body.to_string(),
            marker: marker.to_string(),
            component: axis,
            frame: frame.map(str::to_string),
        },
        displacement: false,
    }
}

const AXES: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

impl ReactionProbes {
    /// The probes of `scene`, whose prepared form is `prepared` (`None` when the reactions
    /// are not computed for it: substructured bodies).
    pub(crate) fn new(scene: &Scene, prepared: &PreparedScene) -> Option<Self> {
        let same_bodies = prepared.scene().bodies.len() == scene.bodies.len()
            && prepared
                .scene()
                .bodies
                .iter()
                .zip(&scene.bodies)
                .all(|(p, b)| p.name == b.name);
        // A stiffening rewrite that changes a body's modes (FNL2's axial basis, FS0 without
        // axial modes) leaves modal coordinates the scene's sensors cannot name.
        let same_modes = scene
            .bodies
            .iter()
            .zip(prepared.bodies())
            .all(|(b, p)| !p.flexible || p.body.n_modes() == b.declared_modes());
        if !(same_bodies && same_modes) {
            return None;
        }
        let components = scene.dim.n_trans();
        let position_axes = &AXES[..components];
        let mut sensors = Vec::new();
        let mut first = Vec::with_capacity(scene.bodies.len());
        for (i, body) in scene.bodies.iter().enumerate() {
            let Some(m0) = body.markers.first() else {
                first.push(None);
                continue;
            };
            first.push(Some(sensors.len()));
            for axis in AXES {
                sensors.push(Sensor {
                    name: format!("{PREFIX}{i}_angle{axis:?}"),
                    kind: SensorKind::Angle {
                        body: body.name.clone(),
                        axis,
                    },
                    displacement: false,
                });
            }
            for (frame, tag) in [(None, "g"), (Some(body.name.as_str()), "l")] {
                for &axis in position_axes {
                    let name = format!("{PREFIX}{i}_origin{tag}{axis:?}");
                    sensors.push(position_sensor(name, &body.name, &m0.name, axis, frame));
                }
            }
            let prepared_body = &prepared.bodies()[i];
            if prepared_body.flexible {
                for index in 0..prepared_body.body.n_modes() {
                    sensors.push(Sensor {
                        name: format!("{PREFIX}{i}_mode{index}"),
                        kind: SensorKind::Modal {
                            body: body.name.clone(),
                            index,
                        },
                        displacement: false,
                    });
                }
                for marker in &body.markers {
                    for &axis in position_axes {
                        let name = format!("{PREFIX}{i}_{}{axis:?}", marker.name);
                        sensors.push(position_sensor(name, &body.name, &marker.name, axis, None));
                    }
                }
            }
        }
        Some(ReactionProbes {
            sensors,
            first,
            components,
        })
    }

    /// The sensors to add to the scene.
    pub(crate) fn sensors(&self) -> &[Sensor] {
        &self.sensors
    }
}

/// A body's placement at the equilibrium, read from the probes.
struct Placement {
    origin: Vector3<f64>,
    rotation: Matrix3<f64>,
    /// R = A A(0)ᵀ, the rotation since t = 0.
    turn: Matrix3<f64>,
    /// Ground positions of the markers of a flexible body, in the body's marker order.
    markers: Vec<Vector3<f64>>,
    /// Centre of mass (ground components) and mass.
    centre: Vector3<f64>,
    mass: f64,
}

/// R = R_x(α) R_y(β) R_z(γ) of the sensors' intrinsic Cardan angles.
fn cardan_matrix(a: f64, b: f64, c: f64) -> Matrix3<f64> {
    let rx = Matrix3::new(1.0, 0.0, 0.0, 0.0, a.cos(), -a.sin(), 0.0, a.sin(), a.cos());
    let ry = Matrix3::new(b.cos(), 0.0, b.sin(), 0.0, 1.0, 0.0, -b.sin(), 0.0, b.cos());
    let rz = Matrix3::new(c.cos(), -c.sin(), 0.0, c.sin(), c.cos(), 0.0, 0.0, 0.0, 1.0);
    rx * ry * rz
}

fn placements(
    scene: &Scene,
    prepared: &PreparedScene,
    probes: &ReactionProbes,
    values: &[f64],
) -> Vec<Option<Placement>> {
    let c = probes.components;
    let v3 = |k: usize| {
        let mut v = Vector3::zeros();
        v.as_mut_slice()[..c].copy_from_slice(&values[k..k + c]);
        v
    };
    scene
        .bodies
        .iter()
        .zip(&probes.first)
        .enumerate()
        .map(|(i, (body, first))| {
            let k = (*first)?;
            let turn = cardan_matrix(values[k], values[k + 1], values[k + 2]);
            let rotation = turn * body.orientation.matrix();
            let origin = v3(k + 3) - rotation * v3(k + 3 + c);
            let prepared_body = &prepared.bodies()[i];
            let mut k = k + 3 + 2 * c;
            let mut y = Vec::new();
            let mut markers = Vec::new();
            if prepared_body.flexible {
                let n = prepared_body.body.n_modes();
                y.extend_from_slice(&values[k..k + n]);
                k += n;
                markers = (0..body.markers.len()).map(|j| v3(k + c * j)).collect();
            } else {
                y.resize(prepared_body.body.n_modes(), 0.0);
            }
            let mass = prepared_body.body.mass();
            let centre = origin + rotation * prepared_body.body.first_moment_at(&y) / mass;
            Some(Placement {
                origin,
                rotation,
                turn,
                markers,
                centre,
                mass,
            })
        })
        .collect()
}

/// Where a marker of the prepared scene is at the equilibrium (ground components).
fn marker_position(
    prepared: &PreparedScene,
    placements: &[Option<Placement>],
    marker: MarkerId,
) -> Option<Vector3<f64>> {
    let local = prepared.marker_position(marker);
    let Some(body) = marker.body else {
        return Some(local);
    };
    let p = placements[body.0].as_ref()?;
    Some(match p.markers.get(marker.index) {
        Some(r) => *r,
        None => p.origin + p.rotation * local,
    })
}

/// The balance equations: a wrench on a body about its frame origin, by rows.
struct Balance {
    dim: Dim,
    /// Per scene body: its first row, `None` if it has no placement.
    rows: Vec<Option<usize>>,
    origins: Vec<Vector3<f64>>,
    n_rows: usize,
}

impl Balance {
    fn new(dim: Dim, placements: &[Option<Placement>]) -> Self {
        let per_body = dim.n_rigid();
        let mut n_rows = 0;
        let rows = placements
            .iter()
            .map(|p| {
                p.as_ref().map(|_| {
                    n_rows += per_body;
                    n_rows - per_body
                })
            })
            .collect();
        let origins = placements
            .iter()
            .map(|p| p.as_ref().map_or(Vector3::zeros(), |p| p.origin))
            .collect();
        Balance {
            dim,
            rows,
            origins,
            n_rows,
        }
    }

    /// Add force `f` at `point` and moment `m` on `body` (ground: nothing) to `column`.
    fn add(
        &self,
        column: &mut [f64],
        body: Option<usize>,
        point: &Vector3<f64>,
        f: &Vector3<f64>,
        m: &Vector3<f64>,
    ) {
        let Some(row) = body.and_then(|b| self.rows[b]) else {
            return;
        };
        let moment = (point - self.origins[body.unwrap_or(0)]).cross(f) + m;
        match self.dim {
            Dim::Planar => {
                column[row] += f.x;
                column[row + 1] += f.y;
                column[row + 2] += moment.z;
            }
            Dim::Spatial => {
                for a in 0..3 {
                    column[row + a] += f[a];
                    column[row + 3 + a] += moment[a];
                }
            }
        }
    }
}

/// A joint's constrained directions (forces, moments), ground components, at the
/// equilibrium (`flexmbd_model::reaction_directions`); `driven` adds its driven direction.
fn joint_directions(
    dim: Dim,
    kind: &JointKind,
    turn1: &Matrix3<f64>,
    turn2: &Matrix3<f64>,
    driven: bool,
) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let (forces, moments) =
        flexmbd_model::reaction_directions::joint_directions(dim, kind, turn1, turn2, driven);
    (forces.as_slice().to_vec(), moments.as_slice().to_vec())
}

/// One reaction component: which reaction it belongs to, its unit force and moment on
/// body2 at `point`.
struct Unknown {
    reaction: usize,
    bodies: [Option<usize>; 2],
    point: Vector3<f64>,
    force: Vector3<f64>,
    moment: Vector3<f64>,
}

/// The reactions of every joint and constraint, their unknowns and the balance's applied
/// side, at the placements found.
fn unknowns(
    prepared: &PreparedScene,
    placements: &[Option<Placement>],
) -> (Vec<JointReaction>, Vec<Unknown>) {
    let scene = prepared.scene();
    let identity = Matrix3::identity();
    let turn = |b: Option<usize>| {
        b.and_then(|b| placements[b].as_ref())
            .map_or(identity, |p| p.turn)
    };
    let mut reactions = Vec::new();
    let mut unknowns = Vec::new();
    let driven: Vec<usize> = prepared.driver_joints().iter().map(|j| j.0).collect();
    for (j, (joint, pair)) in scene
        .joints
        .iter()
        .zip(prepared.joint_markers())
        .enumerate()
    {
        let bodies = [pair.first.body.map(|b| b.0), pair.second.body.map(|b| b.0)];
        let (t1, t2) = (turn(bodies[0]), turn(bodies[1]));
        let t2 = if bodies[1].is_none() { t1 } else { t2 };
        let (forces, moments) =
            joint_directions(scene.dim, &joint.kind, &t1, &t2, driven.contains(&j));
        let point = marker_position(prepared, placements, pair.second).unwrap_or_default();
        let reaction = reactions.len();
        for f in forces {
            unknowns.push(Unknown {
                reaction,
                bodies,
                point,
                force: f,
                moment: Vector3::zeros(),
            });
        }
        for m in moments {
            unknowns.push(Unknown {
                reaction,
                bodies,
                point,
                force: Vector3::zeros(),
                moment: m,
            });
        }
        reactions.push(JointReaction {
            name: joint.name.clone(),
            kind: joint.kind.kind_name(),
            body: joint.body2.clone(),
            force: [0.0; 3],
            moment: [0.0; 3],
            scalar: None,
        });
    }
    for (constraint, pair) in scene.constraints.iter().zip(prepared.constraint_markers()) {
        let bodies = [pair.first.body.map(|b| b.0), pair.second.body.map(|b| b.0)];
        let p1 = marker_position(prepared, placements, pair.first).unwrap_or_default();
        let point = marker_position(prepared, placements, pair.second).unwrap_or_default();
        let force = match constraint {
            Constraint::Distance { .. } => -(point - p1).normalize(),
            Constraint::PointInPlane { normal, .. } => (turn(bodies[0]) * normal.vec()).normalize(),
        };
        let reaction = reactions.len();
        unknowns.push(Unknown {
            reaction,
            bodies,
            point,
            force,
            moment: Vector3::zeros(),
        });
        reactions.push(JointReaction {
            name: constraint.name().to_string(),
            kind: constraint.kind_name(),
            body: constraint.ends()[1].0.to_string(),
            force: [0.0; 3],
            moment: [0.0; 3],
            scalar: Some(0.0),
        });
    }
    (reactions, unknowns)
}

/// The applied side of the balance: gravity and the force elements, per body row.
fn applied_loads(
    prepared: &PreparedScene,
    placements: &[Option<Placement>],
    balance: &Balance,
) -> Result<DVector<f64>, flexmbd_model::ModelError> {
    let scene = prepared.scene();
    let mut b = DVector::zeros(balance.n_rows);
    let g = scene.gravity.vec();
    for (i, p) in placements.iter().enumerate() {
        if let Some(p) = p {
            balance.add(
                b.as_mut_slice(),
                Some(i),
                &p.centre,
                &(p.mass * g),
                &Vector3::zeros(),
            );
        }
    }
    let markers: Vec<MarkerId> = prepared.force_marker_ids().collect();
    if markers.is_empty() {
        return Ok(b);
    }
    let n = 3 * markers.len();
    let slot = |id: MarkerId| markers.iter().position(|m| *m == id).unwrap_or(0);
    let mut q0 = DVector::zeros(n);
    let mut q = DVector::zeros(n);
    for (s, id) in markers.iter().enumerate() {
        let start = start_position(prepared, *id);
        let now = marker_position(prepared, placements, *id).unwrap_or(start);
        q0.fixed_rows_mut::<3>(3 * s).copy_from(&start);
        q.fixed_rows_mut::<3>(3 * s).copy_from(&now);
    }
    let qd = DVector::zeros(n);
    let mut points = MarkerPoints;
    let mut elements = ForceElements::new(prepared, slot, &points, &q0, &qd, n)?;
    let mut terms = SystemTerms::new(n, 0);
    elements.add_forces(&mut points, &q, &qd, false, &mut terms);
    for (s, id) in markers.iter().enumerate() {
        let f = terms.forces.fixed_rows::<3>(3 * s).into_owned();
        let point = q.fixed_rows::<3>(3 * s).into_owned();
        balance.add(
            b.as_mut_slice(),
            id.body.map(|b| b.0),
            &point,
            &f,
            &Vector3::zeros(),
        );
    }
    Ok(b)
}

/// The reactions at the equilibrium whose probe values are `values` (module
/// documentation); `None` when the balance equations are not finite.
pub(crate) fn reactions(
    prepared: &PreparedScene,
    probes: &ReactionProbes,
    values: &[f64],
) -> Result<Option<Reactions>, flexmbd_model::ModelError> {
    let scene = prepared.scene();
    let placements = placements(scene, prepared, probes, values);
    let balance = Balance::new(scene.dim, &placements);
    let (mut joints, unknowns) = unknowns(prepared, &placements);
    let applied = applied_loads(prepared, &placements, &balance)?;
    let mut a = DMatrix::zeros(balance.n_rows, unknowns.len());
    for (k, u) in unknowns.iter().enumerate() {
        let column = a.column_mut(k);
        let column = column.data.into_slice_mut();
        balance.add(column, u.bodies[1], &u.point, &u.force, &u.moment);
        balance.add(column, u.bodies[0], &u.point, &-u.force, &-u.moment);
    }
    let Some((x, rank)) = min_norm_solution(&a, &(-&applied)) else {
        return Ok(None);
    };
    for (u, &x) in unknowns.iter().zip(x.iter()) {
        let r = &mut joints[u.reaction];
        for i in 0..3 {
            r.force[i] += x * u.force[i];
            r.moment[i] += x * u.moment[i];
        }
        if let Some(s) = &mut r.scalar {
            *s += x;
        }
    }
    let left = &a * &x + &applied;
    let (mut residual_force, mut residual_moment) = (0.0f64, 0.0f64);
    let (n_force, per_body) = (scene.dim.n_trans(), scene.dim.n_rigid());
    for (i, v) in left.iter().enumerate() {
        if i % per_body < n_force {
            residual_force = residual_force.max(v.abs());
        } else {
            residual_moment = residual_moment.max(v.abs());
        }
    }
    Ok(Some(Reactions {
        joints,
        equations: balance.n_rows,
        unknowns: unknowns.len(),
        rank,
        redundant: rank < unknowns.len(),
        residual_force,
        residual_moment,
    }))
}

/// The minimum-norm least-squares solution of a x = b and the rank of a (singular values
/// above 1e-10 of the largest count); `None` for non-finite equations or an SVD that does not
/// converge.
fn min_norm_solution(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<(DVector<f64>, usize)> {
    if a.ncols() == 0 || a.nrows() == 0 {
        return Some((DVector::zeros(a.ncols()), 0));
    }
    if !(a.iter().all(|v| v.is_finite()) && b.iter().all(|v| v.is_finite())) {
        return None;
    }
    let svd = nalgebra::SVD::try_new(a.clone(), true, true, f64::EPSILON, 10_000)?;
    let largest = svd.singular_values.max();
    let tolerance = 1e-10 * largest;
    let rank = svd
        .singular_values
        .iter()
        .filter(|&&s| s > tolerance)
        .count();
    let x = svd.solve(b, tolerance).ok()?;
    Some((x, rank))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cardan_matrix_inverts_the_sensors_angles() {
        // The sensors' angles of R: α = atan2(−R₁₂, R₂₂), β = asin R₀₂, γ = atan2(−R₀₁, R₀₀).
        let (a, b, c) = (0.3, -0.7, 2.1);
        let r = cardan_matrix(a, b, c);
        assert!((f64::atan2(-r[(1, 2)], r[(2, 2)]) - a).abs() < 1e-15);
        assert!((r[(0, 2)].asin() - b).abs() < 1e-15);
        assert!((f64::atan2(-r[(0, 1)], r[(0, 0)]) - c).abs() < 1e-15);
    }

    #[test]
    fn min_norm_solution_splits_a_redundant_load_evenly_and_refuses_non_finite_equations() {
        // Two unknowns carrying one load: x₁ + x₂ = 2, the minimum norm (1, 1), rank 1.
        let a = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let (x, rank) = min_norm_solution(&a, &DVector::from_element(1, 2.0)).unwrap();
        assert_eq!(rank, 1);
        assert!(
            (x[0] - 1.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15,
            "{x}"
        );
        assert!(min_norm_solution(&a, &DVector::from_element(1, f64::NAN)).is_none());
        let a = DMatrix::from_row_slice(1, 2, &[f64::INFINITY, 1.0]);
        assert!(min_norm_solution(&a, &DVector::from_element(1, 2.0)).is_none());
    }
}
