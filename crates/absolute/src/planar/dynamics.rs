//! Mass matrix and forces of the planar scene (docs/methods.md §2.5–§2.6, §3.1).
//!
//! A body's natural-set terms are projected on its basis with the constant T:
//! M_b = Tᵀ M_f T, Q_b = Tᵀ Q_f. Rigid bodies' terms are constant and assembled once at
//! compile time; flexible bodies' are evaluated each call (`flex::Flex2`) with their elastic
//! tangents; the spring–dampers add theirs through the shared force elements.

use flexmbd_core::{State, SystemTerms};
use nalgebra::DVector;

use super::Planar;
use super::body::Slot;
use crate::flex::add_elastic_tangents;

impl Planar {
    /// Scatter a body's local terms (basis order, then modes), the first `n_local` rows and
    /// columns of `local_mass` and `local_forces`, into the system.
    pub(super) fn scatter(&mut self, body_index: usize, n_local: usize, out: &mut SystemTerms) {
        self.map_local_to_global(body_index);
        let ld = self.local_mass.nrows();
        scatter_into(
            &self.local_to_global[..n_local],
            self.local_mass.as_slice(),
            ld,
            self.local_forces.as_slice(),
            out,
        );
    }

    /// Body `body_index`'s local coordinates (basis, then modes) to system ones, into
    /// `local_to_global` (`None`: a fixed basis point).
    fn map_local_to_global(&mut self, body_index: usize) {
        let b = &self.bodies[body_index];
        for k in 0..4 {
            self.local_to_global[k] = match b.slots[k] {
                Slot::Q(i) => Some(i),
                Slot::Fixed(_) => None,
            };
        }
        for j in 0..b.n_modes {
            self.local_to_global[4 + j] = Some(b.first_mode + j);
        }
    }

    /// M and Q (and, with `tangents`, K and C) at (q, q̇).
    pub(super) fn dynamics(&mut self, state: State<'_>, tangents: bool, out: &mut SystemTerms) {
        let (q, qd) = (state.q, state.qd);
        // Rigid bodies: their constant M and gravity, assembled once at compile time.
        out.mass
            .as_mut_slice()
            .copy_from_slice(self.rigid_mass.as_slice());
        out.forces
            .as_mut_slice()
            .copy_from_slice(self.rigid_forces.as_slice());
        for body_index in 0..self.bodies.len() {
            if self.bodies[body_index].n_modes == 0 {
                continue;
            }
            self.flexible_body_terms(body_index, q, qd, tangents, out);
        }
        if !self.force_elements.is_empty() {
            let mut force_elements = std::mem::take(&mut self.force_elements);
            force_elements.add_forces(self, q, qd, tangents, out);
            self.force_elements = force_elements;
        }
    }

    /// A flexible body's M_b and Q_b scattered into the system, and its elastic tangents.
    fn flexible_body_terms(
        &mut self,
        body_index: usize,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        out: &mut SystemTerms,
    ) {
        let n_local = 4 + self.bodies[body_index].n_modes;
        let frame = self.frame(&self.bodies[body_index], q, qd);
        let b = &mut self.bodies[body_index];
        let modes = b.modes();
        let ws = b
            .flexible_workspace
            .as_mut()
            .expect("flexible body has a workspace");
        ws.evaluate(
            &b.body,
            self.inertia_method,
            frame.r0,
            frame.u,
            frame.r0_rate,
            frame.u_rate,
            &q.as_slice()[modes.clone()],
            &qd.as_slice()[modes],
            self.gravity,
            &b.frame_map,
        );
        // Straight from the body's workspace (the same additions as `scatter`).
        self.map_local_to_global(body_index);
        let ws = self.bodies[body_index]
            .flexible_workspace
            .as_ref()
            .expect("flexible body has a workspace");
        scatter_into(
            &self.local_to_global[..n_local],
            ws.m_b.as_slice(),
            n_local,
            ws.q_b.as_slice(),
            out,
        );
        if tangents {
            let b = &self.bodies[body_index];
            let (y, yd) = (&q.as_slice()[b.modes()], &qd.as_slice()[b.modes()]);
            add_elastic_tangents(&b.body, y, yd, b.first_mode, out);
        }
    }
}

/// Add local terms into the system: column c of the column-major `mass` (leading dimension
/// `ld`) and `forces[c]` where `local_to_global[c]` names a system coordinate (each entry of
/// M and Q receives one addition, in column order).
fn scatter_into(
    local_to_global: &[Option<usize>],
    mass: &[f64],
    ld: usize,
    forces: &[f64],
    out: &mut SystemTerms,
) {
    let nq = out.mass.nrows();
    let system = out.mass.as_mut_slice();
    for (c, &gc) in local_to_global.iter().enumerate() {
        let Some(qc) = gc else {
            continue;
        };
        out.forces[qc] += forces[c];
        let column = &mass[c * ld..c * ld + local_to_global.len()];
        let target = &mut system[qc * nq..(qc + 1) * nq];
        for (&gr, &v) in local_to_global.iter().zip(column) {
            if let Some(qr) = gr {
                target[qr] += v;
            }
        }
    }
}
