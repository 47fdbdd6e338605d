//! The reduced flexible body of flexmbd at run time (docs/methods.md §1.1, §1.5, §2;
//! thesis chapters 2–3).
//!
//! A [`FlexibleBody`] is built once from a [`ReducedBody`] (FE preprocessing output)
//! and then evaluates, without allocating, the inertia terms of one body in the
//! **relative set** of docs/methods.md §2.4 / §4.1,
//!
//! ```text
//! Z = {ṡ; ω; ẏ}   (3D: 6 + n entries)        Z = {ṡx; ṡy; ωz; ẏ}   (2D: 3 + n entries)
//! ```
//!
//! where ṡ is the velocity of the body point that coincides with the global origin
//! and ω the global angular velocity. With a material point at
//! `r = r0 + A (r̄_u + X y)` (§1.1) its velocity is `ṙ = ṡ + ω × r + A X ẏ`, i.e.
//! `ṙ = B Z` with `B = [I  −r̃  A X]`, and `ṙ0 = ṡ − r̃0 ω` (so `ṡ = ṙ0 + r0 × ω`).
//!
//! The mass matrix `M̄ = ∫ Bᵀ B dm` and the velocity-dependent inertia force
//! `Q̄_v = −∫ Bᵀ Ḃ Z dm` are evaluated by either of two routes
//! ([`InertiaMethod`]), which act on the **same** mass cloud (§2.1) and agree to round-off (§2.7):
//!
//! * [`InertiaMethod::BMatrix`] (§2.2): for each cloud point k,
//!   `B_k = [I  −r̃_k  A X_k]`, `Ḃ_k Z = ω × ṡ + ω × (ω × r_k) + 2 ω × A X_k ẏ`,
//!   `M̄ = Σ w_k B_kᵀ B_k`, `Q̄_v = −Σ w_k B_kᵀ (Ḃ_k Z)`. Cost O(N_p n²).
//! * [`InertiaMethod::ShapeIntegrals`] (§2.3–§2.4 steps 1–3): the configuration-dependent
//!   `m̄(y)`, `P(y)`, `Ī_O(y)`, `L_b(y)`, `C(y)`, `h(y)`, `G(ω̄)`, `W(y, ω̄)` from the 13
//!   shape integrals, the body-frame origin form `M̄_body`, `Q̄_v,body`, rotated to
//!   global components and shifted to the point s with `D`. Cost O(n²), independent
//!   of the mesh.
//!
//! The modal block of both routes is `M_yy = Σ_a Sᵃᵃ` (2D: `S¹¹ + S²²`) of the cloud,
//! which equals the reduced body's `M_ff` when the cloud is consistent with the FE
//! mass (§2.3 identity); using the cloud's value keeps the two routes identical on any cloud.
//!
//! Also: elastic and damping forces `Q_el = −K_ff y − C_ff ẏ` (§1.5) through the
//! [`ElasticModel`] hook (stiffening models of §6 plug in there), gravity in the
//! s form (§2.6), and the invariants at y = 0.
//!
//! 2D (§0 reduction rule): a planar body lives in z = 0, `A` is a rotation about z,
//! ω = ω_z e_z, and the planar set keeps the x, y, θ_z rows and columns of the 3D
//! formulas. It is implemented as its own lean path (see `docs/body.md` for why).
//!
//! A foreshortened body (FS0, docs/methods.md §6.3) is not a separate set of kernels: route (a) is
//! the same B-matrix kernel compiled for the foreshortened point kinematics (`kinematics.rs`:
//! `r̄_k` shortened along the beam axis, `X̂_k` for `X_k`, a velocity-product term in `Ḃ_k`),
//! and route (b) the same shape-integral kernel fed the hatted moments of `fs_shape.rs`. An
//! FS0 planar body runs the spatial kernels and keeps their x, y, θz rows and columns.
//!
//! Scratch is held one way: every kernel takes `&self` and a `&mut Workspace`, the body's own
//! for the relative set and the caller's [`NaturalWorkspace`] for natural coordinates.

mod blocks;
mod bmatrix;
mod construction;
pub mod elastic;
mod foreshortening;
mod fs_shape;
mod kinematics;
mod layout;
mod natural;
mod natural_points;
mod natural_terms;
mod node_rows;
pub mod operations;
mod shape;
mod state;
mod terms;
mod vanished;
pub mod weights;

pub use blocks::RelativeBlocks;
pub use elastic::{ElasticModel, ElasticTangents, LinearElastic};
pub use flexmbd_core::{Dim, InvalidValue};
pub use flexmbd_fe::ReducedBody;
pub use foreshortening::NodeShift;
pub use natural::{BodyPoint, NaturalState, NaturalWorkspace};
pub use node_rows::NodeRows;

use construction::{PackedIntegrals, check_reduced};
use kinematics::{Foreshortened, Linear, PointKinematics, PointScratch};
pub(crate) use layout::{
    relative_layout, write_modal_block, write_modal_rows, write_natural_rigid_block_3d,
    write_planar_coupling, write_planar_rigid, write_relative_couplings, write_relative_rigid,
};
pub use state::BodyState;
pub use terms::InertiaTerms;
pub use vanished::{VANISHING_TOLERANCE, VanishedIntegrals, vanishing_ratios};

use nalgebra::{DMatrix, DMatrixViewMut, Dyn, Matrix, Matrix2, Matrix3, StorageMut, U1, Vector3};
use serde::{Deserialize, Serialize};

/// Which route evaluates the inertia terms (docs/methods.md §2.2 / §2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum InertiaMethod {
    /// Route (a): projection `Σ w_k B_kᵀ B_k` over the mass cloud, O(N_p n²).
    BMatrix,
    /// Route (b): the 13 inertia shape integrals, O(n²).
    ShapeIntegrals,
}

/// Scratch storage sized once at construction (no allocation per evaluation).
///
/// Held one way: every inertia kernel takes `&self` and a `&mut Workspace`. The relative set
/// uses the body's own (lent out of the body for the call), the natural set the caller's
/// [`NaturalWorkspace`]; nothing else holds scratch.
#[derive(Clone, Debug, Default)]
pub(crate) struct Workspace {
    /// 9n: u^{ab} = S^{ab} y (3D), or [M_yy y; G_3 y; G_3 ẏ] (2D, 3n).
    pub(crate) u: Vec<f64>,
    /// 9n: rows (L_b)_a at (3b + a) n.
    pub(crate) l: Vec<f64>,
    /// 3n: G_c ẏ (3D).
    pub(crate) gy: Vec<f64>,
    /// 3n: A X_k of one cloud point, or B-route accumulators.
    pub(crate) ax: Vec<f64>,
    /// 3n: B-route Σ w A X_k.
    pub(crate) sy: Vec<f64>,
    /// 3n: B-route Σ w r̃_k A X_k.
    pub(crate) wy: Vec<f64>,
    /// n²: B-route Σ w (A X_k)ᵀ (A X_k) (upper triangle).
    pub(crate) yy: Vec<f64>,
    /// n: B-route modal inertia force, or shape-route scratch.
    pub(crate) qy: Vec<f64>,
    /// 3n: shape route C(y) rows.
    pub(crate) c: Vec<f64>,
    /// FS0 shape-integral scratch (empty without FS0 data).
    pub(crate) fs: fs_shape::FsScratch,
    /// FS0 cloud-point scratch of route (a) (empty without FS0 data).
    pub(crate) points: PointScratch,
}

impl Workspace {
    fn new(n: usize) -> Self {
        Self {
            u: vec![0.0; 9 * n],
            l: vec![0.0; 9 * n],
            gy: vec![0.0; 3 * n],
            ax: vec![0.0; 3 * n],
            sy: vec![0.0; 3 * n],
            wy: vec![0.0; 3 * n],
            yy: vec![0.0; n * n],
            qy: vec![0.0; n],
            c: vec![0.0; 3 * n],
            fs: fs_shape::FsScratch::default(),
            points: PointScratch::default(),
        }
    }

    /// Sized for n modes, with the FS0 scratch when `fs0`.
    fn for_body(n: usize, fs0: bool) -> Self {
        let mut w = Self::new(n);
        if fs0 {
            w.fs = fs_shape::FsScratch::new(n);
            w.points = PointScratch::new(n);
        }
        w
    }
}

/// One reduced flexible (or rigid, n = 0) body at run time.
#[derive(Clone, Debug)]
pub struct FlexibleBody {
    pub(crate) dim: Dim,
    pub(crate) n: usize,
    pub(crate) mass: f64,
    /// m̄_u.
    pub(crate) m_u: Vector3<f64>,
    /// P̄_u.
    pub(crate) p_u: Matrix3<f64>,
    /// S, rows a at a n (3n).
    pub(crate) s: Vec<f64>,
    /// Sᵇ row a at (3b + a) n (9n).
    pub(crate) sa: Vec<f64>,
    /// Sᵃᵇ row-major at (3a + b) n² (9n²).
    pub(crate) sab: Vec<f64>,
    /// G_1, G_2, G_3 row-major (3n²).
    pub(crate) g: Vec<f64>,
    /// M_yy = Σ_a Sᵃᵃ (3D) or S¹¹ + S²² (2D), row-major (n²).
    pub(crate) m_yy: Vec<f64>,
    /// Cloud positions r̄_u,k.
    pub(crate) pos: Vec<Vector3<f64>>,
    /// Cloud weights w_k.
    pub(crate) w: Vec<f64>,
    /// Cloud mode rows, point-major, 3n per point.
    pub(crate) rows: Vec<f64>,
    cloud_description: String,
    m_ff: DMatrix<f64>,
    k_ff: DMatrix<f64>,
    c_ff: DMatrix<f64>,
    elastic: Box<dyn ElasticModel>,
    /// The workspace of the relative set, boxed so that lending it to a kernel moves a
    /// pointer (`None` only while [`inertia`](Self::inertia) runs).
    workspace: Option<Box<Workspace>>,
    /// FS0 data (docs/methods.md §6.3), when the body is foreshortened.
    pub(crate) fs: Option<foreshortening::Foreshortening>,
    /// The inertia terms kept (issue 31; `terms.rs`), all by default.
    terms: InertiaTerms,
    /// The first-order integrals stored as zeros and skipped (`vanished.rs`).
    pub(crate) vanished: VanishedIntegrals,
}

impl FlexibleBody {
    /// Build the run-time body: copies the invariants into contiguous storage,
    /// precomputes `G_1, G_2, G_3` and `M_yy`, sizes the workspace, and uses the
    /// linear elastic model; the first-order integrals that vanish (a mean-axis basis) are
    /// stored as exact zeros and skipped by the kernels ([`vanished_integrals`](Self::vanished_integrals),
    /// `vanished.rs`). Refuses inconsistent sizes, non-finite weights, and (2D) a cloud that
    /// leaves the plane z = 0.
    pub fn new(reduced: &ReducedBody) -> Result<Self, InvalidValue> {
        let mut body = Self::keeping_integrals(reduced)?;
        body.zero_vanished(vanished::detect(reduced));
        Ok(body)
    }

    /// As [`new`](Self::new) but every shape integral as `reduced` gives it, none skipped:
    /// the full evaluation a body with vanished integrals is checked against.
    pub fn keeping_integrals(reduced: &ReducedBody) -> Result<Self, InvalidValue> {
        check_reduced(reduced)?;
        let cloud = &reduced.cloud;
        let n = cloud.n_modes;
        let si = &reduced.shape_integrals;
        let PackedIntegrals {
            s,
            sa,
            sab,
            g,
            m_yy,
        } = PackedIntegrals::new(si, n, reduced.dim);
        let fs = match &reduced.foreshortening {
            Some(d) => Some(foreshortening::Foreshortening::new(
                d,
                reduced.dim,
                n,
                &cloud.weights,
                &cloud.positions,
                &cloud.mode_rows,
            )?),
            None => None,
        };
        Ok(Self {
            fs,
            dim: reduced.dim,
            n,
            mass: si.mass,
            m_u: si.first_moment,
            p_u: si.second_moment,
            s,
            sa,
            sab,
            g,
            m_yy,
            pos: cloud.positions.clone(),
            w: cloud.weights.clone(),
            rows: cloud.mode_rows.clone(),
            cloud_description: cloud.description.clone(),
            m_ff: reduced.m_ff.clone(),
            k_ff: reduced.k_ff.clone(),
            c_ff: reduced.c_ff.clone(),
            elastic: Box::new(LinearElastic::from_reduced(reduced)),
            workspace: Some(Box::new(Workspace::for_body(
                n,
                reduced.foreshortening.is_some(),
            ))),
            terms: InertiaTerms::FULL,
            vanished: VanishedIntegrals::NONE,
        })
    }

    /// Keep only `terms` of the inertia terms (issue 31; the truncated kinetic energy of
    /// `terms.rs`, in natural coordinates `natural_terms.rs`), for route (b) in the relative
    /// and the natural set. Refused, naming `field`, for an order above 2 and for a
    /// foreshortened body (FS0's hatted moments have no truncated form here). The B-matrix
    /// route ignores the choice: a scene that runs it refuses a truncated body when compiled.
    pub fn set_inertia_terms(
        &mut self,
        terms: InertiaTerms,
        field: &str,
    ) -> Result<(), InvalidValue> {
        terms.check(field)?;
        if !terms.is_full() && self.fs.is_some() {
            return Err(InvalidValue::new(
                field,
                terms,
                "inertia terms cannot be dropped from a foreshortened (FS0) body: its hatted \
                 moments have no truncated form; keep every term or choose another stiffening",
            ));
        }
        self.terms = terms;
        Ok(())
    }

    /// The inertia terms kept (all unless [`set_inertia_terms`](Self::set_inertia_terms)).
    pub fn inertia_terms(&self) -> InertiaTerms {
        self.terms
    }

    /// Planar or spatial.
    pub fn dim(&self) -> Dim {
        self.dim
    }
    /// Number of modal coordinates n.
    pub fn n_modes(&self) -> usize {
        self.n
    }
    /// Size of the body's velocity set: 6 + n (3D) or 3 + n (2D).
    pub fn n_coords(&self) -> usize {
        self.dim.n_rigid() + self.n
    }
    /// Total mass m (kg).
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// First moment about the frame origin at y = 0, m̄_u (kg·m, body components).
    pub fn first_moment(&self) -> Vector3<f64> {
        self.m_u
    }
    /// Centre of mass at y = 0 (m, body components).
    pub fn center_of_mass(&self) -> Vector3<f64> {
        self.m_u / self.mass
    }
    /// Second moment about the frame origin at y = 0, P̄_u = ∫ r̄_u r̄_uᵀ dm.
    pub fn second_moment(&self) -> Matrix3<f64> {
        self.p_u
    }
    /// Inertia tensor about the frame origin at y = 0, `tr(P̄_u) I − P̄_u` (body axes).
    pub fn inertia_about_origin(&self) -> Matrix3<f64> {
        Matrix3::identity() * self.p_u.trace() - self.p_u
    }
    /// The modal mass block both routes use, `Σ_a Sᵃᵃ` (2D: `S¹¹ + S²²`).
    pub fn m_yy(&self) -> DMatrix<f64> {
        DMatrix::from_row_slice(self.n, self.n, &self.m_yy)
    }
    /// The reduced body's `M_ff = Xᵀ M X` as given by FE preprocessing.
    pub fn m_ff(&self) -> &DMatrix<f64> {
        &self.m_ff
    }
    /// Reduced stiffness K_ff.
    pub fn k_ff(&self) -> &DMatrix<f64> {
        &self.k_ff
    }
    /// Strain energy U(y) of the installed elastic model (½yᵀK_ff y when linear; the
    /// stiffening models' U otherwise).
    pub fn strain_energy(&self, y: &[f64]) -> f64 {
        self.elastic.strain_energy(y)
    }
    /// Reduced damping C_ff.
    pub fn c_ff(&self) -> &DMatrix<f64> {
        &self.c_ff
    }
    /// Number of mass-cloud points (the B-matrix route's cost driver).
    pub fn cloud_len(&self) -> usize {
        self.w.len()
    }
    /// Which cloud this is (reported beside cost comparisons, docs/methods.md §2.7).
    pub fn cloud_description(&self) -> &str {
        &self.cloud_description
    }

    /// M̄ and Q̄_v in the relative set {ṡ, ω, ẏ} (3D, (6+n)²) or {ṡx, ṡy, ωz, ẏ}
    /// (2D, (3+n)²), written into caller storage (every entry is overwritten).
    /// Works with `&mut DMatrix`/`&mut DVector` and with mutable views.
    ///
    /// # Panics
    /// If the output sizes or `state.y`, `state.y_dot` lengths do not match.
    pub fn inertia<SM, SQ>(
        &mut self,
        state: &BodyState<'_>,
        method: InertiaMethod,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        qv_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let (nc, m_shape, q_rows) = (self.n_coords(), m_out.shape(), qv_out.nrows());
        self.check_sizes("inertia", nc, m_shape, q_rows, state.y, state.y_dot);
        let mut workspace = self.workspace.take().expect("inertia: workspace lent out");
        let ws = workspace.as_mut();
        let mut out = blocks::Dense {
            m: m_out,
            q: qv_out,
        };
        self.relative_kernel(state, method, ws, &mut out);
        self.workspace = Some(workspace);
    }

    /// M̄ and Q̄_v in the relative set, as [`inertia`](Self::inertia), written by block into
    /// `out` (the rigid 6 × 6 block in the spatial entries {ṡ; ω}, a planar body's x, y, θz):
    /// the spatial kernels write the blocks directly, the lean planar ones through dense
    /// storage. Same values, bit for bit, as [`inertia`](Self::inertia).
    ///
    /// # Panics
    /// If `out` was not made by [`relative_blocks`](Self::relative_blocks) of this body or
    /// `state.y`, `state.y_dot` lengths do not match.
    pub fn inertia_blocks(
        &mut self,
        state: &BodyState<'_>,
        method: InertiaMethod,
        out: &mut RelativeBlocks,
    ) {
        let nc = self.n_coords();
        let shape = (nc, nc);
        self.check_sizes("inertia_blocks", nc, shape, nc, state.y, state.y_dot);
        assert_eq!(
            out.n_modes(),
            self.n,
            "inertia_blocks: blocks must hold n modes"
        );
        let mut workspace = self
            .workspace
            .take()
            .expect("inertia_blocks: workspace lent out");
        let ws = workspace.as_mut();
        if let Some((mut m, mut q)) = out.planar.take() {
            let mut dense = blocks::Dense {
                m: &mut m,
                q: &mut q,
            };
            self.relative_kernel(state, method, ws, &mut dense);
            out.planar = Some((m, q));
            out.take_planar();
        } else {
            self.spatial_kernel(state, method, ws, out);
        }
        self.workspace = Some(workspace);
    }

    /// Blocks for [`inertia_blocks`](Self::inertia_blocks), sized for this body.
    pub fn relative_blocks(&self) -> RelativeBlocks {
        let lean_planar = self.dim == Dim::Planar && self.fs.is_none();
        RelativeBlocks::new(self.n, lean_planar)
    }

    /// The relative-set kernel of this body's route, dimension and terms, into `out`. Linear
    /// spatial bodies and every FS0 body run the spatial kernels (an FS0 planar body keeps
    /// their x, y, θz rows); linear planar bodies the lean planar ones, which only write
    /// dense storage.
    fn relative_kernel<SM, SQ>(
        &self,
        state: &BodyState<'_>,
        method: InertiaMethod,
        ws: &mut Workspace,
        out: &mut blocks::Dense<'_, SM, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let terms = self.terms;
        match (method, self.dim, self.fs.is_some()) {
            (InertiaMethod::ShapeIntegrals, Dim::Planar, false) if !terms.is_full_or_o2_nv() => {
                self.shape_2d_terms(state, terms, ws, out.m, out.q)
            }
            (InertiaMethod::ShapeIntegrals, Dim::Planar, false) => {
                self.shape_2d(state, terms.velocity, ws, out.m, out.q)
            }
            (InertiaMethod::BMatrix, Dim::Planar, false) => {
                self.bmatrix_2d(state, ws, out.m, out.q)
            }
            _ => self.spatial_kernel(state, method, ws, out),
        }
    }

    /// The spatial relative-set kernels (see [`relative_kernel`](Self::relative_kernel)).
    fn spatial_kernel<O: blocks::RelativeSink>(
        &self,
        state: &BodyState<'_>,
        method: InertiaMethod,
        ws: &mut Workspace,
        out: &mut O,
    ) {
        let terms = self.terms;
        match (method, self.fs.is_some()) {
            (InertiaMethod::ShapeIntegrals, false) if !terms.is_full_or_o2_nv() => {
                self.shape_3d_terms(state, terms, ws, out)
            }
            (InertiaMethod::ShapeIntegrals, _) => self.shape_3d(state, terms.velocity, ws, out),
            (InertiaMethod::BMatrix, false) => self.bmatrix_3d(state, Linear, ws, out),
            (InertiaMethod::BMatrix, true) => {
                let mut scratch = std::mem::take(&mut ws.points);
                let points = Foreshortened::new(self, state.y, state.y_dot, &mut scratch);
                self.bmatrix_3d(state, points, ws, out);
                ws.points = scratch;
            }
        }
    }

    /// M̄_0 and Q̄_v0 in the **origin form** {ṙ0, ω, ẏ} (docs/methods.md §2.4 step 2), written
    /// into caller storage. Same sizes as [`inertia`](Self::inertia); the velocity of
    /// the origin is `state.r0_dot()`.
    ///
    /// Computed as the s form at the state moved so that O is at the global origin
    /// (there `D = I` and ṡ = ṙ0), plus the term `M̄_0 {ω × ṙ0; 0; 0}` that the s form
    /// subtracts (s̈ is not a material acceleration, §4.1): one extra (6+n) × 3 product.
    pub fn inertia_origin<SM, SQ>(
        &mut self,
        state: &BodyState<'_>,
        method: InertiaMethod,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        qv_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let r0_dot = state.r0_dot();
        let at_origin = BodyState {
            r0: Vector3::zeros(),
            s_dot: r0_dot,
            ..*state
        };
        self.inertia(&at_origin, method, m_out, qv_out);
        let c = state.omega.cross(&r0_dot);
        let nc = self.n_coords();
        match self.dim {
            Dim::Spatial => {
                for i in 0..nc {
                    qv_out[i] += m_out[(i, 0)] * c.x + m_out[(i, 1)] * c.y + m_out[(i, 2)] * c.z;
                }
            }
            Dim::Planar => {
                for i in 0..nc {
                    qv_out[i] += m_out[(i, 0)] * c.x + m_out[(i, 1)] * c.y;
                }
            }
        }
    }

    /// The size checks of an inertia call `what` with `nc` coordinates: the output M's shape,
    /// the output Q's rows, and the lengths of y and ẏ.
    #[inline(always)]
    #[track_caller]
    fn check_sizes(
        &self,
        what: &str,
        nc: usize,
        m_shape: (usize, usize),
        q_rows: usize,
        y: &[f64],
        y_dot: &[f64],
    ) {
        assert_eq!(m_shape, (nc, nc), "{what}: m_out must be {nc}x{nc}");
        assert_eq!(q_rows, nc, "{what}: qv_out must have {nc} rows");
        assert_eq!(y.len(), self.n, "{what}: y must have n entries");
        assert_eq!(y_dot.len(), self.n, "{what}: y_dot must have n entries");
    }

    /// A workspace for [`inertia_natural`](Self::inertia_natural), sized for this body.
    pub fn natural_workspace(&self) -> NaturalWorkspace {
        NaturalWorkspace(Workspace::for_body(self.n, self.fs.is_some()))
    }

    /// Size of the natural-coordinate set: 12 + n (3D: r0, u, v, w, y) or 4 + n (2D: r0, u, y).
    pub fn n_natural_coords(&self) -> usize {
        match self.dim {
            Dim::Spatial => 12 + self.n,
            Dim::Planar => 4 + self.n,
        }
    }

    /// M and Q_v in natural coordinates (docs/methods.md §2.5) by either route, written into
    /// caller storage ((12+n)² in 3D, (4+n)² in 2D; every entry overwritten). Takes
    /// `&self` and a workspace from [`natural_workspace`](Self::natural_workspace).
    /// The exact `e_a·e_b` is used in M_yy, so M and Q_v derive from one kinetic
    /// energy even when the orthonormality constraints are violated; a body with dropped
    /// terms ([`set_inertia_terms`](Self::set_inertia_terms)) uses the truncated kinetic
    /// energy written in natural coordinates (`natural_terms.rs`), which is also one T.
    ///
    /// # Panics
    /// If the output sizes or `y`, `y_dot` lengths do not match.
    pub fn inertia_natural<SM, SQ>(
        &self,
        state: &NaturalState<'_>,
        method: InertiaMethod,
        ws: &mut NaturalWorkspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        qv_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        let (nc, m_shape, q_rows) = (self.n_natural_coords(), m_out.shape(), qv_out.nrows());
        self.check_sizes("inertia_natural", nc, m_shape, q_rows, state.y, state.y_dot);
        assert_eq!(
            ws.0.qy.len(),
            self.n,
            "inertia_natural: workspace of another body"
        );
        assert_eq!(
            ws.0.fs.is_empty(),
            self.fs.is_none(),
            "inertia_natural: workspace made before set_foreshortening (make it after)"
        );
        // A truncated body (never FS0, `set_inertia_terms`) runs the kernels of
        // `natural_terms.rs`; every term kept, the kernels below unchanged.
        let terms = self.terms;
        match (method, self.dim, self.fs.is_some()) {
            (InertiaMethod::ShapeIntegrals, Dim::Spatial, false) if !terms.is_full() => {
                self.natural_shape_3d_terms(state, terms, &mut ws.0, m_out, qv_out)
            }
            (InertiaMethod::ShapeIntegrals, Dim::Planar, false) if !terms.is_full() => {
                self.natural_shape_2d_terms(state, terms, &mut ws.0, m_out, qv_out)
            }
            (InertiaMethod::ShapeIntegrals, Dim::Spatial, _) => {
                self.natural_shape_3d(state, ws, m_out, qv_out)
            }
            (InertiaMethod::ShapeIntegrals, Dim::Planar, _) => {
                self.natural_shape_2d(state, ws, m_out, qv_out)
            }
            (InertiaMethod::BMatrix, _, false) => {
                self.natural_bmatrix(state, Linear, &mut ws.0, m_out, qv_out)
            }
            (InertiaMethod::BMatrix, _, true) => {
                let ws = &mut ws.0;
                let mut scratch = std::mem::take(&mut ws.points);
                let points = Foreshortened::new(self, state.y, state.y_dot, &mut scratch);
                self.natural_bmatrix(state, points, ws, m_out, qv_out);
                ws.points = scratch;
            }
        }
    }

    /// Route (a) in natural coordinates of this body's dimension for the cloud-point
    /// kinematics `points`.
    fn natural_bmatrix<K, SM, SQ>(
        &self,
        state: &NaturalState<'_>,
        points: K,
        ws: &mut Workspace,
        m_out: &mut Matrix<f64, Dyn, Dyn, SM>,
        qv_out: &mut Matrix<f64, Dyn, U1, SQ>,
    ) where
        K: PointKinematics,
        SM: StorageMut<f64, Dyn, Dyn>,
        SQ: StorageMut<f64, Dyn, U1>,
    {
        match self.dim {
            Dim::Spatial => self.natural_bmatrix_3d(state, points, ws, m_out, qv_out),
            Dim::Planar => self.natural_bmatrix_2d(state, points, ws, m_out, qv_out),
        }
    }

    /// Gravity in natural coordinates (docs/methods.md §2.6): 3D
    /// `{m g; m̄_1 g; m̄_2 g; m̄_3 g; Sᵀ Aᵀ g}`, 2D `{m g; (m̄_1 I − m̄_2 E) g; Sᵀ Aᵀ g}`
    /// (length 12 + n or 4 + n), with m̄ = m̄(y).
    pub fn gravity_natural(&self, state: &NaturalState<'_>, g: &Vector3<f64>, out: &mut [f64]) {
        let n = self.n;
        let nc = self.n_natural_coords();
        assert_eq!(
            out.len(),
            nc,
            "gravity_natural: out must have n_natural_coords entries"
        );
        let mb = self.first_moment_at(state.y);
        let gb = state.a.tr_mul(g);
        let (o, na) = match self.dim {
            Dim::Spatial => {
                out[..3].copy_from_slice((self.mass * g).as_slice());
                for b in 0..3 {
                    out[3 + 3 * b..6 + 3 * b].copy_from_slice((mb[b] * g).as_slice());
                }
                (12, 3)
            }
            Dim::Planar => {
                out[0] = self.mass * g.x;
                out[1] = self.mass * g.y;
                // (m̄1 I − m̄2 E) g = (m̄1 g_x + m̄2 g_y, m̄1 g_y − m̄2 g_x).
                out[2] = mb.x * g.x + mb.y * g.y;
                out[3] = mb.x * g.y - mb.y * g.x;
                (4, 2)
            }
        };
        self.modal_gravity(&gb, na, &mut out[o..o + n]);
        self.add_fs_gravity(state.y, &gb, &mut out[o..]);
    }

    /// Elastic and damping forces on the modal coordinates, `Q_el(y, ẏ)` (length n),
    /// by the body's elastic model (linear: `−K_ff y − C_ff ẏ`, docs/methods.md §1.5).
    pub fn elastic_forces(&self, y: &[f64], y_dot: &[f64], out: &mut [f64]) {
        self.elastic.forces(y, y_dot, out);
    }

    /// Add `k_scale · (−∂Q_el/∂y) + c_scale · (−∂Q_el/∂ẏ)` (n × n) to `out`.
    pub fn add_elastic_tangents(
        &self,
        y: &[f64],
        y_dot: &[f64],
        k_scale: f64,
        c_scale: f64,
        out: DMatrixViewMut<'_, f64>,
    ) {
        self.elastic.add_tangents(y, y_dot, k_scale, c_scale, out);
    }

    /// The elastic model in use.
    pub fn elastic_model(&self) -> &dyn ElasticModel {
        self.elastic.as_ref()
    }

    /// Replace the elastic model (e.g. by a geometric-stiffening model of §6).
    pub fn set_elastic_model(&mut self, model: Box<dyn ElasticModel>) {
        self.elastic = model;
    }

    /// Current first moment in body components, `m̄(y) = m̄_u + S y` (FS0: minus
    /// `½ ē₁ yᵀ(Σ_k w_k F_k) y`, docs/methods.md §6.3).
    pub fn first_moment_at(&self, y: &[f64]) -> Vector3<f64> {
        let n = self.n;
        assert_eq!(y.len(), n);
        let mut m = self.m_u;
        if !self.first_moment_vanished() {
            for a in 0..3 {
                m[a] += dot(&self.s[a * n..(a + 1) * n], y);
            }
        }
        if self.fs.is_some() {
            m += self.fs_first_moment(y);
        }
        m
    }

    /// The modal gravity force `Sᵀ ḡ` over the first `na` body axes into `out` (n), ḡ = Aᵀg;
    /// zero without the products when S vanished (`vanished.rs`).
    fn modal_gravity(&self, gb: &Vector3<f64>, na: usize, out: &mut [f64]) {
        let n = self.n;
        if self.first_moment_vanished() {
            out.fill(0.0);
            return;
        }
        for (j, o) in out.iter_mut().enumerate() {
            let mut v = 0.0;
            for a in 0..na {
                v += self.s[a * n + j] * gb[a];
            }
            *o = v;
        }
    }

    /// Gravity in the s form (docs/methods.md §2.6):
    /// `{m g; (m r0 + A m̄(y)) × g; Sᵀ Aᵀ g}`, written into `out`
    /// (length 6 + n in 3D; 3 + n in 2D, with the x, y, θz rows).
    pub fn gravity_forces(&self, state: &BodyState<'_>, g: &Vector3<f64>, out: &mut [f64]) {
        let n = self.n;
        let nr = self.dim.n_rigid();
        assert_eq!(
            out.len(),
            nr + n,
            "gravity_forces: out must have n_coords entries"
        );
        let mb = self.first_moment_at(state.y);
        let lever = self.mass * state.r0 + state.a * mb;
        let f = self.mass * g;
        let tq = lever.cross(g);
        let gb = state.a.tr_mul(g);
        match self.dim {
            Dim::Spatial => {
                out[..3].copy_from_slice(f.as_slice());
                out[3..6].copy_from_slice(tq.as_slice());
            }
            Dim::Planar => {
                out[0] = f.x;
                out[1] = f.y;
                out[2] = tq.z;
            }
        }
        let na = if self.dim == Dim::Planar { 2 } else { 3 };
        self.modal_gravity(&gb, na, &mut out[nr..nr + n]);
        // FS0: Σ w X̂_kᵀ Aᵀ g adds −(Σ w F_k) y (ē₁ · Aᵀ g).
        self.add_fs_gravity(state.y, &gb, &mut out[nr..]);
    }
}

/// Dot product of two equal-length slices, with four independent accumulators
/// (a single running sum is latency-bound for the short rows used here).
#[inline(always)]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut s = (acc[0] + acc[2]) + (acc[1] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        s += x * y;
    }
    s
}

/// The in-plane 2 × 2 block of a rotation about z.
#[inline(always)]
pub(crate) fn planar_rotation(a: &Matrix3<f64>) -> Matrix2<f64> {
    a.fixed_view::<2, 2>(0, 0).into_owned()
}
