//! The total mechanical energy for the energy sensor: kinetic `½ q̇ᵀ M q̇`, gravity and
//! elastic potential of every body, and the spring potential of the force elements.

use flexmbd_body::NaturalState;
use flexmbd_core::Dim;
use nalgebra::DVector;

use super::Spatial;

impl Spatial {
    /// Total mechanical energy: kinetic + gravity + elastic + springs.
    pub(super) fn energy(&mut self, q: &DVector<f64>, qd: &DVector<f64>) -> f64 {
        let g = self.gravity;
        let mut e = 0.0;
        for b in &mut self.bodies {
            let (o, n_modes) = (b.offset, b.n_modes);
            let n_local = 12 + n_modes;
            let (qs, qds) = (
                &q.as_slice()[o..o + n_local],
                &qd.as_slice()[o..o + n_local],
            );
            let state = NaturalState::from_coords(Dim::Spatial, qs, qds);
            let m = match b.flexible.as_mut() {
                None => &b.rigid_mass,
                Some(f) => {
                    b.body.inertia_natural(
                        &state,
                        self.inertia_method,
                        &mut f.natural,
                        &mut f.energy_mass,
                        &mut f.energy_forces,
                    );
                    &f.energy_mass
                }
            };
            let mut kin = 0.0;
            for r in 0..n_local {
                for c in 0..n_local {
                    kin += qds[r] * m[(r, c)] * qds[c];
                }
            }
            e += 0.5 * kin + b.body.natural_potential_energy(&state, &g);
            if n_modes > 0 {
                e += b.body.strain_energy(state.y);
            }
        }
        e + self.force_elements.potential_energy(self, q, qd)
    }
}
