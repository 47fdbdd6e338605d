//! Point kinematics of the mass cloud (docs/methods.md §1.1, §6.3): the one place where the
//! linear and the foreshortened (FS0) B-matrix kernels differ.
//!
//! Cloud point k of a body sits, in body components, at
//!
//! ```text
//! r̄_k = r̄_uk + X_k y + δ_k(y),      ṙ̄_k = X̂_k ẏ,      r̈̄_k = X̂_k ÿ + b_k(ẏ),
//! ```
//!
//! and a kernel generic over [`PointKinematics`] forms `B_k` from `r̄_k` and `X̂_k` and adds
//! `A b_k` to the point's velocity-product acceleration (`Ḃ_k Z` or `Ḃ_k q̇`). The variants:
//!
//! * [`Linear`] (§1.1): `δ_k = 0`, `X̂_k = X_k`, `b_k = 0`. Zero-sized: the generic kernels
//!   compiled for it are the linear kernels, operation for operation.
//! * [`Foreshortened`] (§6.3, a straight beam shortening along its axis ē₁, with the
//!   symmetric `F_k` of its station): `δ_k = −½ ē₁ yᵀF_k y`, `X̂_k = X_k − ē₁ (F_k y)ᵀ`,
//!   `b_k = −ē₁ ẏᵀF_k ẏ`. `F_k y`, `yᵀF_k y` and `ẏᵀF_k ẏ` are formed once per station
//!   (the 4 section points of a 3D Gauss station share `F_k`).

use flexmbd_core::Dim;
use nalgebra::Vector3;

use crate::foreshortening::{Foreshortening, mat_vec};
use crate::{FlexibleBody, dot};

/// The second-order axial terms of one cloud point: `δ_k = −shortening · ē₁` and
/// `b_k = −velocity_product · ē₁`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxialShortening {
    /// ½ yᵀF_k y.
    pub(crate) shortening: f64,
    /// ẏᵀF_k ẏ.
    pub(crate) velocity_product: f64,
}

/// `(X_k y, X̂_k ẏ)` of one cloud point (body components).
pub(crate) type ModalProducts = (Vector3<f64>, Vector3<f64>);

/// The kinematics of the cloud points of one body at one (y, ẏ): see the module doc.
pub(crate) trait PointKinematics {
    /// The beam axis ē₁ along which points shorten (zero when they do not).
    fn axis(&self) -> Vector3<f64>;
    /// Move to cloud point `k`, whose linear mode rows are `rows` (3n, row-major).
    fn at(&mut self, k: usize, rows: &[f64]);
    /// The velocity mode rows X̂_k of the current point (3n, row-major); `rows` are its X_k.
    fn velocity_rows<'r>(&'r self, rows: &'r [f64]) -> &'r [f64];
    /// The axial terms of the current point, `None` for linear kinematics.
    fn axial(&self) -> Option<AxialShortening>;
    /// `(X_k y, X̂_k ẏ)` of the current point as the relative-set kernel sums them.
    fn relative_products(&self, rows: &[f64], y: &[f64], y_dot: &[f64]) -> ModalProducts;
}

/// Linear kinematics, `r̄_k = r̄_uk + X_k y` (docs/methods.md §1.1).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Linear;

impl PointKinematics for Linear {
    #[inline(always)]
    fn axis(&self) -> Vector3<f64> {
        Vector3::zeros()
    }
    #[inline(always)]
    fn at(&mut self, _k: usize, _rows: &[f64]) {}
    #[inline(always)]
    fn velocity_rows<'r>(&'r self, rows: &'r [f64]) -> &'r [f64] {
        rows
    }
    #[inline(always)]
    fn axial(&self) -> Option<AxialShortening> {
        None
    }
    /// One pass over the three rows, six independent sums.
    #[inline(always)]
    fn relative_products(&self, rows: &[f64], y: &[f64], y_dot: &[f64]) -> ModalProducts {
        let n = y.len();
        let (x0, x1, x2) = (&rows[..n], &rows[n..2 * n], &rows[2 * n..3 * n]);
        let (mut xy, mut xyd) = ([0.0f64; 3], [0.0f64; 3]);
        for (((&u, &v), &w), (&p, &q)) in x0.iter().zip(x1).zip(x2).zip(y.iter().zip(y_dot)) {
            xy[0] += u * p;
            xy[1] += v * p;
            xy[2] += w * p;
            xyd[0] += u * q;
            xyd[1] += v * q;
            xyd[2] += w * q;
        }
        (Vector3::from(xy), Vector3::from(xyd))
    }
}

/// The scratch of [`Foreshortened`]: `F_k y` of the current station (n) and X̂_k (3n).
#[derive(Clone, Debug, Default)]
pub(crate) struct PointScratch {
    station_fy: Vec<f64>,
    velocity_rows: Vec<f64>,
}

impl PointScratch {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            station_fy: vec![0.0; n],
            velocity_rows: vec![0.0; 3 * n],
        }
    }
}

/// FS0 kinematics (docs/methods.md §6.3) at one (y, ẏ).
pub(crate) struct Foreshortened<'a> {
    data: &'a Foreshortening,
    y: &'a [f64],
    y_dot: &'a [f64],
    scratch: &'a mut PointScratch,
    /// Rows of X̂_k formed: 3, or 2 for a planar body (whose z rows are zero).
    axes: usize,
    /// The station whose `F_k y`, `yᵀF_k y`, `ẏᵀF_k ẏ` are held (`usize::MAX`: none yet).
    station: usize,
    axial: AxialShortening,
}

impl<'a> Foreshortened<'a> {
    /// The FS0 kinematics of `body` (which must carry FS0 data) at (y, ẏ).
    pub(crate) fn new(
        body: &'a FlexibleBody,
        y: &'a [f64],
        y_dot: &'a [f64],
        scratch: &'a mut PointScratch,
    ) -> Self {
        Self {
            data: body
                .fs
                .as_ref()
                .expect("foreshortened kinematics without FS0 data"),
            y,
            y_dot,
            scratch,
            axes: match body.dim {
                Dim::Spatial => 3,
                Dim::Planar => 2,
            },
            station: usize::MAX,
            axial: AxialShortening {
                shortening: 0.0,
                velocity_product: 0.0,
            },
        }
    }
}

impl PointKinematics for Foreshortened<'_> {
    fn axis(&self) -> Vector3<f64> {
        self.data.axis
    }

    #[inline]
    fn at(&mut self, k: usize, rows: &[f64]) {
        let n = self.y.len();
        let (y, yd) = (self.y, self.y_dot);
        let fy = &mut self.scratch.station_fy[..n];
        let station = self.data.station[k];
        if station != self.station {
            let f = &self.data.cloud[station * n * n..(station + 1) * n * n];
            mat_vec(f, y, fy);
            let yfy = dot(y, fy);
            let mut c = 0.0;
            for i in 0..n {
                c += yd[i] * dot(&f[i * n..(i + 1) * n], yd);
            }
            self.axial = AxialShortening {
                shortening: 0.5 * yfy,
                velocity_product: c,
            };
            self.station = station;
        }
        // X̂_k = X_k − ē₁ (F_k y)ᵀ, row by row (a planar body's z row stays zero).
        let xhat = &mut self.scratch.velocity_rows[..self.axes * n];
        for ((xhat_row, x_row), e) in xhat
            .chunks_exact_mut(n)
            .zip(rows.chunks_exact(n))
            .zip(self.data.axis.iter())
        {
            for ((o, x), f) in xhat_row.iter_mut().zip(x_row).zip(&*fy) {
                *o = x - e * f;
            }
        }
    }

    fn velocity_rows<'r>(&'r self, _rows: &'r [f64]) -> &'r [f64] {
        &self.scratch.velocity_rows
    }

    fn axial(&self) -> Option<AxialShortening> {
        Some(self.axial)
    }

    /// Row by row (`dot`), X_k for y and X̂_k for ẏ.
    fn relative_products(&self, rows: &[f64], y: &[f64], y_dot: &[f64]) -> ModalProducts {
        let n = y.len();
        let xhat = &self.scratch.velocity_rows;
        let mut xy = Vector3::zeros();
        let mut xhyd = Vector3::zeros();
        for r in 0..3 {
            xy[r] = dot(&rows[r * n..(r + 1) * n], y);
            xhyd[r] = dot(&xhat[r * n..(r + 1) * n], y_dot);
        }
        (xy, xhyd)
    }
}
