//! Where the spatial relative-set kernels put M̄ and Q̄_v (docs/methods.md §2.4): either a
//! dense (6 + n)² matrix in the layout of the body's dimension, or [`RelativeBlocks`], the
//! blocks a recursive formulation reads — the rigid 6 × 6 block and its six forces, the
//! rigid–modal coupling columns and the modal rows,
//!
//! ```text
//! M̄ = [ M̄_rr   M̄_ry ]     Q̄_v = { Q̄_r }
//!     [ M̄_ryᵀ  M̄_yy ]           { Q̄_y }
//! ```
//!
//! in the spatial entries {ṡ; ω} (a planar body's x, y, θz; the others stay zero). Both sinks
//! receive the same values from the same kernels, so either holds the same bits.

use crate::{
    relative_layout, write_modal_block, write_modal_rows, write_relative_couplings,
    write_relative_rigid,
};
use flexmbd_core::Dim;
use nalgebra::{DMatrix, DVector, Dyn, Matrix, Matrix3, Matrix6, StorageMut, U1, Vector3, Vector6};

/// What the spatial relative-set kernels write (the writers of `layout.rs`, by block).
pub(crate) trait RelativeSink {
    /// The rigid block [[m I, −g̃], [g̃, J]] and the six rigid forces.
    fn rigid(
        &mut self,
        dim: Dim,
        mass: f64,
        moment: &Vector3<f64>,
        j: &Matrix3<f64>,
        force: &[f64; 6],
    );
    /// The couplings: rows ṡ from `translation`, rows ω from `rotation` (3 × n, row-major).
    fn couplings(&mut self, dim: Dim, n: usize, translation: &[f64], rotation: &[f64]);
    /// The modal mass from the full row-major `mass` and the modal forces `force`.
    fn modal_rows(&mut self, dim: Dim, mass: &[f64], force: &[f64]);
    /// The modal mass from the upper triangle of `yy` and the modal forces `−qy`.
    fn modal_block(&mut self, dim: Dim, n: usize, yy: &[f64], qy: &[f64]);
}

/// Dense caller storage, (6 + n)² or (3 + n)².
pub(crate) struct Dense<'a, SM, SQ> {
    pub(crate) m: &'a mut Matrix<f64, Dyn, Dyn, SM>,
    pub(crate) q: &'a mut Matrix<f64, Dyn, U1, SQ>,
}

impl<SM, SQ> RelativeSink for Dense<'_, SM, SQ>
where
    SM: StorageMut<f64, Dyn, Dyn>,
    SQ: StorageMut<f64, Dyn, U1>,
{
    #[inline(always)]
    fn rigid(
        &mut self,
        dim: Dim,
        mass: f64,
        moment: &Vector3<f64>,
        j: &Matrix3<f64>,
        force: &[f64; 6],
    ) {
        write_relative_rigid(self.m, self.q, dim, mass, moment, j, force);
    }
    #[inline(always)]
    fn couplings(&mut self, dim: Dim, n: usize, translation: &[f64], rotation: &[f64]) {
        write_relative_couplings(self.m, dim, n, translation, rotation);
    }
    #[inline(always)]
    fn modal_rows(&mut self, dim: Dim, mass: &[f64], force: &[f64]) {
        write_modal_rows(self.m, self.q, relative_layout(dim).1, mass, force);
    }
    #[inline(always)]
    fn modal_block(&mut self, dim: Dim, n: usize, yy: &[f64], qy: &[f64]) {
        write_modal_block(self.m, self.q, relative_layout(dim).1, n, yy, qy);
    }
}

/// M̄ and Q̄_v of a flexible body by block (module doc), filled by
/// [`FlexibleBody::inertia_blocks`](crate::FlexibleBody::inertia_blocks).
#[derive(Clone, Debug)]
pub struct RelativeBlocks {
    /// M̄_rr in the spatial entries {ṡ; ω}.
    pub rigid: Matrix6<f64>,
    /// Q̄_r in the spatial entries.
    pub rigid_force: Vector6<f64>,
    /// Column m of M̄_ry (mode m's coupling to the rigid entries).
    pub coupling: Vec<Vector6<f64>>,
    /// M̄_yy, n × n row-major.
    pub modal_mass: Vec<f64>,
    /// Q̄_y.
    pub modal_force: Vec<f64>,
    /// Dense storage for the planar kernels, which write (3 + n)² (copied into the blocks).
    pub(crate) planar: Option<(DMatrix<f64>, DVector<f64>)>,
}

impl RelativeBlocks {
    /// Zeroed blocks for n modes; `planar` adds the dense storage of the planar kernels.
    pub(crate) fn new(n: usize, planar: bool) -> Self {
        RelativeBlocks {
            rigid: Matrix6::zeros(),
            rigid_force: Vector6::zeros(),
            coupling: vec![Vector6::zeros(); n],
            modal_mass: vec![0.0; n * n],
            modal_force: vec![0.0; n],
            planar: planar.then(|| (DMatrix::zeros(3 + n, 3 + n), DVector::zeros(3 + n))),
        }
    }

    /// The modes' count these blocks hold.
    pub fn n_modes(&self) -> usize {
        self.modal_force.len()
    }

    /// Copies a planar kernel's dense result (rows x, y, θz, modes) into the blocks.
    pub(crate) fn take_planar(&mut self) {
        let Some((m, q)) = self.planar.take() else {
            return;
        };
        const E: [usize; 3] = [0, 1, 5];
        let n = self.modal_force.len();
        // Column-major (3 + n)² slices: column c of the dense matrix at c (3 + n).
        let (ms, qs, k) = (m.as_slice(), q.as_slice(), 3 + n);
        for (r, &er) in E.iter().enumerate() {
            self.rigid_force[er] = qs[r];
            for (c, &ec) in E.iter().enumerate() {
                self.rigid[(er, ec)] = ms[c * k + r];
            }
        }
        for (column, u) in ms[3 * k..].chunks_exact(k).zip(&mut self.coupling) {
            for (r, &er) in E.iter().enumerate() {
                u[er] = column[r];
            }
        }
        self.modal_force.copy_from_slice(&qs[3..]);
        for (j, column) in ms[3 * k..].chunks_exact(k).enumerate() {
            for (i, &v) in column[3..].iter().enumerate() {
                self.modal_mass[i * n + j] = v;
            }
        }
        self.planar = Some((m, q));
    }
}

impl RelativeSink for RelativeBlocks {
    #[inline(always)]
    fn rigid(
        &mut self,
        dim: Dim,
        mass: f64,
        moment: &Vector3<f64>,
        j: &Matrix3<f64>,
        force: &[f64; 6],
    ) {
        let (layout, _) = relative_layout(dim);
        let gt = flexmbd_core::skew(moment);
        for r in 0..3 {
            for c in 0..3 {
                let keep = |a: usize, b: usize| layout[a].is_some() && layout[b].is_some();
                if keep(r, c) {
                    self.rigid[(r, c)] = if r == c { mass } else { 0.0 };
                }
                if keep(r, c + 3) {
                    self.rigid[(r, c + 3)] = -gt[(r, c)];
                }
                if keep(r + 3, c) {
                    self.rigid[(r + 3, c)] = gt[(r, c)];
                }
                if keep(r + 3, c + 3) {
                    self.rigid[(r + 3, c + 3)] = j[(r, c)];
                }
            }
        }
        for (i, row) in layout.iter().enumerate() {
            if row.is_some() {
                self.rigid_force[i] = force[i];
            }
        }
    }
    #[inline(always)]
    fn couplings(&mut self, dim: Dim, n: usize, translation: &[f64], rotation: &[f64]) {
        let (layout, _) = relative_layout(dim);
        for (i, row) in layout.iter().enumerate() {
            if row.is_none() {
                continue;
            }
            let source = if i < 3 {
                &translation[i * n..(i + 1) * n]
            } else {
                &rotation[(i - 3) * n..(i - 2) * n]
            };
            for (u, &v) in self.coupling.iter_mut().zip(source) {
                u[i] = v;
            }
        }
    }
    #[inline(always)]
    fn modal_rows(&mut self, _dim: Dim, mass: &[f64], force: &[f64]) {
        self.modal_force.copy_from_slice(force);
        self.modal_mass.copy_from_slice(mass);
    }
    #[inline(always)]
    fn modal_block(&mut self, _dim: Dim, n: usize, yy: &[f64], qy: &[f64]) {
        for i in 0..n {
            self.modal_force[i] = -qy[i];
            for j in i..n {
                let v = yy[i * n + j];
                self.modal_mass[i * n + j] = v;
                self.modal_mass[j * n + i] = v;
            }
        }
    }
}
