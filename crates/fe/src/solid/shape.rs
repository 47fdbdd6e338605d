//! Isoparametric solid elements: node order, shape functions and their parent-coordinate
//! derivatives (Zienkiewicz, Taylor & Zhu, *The Finite Element Method: Its Basis and
//! Fundamentals*, 7th ed., 2013, §6.3–§6.5; Bathe, *Finite Element Procedures*, 1996, §5.3).
//!
//! Node order is Abaqus's (and CalculiX's), so that an element's matrices can be compared
//! entry for entry with theirs (Abaqus Analysis User's Guide §28.1.4, "Three-dimensional
//! solid element library"; CalculiX User's Manual §6.2):
//!
//! - **tetrahedra** on the parent ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1 with the volume coordinates
//!   L₀ = 1 − ξ − η − ζ, L₁ = ξ, L₂ = η, L₃ = ζ; nodes 0–3 the corners (0 at the origin,
//!   1 on ξ, 2 on η, 3 on ζ: nodes 0, 1, 2 turn counter-clockwise seen from node 3).
//!   `C3D4`: N_a = L_a. `C3D10`: corners N_a = L_a (2 L_a − 1), mid-edge nodes 4–9 on the
//!   edges (0,1), (1,2), (2,0), (0,3), (1,3), (2,3), N = 4 L_i L_j;
//! - **hexahedra** on the parent cube ξ, η, ζ ∈ [−1, 1]; nodes 0–3 the corners of face
//!   ζ = −1 counter-clockwise seen from ζ > 0 starting at (−1, −1, −1), 4–7 those of ζ = +1.
//!   `C3D8`: N_a = ⅛ (1 + ξ ξ_a)(1 + η η_a)(1 + ζ ζ_a). `C3D20` (serendipity): corners
//!   N_a = ⅛ (1 + ξ ξ_a)(1 + η η_a)(1 + ζ ζ_a)(ξ ξ_a + η η_a + ζ ζ_a − 2), mid-edge nodes
//!   8–11 on the bottom edges (0,1), (1,2), (2,3), (3,0), 12–15 on the top edges (4,5), (5,6),
//!   (6,7), (7,4), 16–19 on the vertical edges (0,4), (1,5), (2,6), (3,7); a mid-edge node
//!   with ξ_a = 0 has N_a = ¼ (1 − ξ²)(1 + η η_a)(1 + ζ ζ_a), and likewise along η, ζ.

use std::fmt;

/// A built-in solid element type (Abaqus names).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolidKind {
    /// 4-node linear tetrahedron.
    Tet4,
    /// 10-node quadratic tetrahedron.
    Tet10,
    /// 8-node trilinear hexahedron.
    Hex8,
    /// 20-node serendipity hexahedron.
    Hex20,
}

/// Tet10 mid-edge nodes: the corners of each edge, nodes 4–9.
pub const TET10_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// Hex20 mid-edge nodes: the corners of each edge, nodes 8–19.
pub const HEX20_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// Corners of the parent cube in node order.
pub const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Corners of the parent tetrahedron in node order.
pub const TET_CORNERS: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];

impl SolidKind {
    /// Every kind.
    pub const ALL: [SolidKind; 4] = [
        SolidKind::Tet4,
        SolidKind::Tet10,
        SolidKind::Hex8,
        SolidKind::Hex20,
    ];

    /// Number of nodes.
    pub fn n_nodes(self) -> usize {
        match self {
            SolidKind::Tet4 => 4,
            SolidKind::Tet10 => 10,
            SolidKind::Hex8 => 8,
            SolidKind::Hex20 => 20,
        }
    }

    /// The Abaqus/CalculiX element name (`C3D4`, `C3D10`, `C3D8`, `C3D20`).
    pub fn abaqus_name(self) -> &'static str {
        match self {
            SolidKind::Tet4 => "C3D4",
            SolidKind::Tet10 => "C3D10",
            SolidKind::Hex8 => "C3D8",
            SolidKind::Hex20 => "C3D20",
        }
    }

    /// The kind of an Abaqus element name (case-insensitive), if built in.
    pub fn from_abaqus_name(name: &str) -> Option<SolidKind> {
        SolidKind::ALL
            .into_iter()
            .find(|k| k.abaqus_name().eq_ignore_ascii_case(name))
    }

    /// True for the tetrahedra.
    pub fn is_tetrahedron(self) -> bool {
        matches!(self, SolidKind::Tet4 | SolidKind::Tet10)
    }

    /// Parent coordinates of every node, in node order.
    pub fn parent_nodes(self) -> Vec<[f64; 3]> {
        let mid =
            |c: &[[f64; 3]], e: &[usize; 2]| [0, 1, 2].map(|d| 0.5 * (c[e[0]][d] + c[e[1]][d]));
        match self {
            SolidKind::Tet4 => TET_CORNERS.to_vec(),
            SolidKind::Tet10 => TET_CORNERS
                .into_iter()
                .chain(TET10_EDGES.iter().map(|e| mid(&TET_CORNERS, e)))
                .collect(),
            SolidKind::Hex8 => HEX_CORNERS.to_vec(),
            SolidKind::Hex20 => HEX_CORNERS
                .into_iter()
                .chain(HEX20_EDGES.iter().map(|e| mid(&HEX_CORNERS, e)))
                .collect(),
        }
    }

    /// Shape functions N_a and their parent derivatives ∂N_a/∂(ξ, η, ζ) at `p`, written
    /// into `n` and `dn` (each of length [`Self::n_nodes`]).
    pub fn shape(self, p: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
        match self {
            SolidKind::Tet4 | SolidKind::Tet10 => tet_shape(self, p, n, dn),
            SolidKind::Hex8 => hex8_shape(p, n, dn),
            SolidKind::Hex20 => hex20_shape(p, n, dn),
        }
    }
}

impl fmt::Display for SolidKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.abaqus_name())
    }
}

/// Volume coordinates and their (constant) parent derivatives.
fn volume_coordinates(p: [f64; 3]) -> ([f64; 4], [[f64; 3]; 4]) {
    (
        [1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]],
        [
            [-1.0, -1.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
    )
}

fn tet_shape(kind: SolidKind, p: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let (l, dl) = volume_coordinates(p);
    if kind == SolidKind::Tet4 {
        n[..4].copy_from_slice(&l);
        dn[..4].copy_from_slice(&dl);
        return;
    }
    for a in 0..4 {
        n[a] = l[a] * (2.0 * l[a] - 1.0);
        dn[a] = dl[a].map(|d| (4.0 * l[a] - 1.0) * d);
    }
    for (k, [i, j]) in TET10_EDGES.into_iter().enumerate() {
        n[4 + k] = 4.0 * l[i] * l[j];
        dn[4 + k] = [0, 1, 2].map(|d| 4.0 * (dl[i][d] * l[j] + l[i] * dl[j][d]));
    }
}

fn hex8_shape(p: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        let f = [0, 1, 2].map(|d| 1.0 + p[d] * c[d]);
        n[a] = f[0] * f[1] * f[2] / 8.0;
        dn[a] = [
            c[0] * f[1] * f[2] / 8.0,
            c[1] * f[0] * f[2] / 8.0,
            c[2] * f[0] * f[1] / 8.0,
        ];
    }
}

fn hex20_shape(p: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        let f = [0, 1, 2].map(|d| 1.0 + p[d] * c[d]);
        let s = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] - 2.0;
        let prod = f[0] * f[1] * f[2];
        n[a] = prod * s / 8.0;
        let others = [f[1] * f[2], f[0] * f[2], f[0] * f[1]];
        dn[a] = [0, 1, 2].map(|d| c[d] * (others[d] * s + prod) / 8.0);
    }
    for (k, [i, j]) in HEX20_EDGES.into_iter().enumerate() {
        let (ci, cj) = (HEX_CORNERS[i], HEX_CORNERS[j]);
        // The axis the edge runs along, where the node's parent coordinate is 0.
        let along = (0..3).find(|&d| ci[d] != cj[d]).unwrap_or(0);
        let c = [0, 1, 2].map(|d| if d == along { 0.0 } else { ci[d] });
        let f = [0, 1, 2].map(|d| {
            if d == along {
                1.0 - p[d] * p[d]
            } else {
                1.0 + p[d] * c[d]
            }
        });
        let df = [0, 1, 2].map(|d| if d == along { -2.0 * p[d] } else { c[d] });
        n[8 + k] = f[0] * f[1] * f[2] / 4.0;
        dn[8 + k] = [
            df[0] * f[1] * f[2] / 4.0,
            f[0] * df[1] * f[2] / 4.0,
            f[0] * f[1] * df[2] / 4.0,
        ];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kronecker property at the nodes, partition of unity and derivatives against central
    /// differences at an interior point.
    #[test]
    fn shape_functions_interpolate_and_differentiate() {
        for kind in SolidKind::ALL {
            let nn = kind.n_nodes();
            let (mut n, mut dn) = (vec![0.0; nn], vec![[0.0; 3]; nn]);
            for (b, pb) in kind.parent_nodes().into_iter().enumerate() {
                kind.shape(pb, &mut n, &mut dn);
                for (a, &v) in n.iter().enumerate() {
                    let want = f64::from(u8::from(a == b));
                    assert!((v - want).abs() < 1e-14, "{kind} N_{a} at node {b}: {v}");
                }
            }
            let p = [0.21, 0.17, 0.29];
            // (Derivatives at the nodes are checked by the stress recovery, which evaluates B there.)
            kind.shape(p, &mut n, &mut dn);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            let h = 1e-6;
            for d in 0..3 {
                let (mut np, mut nm, mut scratch) =
                    (vec![0.0; nn], vec![0.0; nn], vec![[0.0; 3]; nn]);
                let mut q = p;
                q[d] += h;
                kind.shape(q, &mut np, &mut scratch);
                q[d] -= 2.0 * h;
                kind.shape(q, &mut nm, &mut scratch);
                for a in 0..nn {
                    let fd = (np[a] - nm[a]) / (2.0 * h);
                    assert!((fd - dn[a][d]).abs() < 1e-8, "{kind} dN_{a}/d{d}");
                }
            }
        }
    }
}
