//! Spring–dampers between two markers (the scene's `SpringDamper` force elements) in the
//! relative formulation.
//!
//! With d = r_P2 − r_P1, l = |d|, n = d/l and the tension f = k (l − l₀) + c l̇, the markers
//! feel −f n (at P2) and +f n (at P1), so Q_z += J_zᵀ(−f n) with J_z = ∂d/∂z. J_z is built
//! like the cut-joint rows (docs/methods.md §4.4–§4.6): each marker's velocity per unit rate of
//! every elementary joint on its body's path, u_a = ṡ_a + ω_a × r_P (the twist in the s form),
//! plus the node's modal columns A X^t of a flexible body, then folded into z through L.
//! Tangents as in the absolute formulation: K += J_zᵀ(k nnᵀ + f/l (I − nnᵀ)) J_z and
//! C += c J_zᵀ nnᵀ J_z; the terms from ∂J_z/∂z and the damper's ∂l̇/∂z are left out (they
//! would only speed up Newton), as is the relative formulation's own K (§4.6).

use flexmbd_core::SystemTerms;
use nalgebra::{DMatrix, Matrix3, Vector3};

use crate::Relative;
use crate::system::point_at;
use crate::topology::Side;

/// One spring–damper, resolved.
#[derive(Clone, Debug)]
pub(crate) struct Spring {
    pub(crate) m1: Side,
    pub(crate) m2: Side,
    pub(crate) k: f64,
    pub(crate) c: f64,
    pub(crate) l0: f64,
}

/// The scene's spring–dampers and the scratch of their Jacobians (sized once).
#[derive(Clone, Debug, Default)]
pub(crate) struct Springs {
    pub(crate) list: Vec<Spring>,
    /// ∂d/∂w (3 × n_w).
    jw: DMatrix<f64>,
    /// ∂d/∂z (3 × n_z).
    jz: DMatrix<f64>,
}

impl Springs {
    pub(crate) fn new(list: Vec<Spring>, n_w: usize, n_z: usize) -> Self {
        Springs {
            list,
            jw: DMatrix::zeros(3, n_w),
            jz: DMatrix::zeros(3, n_z),
        }
    }
}

impl Relative {
    /// Add the spring–damper forces (and tangents) to `out`; positions and velocities of
    /// the tree are current.
    pub(crate) fn spring_forces(&mut self, tangents: bool, out: &mut SystemTerms) {
        let mut sp = std::mem::take(&mut self.springs);
        for s in &sp.list {
            let (r1, v1) = point_at(self, &s.m1);
            let (r2, v2) = point_at(self, &s.m2);
            let d = r2 - r1;
            let l = d.norm();
            let n = d / l;
            let f = s.k * (l - s.l0) + s.c * n.dot(&(v2 - v1));
            sp.jw.fill(0.0);
            self.add_point_jacobian(&s.m2, &r2, 1.0, &mut sp.jw);
            self.add_point_jacobian(&s.m1, &r1, -1.0, &mut sp.jw);
            sp.jz.fill(0.0);
            for (w, lw) in self.l_rows.iter().enumerate() {
                for &(c, a) in lw {
                    for r in 0..3 {
                        sp.jz[(r, c)] += a * sp.jw[(r, w)];
                    }
                }
            }
            let nz = self.n_z;
            for i in 0..nz {
                let ji = Vector3::new(sp.jz[(0, i)], sp.jz[(1, i)], sp.jz[(2, i)]);
                out.forces[i] -= f * n.dot(&ji);
            }
            if tangents {
                let nn = n * n.transpose();
                let km = nn * s.k + (Matrix3::identity() - nn) * (f / l);
                for i in 0..nz {
                    let ji = Vector3::new(sp.jz[(0, i)], sp.jz[(1, i)], sp.jz[(2, i)]);
                    if ji == Vector3::zeros() {
                        continue;
                    }
                    let kc = km * ji;
                    let cc = s.c * n.dot(&ji);
                    for j in 0..nz {
                        let jj = Vector3::new(sp.jz[(0, j)], sp.jz[(1, j)], sp.jz[(2, j)]);
                        out.stiffness[(j, i)] += jj.dot(&kc);
                        out.damping[(j, i)] += cc * n.dot(&jj);
                    }
                }
            }
        }
        self.springs = sp;
    }

    /// Elastic energy of the springs, Σ ½ k (l − l₀)².
    pub(crate) fn spring_energy(&self) -> f64 {
        self.springs
            .list
            .iter()
            .map(|s| {
                let (r1, _) = point_at(self, &s.m1);
                let (r2, _) = point_at(self, &s.m2);
                let dl = (r2 - r1).norm() - s.l0;
                0.5 * s.k * dl * dl
            })
            .sum()
    }

    /// jw += sign · ∂r_P/∂w for the marker `s` at the point `p`.
    fn add_point_jacobian(&self, s: &Side, p: &Vector3<f64>, sign: f64, jw: &mut DMatrix<f64>) {
        let Some(k) = s.body else { return };
        let b = &self.bodies[k];
        let f = b.frame;
        for &a in &self.paths[f] {
            let ev = &self.ev[a];
            let u = ev.fixed_rows::<3>(0) + ev.fixed_rows::<3>(3).cross(p);
            let wa = self.elem_w[a];
            for r in 0..3 {
                jw[(r, wa)] += sign * u[r];
            }
        }
        if let Some(node) = s.node {
            let a = self.fr_a[f];
            for m in 0..b.n {
                let col = a * Vector3::new(
                    b.rows.t(node, 0, m),
                    b.rows.t(node, 1, m),
                    b.rows.t(node, 2, m),
                );
                for r in 0..3 {
                    jw[(r, b.y_off + m)] += sign * col[r];
                }
            }
        }
    }
}
