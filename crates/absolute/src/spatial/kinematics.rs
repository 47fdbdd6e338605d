//! Kinematics of body points and body-fixed directions (docs/methods.md §3.3).
//!
//! A term is `x(q) = δ r0 + A (x̄ + V y)` (δ = 1 for a point, 0 for a direction), bilinear in
//! (A, y). With `x̃ = x̄ + V y` its rate is `ẋ = δ ṙ0 + Ȧ x̃ + A V ẏ`, its bias (the second
//! derivative at q̈ = 0) `2 Ȧ V ẏ`, and its Jacobian `[δ I  x̃_1 I  x̃_2 I  x̃_3 I  A V]`.
//! A point at an FE node of a foreshortened body (FS0, docs/methods.md §6.3) adds the
//! node's axial shift −½ ē₁ yᵀF y to `x̃`, −ē₁ (F y)·ẏ to the rate, `A (−ē₁ ẏᵀF ẏ)` to the
//! bias and −A ē₁ (F y)ᵀ to the y columns of the Jacobian.
//!
//! The same terms are the markers of the shared force elements: `impl MarkerKinematics for
//! Spatial` reports their position, velocity and Jacobian columns.

use flexmbd_core::MarkerKinematics;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::{Spatial, SpatialBody};

/// A body point or body-fixed direction `x = δ r0 + A (x̄ + V y)`, or a ground constant.
#[derive(Clone, Debug)]
pub struct Term {
    /// The body the term is fixed in; `None`: a ground constant `undeformed`.
    pub(super) body: Option<usize>,
    /// δ = 1 (point) or 0 (direction).
    pub(super) point: bool,
    /// x̄: the undeformed local vector, in body components (ground components on the ground).
    pub(super) undeformed: Vector3<f64>,
    /// V, 3 × n row-major (empty for rigid bodies).
    pub(super) modal_rows: Vec<f64>,
    /// FS0 (docs/methods.md §6.3): the FE node of a point on a foreshortened body, whose axial
    /// shift −½ ē₁ yᵀF y joins x̄ + V y.
    pub(super) foreshortening_node: Option<usize>,
}

/// Value, rate and bias of a term, and its local vector x̃ = x̄ + V y (for the Jacobian).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct TermValue {
    /// x, ground components.
    pub(super) value: Vector3<f64>,
    /// ẋ.
    pub(super) rate: Vector3<f64>,
    /// ẍ at q̈ = 0.
    pub(super) bias: Vector3<f64>,
    /// x̃ = x̄ + V y (+ the FS0 shift), body components.
    pub(super) local: Vector3<f64>,
}

#[inline]
fn vector_at(s: &[f64], i: usize) -> Vector3<f64> {
    Vector3::new(s[i], s[i + 1], s[i + 2])
}

/// The origin r0 and the rotation `A = [u v w]` of the body whose coordinates start at
/// `offset` (or their rates, given q̇).
#[inline]
pub(super) fn frame_of(q: &[f64], offset: usize) -> (Vector3<f64>, Matrix3<f64>) {
    (
        vector_at(q, offset),
        Matrix3::from_columns(&[
            vector_at(q, offset + 3),
            vector_at(q, offset + 6),
            vector_at(q, offset + 9),
        ]),
    )
}

/// The angle from `p1` to `p2` about `a`: `atan2((p1 × p2)·a, p1·p2)`.
pub(super) fn triple_angle(p1: &Vector3<f64>, p2: &Vector3<f64>, a: &Vector3<f64>) -> f64 {
    p1.cross(p2).dot(a).atan2(p1.dot(p2))
}

impl Term {
    pub(super) fn eval(
        &self,
        bodies: &[SpatialBody],
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> TermValue {
        let Some(body_index) = self.body else {
            return TermValue {
                value: self.undeformed,
                local: self.undeformed,
                ..Default::default()
            };
        };
        let b = &bodies[body_index];
        let (q, qd) = (q.as_slice(), qd.as_slice());
        let (r0, a) = frame_of(q, b.offset);
        let (r0d, ad) = frame_of(qd, b.offset);
        let mut local = self.undeformed;
        let mut vyd = Vector3::zeros();
        let n = b.n_modes;
        if !self.modal_rows.is_empty() {
            let (y, yd) = (
                &q[b.offset + 12..b.offset + 12 + n],
                &qd[b.offset + 12..b.offset + 12 + n],
            );
            for c in 0..3 {
                let r = &self.modal_rows[c * n..(c + 1) * n];
                for j in 0..n {
                    local[c] += r[j] * y[j];
                    vyd[c] += r[j] * yd[j];
                }
            }
        }
        // FS0: x̃ gains −½ ē₁ yᵀF y, its rate −ē₁ (F y)·ẏ and the bias A (−ē₁ ẏᵀF ẏ).
        let mut fs_bias = Vector3::zeros();
        if let Some(node) = self.foreshortening_node {
            let (y, yd) = (
                &q[b.offset + 12..b.offset + 12 + n],
                &qd[b.offset + 12..b.offset + 12 + n],
            );
            if let Some(shift) = b.body.node_foreshortening(node, y, yd) {
                local += shift.position;
                vyd += shift.velocity;
                fs_bias = shift.bias;
            }
        }
        let d = if self.point { 1.0 } else { 0.0 };
        TermValue {
            value: d * r0 + a * local,
            rate: d * r0d + ad * local + a * vyd,
            bias: 2.0 * (ad * vyd) + a * fs_bias,
            local,
        }
    }

    /// Add `wᵀ ∂x/∂q` to `row` of Φ_q.
    pub(super) fn add_jacobian(
        &self,
        bodies: &[SpatialBody],
        ev: &TermValue,
        w: &Vector3<f64>,
        q: &DVector<f64>,
        phi_q: &mut DMatrix<f64>,
        row: usize,
    ) {
        let Some(body_index) = self.body else { return };
        let b = &bodies[body_index];
        let o = b.offset;
        if self.point {
            for i in 0..3 {
                phi_q[(row, o + i)] += w[i];
            }
        }
        for c in 0..3 {
            for i in 0..3 {
                phi_q[(row, o + 3 + 3 * c + i)] += ev.local[c] * w[i];
            }
        }
        if !self.modal_rows.is_empty() {
            let (_, a) = frame_of(q.as_slice(), o);
            let aw = a.tr_mul(w);
            let n = b.n_modes;
            let rows = &self.modal_rows;
            for j in 0..n {
                phi_q[(row, o + 12 + j)] +=
                    aw.x * rows[j] + aw.y * rows[n + j] + aw.z * rows[2 * n + j];
            }
            // FS0: the shift's Jacobian −ē₁ (F y)ᵀ.
            if let Some(node) = self.foreshortening_node {
                let y = &q.as_slice()[o + 12..o + 12 + n];
                for j in 0..n {
                    let c = b.body.node_foreshortening_column(node, y, j);
                    phi_q[(row, o + 12 + j)] += aw.dot(&c);
                }
            }
        }
    }
}

impl Spatial {
    /// The angle from `p1` to `p2` about `a` (all three evaluated at (q, q̇)).
    pub(super) fn angle(
        &self,
        p1: &Term,
        p2: &Term,
        a: &Term,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> f64 {
        let (e1, e2, ea) = (
            p1.eval(&self.bodies, q, qd),
            p2.eval(&self.bodies, q, qd),
            a.eval(&self.bodies, q, qd),
        );
        triple_angle(&e1.value, &e2.value, &ea.value)
    }

    /// The origin and rotation `A = [u v w]` of body `body_index`.
    pub(super) fn frame(
        &self,
        body_index: usize,
        q: &DVector<f64>,
    ) -> (Vector3<f64>, Matrix3<f64>) {
        frame_of(q.as_slice(), self.bodies[body_index].offset)
    }
}

impl MarkerKinematics for Spatial {
    type Marker = Term;

    fn marker_state(
        &self,
        marker: &Term,
        q: &DVector<f64>,
        qd: &DVector<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let ev = marker.eval(&self.bodies, q, qd);
        (ev.value, ev.rate)
    }

    /// ∂x/∂r0 = I, ∂x/∂(column c of A) = x̃_c I, ∂x/∂y_j = A (V_j + FS0 shift column).
    fn marker_jacobian(
        &mut self,
        marker: &Term,
        q: &DVector<f64>,
        visit: &mut dyn FnMut(usize, Vector3<f64>),
    ) {
        let Some(body_index) = marker.body else {
            return;
        };
        let ev = marker.eval(&self.bodies, q, &self.zero_rates);
        let b = &self.bodies[body_index];
        let o = b.offset;
        let unit = Matrix3::<f64>::identity();
        if marker.point {
            for i in 0..3 {
                visit(o + i, unit.column(i).into_owned());
            }
        }
        for c in 0..3 {
            for i in 0..3 {
                visit(o + 3 + 3 * c + i, ev.local[c] * unit.column(i));
            }
        }
        if marker.modal_rows.is_empty() {
            return;
        }
        let (_, a) = frame_of(q.as_slice(), o);
        let n = b.n_modes;
        let y = &q.as_slice()[o + 12..o + 12 + n];
        for j in 0..n {
            let rows = &marker.modal_rows;
            let mut column = Vector3::new(rows[j], rows[n + j], rows[2 * n + j]);
            if let Some(node) = marker.foreshortening_node {
                column += b.body.node_foreshortening_column(node, y, j);
            }
            visit(o + 12 + j, a * column);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_model::{PreparedScene, Scene, Stiffening};

    fn compiled(name: &str, edit: impl FnOnce(&mut Scene)) -> Spatial {
        let mut scene = Scene::load(format!(
            "{}/../../models/{name}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap();
        edit(&mut scene);
        Spatial::compile(&PreparedScene::new(&scene).unwrap()).unwrap()
    }

    /// Deterministic pseudo-random numbers in [−1, 1].
    fn noise(k: usize) -> f64 {
        ((k as f64 * 12.9898 + 4.1414).sin() * 43758.5453).fract() * 2.0 - 1.0
    }

    #[test]
    fn triple_angle_is_the_signed_angle_about_the_axis() {
        for phi in [0.3f64, 2.0, -1.2, 3.0, -3.0] {
            let p2 = 2.0 * Vector3::new(phi.cos(), phi.sin(), 0.0);
            let got = triple_angle(&Vector3::x(), &p2, &Vector3::z());
            assert!((got - phi).abs() < 1e-14, "{phi}: {got}");
            let reversed = triple_angle(&Vector3::x(), &p2, &-Vector3::z());
            assert!((reversed + phi).abs() < 1e-14, "{phi}: {reversed}");
        }
    }

    /// A point and a direction on a rigid body turned 90° about z, by hand:
    /// A = [ŷ −x̂ ẑ], r0 = (1, 2, 3), ṙ0 = (0.5, 0, 0), ω = 2 ẑ (Ȧ = ω̃ A = [−2x̂ −2ŷ 0]).
    #[test]
    fn a_rigid_point_is_r0_plus_a_xbar() {
        let spatial = compiled("double_pendulum_3d.ron", |_| {});
        let body = &spatial.bodies[1];
        assert_eq!(body.n_modes, 0);
        let n = spatial.coordinates.len();
        let (mut q, mut qd) = (DVector::zeros(n), DVector::zeros(n));
        let o = body.offset;
        let frame = [1.0, 2.0, 3.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        let rates = [0.5, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0];
        q.rows_mut(o, 12).copy_from_slice(&frame);
        qd.rows_mut(o, 12).copy_from_slice(&rates);
        let mut term = Term {
            body: Some(1),
            point: true,
            undeformed: Vector3::new(0.5, 0.25, 0.0),
            modal_rows: Vec::new(),
            foreshortening_node: None,
        };
        let point = term.eval(&spatial.bodies, &q, &qd);
        assert_eq!(point.value, Vector3::new(0.75, 2.5, 3.0));
        assert_eq!(point.rate, Vector3::new(-0.5, -0.5, 0.0));
        assert_eq!(point.bias, Vector3::zeros());
        assert_eq!(point.local, term.undeformed);
        term.point = false;
        let direction = term.eval(&spatial.bodies, &q, &qd);
        assert_eq!(direction.value, Vector3::new(-0.25, 0.5, 0.0));
        assert_eq!(direction.rate, Vector3::new(-1.0, -0.5, 0.0));
        term.body = None;
        let ground = term.eval(&spatial.bodies, &q, &qd);
        assert_eq!(ground.value, term.undeformed);
        assert_eq!(ground.rate, Vector3::zeros());
    }

    /// Φ_q rows from `add_jacobian` against central differences of `eval` (x is at most
    /// quadratic in any one coordinate, so the differences are exact but for rounding), the
    /// rate against J q̇, the bias against a difference of the rate along q̇, and the
    /// `MarkerKinematics` columns against `add_jacobian`.
    fn check_term(spatial: &mut Spatial, term: &Term, label: &str) {
        let n = spatial.coordinates.len();
        let q = DVector::from_fn(n, |i, _| spatial.coordinates.q0[i] + 0.1 * noise(i));
        let qd = DVector::from_fn(n, |i, _| noise(i + 1000));
        let zero = DVector::zeros(n);
        let bodies = &spatial.bodies;
        let at = term.eval(bodies, &q, &qd);
        let mut jacobian = DMatrix::zeros(3, n);
        for k in 0..3 {
            let mut w = Vector3::zeros();
            w[k] = 1.0;
            term.add_jacobian(bodies, &at, &w, &q, &mut jacobian, k);
        }
        let h = 1e-6;
        for i in 0..n {
            let (mut plus, mut minus) = (q.clone(), q.clone());
            plus[i] += h;
            minus[i] -= h;
            let difference = (term.eval(bodies, &plus, &zero).value
                - term.eval(bodies, &minus, &zero).value)
                / (2.0 * h);
            let column = jacobian.column(i).into_owned();
            let error = (difference - &column).norm();
            assert!(
                error < 1e-7 * (1.0 + column.norm()),
                "{label}: column {i}: {error:e}"
            );
        }
        let rate_error = (&jacobian * &qd - at.rate).norm();
        assert!(
            rate_error < 1e-12 * (1.0 + at.rate.norm()),
            "{label}: rate {rate_error:e}"
        );
        let (plus, minus) = (&q + h * &qd, &q - h * &qd);
        let difference =
            (term.eval(bodies, &plus, &qd).rate - term.eval(bodies, &minus, &qd).rate) / (2.0 * h);
        let bias_error = (difference - at.bias).norm();
        assert!(
            bias_error < 1e-7 * (1.0 + at.bias.norm()),
            "{label}: bias {bias_error:e}"
        );
        let mut visited = DMatrix::zeros(3, n);
        spatial.marker_jacobian(term, &q, &mut |i, column| {
            visited.column_mut(i).copy_from(&column);
        });
        let marker_error = (visited - jacobian).amax();
        assert!(
            marker_error < 1e-12,
            "{label}: MarkerKinematics {marker_error:e}"
        );
    }

    fn modal_rows(n: usize) -> Vec<f64> {
        (0..3 * n).map(|k| 0.1 * noise(k + 500)).collect()
    }

    #[test]
    fn flexible_term_jacobian_matches_differences() {
        let mut spatial = compiled("flexible_pendulum_3d.ron", |_| {});
        let n_modes = spatial.bodies[0].n_modes;
        assert!(n_modes > 0);
        for point in [true, false] {
            let term = Term {
                body: Some(0),
                point,
                undeformed: Vector3::new(1.0, 0.2, -0.1),
                modal_rows: modal_rows(n_modes),
                foreshortening_node: None,
            };
            check_term(
                &mut spatial,
                &term,
                if point { "point" } else { "direction" },
            );
        }
    }

    #[test]
    fn foreshortened_term_jacobian_matches_differences() {
        let mut spatial = compiled("spin_up_beam_3d.ron", |scene| {
            scene.solver.stiffening = Stiffening::Foreshortening;
        });
        let body = &spatial.bodies[0];
        assert!(body.body.has_foreshortening());
        let tip = body.markers[1].node;
        assert!(tip.is_some());
        let term = Term {
            body: Some(0),
            point: true,
            undeformed: body.markers[1].position,
            modal_rows: modal_rows(body.n_modes),
            foreshortening_node: tip,
        };
        check_term(&mut spatial, &term, "FS0 tip");
    }
}
