//! The second-order displacement of a foreshortened (FS0) body drawn exactly by morph
//! targets whose weights are quadratic in the modal coordinates.
//!
//! FS0 (docs/methods.md §6.3; thesis ch. 4; Kane, Ryan & Banerjee 1987) moves a point of
//! the beam at FE node P by
//!
//! ```text
//! u_P = X_P y − ½ ē₁ yᵀ F_P y,        F_P = ∫₀^{x_P} (g_v g_vᵀ + g_w g_wᵀ) dξ,
//! ```
//!
//! every point of P's cross-section shortening with it (the section points of a cloud
//! station share its F). The linear part is the modes' targets ([`crate::shapes`]); the
//! shortening is drawn by extra targets t_m with weights s yᵀ Q_m y, in whichever of two
//! exact forms has fewer targets:
//!
//! - **by pairs** (n(n+1)/2 targets): target (i, j), i ≤ j, moves a vertex of node P by
//!   −½ ē₁ F_P,ij (twice that for i < j, the two symmetric terms), weighted by s y_i y_j
//!   (Q = e_i e_jᵀ), since yᵀF y = Σ_i F_ii y_i² + 2 Σ_{i<j} F_ij y_i y_j;
//! - **by nodes** (one target per drawn node with F_P ≠ 0): target P moves P's vertices by
//!   ē₁, weighted by −½ s yᵀ F_P y (Q = −½ F_P): the per-node axial shift, animated frame by
//!   frame.
//!
//! So a body of n modes never needs more targets than it has nodes, and the drawn
//! displacement is s u_P at every vertex of a node, as the body's own kinematics put it
//! (`FlexibleBody::node_foreshortening`). The scale multiplies the whole displacement,
//! u_drawn = s u(y), as the page's deformation factor multiplies every weight.
//!
//! FNL1 and FNL2 (docs/methods.md §6.1, §6.2) change the elastic forces only: their points
//! move by u = X y (FNL2 with its complete axial basis among the modes), linear in y, and
//! the modes' targets draw them exactly without quadratic ones.

use flexmbd::fe::ForeshorteningData;
use nalgebra::{DMatrix, Vector3};

use crate::shapes::BodyShape;

/// Append to `shape` (its `n` modes' targets already there, its vertices' nodes noted) the
/// targets of the FS0 shortening `fs`, by pairs or by nodes, whichever are fewer.
pub(crate) fn foreshorten(shape: &mut BodyShape, fs: &ForeshorteningData, n: usize) {
    if n == 0 || shape.targets.len() != n {
        return; // nothing deformed is drawn (sticks): nothing to shorten
    }
    let vertices = shape.positions.len();
    let node_of = |v: usize| shape.vertex_nodes.get(v).copied().flatten();
    let mut drawn: Vec<usize> = (0..vertices)
        .filter_map(node_of)
        .filter(|&p| fs.nodes.get(p).is_some_and(|f| f.amax() > 0.0))
        .collect();
    drawn.sort_unstable();
    drawn.dedup();
    let pairs: Vec<(usize, usize)> = (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect();
    let axis = fs.axis;
    let shift = |v: usize, amount: &dyn Fn(&DMatrix<f64>) -> f64| {
        node_of(v)
            .and_then(|p| fs.nodes.get(p))
            .map_or(Vector3::zeros(), |f| amount(f) * axis)
    };
    if pairs.len() <= drawn.len() {
        for (i, j) in pairs {
            let twice = if i == j { 1.0 } else { 2.0 };
            let target = (0..vertices)
                .map(|v| shift(v, &|f| -0.5 * twice * f[(i, j)]))
                .collect();
            shape.targets.push(target);
            let mut q = DMatrix::zeros(n, n);
            q[(i, j)] = 1.0;
            shape.quadratic.push(q);
        }
    } else {
        for p in drawn {
            let target = (0..vertices)
                .map(|v| {
                    if node_of(v) == Some(p) {
                        axis
                    } else {
                        Vector3::zeros()
                    }
                })
                .collect();
            shape.targets.push(target);
            shape.quadratic.push(-0.5 * &fs.nodes[p]);
        }
    }
}
