//! Shape integrals that vanish under the mean-axis conditions (issue 31 item 3;
//! `flexmbd_fe::reference`, "Shape integrals that vanish"), detected when a body is built,
//! stored as exact zeros, and skipped by the shape-integral kernels.
//!
//! A basis that is M-orthogonal to the rigid-body motions (a beam's `reference: Buckens`, the
//! free-free modes of an imported part) has
//!
//! ```text
//! S_j = ∫ X_j dm = 0,        c_j = ∫ r̄ × X_j dm = (S²_3 − S³_2, S³_1 − S¹_3, S¹_2 − S²_1)_j = 0
//! ```
//!
//! for every mode j (Sᵇ_a = ∫ r̄_b X_a dm; c is the skew part of Sᵃ, C(Sᵃ) of docs/methods.md
//! §2.3). On the mass cloud they hold to round-off only. Each is tested against the round-off
//! bound of its own sum (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
//! SIAM 2002, §4.2: `|fl(Σ t_k) − Σ t_k| ≤ γ_N Σ |t_k|`), per mode,
//!
//! ```text
//! ‖S_j‖∞ ≤ τ Σ_k |w_k| ‖X_k,j‖,        ‖c_j‖∞ ≤ τ Σ_k |w_k| ‖r̄_k‖ ‖X_k,j‖,        τ = 1e-9,
//! ```
//!
//! the scales m·‖X_j‖ and m·L·‖X_j‖ of the body (Σ|w_k| = m for a lumped cloud; an imported
//! body's consistent cloud has negative weights, and Σ|w_k| bounds its sums' round-off).
//! Measured (`tests/vanished.rs`, which prints them): the Buckens beams leave 3e-15 to 1e-14
//! of these scales, the free-free imported hex8 bar 9e-13; the interface-fixed bases ≥ 1e-2.
//! τ sits three decades above the one and seven below the other, and dropping an integral of
//! relative size τ changes M̄ by as much, far below any integration tolerance.
//!
//! When all of S vanishes, S is stored as exact zeros and the kernels skip its products: m̄(y)
//! = m̄_u (no S y), S ẏ, the couplings A S (and r0 × A S in the relative set), Sᵀā and
//! Sᵀ Ȧᵀṙ0 in the modal forces, Sᵀ Aᵀ g in gravity. When all of c vanishes, the off-diagonal
//! pairs of Sᵃ are replaced by their mean, so C(Sᵃ) is exactly zero; the symmetric part (Ī's
//! first-order change) remains. Only a kernel that forms C(Sᵃ) alone can skip it: the order-0
//! kernels with couplings (`terms.rs`, `natural_terms.rs`), where C(y) = C(Sᵃ) = 0 and C ẏ,
//! A C go; the full kernels form C(y) = C(Sᵃ) + G y from the L rows by subtractions, which
//! cost no multiply-add either way. A body whose integrals do not vanish keeps them bit for bit
//! and runs the kernels unchanged. A foreshortened (FS0) body is not tested: its kernels read
//! the hatted Ŝ, which does not vanish.

use crate::FlexibleBody;
use flexmbd_fe::ReducedBody;
use serde::{Deserialize, Serialize};

/// The relative tolerance τ of the module documentation.
pub const VANISHING_TOLERANCE: f64 = 1e-9;

/// Which first-order shape integrals of a body vanish and are skipped (module doc of
/// `vanished.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct VanishedIntegrals {
    /// S = ∫ X dm = 0 (stored as zeros; its products skipped).
    pub first_moment: bool,
    /// The skew part of Sᵃ, ∫ r̄ × X dm = 0 (stored as zero; C(Sᵃ) skipped where formed alone).
    pub skew_first_moments: bool,
}

impl VanishedIntegrals {
    /// Nothing vanishes: every kernel runs in full.
    pub const NONE: Self = Self {
        first_moment: false,
        skew_first_moments: false,
    };
}

/// The largest ratios `‖S_j‖∞ / Σ|w|‖X_j‖` and `‖c_j‖∞ / Σ|w|‖r̄‖‖X_j‖` over the modes of a
/// reduced body (module doc); 0 for a body without modes.
pub fn vanishing_ratios(reduced: &ReducedBody) -> (f64, f64) {
    let cloud = &reduced.cloud;
    let si = &reduced.shape_integrals;
    let n = cloud.n_modes;
    let (mut s_ratio, mut c_ratio) = (0.0_f64, 0.0_f64);
    for j in 0..n {
        let (mut scale_s, mut scale_c) = (0.0, 0.0);
        for (k, (w, p)) in cloud.weights.iter().zip(&cloud.positions).enumerate() {
            let rows = cloud.rows(k);
            let x = nalgebra::Vector3::new(rows[j], rows[n + j], rows[2 * n + j]).norm();
            scale_s += w.abs() * x;
            scale_c += w.abs() * p.norm() * x;
        }
        let s = (0..3).map(|a| si.s[(a, j)].abs()).fold(0.0, f64::max);
        // c = ∫ r̄ × X: (S²_3 − S³_2, S³_1 − S¹_3, S¹_2 − S²_1), s_a[b][(a, j)] = Sᵇ_a.
        let sa = |b: usize, a: usize| si.s_a[b][(a, j)];
        let c = [
            sa(1, 2) - sa(2, 1),
            sa(2, 0) - sa(0, 2),
            sa(0, 1) - sa(1, 0),
        ]
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
        s_ratio = s_ratio.max(ratio(s, scale_s));
        c_ratio = c_ratio.max(ratio(c, scale_c));
    }
    (s_ratio, c_ratio)
}

/// `v / scale`, 0 for 0 / 0 (a mode that moves no mass), ∞ for v ≠ 0 over a zero scale.
fn ratio(v: f64, scale: f64) -> f64 {
    if v == 0.0 {
        0.0
    } else if scale > 0.0 {
        v / scale
    } else {
        f64::INFINITY
    }
}

/// What vanishes in `reduced` at tolerance [`VANISHING_TOLERANCE`] (nothing for a rigid or a
/// foreshortened body).
pub(crate) fn detect(reduced: &ReducedBody) -> VanishedIntegrals {
    if reduced.cloud.n_modes == 0 || reduced.foreshortening.is_some() {
        return VanishedIntegrals::NONE;
    }
    let (s, c) = vanishing_ratios(reduced);
    VanishedIntegrals {
        first_moment: s <= VANISHING_TOLERANCE,
        skew_first_moments: c <= VANISHING_TOLERANCE,
    }
}

impl FlexibleBody {
    /// Store what `vanished` says vanishes as exact zeros (module doc) and remember it.
    pub(crate) fn zero_vanished(&mut self, vanished: VanishedIntegrals) {
        let n = self.n;
        if vanished.first_moment {
            self.s.fill(0.0);
        }
        if vanished.skew_first_moments {
            // sa: Sᵇ row a at (3b + a) n; the pair (a, b), a ≠ b, to its mean.
            for b in 0..3 {
                for a in 0..b {
                    for j in 0..n {
                        let (ab, ba) = ((3 * b + a) * n + j, (3 * a + b) * n + j);
                        let mean = 0.5 * (self.sa[ab] + self.sa[ba]);
                        self.sa[ab] = mean;
                        self.sa[ba] = mean;
                    }
                }
            }
        }
        self.vanished = vanished;
    }

    /// Which first-order shape integrals vanished when the body was built and are skipped
    /// by its kernels (module doc of `vanished.rs`).
    pub fn vanished_integrals(&self) -> VanishedIntegrals {
        self.vanished
    }

    /// True when S vanished and its products are skipped.
    #[inline(always)]
    pub(crate) fn first_moment_vanished(&self) -> bool {
        self.vanished.first_moment
    }
}
