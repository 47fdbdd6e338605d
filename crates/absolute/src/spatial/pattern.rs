//! The declared structure of the spatial formulation's matrices
//! ([`flexmbd_core::DeclaredPattern`], issue 26 item 3): M, K and C couple a body's own
//! coordinates `{r0; u; v; w; y}` (its mass matrix and elastic tangents) and the
//! coordinates of the markers of one force element (its tangents J_aᵀ k J_b); a rigid
//! body's constant mass matrix J̄ ⊗ I₃ couples like components of r0, u, v, w only. A
//! constraint row involves the columns of the terms it is written over, each term those of
//! its body: `r0` for a point, `u, v, w` always, `y` when it moves with the modes (the
//! Jacobian `[δ I  x̃_1 I  x̃_2 I  x̃_3 I  A V]` of `kinematics`); a coincidence row
//! `e_kᵀ(J_2 − J_1)` only the k-th components of r0, u, v, w, and an orthonormality row
//! only the two axes it multiplies. The tests evaluate every term at
//! perturbed states and check that no non-zero falls outside.

use flexmbd_core::DeclaredPattern;

use super::constraints::Constraint;
use super::kinematics::Term;
use super::{Spatial, SpatialBody};

impl Term {
    /// The coordinates this term's Jacobian can touch (none on the ground).
    fn columns(&self, bodies: &[SpatialBody], out: &mut Vec<usize>) {
        let Some(body) = self.body else { return };
        let b = &bodies[body];
        let o = b.offset;
        let first = if self.point { o } else { o + 3 };
        out.extend(first..o + 12);
        if !self.modal_rows.is_empty() {
            out.extend(o + 12..o + 12 + b.n_modes);
        }
    }
}

impl Term {
    /// The coordinates row component `k` of `J` touches when the row is `e_kᵀ J` (a
    /// coincidence row): `r0_k`, `u_k`, `v_k`, `w_k` and the modes.
    fn component_columns(&self, bodies: &[SpatialBody], k: usize, out: &mut Vec<usize>) {
        let Some(body) = self.body else { return };
        let b = &bodies[body];
        let o = b.offset;
        if self.point {
            out.push(o + k);
        }
        out.extend([o + 3 + k, o + 6 + k, o + 9 + k]);
        if !self.modal_rows.is_empty() {
            out.extend(o + 12..o + 12 + b.n_modes);
        }
    }
}

impl Constraint {
    /// The columns row `k` of this constraint block is written over.
    fn row_columns(&self, bodies: &[SpatialBody], k: usize, out: &mut Vec<usize>) {
        let terms: Vec<&Term> = match self {
            Constraint::Orthonormality { offset } => {
                // (u,u), (v,v), (w,w), (u,v), (v,w), (w,u), as `orthonormality` writes them.
                const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
                let (i, j) = PAIRS[k];
                out.extend(offset + 3 + 3 * i..offset + 6 + 3 * i);
                out.extend(offset + 3 + 3 * j..offset + 6 + 3 * j);
                return;
            }
            Constraint::Coincide { point2, point1 } => {
                point2.component_columns(bodies, k, out);
                point1.component_columns(bodies, k, out);
                return;
            }
            Constraint::Dot(dot) => {
                let mut terms = vec![&dot.x, &dot.z];
                terms.extend(dot.origin.as_ref());
                terms
            }
            Constraint::Angle(angle) => vec![&angle.p1, &angle.p2, &angle.a],
            Constraint::Distance(distance) => vec![&distance.point1, &distance.point2],
        };
        for term in terms {
            term.columns(bodies, out);
        }
    }
}

/// Sort and drop repeats.
fn sorted(mut columns: Vec<usize>) -> Vec<usize> {
    columns.sort_unstable();
    columns.dedup();
    columns
}

impl Spatial {
    /// The structure of M, K, C and Φ_q (module docs).
    pub(super) fn pattern(&self) -> DeclaredPattern {
        let bodies = &self.bodies;
        // A rigid body's constant mass matrix is J̄ ⊗ I₃ over {r0, u, v, w}: component c of
        // each couples with component c of the others only. A flexible body's is full.
        let mut coupled: Vec<Vec<usize>> = Vec::new();
        for b in bodies {
            let o = b.offset;
            if b.flexible.is_some() {
                coupled.push((o..o + 12 + b.n_modes).collect());
            } else {
                coupled.extend((0..3).map(|c| vec![o + c, o + 3 + c, o + 6 + c, o + 9 + c]));
            }
        }
        for markers in self.force_elements.markers_of_each() {
            let mut columns = Vec::new();
            for term in markers {
                term.columns(bodies, &mut columns);
            }
            coupled.push(sorted(columns));
        }
        let mut jacobian_rows = Vec::with_capacity(self.coordinates.n_constraints);
        for constraint in &self.constraints {
            for k in 0..constraint.rows() {
                let mut columns = Vec::new();
                constraint.row_columns(bodies, k, &mut columns);
                jacobian_rows.push(sorted(columns));
            }
        }
        DeclaredPattern {
            coupled,
            jacobian_rows,
        }
    }
}

#[cfg(test)]
mod tests {
    use flexmbd_core::{Formulation, Request, State, SystemTerms};
    use flexmbd_model::{PreparedScene, Scene};
    use nalgebra::DVector;

    use super::super::Spatial;

    fn compiled(name: &str, sets: &[(String, String)]) -> Spatial {
        let path = format!("{}/../../models/{name}", env!("CARGO_MANIFEST_DIR"));
        let mut scene = Scene::load(&path).unwrap();
        scene.apply_sets(sets).unwrap();
        Spatial::compile(&PreparedScene::new(&scene).unwrap()).unwrap()
    }

    /// Deterministic pseudo-random numbers in [−1, 1].
    fn noise(k: usize) -> f64 {
        ((k as f64 * 12.9898 + 4.1414).sin() * 43758.5453).fract() * 2.0 - 1.0
    }

    /// Every non-zero of M, K, C and Φ_q, at the start and at perturbed states (every
    /// coordinate and rate moved, so that no entry is zero by symmetry), lies in the
    /// declared pattern; and the pattern is not dense (it would not be worth declaring).
    fn covers(name: &str, sets: &[(String, String)]) {
        let mut spatial = compiled(name, sets);
        let pattern = spatial.declared_pattern().expect("spatial scenes declare");
        let (n, m) = (spatial.n_coordinates(), spatial.n_constraints());
        assert_eq!(pattern.jacobian_rows.len(), m, "{name}");
        let (mut q, mut qd) = (DVector::zeros(n), DVector::zeros(n));
        spatial.initial_guess(&mut q, &mut qd);
        for trial in 0..3 {
            let scale = 0.01 * trial as f64;
            let q = DVector::from_fn(n, |i, _| q[i] + scale * noise(i + 7 * trial));
            let qd = DVector::from_fn(n, |i, _| qd[i] + scale * noise(i + 11 * trial + n));
            let mut terms = SystemTerms::new(n, m);
            spatial.evaluate(State::new(0.3, &q, &qd), Request::ALL, &mut terms);
            for (what, matrix) in [
                ("M", &terms.mass),
                ("K", &terms.stiffness),
                ("C", &terms.damping),
            ] {
                let outside = pattern.uncovered_coupling(matrix.as_slice(), n);
                assert_eq!(outside, None, "{name}: {what} outside the pattern");
            }
            let outside = pattern.uncovered_jacobian(terms.phi_q.as_slice(), m);
            assert_eq!(outside, None, "{name}: Φ_q outside the pattern");
        }
    }

    #[test]
    fn the_declared_pattern_covers_every_non_zero() {
        let twelve: Vec<(String, String)> = ["aarm", "leaf_link", "tie_rod"]
            .iter()
            .flat_map(|b| ["fl", "fr", "rl", "rr"].map(|c| format!("bodies.{b}_{c}.flexible")))
            .map(|path| (path, "true".to_string()))
            .collect();
        covers("iltis_vehicle.ron", &twelve);
        // The vehicle's M, K, C pattern: the bodies' blocks and the force elements' pairs,
        // about a tenth of n² (10.2 %).
        let vehicle = compiled("iltis_vehicle.ron", &twelve);
        let n = vehicle.n_coordinates();
        let flags = vehicle.declared_pattern().unwrap().coupling_flags(n);
        let share = flags.iter().filter(|&&f| f).count() as f64 / (n * n) as f64;
        assert!(share < 0.11, "{share}");
        covers("iltis_bump.ron", &[]);
        covers("double_pendulum_3d.ron", &[]);
        covers("flexible_pendulum_3d.ron", &[]);
        covers("spin_up_beam_3d.ron", &[]);
        covers("floating_platform_3d.ron", &[]);
    }
}
