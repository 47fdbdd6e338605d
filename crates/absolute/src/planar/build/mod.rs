//! Compiling a prepared planar scene, step by step: the marker table, the shared points,
//! the bodies and their bases (with the initial velocities), the joints and drivers, the
//! force elements, the sensors and the constant rigid terms.

pub(super) mod marker_table;

mod bodies;
mod joints;
mod points;

use flexmbd_core::SystemTerms;
use flexmbd_model::force_elements::ForceElements;
use flexmbd_model::{BodyId, FormulationKind, MarkerId, ModelError, PreparedScene};
use nalgebra::{DMatrix, DVector, Vector2};

use super::Planar;
use super::constraints::Constraint;
use super::kinematics::PlanarMarker;
use bodies::BodyBuilder;
use marker_table::MarkerTable;
use points::Coordinates;

impl Planar {
    /// Compile a prepared planar scene.
    ///
    /// Coordinates come in order of allocation: the shared points, then body by body its
    /// own point and unit vector (when its basis has them) and its modal coordinates.
    /// Constraint rows: body by body its basis constraint and its other joint points, then
    /// the joints and drivers in joint order, then the scene's `Distance` constraints.
    ///
    /// Refused ([`ModelError::Unsupported`] or [`ModelError::Invalid`]): joint kinds other
    /// than revolute, prismatic, rigid and free; joined markers that do not coincide at
    /// t = 0; a prismatic axis that is zero or leaves the x–y plane; a sensor's z component;
    /// and what the shared force elements refuse.
    pub fn compile(prepared: &PreparedScene) -> Result<Planar, ModelError> {
        let scene = prepared.scene();
        debug_assert_eq!(scene.solver.formulation, FormulationKind::Absolute);
        let table = MarkerTable::new(scene);
        let mut coordinates = Coordinates::default();
        let points = points::shared_points(prepared, &table, &mut coordinates)?;
        let gravity = Vector2::new(scene.gravity.0[0], scene.gravity.0[1]);
        let mut constraints = Vec::new();
        let mut initial_rates = Vec::new();
        let mut builder = BodyBuilder {
            table: &table,
            points: &points,
            coordinates: &mut coordinates,
            constraints: &mut constraints,
            initial_rates: &mut initial_rates,
            gravity,
        };
        let bodies = (scene.bodies.iter().zip(prepared.bodies()).enumerate())
            .map(|(index, (b, prep))| builder.body(index, b, prep))
            .collect();
        let n = coordinates.len();
        let qd0 = initial_velocities(n, &initial_rates);
        let q0 = DVector::from_vec(coordinates.initial);
        let mut planar = Planar {
            coordinates: flexmbd_core::Coordinates::new(q0.clone(), qd0, 0),
            gravity,
            bodies,
            constraints: Vec::new(),
            force_elements: ForceElements::default(),
            rigid_mass: DMatrix::zeros(0, 0),
            rigid_forces: DVector::zeros(0),
            sensors: Default::default(),
            zero_rates: DVector::zeros(n),
            inertia_method: scene.solver.inertia,
            local_mass: DMatrix::zeros(0, 0),
            local_forces: DVector::zeros(0),
            local_to_global: Vec::new(),
            driven_frames: Vec::new(),
        };
        constraints.extend(planar.joint_constraints(prepared, &q0)?);
        constraints.extend(planar.marker_constraints(prepared)?);
        planar.coordinates.n_constraints = constraints.iter().map(Constraint::rows).sum();
        planar.constraints = constraints;
        planar.driven_frames = planar.find_driven_frames();
        planar.force_elements = planar.build_force_elements(prepared, &q0)?;
        planar.sensors = planar.build_sensors(prepared, &q0)?;
        planar.assemble_rigid_terms();
        Ok(planar)
    }

    /// The spring–dampers, through the shared force elements over `MarkerKinematics`.
    fn build_force_elements(
        &self,
        prepared: &PreparedScene,
        q0: &DVector<f64>,
    ) -> Result<ForceElements<PlanarMarker>, ModelError> {
        let marker_of_id = |id: MarkerId| self.marker_of(prepared, id);
        let zero = &self.zero_rates;
        ForceElements::new(
            prepared,
            marker_of_id,
            self,
            q0,
            zero,
            self.coordinates.len(),
        )
    }

    /// The formulation's handle of a marker.
    pub(in super::super) fn marker_of(
        &self,
        prepared: &PreparedScene,
        id: MarkerId,
    ) -> PlanarMarker {
        match id.body {
            None => {
                let p = prepared.marker_position(id);
                PlanarMarker::Ground(Vector2::new(p.x, p.y))
            }
            Some(BodyId(b)) => self.bodies[b].marker_by_index(b, id.index),
        }
    }

    /// Size the per-body scratch and assemble the rigid bodies' constant Tᵀ M_f T and
    /// Tᵀ Q_g into the system once.
    fn assemble_rigid_terms(&mut self) {
        let max_local = self.bodies.iter().map(|b| 4 + b.n_modes).max().unwrap_or(4);
        self.local_mass = DMatrix::zeros(max_local, max_local);
        self.local_forces = DVector::zeros(max_local);
        self.local_to_global = vec![None; max_local];
        let mut rigid = SystemTerms::new(self.coordinates.len(), 0);
        for body_index in 0..self.bodies.len() {
            if self.bodies[body_index].n_modes == 0 {
                let b = &self.bodies[body_index];
                self.local_mass
                    .view_mut((0, 0), (4, 4))
                    .copy_from(&b.rigid_mass);
                self.local_forces.rows_mut(0, 4).copy_from(&b.rigid_forces);
                self.scatter(body_index, 4, &mut rigid);
            }
        }
        self.rigid_mass = rigid.mass;
        self.rigid_forces = rigid.forces;
    }
}

/// q̇0: the rigid initial motion of each body on its basis coordinates, zero elsewhere (the
/// modal rates).
fn initial_velocities(n: usize, rates: &[(usize, f64)]) -> DVector<f64> {
    let mut qd0 = DVector::zeros(n);
    for &(i, v) in rates {
        qd0[i] = v;
    }
    qd0
}
