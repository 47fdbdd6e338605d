//! The dynamic terms (docs/methods.md §3.3, §2.5–§2.6): every body's natural-set mass
//! matrix and forces (inertia, gravity, elastic) into its diagonal block, the elastic
//! tangents K_ff and C_ff on request, then the spring–dampers of the shared force elements
//! over `impl MarkerKinematics for Spatial`.

use flexmbd_body::{InertiaMethod, NaturalState};
use flexmbd_core::{Dim, State, SystemTerms};
use nalgebra::{DVector, Vector3};

use super::{Spatial, SpatialBody};
use crate::flex::add_elastic_tangents;

impl Spatial {
    /// Fill M and Q (and K, C when `tangents`).
    pub(super) fn dynamics(&mut self, state: State<'_>, tangents: bool, out: &mut SystemTerms) {
        let (q, qd) = (state.q, state.qd);
        let g = self.gravity;
        for b in &mut self.bodies {
            body_dynamics(b, self.inertia_method, &g, q, qd, tangents, out);
        }
        if !self.force_elements.is_empty() {
            let mut force_elements = std::mem::take(&mut self.force_elements);
            force_elements.add_forces(self, q, qd, tangents, out);
            self.force_elements = force_elements;
        }
    }
}

/// One body's block: the constant M and gravity of a rigid body, or the flexible body's
/// inertia, gravity and elastic forces at (q, q̇).
fn body_dynamics(
    b: &mut SpatialBody,
    method: InertiaMethod,
    g: &Vector3<f64>,
    q: &DVector<f64>,
    qd: &DVector<f64>,
    tangents: bool,
    out: &mut SystemTerms,
) {
    let (o, n_modes) = (b.offset, b.n_modes);
    let n_local = 12 + n_modes;
    let Some(f) = b.flexible.as_mut() else {
        out.mass.view_mut((o, o), (12, 12)).copy_from(&b.rigid_mass);
        out.forces.rows_mut(o, 12).copy_from(&b.rigid_gravity);
        return;
    };
    let (qs, qds) = (
        &q.as_slice()[o..o + n_local],
        &qd.as_slice()[o..o + n_local],
    );
    let state = NaturalState::from_coords(Dim::Spatial, qs, qds);
    b.body.inertia_natural(
        &state,
        method,
        &mut f.natural,
        &mut out.mass.view_mut((o, o), (n_local, n_local)),
        &mut out.forces.rows_mut(o, n_local),
    );
    b.body.gravity_natural(&state, g, &mut f.gravity);
    b.body.elastic_forces(state.y, state.y_dot, &mut f.elastic);
    for (i, gv) in f.gravity.iter().enumerate() {
        out.forces[o + i] += gv;
    }
    for (j, e) in f.elastic.iter().enumerate() {
        out.forces[o + 12 + j] += e;
    }
    if tangents {
        add_elastic_tangents(&b.body, state.y, state.y_dot, o + 12, out);
    }
}
