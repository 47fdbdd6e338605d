//! From the entries a matrix file stores to a full-storage symmetric matrix.
//!
//! A file stores a symmetric matrix in one of three ways: one triangle (Matrix Market
//! `symmetric`, CalculiX), both (Matrix Market `general`) or either (Abaqus); each pair
//! (i, j), i ≠ j, is then given once or twice. Entries given twice in the same
//! orientation are refused (whatever their values); a pair given in both orientations
//! must agree, and a matrix whose worst asymmetry |a_ij − a_ji| exceeds
//! [`SYMMETRY_TOL`] × max |a| is refused naming that entry. Where both orientations
//! are given the lower-triangle value (row ≥ column) is kept, bit for bit.

use sprs::CsMat;

use super::text::import_error;
use crate::error::FeError;

/// Relative tolerance of the symmetry check, against the largest |entry|.
pub const SYMMETRY_TOL: f64 = 1e-10;

/// One stored entry: 0-based row and column, value, 1-based line of the file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Entry {
    pub row: usize,
    pub col: usize,
    pub value: f64,
    pub line: usize,
}

/// How a file stores a symmetric matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Storage {
    /// One triangle only (Matrix Market `symmetric`, CalculiX): a pair given in both
    /// orientations is refused.
    OneTriangle,
    /// Every entry (Matrix Market `general`): a pair given once is an asymmetry
    /// against the missing zero.
    Full,
    /// Either triangle or both (Abaqus matrix input): a pair given once is mirrored,
    /// a pair given twice must agree.
    Either,
}

/// A symmetric matrix in full storage, as a list of (row, column, value), both
/// triangles, each position once.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FullSymmetric {
    pub n: usize,
    pub entries: Vec<(usize, usize, f64)>,
}

/// Build the full symmetric matrix of order `n` from a file's `entries`.
/// `what` names the matrix in errors (e.g. `K`).
pub(crate) fn symmetrise(
    file: &str,
    what: &str,
    n: usize,
    entries: Vec<Entry>,
    storage: Storage,
) -> Result<FullSymmetric, FeError> {
    let key = |e: &Entry| (e.row.min(e.col), e.row.max(e.col), e.row < e.col);
    let entries = bucket_sort(
        entries,
        n,
        |e| e.row.min(e.col),
        |e| (key(e).1, key(e).2, e.line),
    );
    let max_abs = entries.iter().fold(0.0_f64, |m, e| m.max(e.value.abs()));
    let mut out = Vec::with_capacity(2 * entries.len());
    let mut worst = Asymmetry::default();
    let mut k = 0;
    while k < entries.len() {
        let (lo, hi, _) = key(&entries[k]);
        let mut end = k + 1;
        while end < entries.len() && (key(&entries[end]).0, key(&entries[end]).1) == (lo, hi) {
            end += 1;
        }
        let group = &entries[k..end];
        refuse_duplicates(file, what, group)?;
        if lo == hi {
            out.push((lo, lo, group[0].value));
        } else {
            let value = pair_value(file, what, group, storage, &mut worst)?;
            out.push((hi, lo, value));
            out.push((lo, hi, value));
        }
        k = end;
    }
    if worst.size > SYMMETRY_TOL * max_abs {
        return Err(import_error(
            file,
            &format!("{what}[{}, {}]", worst.row + 1, worst.col + 1),
            format!(
                "{what} is not symmetric: {what}[{r}, {c}] = {:e} but {what}[{c}, {r}] = {:e} \
                 (lines {}); the worst asymmetry {:e} exceeds {SYMMETRY_TOL:e} × max |{what}| = {:e}",
                worst.a,
                worst.b,
                worst.lines,
                worst.size,
                SYMMETRY_TOL * max_abs,
                r = worst.row + 1,
                c = worst.col + 1,
            ),
        ));
    }
    Ok(FullSymmetric { n, entries: out })
}

/// Stable sort of `items` by (`bucket`, `fine`), `bucket` < n: a counting sort by
/// bucket (O(len + n)), then a stable sort of each bucket by `fine` — the matrices'
/// rows or columns hold few entries each, where one global sort was most of the time
/// of reading a large file.
fn bucket_sort<T: Copy, K: Ord>(
    items: Vec<T>,
    n: usize,
    bucket: impl Fn(&T) -> usize,
    fine: impl Fn(&T) -> K,
) -> Vec<T> {
    let Some(&first) = items.first() else {
        return items;
    };
    let mut start = vec![0usize; n + 1];
    for it in &items {
        start[bucket(it) + 1] += 1;
    }
    for b in 0..n {
        start[b + 1] += start[b];
    }
    let mut next = start.clone();
    let mut out = vec![first; items.len()];
    for it in items {
        let b = bucket(&it);
        out[next[b]] = it;
        next[b] += 1;
    }
    for b in 0..n {
        out[start[b]..start[b + 1]].sort_by_key(&fine);
    }
    out
}

#[derive(Default)]
struct Asymmetry {
    size: f64,
    row: usize,
    col: usize,
    a: f64,
    b: f64,
    lines: String,
}

/// Two entries of the same position and orientation.
fn refuse_duplicates(file: &str, what: &str, group: &[Entry]) -> Result<(), FeError> {
    for w in group.windows(2) {
        let same_orientation = (w[0].row, w[0].col) == (w[1].row, w[1].col);
        if same_orientation {
            return Err(import_error(
                file,
                &format!("{what}[{}, {}]", w[0].row + 1, w[0].col + 1),
                format!("entry given twice (lines {} and {})", w[0].line, w[1].line),
            ));
        }
    }
    Ok(())
}

/// The value of an off-diagonal pair (lower triangle kept), recording its asymmetry.
fn pair_value(
    file: &str,
    what: &str,
    group: &[Entry],
    storage: Storage,
    worst: &mut Asymmetry,
) -> Result<f64, FeError> {
    let lower = group[0];
    if group.len() == 2 {
        let upper = group[1];
        if storage == Storage::OneTriangle {
            return Err(import_error(
                file,
                &format!("{what}[{}, {}]", lower.row + 1, lower.col + 1),
                format!(
                    "the file stores one triangle, but this pair is given in both \
                     orientations (lines {} and {})",
                    lower.line, upper.line
                ),
            ));
        }
        note(
            worst,
            &lower,
            upper.value,
            format!("{} and {}", lower.line, upper.line),
        );
        return Ok(lower.value);
    }
    if storage == Storage::Full {
        note(worst, &lower, 0.0, format!("{} and none", lower.line));
    }
    Ok(lower.value)
}

fn note(worst: &mut Asymmetry, e: &Entry, mirror: f64, lines: String) {
    let size = (e.value - mirror).abs();
    if size > worst.size {
        *worst = Asymmetry {
            size,
            row: e.row,
            col: e.col,
            a: e.value,
            b: mirror,
            lines,
        };
    }
}

impl FullSymmetric {
    /// Multiply every entry by `factor`.
    pub fn scale(&mut self, factor: f64) {
        for e in &mut self.entries {
            e.2 *= factor;
        }
    }

    /// Add `value` at (i, j) and, off the diagonal, at (j, i).
    pub fn add_symmetric(&mut self, i: usize, j: usize, value: f64) {
        self.entries.push((i, j, value));
        if i != j {
            self.entries.push((j, i, value));
        }
    }

    /// CSC storage (both triangles), duplicates summed in insertion order.
    pub fn into_csc(self) -> CsMat<f64> {
        let entries = bucket_sort(self.entries, self.n, |e| e.1, |e| e.0);
        let mut indptr = vec![0usize; self.n + 1];
        let mut indices: Vec<usize> = Vec::with_capacity(entries.len());
        let mut data: Vec<f64> = Vec::with_capacity(entries.len());
        let mut last: Option<(usize, usize)> = None;
        for &(r, c, v) in &entries {
            if last == Some((r, c)) {
                *data.last_mut().expect("an entry was pushed") += v;
                continue;
            }
            indices.push(r);
            data.push(v);
            indptr[c + 1] += 1;
            last = Some((r, c));
        }
        for c in 0..self.n {
            indptr[c + 1] += indptr[c];
        }
        CsMat::new_csc((self.n, self.n), indptr, indices, data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(row: usize, col: usize, value: f64, line: usize) -> Entry {
        Entry {
            row,
            col,
            value,
            line,
        }
    }

    #[test]
    fn one_triangle_is_mirrored() {
        let s = symmetrise(
            "f",
            "K",
            2,
            vec![e(0, 0, 2.0, 1), e(1, 0, -1.0, 2), e(1, 1, 2.0, 3)],
            Storage::OneTriangle,
        )
        .unwrap();
        let a = s.into_csc();
        assert_eq!(a.get(0, 1), Some(&-1.0));
        assert_eq!(a.get(1, 0), Some(&-1.0));
        assert!(a.is_csc());
    }

    #[test]
    fn both_orientations_must_agree() {
        let ok = vec![
            e(0, 0, 2.0, 1),
            e(1, 0, -1.0, 2),
            e(0, 1, -1.0, 3),
            e(1, 1, 2.0, 4),
        ];
        assert!(symmetrise("f", "K", 2, ok.clone(), Storage::Either).is_ok());
        assert!(symmetrise("f", "K", 2, ok.clone(), Storage::Full).is_ok());
        let msg = symmetrise("f", "K", 2, ok, Storage::OneTriangle)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("both orientations"), "{msg}");
        let bad = vec![
            e(0, 0, 2.0, 1),
            e(1, 0, -1.0, 2),
            e(0, 1, -1.5, 3),
            e(1, 1, 2.0, 4),
        ];
        let msg = symmetrise("f", "K", 2, bad, Storage::Either)
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("K[2, 1]") && msg.contains("not symmetric"),
            "{msg}"
        );
    }

    #[test]
    fn general_storage_needs_both_triangles_and_duplicates_are_refused() {
        let lone = vec![e(0, 0, 2.0, 1), e(1, 0, -1.0, 2), e(1, 1, 2.0, 3)];
        let msg = symmetrise("f", "M", 2, lone, Storage::Full)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("not symmetric"), "{msg}");
        let dup = vec![e(0, 0, 2.0, 1), e(0, 0, 2.0, 7)];
        let msg = symmetrise("f", "M", 1, dup, Storage::Either)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("given twice (lines 1 and 7)"), "{msg}");
    }
}
