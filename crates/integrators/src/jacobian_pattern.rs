//! The non-zero pattern of the constraint Jacobian Φ_q, kept from one evaluation to the next,
//! for forming the penalty term Φ_qᵀ α Φ_q of the leading matrix (docs/methods.md §5.2) over
//! each row's non-zeros only. A formulation's Φ_q keeps its pattern along a run (which
//! coordinates a constraint involves is topology), so instead of searching every row for
//! its non-zeros at each forming, one branch-free pass checks that no entry outside the
//! pattern is non-zero, and the pattern grows when one is. Entries of the pattern that are
//! zero at the moment add exact zeros to the leading matrix.

/// Φ_q's non-zero pattern (m × n, column-major as `SystemTerms::phi_q`), only ever growing.
#[derive(Clone, Debug)]
pub(crate) struct JacobianPattern {
    m: usize,
    /// Per entry of Φ_q: whether it is in the pattern.
    member: Vec<bool>,
    /// Per row, the pattern's columns in increasing order (each with room for all n).
    rows: Vec<Vec<usize>>,
}

impl JacobianPattern {
    /// The empty pattern of an m × n Jacobian.
    pub(crate) fn new(m: usize, n: usize) -> Self {
        JacobianPattern {
            m,
            member: vec![false; m * n],
            rows: (0..m).map(|_| Vec::with_capacity(n)).collect(),
        }
    }

    /// Make the pattern cover every non-zero of `phi_q` (column-major m × n).
    pub(crate) fn cover(&mut self, phi_q: &[f64]) {
        let outside = phi_q
            .iter()
            .zip(&self.member)
            .fold(false, |any, (&v, &inside)| any | ((v != 0.0) & !inside));
        if !outside {
            return;
        }
        for (inside, &v) in self.member.iter_mut().zip(phi_q) {
            *inside |= v != 0.0;
        }
        let m = self.m;
        for (r, row) in self.rows.iter_mut().enumerate() {
            row.clear();
            let columns = self.member[r..].iter().step_by(m).enumerate();
            row.extend(columns.filter(|&(_, &inside)| inside).map(|(j, _)| j));
        }
    }

    /// Row r's columns in the pattern, increasing.
    pub(crate) fn row(&self, r: usize) -> &[usize] {
        &self.rows[r]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pattern_grows_to_cover_new_non_zeros_and_keeps_old_ones() {
        // 2 × 3, column-major: row 0 = (1, 0, 2), row 1 = (0, 0, 3).
        let mut pattern = JacobianPattern::new(2, 3);
        pattern.cover(&[1.0, 0.0, 0.0, 0.0, 2.0, 3.0]);
        assert_eq!(pattern.row(0), [0, 2]);
        assert_eq!(pattern.row(1), [2]);
        // Entry (0, 2) turns zero and (1, 1) non-zero: (0, 2) stays, (1, 1) joins.
        pattern.cover(&[1.0, 0.0, 0.0, 5.0, 0.0, 3.0]);
        assert_eq!(pattern.row(0), [0, 2]);
        assert_eq!(pattern.row(1), [1, 2]);
        // A NaN is a non-zero: it reaches the leading matrix.
        pattern.cover(&[f64::NAN, f64::NAN, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(pattern.row(1), [0, 1, 2]);
    }
}
