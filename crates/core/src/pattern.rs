//! The structure of a formulation's matrices, declared when it is compiled (issue 26 item
//! 2): which entries of M, K, C and Φ_q can ever be non-zero. The integrator forms the
//! leading matrix f_q = M + h/2 C + h²/4 (K + Φ_qᵀ α Φ_q) (docs/methods.md §5.2) over
//! these entries only, clears only them between passes, and factorises f_q by a sparse
//! Cholesky whose symbolic analysis is done once, instead of discovering the structure from
//! the numbers at run time.
//!
//! The pattern is topology: in natural coordinates (García de Jalón & Bayo 1994, ch. 3)
//! a body's mass matrix and elastic tangents couple its own coordinates, a force element's
//! tangents couple the coordinates of the bodies its markers sit on, and a constraint row
//! involves the coordinates of the bodies of its points and vectors. A declared pattern may
//! hold entries that are zero at some state (a rigid body's modal columns, a symmetric
//! start); it must hold every entry that is ever non-zero, which the formulation's tests
//! check against its own evaluations.

/// The declared non-zero structure of M, K, C (together) and Φ_q.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeclaredPattern {
    /// Groups of coordinates: M, K and C may be non-zero at (i, j) only where i and j
    /// both belong to one group (a body's block, the bodies of a force element).
    pub coupled: Vec<Vec<usize>>,
    /// Per constraint row, the columns of Φ_q that may be non-zero, increasing and without
    /// repeats.
    pub jacobian_rows: Vec<Vec<usize>>,
}

impl DeclaredPattern {
    /// Whether entry (i, j) of M, K or C is in the pattern, as an n × n column-major flag
    /// matrix (symmetric).
    pub fn coupling_flags(&self, n: usize) -> Vec<bool> {
        let mut flags = vec![false; n * n];
        for group in &self.coupled {
            for &j in group {
                for &i in group {
                    flags[i + j * n] = true;
                }
            }
        }
        flags
    }

    /// The first entry of the dense, column-major n × n matrix `matrix` (M, K or C) that is
    /// non-zero outside the pattern, as (row, column); `None` when the pattern covers it.
    pub fn uncovered_coupling(&self, matrix: &[f64], n: usize) -> Option<(usize, usize)> {
        let flags = self.coupling_flags(n);
        let k = (0..n * n).find(|&k| matrix[k] != 0.0 && !flags[k])?;
        Some((k % n, k / n))
    }

    /// The first entry of the dense, column-major m × n Jacobian `phi_q` that is non-zero
    /// outside the pattern, as (row, column); `None` when the pattern covers it.
    pub fn uncovered_jacobian(&self, phi_q: &[f64], m: usize) -> Option<(usize, usize)> {
        (0..phi_q.len()).map(|k| (k % m, k / m)).find(|&(r, j)| {
            phi_q[r + j * m] != 0.0
                && self
                    .jacobian_rows
                    .get(r)
                    .is_none_or(|row| row.binary_search(&j).is_err())
        })
    }
}
