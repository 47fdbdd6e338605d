//! A flexible body's terms in the planar natural set, projected on its basis.
//!
//! The body crate gives M_f and Q_v,f in frame coordinates {r0, u, y}
//! (docs/methods.md §2.5); gravity (§2.6, folded 2D rows) and the elastic forces are
//! added here, and the constant basis map T (see `planar`) gives
//! M_b = T_extᵀ M_f T_ext, Q_b = T_extᵀ Q_f with T_ext = blockdiag(T, I_n). The elastic
//! tangents of a body's modal block ([`add_elastic_tangents`]) serve the spatial bodies
//! too.

use flexmbd_body::{FlexibleBody, InertiaMethod, NaturalState, NaturalWorkspace, NodeRows};
use flexmbd_core::SystemTerms;
use nalgebra::{DMatrix, DVector, Matrix4, Vector2, Vector3};

/// A flexible body's elastic tangents K_ff (into K) and C_ff (into C), in the diagonal
/// block of its modal coordinates, which start at coordinate `first`.
pub(crate) fn add_elastic_tangents(
    body: &FlexibleBody,
    y: &[f64],
    yd: &[f64],
    first: usize,
    out: &mut SystemTerms,
) {
    let n = y.len();
    body.add_elastic_tangents(
        y,
        yd,
        1.0,
        0.0,
        out.stiffness.view_mut((first, first), (n, n)),
    );
    body.add_elastic_tangents(
        y,
        yd,
        0.0,
        1.0,
        out.damping.view_mut((first, first), (n, n)),
    );
}

/// Storage of one flexible body, sized once.
pub(crate) struct Flex2 {
    n: usize,
    /// Node rows: X^t_x, X^t_y and X^r_z are read.
    nodes: NodeRows,
    /// Frame-coordinate terms.
    m_f: DMatrix<f64>,
    q_f: DVector<f64>,
    elastic: Vec<f64>,
    gravity: Vec<f64>,
    ws: NaturalWorkspace,
    /// Basis-coordinate terms (read by `planar`).
    pub(crate) m_b: DMatrix<f64>,
    pub(crate) q_b: DVector<f64>,
}

impl Flex2 {
    pub(crate) fn new(body: &FlexibleBody, nodes: &NodeRows) -> Self {
        let n = body.n_modes();
        debug_assert_eq!(n, nodes.n_modes());
        Flex2 {
            n,
            nodes: nodes.clone(),
            m_f: DMatrix::zeros(4 + n, 4 + n),
            q_f: DVector::zeros(4 + n),
            elastic: vec![0.0; n],
            gravity: vec![0.0; 4 + n],
            ws: body.natural_workspace(),
            m_b: DMatrix::zeros(4 + n, 4 + n),
            q_b: DVector::zeros(4 + n),
        }
    }

    /// X^r_z row of a node.
    pub(crate) fn rot_row(&self, node: usize) -> &[f64] {
        self.nodes.rotation_row(node, 2)
    }

    /// X^t_x and X^t_y rows of a node.
    pub(crate) fn trans_rows(&self, node: usize) -> (&[f64], &[f64]) {
        (
            self.nodes.translation_row(node, 0),
            self.nodes.translation_row(node, 1),
        )
    }

    /// M_b and Q_b (inertia, gravity, elastic) at the given frame state.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn evaluate(
        &mut self,
        body: &FlexibleBody,
        method: InertiaMethod,
        r0: Vector2<f64>,
        u: Vector2<f64>,
        r0d: Vector2<f64>,
        ud: Vector2<f64>,
        y: &[f64],
        yd: &[f64],
        g: Vector2<f64>,
        t: &Matrix4<f64>,
    ) {
        let state = NaturalState::planar(r0, u, r0d, ud, y, yd);
        body.inertia_natural(&state, method, &mut self.ws, &mut self.m_f, &mut self.q_f);
        body.gravity_natural(&state, &Vector3::new(g.x, g.y, 0.0), &mut self.gravity);
        body.elastic_forces(y, yd, &mut self.elastic);
        let n = self.n;
        for (q, g) in self.q_f.iter_mut().zip(&self.gravity) {
            *q += g;
        }
        for j in 0..n {
            self.q_f[4 + j] += self.elastic[j];
        }
        // A basis point at the frame's origin (r̄_P = 0, the spin-up beam's root) makes T
        // the identity: M_b = M_f, Q_b = Q_f (the products below would only add zeros).
        if *t == Matrix4::identity() {
            self.m_b.copy_from(&self.m_f);
            self.q_b.copy_from(&self.q_f);
            return;
        }
        // T_ext = blockdiag(T, I): only the 4 basis rows/columns are transformed.
        let nl = 4 + n;
        for c in 0..nl {
            for r in 0..nl.min(if c < 4 { nl } else { 4 }) {
                let mut v = 0.0;
                match (r < 4, c < 4) {
                    (true, true) => {
                        for a in 0..4 {
                            let mut inner = 0.0;
                            for b in 0..4 {
                                inner += self.m_f[(a, b)] * t[(b, c)];
                            }
                            v += t[(a, r)] * inner;
                        }
                    }
                    (true, false) => {
                        for a in 0..4 {
                            v += t[(a, r)] * self.m_f[(a, c)];
                        }
                    }
                    (false, true) => {
                        for b in 0..4 {
                            v += self.m_f[(r, b)] * t[(b, c)];
                        }
                    }
                    (false, false) => unreachable!("the modal block is copied below"),
                }
                self.m_b[(r, c)] = v;
            }
            if c >= 4 {
                // The modal block as it is (T_ext is the identity there).
                let column = c * nl + 4..(c + 1) * nl;
                self.m_b.as_mut_slice()[column.clone()]
                    .copy_from_slice(&self.m_f.as_slice()[column]);
            }
        }
        for r in 0..nl {
            self.q_b[r] = if r < 4 {
                (0..4).map(|a| t[(a, r)] * self.q_f[a]).sum()
            } else {
                self.q_f[r]
            };
        }
    }

    /// Gravity and elastic potential energy: −gᵀ(m r0 + A m̄(y)) + U(y) (the elastic model's).
    pub(crate) fn potential(
        &self,
        body: &FlexibleBody,
        r0: Vector2<f64>,
        u: Vector2<f64>,
        y: &[f64],
        g: Vector2<f64>,
    ) -> f64 {
        let mb = body.first_moment_at(y);
        let am = crate::planar::c_of(&Vector2::new(mb.x, mb.y)) * u;
        -g.dot(&(r0 * body.mass() + am)) + body.strain_energy(&y[..self.n])
    }
}
