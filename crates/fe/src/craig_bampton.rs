//! Craig–Bampton reduction (docs/methods.md §1.3–§1.5; [R: Craig & Bampton 1968]).
//!
//! With the DOFs split into r (frame, removed), b (boundary) and i (interior):
//!
//! - static modes X_s = [I_bb; −K_ii⁻¹ K_ib], **not** normalised (η_k is the
//!   physical value of boundary DOF k);
//! - dynamic modes: the n_d lowest of K_ii φ = ω² M_ii φ, mass-normalised,
//!   expanded as [0; φ];
//! - X = [X_s X_d] (N × n) with zero rows on r; M_ff = XᵀMX, K_ff = XᵀKX
//!   (static–dynamic stiffness coupling vanishes);
//! - C_ff from the damping choice of §1.5.
//!
//! Refusals (docs/methods.md §1.4, "Pitfall"): K_ii singular (Cholesky pivot fails or
//! is negligible), or K_ff x = λ M_ff x with λ ≤ 0 (a static mode is a rigid
//! motion). Both mean the r set does not hold all rigid-body motion.

use faer::linalg::solvers::{Llt, Solve};
use faer::{Mat, Side};
use nalgebra::{DMatrix, DVector};

use crate::assembly::{DofSets, submatrix};
use crate::error::FeError;
use crate::modal::generalized_eigen;
use crate::spec::Damping;

/// Relative size below which a Cholesky pivot² of K_ii counts as zero.
pub const SINGULAR_PIVOT_TOL: f64 = 1e-13;
/// Relative size (to the largest) below which an eigenvalue of (K_ff, M_ff) counts as ≤ 0.
pub const RIGID_EIGEN_TOL: f64 = 1e-12;

/// The result of a Craig–Bampton reduction.
#[derive(Clone, Debug, PartialEq)]
pub struct Reduction {
    /// The r / b / i split.
    pub sets: DofSets,
    /// Mode matrix X = [X_s X_d] (N × n), zero rows on r.
    pub x: DMatrix<f64>,
    /// M_ff = XᵀMX (symmetrised).
    pub m_ff: DMatrix<f64>,
    /// K_ff = XᵀKX (symmetrised).
    pub k_ff: DMatrix<f64>,
    /// ω² of the kept fixed-interface modes, ascending.
    pub omega_sq: Vec<f64>,
}

impl Reduction {
    /// Number of static modes n_s.
    pub fn n_static(&self) -> usize {
        self.sets.b.len()
    }
    /// Number of dynamic modes n_d.
    pub fn n_dynamic(&self) -> usize {
        self.omega_sq.len()
    }
}

fn to_faer(a: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)])
}

/// The fixed-interface problem a dynamic basis is built on: the interior blocks, the
/// factorised K_ii and the static modes already computed.
pub struct InteriorProblem<'a> {
    /// K_ii (n_i × n_i).
    pub kii: &'a DMatrix<f64>,
    /// M_ii (n_i × n_i).
    pub mii: &'a DMatrix<f64>,
    /// The Cholesky factorisation of K_ii (checked non-singular).
    pub kii_llt: &'a Llt<f64>,
    /// The static modes X_s (N × n_b).
    pub x_static: &'a DMatrix<f64>,
    /// The spec origin, for errors.
    pub name: &'a str,
}

impl InteriorProblem<'_> {
    /// K_ii⁻¹ B for a block of right-hand sides B (n_i × c).
    pub fn solve(&self, b: &DMatrix<f64>) -> DMatrix<f64> {
        let z = self.kii_llt.solve(to_faer(b));
        DMatrix::from_fn(b.nrows(), b.ncols(), |i, j| z[(i, j)])
    }
}

/// What the dynamic-basis algorithms ([`crate::ritz`], [`crate::participation`],
/// [`crate::pod`]) need of a fixed-interface problem: solves with K_ii, products with M_ii
/// and the projections VᵀK_iiV, VᵀM_iiV. Implemented on dense blocks ([`InteriorProblem`],
/// the built-in beams) and on sparse ones
/// ([`crate::sparse_reduction::SparseInteriorProblem`], imported bodies), so that the same
/// algorithm runs on both without an N × N dense matrix on the sparse side.
pub trait InteriorOperator {
    /// The spec origin, for errors.
    fn name(&self) -> &str;
    /// The number of interior DOFs n_i.
    fn n_interior(&self) -> usize;
    /// K_ii⁻¹ B for a block of right-hand sides B (n_i × c).
    fn solve_block(&self, b: &DMatrix<f64>) -> DMatrix<f64>;
    /// M_ii v.
    fn mass_times(&self, v: &DVector<f64>) -> DVector<f64>;
    /// Vᵀ K_ii V (not symmetrised).
    fn stiffness_form(&self, v: &DMatrix<f64>) -> DMatrix<f64>;
    /// Vᵀ M_ii V (not symmetrised).
    fn mass_form(&self, v: &DMatrix<f64>) -> DMatrix<f64>;
}

impl InteriorOperator for InteriorProblem<'_> {
    fn name(&self) -> &str {
        self.name
    }
    fn n_interior(&self) -> usize {
        self.kii.nrows()
    }
    fn solve_block(&self, b: &DMatrix<f64>) -> DMatrix<f64> {
        self.solve(b)
    }
    fn mass_times(&self, v: &DVector<f64>) -> DVector<f64> {
        self.mii * v
    }
    fn stiffness_form(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        v.transpose() * self.kii * v
    }
    fn mass_form(&self, v: &DMatrix<f64>) -> DMatrix<f64> {
        v.transpose() * self.mii * v
    }
}

/// The dynamic part of a reduction basis: interior vectors, K_ii- and M_ii-orthogonal,
/// mass-normalised, with their ω² (= φᵀ K_ii φ) ascending.
#[derive(Clone, Debug, PartialEq)]
pub struct InteriorBasis {
    /// The vectors on the interior DOFs, one per column (n_i × n_d).
    pub vectors: DMatrix<f64>,
    /// ω² of each vector.
    pub omega_sq: Vec<f64>,
}

/// Reduce the free-floating (K, M) on `sets`, keeping `n_d` fixed-interface
/// modes. `name` (the spec origin) and `frame` (the r set, formatted) name the
/// model in refusals.
pub fn reduce_matrices(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    sets: &DofSets,
    n_d: usize,
    name: &str,
    frame: &str,
) -> Result<Reduction, FeError> {
    let ni = sets.i.len();
    if n_d > ni {
        return Err(FeError::TooManyModes {
            requested: n_d,
            available: ni,
        });
    }
    reduce_with_basis(k, m, sets, name, frame, |p| lowest_normal_modes(p, n_d))
}

/// The `n_d` lowest fixed-interface normal modes of K_ii φ = ω² M_ii φ.
pub fn lowest_normal_modes(p: &InteriorProblem, n_d: usize) -> Result<InteriorBasis, FeError> {
    if n_d == 0 {
        return Ok(InteriorBasis {
            vectors: DMatrix::zeros(p.kii.nrows(), 0),
            omega_sq: Vec::new(),
        });
    }
    let e = generalized_eigen(p.kii, p.mii, &format!("{}: fixed-interface modes", p.name))?
        .truncate(n_d);
    Ok(InteriorBasis {
        vectors: e.vectors,
        omega_sq: e.omega_sq,
    })
}

/// Reduce the free-floating (K, M) on `sets` with the static modes and the dynamic
/// basis `dynamic` builds on the fixed-interface problem (not called when there are no
/// interior DOFs). `name` and `frame` as in [`reduce_matrices`].
pub fn reduce_with_basis(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    sets: &DofSets,
    name: &str,
    frame: &str,
    dynamic: impl FnOnce(&InteriorProblem) -> Result<InteriorBasis, FeError>,
) -> Result<Reduction, FeError> {
    let n = k.nrows();
    let (nb, ni) = (sets.b.len(), sets.i.len());
    let singular = |detail: String| FeError::SingularInterior {
        spec: name.to_string(),
        frame: frame.to_string(),
        detail,
    };
    let kii = submatrix(k, &sets.i, &sets.i);
    let mii = submatrix(m, &sets.i, &sets.i);
    let kib = submatrix(k, &sets.i, &sets.b);

    let mut x_static = DMatrix::zeros(n, nb);
    for (c, &bdof) in sets.b.iter().enumerate() {
        x_static[(bdof, c)] = 1.0;
    }
    let mut basis = InteriorBasis {
        vectors: DMatrix::zeros(0, 0),
        omega_sq: Vec::new(),
    };
    if ni > 0 {
        let kf = to_faer(&kii);
        let llt = kf.llt(Side::Lower).map_err(|e| {
            let faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } = e;
            singular(format!(
                "Cholesky pivot of interior DOF {} is not positive",
                sets.i[index]
            ))
        })?;
        let l = llt.L();
        let dmax = (0..ni).map(|j| kii[(j, j)].abs()).fold(0.0, f64::max);
        for j in 0..ni {
            let p = l[(j, j)] * l[(j, j)];
            if p <= SINGULAR_PIVOT_TOL * dmax {
                return Err(singular(format!(
                    "Cholesky pivot of interior DOF {} is {p:e}, against {dmax:e} on the diagonal",
                    sets.i[j]
                )));
            }
        }
        if nb > 0 {
            let z = llt.solve(to_faer(&kib));
            for c in 0..nb {
                for (a, &idof) in sets.i.iter().enumerate() {
                    x_static[(idof, c)] = -z[(a, c)];
                }
            }
        }
        let problem = InteriorProblem {
            kii: &kii,
            mii: &mii,
            kii_llt: &llt,
            x_static: &x_static,
            name,
        };
        basis = dynamic(&problem)?;
    }
    let n_d = basis.omega_sq.len();
    let mut x = DMatrix::zeros(n, nb + n_d);
    x.columns_mut(0, nb).copy_from(&x_static);
    for c in 0..n_d {
        for (a, &idof) in sets.i.iter().enumerate() {
            x[(idof, nb + c)] = basis.vectors[(a, c)];
        }
    }
    let omega_sq = basis.omega_sq;
    let m_ff = sym(&(x.transpose() * m * &x));
    let k_ff = sym(&(x.transpose() * k * &x));

    check_reduced_stiffness(&k_ff, &m_ff, name, frame)?;
    Ok(Reduction {
        sets: sets.clone(),
        x,
        m_ff,
        k_ff,
        omega_sq,
    })
}

fn sym(a: &DMatrix<f64>) -> DMatrix<f64> {
    (a + a.transpose()) * 0.5
}

/// K_ff must be positive definite: the unit-consistent problem K_ff v = λ M_ff v has no
/// λ ≤ [`RIGID_EIGEN_TOL`] λ_max, else a static mode moves the body rigidly (§1.4, Pitfall).
pub fn check_reduced_stiffness(
    k_ff: &DMatrix<f64>,
    m_ff: &DMatrix<f64>,
    name: &str,
    frame: &str,
) -> Result<(), FeError> {
    if k_ff.nrows() == 0 {
        return Ok(());
    }
    let e = generalized_eigen(k_ff, m_ff, &format!("{name}: reduced (K_ff, M_ff)"))?;
    let lmin = e.omega_sq[0];
    let lmax = e.omega_sq[e.omega_sq.len() - 1]
        .abs()
        .max(f64::MIN_POSITIVE);
    if lmin <= RIGID_EIGEN_TOL * lmax {
        return Err(FeError::RigidStaticMode {
            spec: name.to_string(),
            frame: frame.to_string(),
            eigenvalue: lmin,
            largest: lmax,
        });
    }
    Ok(())
}

/// Reduced damping C_ff (docs/methods.md §1.5): none, a_K K_ff, or modal ratio ζ
/// on the normal modes (C_jj = 2ζω_j) with a_K on the static block K̂_bb.
pub fn damping_matrix(d: &Damping, r: &Reduction) -> DMatrix<f64> {
    let n = r.k_ff.nrows();
    match *d {
        Damping::None => DMatrix::zeros(n, n),
        Damping::StiffnessProportional { a_k } => &r.k_ff * a_k,
        Damping::ModalRatio { zeta, a_k_static } => {
            let ns = r.n_static();
            let mut c = DMatrix::zeros(n, n);
            for i in 0..ns {
                for j in 0..ns {
                    c[(i, j)] = a_k_static * r.k_ff[(i, j)];
                }
            }
            for (j, w2) in r.omega_sq.iter().enumerate() {
                c[(ns + j, ns + j)] = 2.0 * zeta * w2.max(0.0).sqrt();
            }
            c
        }
    }
}
