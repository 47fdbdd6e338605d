//! Compiling a prepared scene into [`Spatial`], step by step: the bodies and their natural
//! coordinates at t = 0 (with a rigid body's constant mass matrix and gravity), the term
//! lookup, the joints and drivers as constraints, the scene's marker constraints, the sensors, the reference angles at
//! t = 0, and the force elements over the marker terms.

use std::collections::HashMap;

use flexmbd_body::{InertiaMethod, NaturalState};
use flexmbd_core::{Coordinates, Dim};
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{Body, FormulationKind, MarkerId, ModelError, PreparedScene};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::constraints::{AngleConstraint, Constraint};
use super::joints::joint_constraints;
use super::lookup::TermLookup;
use super::marker_constraints::marker_constraints;
use super::sensors::sensor_terms;
use super::{FlexibleScratch, MarkerSite, Spatial, SpatialBody};

/// The bodies, their coordinates at t = 0 and the data the term lookup needs.
struct BuiltBodies {
    bodies: Vec<SpatialBody>,
    q0: Vec<f64>,
    qd0: Vec<f64>,
    initial_frames: Vec<(Vector3<f64>, Matrix3<f64>)>,
}

impl Spatial {
    /// Compile a spatial scene.
    pub fn compile(prepared: &PreparedScene) -> Result<Spatial, ModelError> {
        let scene = prepared.scene();
        debug_assert_eq!(scene.solver.formulation, FormulationKind::Absolute);
        debug_assert_eq!(scene.dim, Dim::Spatial);
        let method = scene.solver.inertia;
        let g = scene.gravity.vec();
        let built = build_bodies(prepared, method, &g);
        let n = built.q0.len();
        let mut constraints: Vec<Constraint> = built
            .bodies
            .iter()
            .map(|b| Constraint::Orthonormality { offset: b.offset })
            .collect();
        let lookup = TermLookup {
            scene,
            joints: prepared.joint_markers(),
            constraints: prepared.constraint_markers(),
            bodies: &built.bodies,
            initial_frames: built.initial_frames,
            nodes: prepared.bodies().iter().map(|prep| &prep.nodes).collect(),
        };
        let force_markers: HashMap<_, _> = prepared
            .force_marker_ids()
            .map(|id: MarkerId| (id, lookup.point(id)))
            .collect();
        joint_constraints(&lookup, &mut constraints)?;
        marker_constraints(&lookup, &mut constraints)?;
        let m = constraints.iter().map(Constraint::rows).sum();
        let sensor_terms = sensor_terms(&lookup, prepared)?;
        drop(lookup);
        let (q0, qd0) = (DVector::from_vec(built.q0), DVector::from_vec(built.qd0));
        let mut spatial = Spatial {
            coordinates: Coordinates::new(q0, qd0, m),
            gravity: g,
            bodies: built.bodies,
            constraints,
            sensors: Default::default(),
            inertia_method: method,
            force_elements: ForceElements::default(),
            zero_rates: DVector::zeros(n),
            driven_frames: Vec::new(),
        };
        spatial.set_reference_angles();
        spatial.driven_frames = spatial.find_driven_frames();
        spatial.sensors = spatial.build_sensors(prepared, sensor_terms)?;
        let (q0, qd0) = (
            spatial.coordinates.q0.clone(),
            spatial.coordinates.qd0.clone(),
        );
        spatial.force_elements = ForceElements::new(
            prepared,
            |id| force_markers[&id].clone(),
            &spatial,
            &q0,
            &qd0,
            n,
        )?;
        Ok(spatial)
    }

    /// The reference angles φ0 of the angle drivers: their angles at t = 0.
    fn set_reference_angles(&mut self) {
        let z = DVector::zeros(self.coordinates.len());
        let q0 = self.coordinates.q0.clone();
        let mut phis = Vec::new();
        for c in &self.constraints {
            if let Constraint::Angle(AngleConstraint { p1, p2, a, .. }) = c {
                phis.push(self.angle(p1, p2, a, &q0, &z));
            }
        }
        let mut it = phis.into_iter();
        for c in &mut self.constraints {
            if let Constraint::Angle(AngleConstraint { phi0, .. }) = c {
                *phi0 = it.next().expect("one angle per driver");
            }
        }
    }
}

/// Every body in scene order, its coordinates `q_b = {r0; u; v; w; y}` at t = 0 appended to
/// q0 and q̇0, and its markers' node modes.
fn build_bodies(prepared: &PreparedScene, method: InertiaMethod, g: &Vector3<f64>) -> BuiltBodies {
    let scene = prepared.scene();
    let mut built = BuiltBodies {
        bodies: Vec::new(),
        q0: Vec::new(),
        qd0: Vec::new(),
        initial_frames: Vec::new(),
    };
    for (b, prep) in scene.bodies.iter().zip(prepared.bodies()) {
        let body = prep.body.clone();
        let n_modes = if prep.flexible { body.n_modes() } else { 0 };
        debug_assert_eq!(n_modes, body.n_modes());
        let offset = built.q0.len();
        let a0 = b.orientation.matrix();
        built.initial_frames.push((b.origin.vec(), a0));
        initial_coordinates(b, a0, n_modes, &mut built.q0, &mut built.qd0);
        let markers: Vec<MarkerSite> = b
            .markers
            .iter()
            .zip(&prep.marker_nodes)
            .map(|(m, node)| MarkerSite {
                position: m.position.vec(),
                node: if n_modes > 0 { *node } else { None },
            })
            .collect();
        let spatial_body = if n_modes > 0 {
            flexible_body(body, n_modes, offset, markers)
        } else {
            let states = (
                &built.q0[offset..offset + 12],
                &built.qd0[offset..offset + 12],
            );
            rigid_body(body, states, method, g, offset, markers)
        };
        built.bodies.push(spatial_body);
    }
    built
}

/// Append a body's `{r0; u; v; w; y}` to q0 and `{ṙ0; ω̃ u; ω̃ v; ω̃ w; 0}` to q̇0.
fn initial_coordinates(
    b: &Body,
    a0: Matrix3<f64>,
    n_modes: usize,
    q0: &mut Vec<f64>,
    qd0: &mut Vec<f64>,
) {
    let o = b.origin.vec();
    q0.extend(o.iter());
    let om = b.velocity.angular.vec();
    qd0.extend(b.velocity.linear.vec().iter());
    for c in 0..3 {
        let e = a0.column(c).into_owned();
        q0.extend(e.iter());
        qd0.extend(om.cross(&e).iter());
    }
    q0.extend((0..n_modes).map(|j| b.initial_modes.get(j).copied().unwrap_or(0.0)));
    qd0.extend(std::iter::repeat_n(0.0, n_modes));
}

/// A flexible body with its scratch sized once.
fn flexible_body(
    body: flexmbd_body::FlexibleBody,
    n_modes: usize,
    offset: usize,
    markers: Vec<MarkerSite>,
) -> SpatialBody {
    let flexible = FlexibleScratch {
        natural: body.natural_workspace(),
        gravity: vec![0.0; 12 + n_modes],
        elastic: vec![0.0; n_modes],
        energy_mass: DMatrix::zeros(12 + n_modes, 12 + n_modes),
        energy_forces: DVector::zeros(12 + n_modes),
    };
    SpatialBody {
        body,
        offset,
        n_modes,
        rigid_mass: DMatrix::zeros(0, 0),
        rigid_gravity: DVector::zeros(0),
        markers,
        flexible: Some(flexible),
    }
}

/// A rigid body with its constant M and gravity, computed at its initial state (any state
/// will do: n = 0).
fn rigid_body(
    body: flexmbd_body::FlexibleBody,
    (qs, qds): (&[f64], &[f64]),
    method: InertiaMethod,
    g: &Vector3<f64>,
    offset: usize,
    markers: Vec<MarkerSite>,
) -> SpatialBody {
    let mut rigid_mass = DMatrix::zeros(12, 12);
    let mut qv = DVector::zeros(12);
    let st = NaturalState::from_coords(Dim::Spatial, qs, qds);
    let mut ws = body.natural_workspace();
    body.inertia_natural(&st, method, &mut ws, &mut rigid_mass, &mut qv);
    let mut gv = vec![0.0; 12];
    body.gravity_natural(&st, g, &mut gv);
    SpatialBody {
        body,
        offset,
        n_modes: 0,
        rigid_mass,
        rigid_gravity: DVector::from_vec(gv),
        markers,
        flexible: None,
    }
}
