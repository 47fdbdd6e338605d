//! The multiply-adds of one evaluation of the shape-integral kernels (route (b)), counted from
//! their structure (issue 31 item 3: "the number of operations depends on the reference
//! conditions"; thesis ch. 5).
//!
//! Counted: every multiplication inside a loop over the modes (a product of a shape-integral
//! row or matrix with y, ẏ or a 3-vector, and the scalings there), as the kernels of `shape.rs`,
//! `terms.rs`, `natural.rs` and `natural_terms.rs` perform them for n modes, the kept
//! [`InertiaTerms`] and the [`VanishedIntegrals`] they skip. Not counted: the O(1) rigid work
//! (3 × 3 products, the rotation to global components, about 200 flops whatever n is),
//! additions and copies. FS0 (foreshortened) bodies are not covered.
//!
//! The n² part is [`crate::weights::kernel_work`]'s (relative set); what a vanished S saves is
//! O(n): S y, S ẏ, A S (and r0 × A S), Sᵀā (relative) or Sᵀ Ȧᵀṙ0 (natural). A vanished skew part
//! of Sᵃ saves C ẏ and A C only where C(Sᵃ) is formed alone, at order 0 with couplings.

use crate::{Dim, InertiaTerms, VanishedIntegrals};

/// The coordinate set a kernel evaluates in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CoordinateSet {
    /// The relative set {ṡ, ω, ẏ} (docs/methods.md §2.4).
    Relative,
    /// Natural coordinates {r0, u, v, w, y} (§2.5).
    Natural,
}

/// Multiply-adds per evaluation of the shape-integral kernel of a body with `n` modes in
/// `set`, keeping `terms` and skipping `vanished` (module doc).
pub fn kernel_operations(
    dim: Dim,
    n: usize,
    terms: InertiaTerms,
    vanished: VanishedIntegrals,
    set: CoordinateSet,
) -> u64 {
    let n = n as u64;
    let k = Count {
        n,
        s: !vanished.first_moment,
        c0: !vanished.skew_first_moments,
        order: terms.order,
        coupling: terms.coupling,
        gyro: terms.coupling && terms.order >= 1 && terms.velocity,
    };
    match (set, dim, terms.is_full()) {
        (CoordinateSet::Relative, Dim::Spatial, true) => k.relative_3d_full(),
        (CoordinateSet::Relative, Dim::Spatial, false) => k.relative_3d_terms(),
        (CoordinateSet::Relative, Dim::Planar, true) => k.relative_2d_full(),
        (CoordinateSet::Relative, Dim::Planar, false) => k.relative_2d_terms(),
        (CoordinateSet::Natural, Dim::Spatial, true) => k.natural_3d_full(),
        (CoordinateSet::Natural, Dim::Spatial, false) => k.natural_3d_terms(),
        (CoordinateSet::Natural, Dim::Planar, true) => k.natural_2d_full(),
        (CoordinateSet::Natural, Dim::Planar, false) => k.natural_2d_terms(),
    }
}

/// One count: n, whether S is multiplied (`s`) and C(Sᵃ) is nonzero (`c0`), and the terms.
struct Count {
    n: u64,
    s: bool,
    c0: bool,
    order: u8,
    coupling: bool,
    gyro: bool,
}

/// `v` when `cond`, else 0.
fn when(cond: bool, v: u64) -> u64 {
    if cond { v } else { 0 }
}

impl Count {
    /// m̄(y) = m̄_u + S y and P(y) truncated at `order` over three axes (`truncated_moments`,
    /// `linear_moments`): S y 3n, Sᵃᵇ y 9n², P's twelve dots 12n (order 1 and 2).
    fn moments_3d(&self, order: u8) -> u64 {
        let n = self.n;
        when(order >= 1, when(self.s, 3 * n) + 12 * n) + when(order >= 2, 9 * n * n)
    }

    /// `shape_3d`: moments, S ẏ 3n, L ẏ 9n, G ẏ 3n², G(ω̄)ẏ 3n, the modal forces 10n (+ Sᵀā
    /// 3n), the couplings A C 9n (+ A S 9n and r0 × A S 6n).
    fn relative_3d_full(&self) -> u64 {
        let n = self.n;
        self.moments_3d(2)
            + when(self.s, 3 * n + 3 * n + 15 * n)
            + 9 * n
            + 3 * n * n
            + 3 * n
            + 10 * n
            + 9 * n
    }

    /// `shape_3d_terms`.
    fn relative_3d_terms(&self) -> u64 {
        let (n, k, cpl) = (self.n, self.order, self.coupling);
        let c_alone_zero = k == 0 && !self.c0;
        let mut ops = self.moments_3d(k);
        ops += when(k >= 1 || cpl, when(self.s, 3 * n));
        ops += when(k >= 1, 9 * n); // L ẏ (Sᵃ at order 1, L at 2)
        if cpl && !c_alone_zero {
            ops += when(k == 1, 3 * n * n) + 3 * n; // G y, C ẏ
        }
        ops += when(self.gyro, 3 * n * n + 4 * n);
        ops += when(k >= 1, 9 * n + when(self.s, 3 * n)); // centrifugal, Sᵀā
        if cpl {
            ops += when(self.s, 15 * n) + when(!c_alone_zero, 9 * n);
        }
        ops
    }

    /// `shape_2d`: S y, S ẏ 4n; M_yy y, G₃ y, G₃ ẏ 3n²; I_zz and h·ẏ 4n; the modal rows 4n
    /// (+ A S, r0 × A S and Sᵀā 8n).
    fn relative_2d_full(&self) -> u64 {
        let n = self.n;
        when(self.s, 4 * n + 8 * n) + 3 * n * n + 4 * n + 4 * n
    }

    /// `shape_2d_terms`.
    fn relative_2d_terms(&self) -> u64 {
        let (n, k, cpl) = (self.n, self.order, self.coupling);
        let mut ops = when(self.s, 4 * n);
        ops += when(k >= 2, n * n + n);
        ops += when(k >= 1, 3 * n);
        if cpl {
            ops += when(k >= 1, n * n) + when(self.gyro, n * n) + when(self.s, 6 * n);
        }
        ops += when(k >= 1, 2 * n + when(self.s, 2 * n)) + 2 * n;
        ops
    }

    /// `natural_shape_3d`: moments, S ẏ 3n, L_b ẏ 9n, A S 9n, A L_b 27n, Σ (e_a·ė_b) Sᵃᵇ ẏ
    /// 9n² + 9n, M_yy = Σ (e_a·e_b) Sᵃᵇ 9 n(n+1)/2, −2 q_y n.
    fn natural_3d_full(&self) -> u64 {
        let n = self.n;
        self.moments_3d(2)
            + when(self.s, 3 * n + 9 * n)
            + 9 * n
            + 27 * n
            + 9 * n * n
            + 9 * n
            + 9 * n * (n + 1) / 2
            + n
    }

    /// `natural_shape_3d_terms`.
    fn natural_3d_terms(&self) -> u64 {
        let (n, k, cpl) = (self.n, self.order, self.coupling);
        let linear = k >= 1;
        let c_alone_zero = k == 0 && !self.c0;
        let mut ops = self.moments_3d(k) + when(k >= 1, 9 * n) + when(self.s, 3 * n);
        if cpl {
            ops += when(linear, 3 * n * n) + when(!c_alone_zero, 3 * n) + 9 * n;
            ops += when(self.s, 9 * n) + 27 * n;
        } else {
            ops += 36 * n; // the couplings written as A times zero rows
        }
        ops += when(self.gyro, 3 * n * n + 3 * n);
        ops += when(linear != cpl, 10 * n + when(self.s, 3 * n));
        ops += when(k >= 2, 9 * n);
        ops
    }

    /// `natural_shape_2d`: S y, S ẏ 4n; L rows 4n² and L ẏ 4n; P₁₁ + P₂₂ 4n; A S 4n, the u–y
    /// couplings 8n; |u|² M_yy n(n+1)/2; Q_y 2n² + 3n.
    fn natural_2d_full(&self) -> u64 {
        let n = self.n;
        when(self.s, 8 * n)
            + 4 * n * n
            + 4 * n
            + 4 * n
            + 8 * n
            + n * (n + 1) / 2
            + 2 * n * n
            + 3 * n
    }

    /// `natural_shape_2d_terms`.
    fn natural_2d_terms(&self) -> u64 {
        let (n, k, cpl) = (self.n, self.order, self.coupling);
        let mut ops = when(self.s, 4 * n) + when(k >= 1, 2 * n) + when(k >= 2, n * n + 2 * n);
        if cpl {
            ops += when(k >= 1, n * n) + when(self.gyro, n * n) + n;
            ops += when(self.s, 4 * n) + 4 * n;
        }
        ops += when(self.s, 2 * n) + 2 * n;
        ops += when(k >= 2, n) + when(self.gyro, n);
        ops
    }
}
