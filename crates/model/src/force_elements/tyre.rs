//! The **tyre**: the contact of a wheel-centre marker W with a road z = h(x)
//! ([`crate::roads`]), and a linear lateral damper (docs/methods.md §2.6, docs/scenes.md
//! §2.5, §3.2, §3.4).
//!
//! With (x_W, y_W, z_W) the wheel centre, h and s = h'(x_W) the road's height and slope under
//! it, the deflection is δ = R − (z_W − h); the tyre touches the road while δ > 0 and
//! otherwise carries exactly nothing (it never pulls):
//!
//! - `Vertical` (docs/scenes.md §2.5, S9 user_ExtForces.c): F = K δ e_z applied at W;
//! - `ProfileNormal` (docs/scenes.md §3.2, S9 GroundContact.c): with H = √(1 + s²), the
//!   force K δ/H along the profile normal n = (−s, 0, 1)/H, applied at W as S9 does (its
//!   radial force K (R − (z_W − h))/H, with the contact test h > z_W − R); on a flat road
//!   it is `Vertical`.
//!
//! The lateral damper F_y = −c ẏ_W (ground y) acts at the wheel centre (docs/scenes.md §3.4:
//! the benchmark's contact point, moved to W; on the in-phase bump it only stops drift).
//!
//! Q += J_Wᵀ F; tangents K += J_Wᵀ S J_W with S ≈ −∂F/∂r_W in contact: K e_z e_zᵀ for
//! `Vertical` (its slope term −K s e_z e_xᵀ left out, so that S stays symmetric: a tangent
//! only steers Newton, and the integrator may factorise a symmetric one by Cholesky) and
//! (K/H) n (e_z − s e_x)ᵀ = (K/H²)(−s, 0, 1)(−s, 0, 1)ᵀ for `ProfileNormal` (the road's
//! curvature left out); and C += c J_Wᵀ e_y e_yᵀ J_W. A sensor reads the normal force K δ (÷ H) and the deflection δ.
//! The potential energy is ½ K δ² in contact (exact for `Vertical`; for `ProfileNormal` on a
//! slope, where the force is not the gradient of a potential, it is this vertical measure).

use flexmbd_core::{ElementReading, MarkerKinematics, SystemTerms};
use nalgebra::{DVector, Vector3};

use crate::inputs::{InputSlots, InputTable};
use crate::roads::{Contact, Profile, Road};
use crate::scene::Force;

/// A compiled tyre, `M` being the formulation's marker handle.
#[derive(Clone, Debug)]
pub struct Tyre<M> {
    /// The wheel centre W.
    pub wheel: M,
    /// Its road's profile.
    pub road: Profile,
    /// The `Road` input that moves the profile by (Δx, Δz), if any ([`crate::inputs`]).
    pub road_offset: Option<InputSlots>,
    /// Unloaded radius R (m).
    pub radius: f64,
    /// Radial stiffness K (N/m).
    pub stiffness: f64,
    /// Contact model.
    pub contact: Contact,
    /// Lateral damping c (N·s/m).
    pub lateral_damping: f64,
}

/// The contact at (q, q̇): the normal force's magnitude and direction, δ, and the slope.
struct ContactState {
    normal_force: f64,
    normal: Vector3<f64>,
    deflection: f64,
    slope: f64,
    lateral_velocity: f64,
}

impl<M> Tyre<M> {
    /// Compile `force` (a `Tyre`, its road validated to exist) over W's handle.
    pub(super) fn new(force: &Force, roads: &[Road], wheel: M, inputs: &InputTable) -> Self {
        let Force::Tyre {
            road,
            radius,
            stiffness,
            contact,
            lateral_damping,
            ..
        } = force
        else {
            unreachable!("Tyre::new is given tyres")
        };
        let index = roads.iter().position(|r| &r.name == road);
        Tyre {
            wheel,
            road: index.map(|k| roads[k].profile.clone()).unwrap_or_default(),
            road_offset: index.and_then(|k| inputs.road_slots(k)),
            radius: *radius,
            stiffness: *stiffness,
            contact: *contact,
            lateral_damping: *lateral_damping,
        }
    }

    /// The road's height and slope under x: h(x − Δx) + Δz with the input's offset.
    fn road_at(&self, x: f64) -> (f64, f64) {
        match &self.road_offset {
            None => self.road.eval(x),
            Some(offset) => {
                let (h, s) = self.road.eval(x - offset.get(0));
                (h + offset.get(1), s)
            }
        }
    }

    fn state<K>(&self, kinematics: &K, q: &DVector<f64>, qd: &DVector<f64>) -> ContactState
    where
        K: MarkerKinematics<Marker = M>,
    {
        let (r, v) = kinematics.marker_state(&self.wheel, q, qd);
        let (h, s) = self.road_at(r.x);
        let deflection = self.radius - (r.z - h);
        let (normal_force, normal) = match (deflection > 0.0, self.contact) {
            (false, _) => (0.0, Vector3::z()),
            (true, Contact::Vertical) => (self.stiffness * deflection, Vector3::z()),
            (true, Contact::ProfileNormal) => {
                let big_h = (1.0 + s * s).sqrt();
                (
                    self.stiffness * deflection / big_h,
                    Vector3::new(-s, 0.0, 1.0) / big_h,
                )
            }
        };
        ContactState {
            normal_force,
            normal,
            deflection,
            slope: s,
            lateral_velocity: v.y,
        }
    }

    /// Q (and K, C) of the tyre at (q, q̇).
    pub(super) fn add_forces<K>(
        &self,
        kinematics: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        columns: &mut Vec<(usize, Vector3<f64>)>,
        out: &mut SystemTerms,
    ) where
        K: MarkerKinematics<Marker = M>,
    {
        let st = self.state(kinematics, q, qd);
        let force = st.normal * st.normal_force
            + Vector3::new(0.0, -self.lateral_damping * st.lateral_velocity, 0.0);
        columns.clear();
        kinematics.marker_jacobian(&self.wheel, q, &mut |i, c| columns.push((i, c)));
        for &(i, c) in columns.iter() {
            out.forces[i] += c.dot(&force);
        }
        if !tangents {
            return;
        }
        // S = w m mᵀ, symmetric in both models (the integrator may factorise by Cholesky):
        // K e_z e_zᵀ, and (K/H) n (−s, 0, 1)ᵀ = (K/H²) m mᵀ with m = (−s, 0, 1).
        let (w, m) = match (st.deflection > 0.0, self.contact) {
            (false, _) => (0.0, Vector3::z()),
            (true, Contact::Vertical) => (self.stiffness, Vector3::z()),
            (true, Contact::ProfileNormal) => (
                self.stiffness / (1.0 + st.slope * st.slope),
                Vector3::new(-st.slope, 0.0, 1.0),
            ),
        };
        for &(i, ci) in columns.iter() {
            let mi = m.dot(&ci);
            for &(j, cj) in columns.iter() {
                out.stiffness[(j, i)] += w * (m.dot(&cj) * mi);
                out.damping[(j, i)] += self.lateral_damping * (cj.y * ci.y);
            }
        }
    }

    /// Normal force and deflection at (q, q̇).
    pub(super) fn reading<K>(
        &self,
        kinematics: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> ElementReading
    where
        K: MarkerKinematics<Marker = M>,
    {
        let st = self.state(kinematics, q, qd);
        ElementReading {
            force: st.normal_force,
            length: st.deflection,
        }
    }

    /// ½ K δ² in contact (J).
    pub(super) fn potential_energy<K>(
        &self,
        kinematics: &K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> f64
    where
        K: MarkerKinematics<Marker = M>,
    {
        let delta = self.state(kinematics, q, qd).deflection;
        if delta > 0.0 {
            0.5 * self.stiffness * delta * delta
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_core::Request;

    /// A free point whose coordinates are its position: J = I.
    struct Point;

    impl MarkerKinematics for Point {
        type Marker = ();
        fn marker_state(
            &self,
            _: &(),
            q: &DVector<f64>,
            qd: &DVector<f64>,
        ) -> (Vector3<f64>, Vector3<f64>) {
            (
                Vector3::new(q[0], q[1], q[2]),
                Vector3::new(qd[0], qd[1], qd[2]),
            )
        }
        fn marker_jacobian(
            &mut self,
            _: &(),
            _: &DVector<f64>,
            visit: &mut dyn FnMut(usize, Vector3<f64>),
        ) {
            for i in 0..3 {
                let mut c = Vector3::zeros();
                c[i] = 1.0;
                visit(i, c);
            }
        }
    }

    fn bump_tyre(contact: Contact) -> Tyre<()> {
        Tyre {
            wheel: (),
            road: Profile::CosineBump {
                start: 0.97,
                length: 5.0,
                height: 0.2,
            },
            radius: 0.364325,
            stiffness: 460000.0,
            contact,
            lateral_damping: 0.0,
            road_offset: None,
        }
    }

    fn terms(tyre: &Tyre<()>, q: &DVector<f64>) -> SystemTerms {
        let mut out = SystemTerms::new(3, 0);
        out.clear(Request::ALL);
        let mut columns = Vec::new();
        let qd = DVector::zeros(3);
        tyre.add_forces(&mut Point, q, &qd, true, &mut columns, &mut out);
        out
    }

    #[test]
    fn on_the_cosine_bump_the_profile_normal_force_is_normal_to_the_profile() {
        let tyre = bump_tyre(Contact::ProfileNormal);
        let x = 2.1;
        let (h, s) = tyre.road.eval(x);
        assert!(s > 0.1, "on the rising flank: slope {s}");
        let q = DVector::from_vec(vec![x, 0.3, h + 0.35]);
        let f = terms(&tyre, &q).forces;
        let f = Vector3::new(f[0], f[1], f[2]);
        // Along (−s, 0, 1): orthogonal to the profile's tangent (1, 0, s).
        assert!(
            f.dot(&Vector3::new(1.0, 0.0, s)).abs() < 1e-9 * f.norm(),
            "{f}"
        );
        assert!(f.z > 0.0 && f.x < 0.0, "{f}");
        let big_h = (1.0 + s * s).sqrt();
        let expected = 460000.0 * (0.364325 - 0.35) / big_h;
        assert!(
            (f.norm() - expected).abs() < 1e-9 * expected,
            "{} vs {expected}",
            f.norm()
        );
        assert_eq!(tyre.reading(&Point, &q, &DVector::zeros(3)).force, f.norm());
        // The vertical contact at the same point pushes straight up, K δ.
        let vertical = terms(&bump_tyre(Contact::Vertical), &q).forces;
        assert_eq!((vertical[0], vertical[1]), (0.0, 0.0));
        assert!((vertical[2] - 460000.0 * (0.364325 - 0.35)).abs() < 1e-9);
    }

    #[test]
    fn tyre_stiffness_is_symmetric_and_minus_the_force_slope_in_z() {
        for contact in [Contact::Vertical, Contact::ProfileNormal] {
            let tyre = bump_tyre(contact);
            let x = 2.1;
            let q = DVector::from_vec(vec![x, 0.0, tyre.road.eval(x).0 + 0.35]);
            let k = terms(&tyre, &q).stiffness;
            // z only moves the deflection: −∂Q/∂z is exact.
            let e = 1e-7;
            let mut qp = q.clone();
            qp[2] += e;
            let mut qm = q.clone();
            qm[2] -= e;
            let slope = (terms(&tyre, &qp).forces - terms(&tyre, &qm).forces) / (2.0 * e);
            for i in 0..3 {
                assert!(
                    (k[(i, 2)] + slope[i]).abs() < 1e-5 * 460000.0,
                    "{contact:?} K[{i}, z] = {} vs {}",
                    k[(i, 2)],
                    -slope[i]
                );
            }
            assert!(k[(2, 2)] > 1e5);
            assert_eq!(k, k.transpose(), "{contact:?}: a symmetric tangent");
        }
    }
}
