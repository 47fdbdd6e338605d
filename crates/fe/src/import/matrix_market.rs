//! Matrix Market coordinate files (the NIST format: R. F. Boisvert, R. Pozo,
//! K. Remington, *The Matrix Market Exchange Formats: Initial Design*, NISTIR 5935,
//! 1996; <https://math.nist.gov/MatrixMarket/formats.html>).
//!
//! Accepted: the banner `%%MatrixMarket matrix coordinate <field> <symmetry>` (tokens
//! case-insensitive) with field `real`, `double` or `integer` and symmetry `general`
//! or `symmetric`; then `%` comment lines and blank lines; the size line
//! `rows cols nnz` (rows = cols); then exactly `nnz` entry lines `i j value`
//! (1-based, white space separated). A `symmetric` file holds one triangle (either);
//! a `general` file holds both and must be symmetric (see [`super::symmetric`]).
//! `array` files, `pattern`, `complex`, `skew-symmetric` and `hermitian` are refused.
//! Ansys writes this format with `*EXPORT, …, MMF` (see docs/import.md).
//!
//! Before anything is allocated from the declared sizes they are bounded by the text:
//! each entry needs a line of at least 6 bytes (`i j v` and a line end), and a usable
//! model needs a diagonal entry of M on every row, so `rows` may not exceed the
//! number of bytes either.

use super::symmetric::{Entry, Storage};
use super::text::{At, fields, format_error, numbered_lines, quote};
use crate::error::FeError;

/// The stored entries of a Matrix Market file.
#[derive(Clone, Debug)]
pub(crate) struct MatrixFile {
    /// Order of the (square) matrix.
    pub n: usize,
    /// One triangle (`symmetric`) or both (`general`).
    pub storage: Storage,
    /// The entries, 0-based, in file order.
    pub entries: Vec<Entry>,
}

/// Parse Matrix Market coordinate text; `file` names it in errors.
pub(crate) fn parse(text: &str, file: &str) -> Result<MatrixFile, FeError> {
    let mut lines = numbered_lines(text);
    let (line1, banner) = lines
        .next()
        .ok_or_else(|| format_error(file, 1, "header", "the file is empty".into()))?;
    let storage = parse_banner(At { file, line: line1 }, banner)?;
    let mut size: Option<(usize, usize)> = None;
    let mut entries = Vec::new();
    let mut last_line = line1;
    for (line, raw) in lines {
        last_line = line;
        let t = raw.trim();
        if t.is_empty() || t.starts_with('%') {
            continue;
        }
        let at = At { file, line };
        match size {
            None => {
                let (n, nnz) = parse_size(at, &fields(t), text.len())?;
                entries.reserve(nnz); // bounded by the text's length (parse_size)
                size = Some((n, nnz));
            }
            Some((n, nnz)) => {
                if entries.len() == nnz {
                    return Err(at.error(
                        "entry",
                        format!("more entries than the {nnz} declared in the size line"),
                    ));
                }
                let f = at.three(t, "row column value")?;
                entries.push(Entry {
                    row: at.index1("row", f[0], n)?,
                    col: at.index1("column", f[1], n)?,
                    value: at.real("value", f[2])?,
                    line,
                });
            }
        }
    }
    let (n, nnz) = size.ok_or_else(|| {
        format_error(
            file,
            last_line,
            "size",
            "no size line `rows cols nnz` before the end of the file".into(),
        )
    })?;
    if entries.len() != nnz {
        return Err(format_error(
            file,
            last_line,
            "entry",
            format!(
                "the file ends after {} entries, but the size line declares {nnz}",
                entries.len()
            ),
        ));
    }
    Ok(MatrixFile {
        n,
        storage,
        entries,
    })
}

fn parse_banner(at: At, banner: &str) -> Result<Storage, FeError> {
    let t: Vec<String> = banner
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .collect();
    if t.first().map(String::as_str) != Some("%%matrixmarket") {
        return Err(at.error(
            "header",
            format!(
                "expected the banner `%%MatrixMarket matrix coordinate real symmetric|general`, found {}",
                quote(banner)
            ),
        ));
    }
    let want = |i: usize, what: &str, ok: &[&str]| -> Result<String, FeError> {
        match t.get(i) {
            Some(v) if ok.contains(&v.as_str()) => Ok(v.clone()),
            Some(v) => Err(at.error(
                what,
                format!("`{v}` is not supported (accepted: {})", ok.join(", ")),
            )),
            None => Err(at.error(what, "missing in the banner".into())),
        }
    };
    want(1, "object", &["matrix"])?;
    want(2, "format", &["coordinate"])?;
    want(3, "field", &["real", "double", "integer"])?;
    let sym = want(4, "symmetry", &["general", "symmetric"])?;
    Ok(if sym == "symmetric" {
        Storage::OneTriangle
    } else {
        Storage::Full
    })
}

fn parse_size(at: At, f: &[&str], text_len: usize) -> Result<(usize, usize), FeError> {
    at.expect_fields(f, 3, "rows cols nnz")?;
    let rows = at.count("rows", f[0])?;
    let cols = at.count("cols", f[1])?;
    let nnz = at.count("nnz", f[2])?;
    if rows != cols {
        return Err(at.error(
            "cols",
            format!("the matrix is {rows} × {cols}; K and M must be square"),
        ));
    }
    if rows > text_len {
        return Err(at.error(
            "rows",
            format!(
                "{rows} rows cannot be held by a file of {text_len} bytes (a diagonal entry per row is needed)"
            ),
        ));
    }
    if nnz > text_len / 6 {
        return Err(at.error(
            "nnz",
            format!("{nnz} entries cannot be held by a file of {text_len} bytes"),
        ));
    }
    Ok((rows, nnz))
}

#[cfg(test)]
mod tests {
    use super::*;

    const OK: &str =
        "%%MatrixMarket matrix coordinate real symmetric\n% c\n2 2 3\n1 1 2.0\n2 1 -1\n2 2 2\n";

    #[test]
    fn reads_a_small_file() {
        let m = parse(OK, "k.mtx").unwrap();
        assert_eq!(m.n, 2);
        assert_eq!(m.storage, Storage::OneTriangle);
        assert_eq!(m.entries.len(), 3);
        assert_eq!(
            (m.entries[1].row, m.entries[1].col, m.entries[1].line),
            (1, 0, 5)
        );
        let crlf = OK.replace('\n', "\r\n");
        assert_eq!(parse(&crlf, "k.mtx").unwrap().entries, m.entries);
    }

    fn err(text: &str) -> String {
        parse(text, "k.mtx").unwrap_err().to_string()
    }

    #[test]
    fn refuses_malformed_files() {
        let cases: &[(&str, &str)] = &[
            ("", "k.mtx:1: header: the file is empty"),
            ("hello\n", "k.mtx:1: header: expected the banner"),
            (
                "%%MatrixMarket matrix array real general\n",
                "format: `array`",
            ),
            (
                "%%MatrixMarket matrix coordinate complex general\n",
                "field: `complex`",
            ),
            (
                "%%MatrixMarket matrix coordinate real hermitian\n",
                "symmetry: `hermitian`",
            ),
            (
                "%%MatrixMarket matrix coordinate real\n",
                "symmetry: missing",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n",
                "no size line",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 3 1\n1 1 1\n",
                "must be square",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n99999999999 99999999999 1\n",
                "rows cannot be held",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 4000000000000\n",
                "entries cannot be held",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 x\n",
                "k.mtx:2: nnz: expected a non-negative integer, found `x`",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n",
                "ends after 1 entries",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1\n2 2 1\n",
                "k.mtx:4: entry: more entries",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 1\n",
                "k.mtx:3: row: index 3 is outside 1..=2",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 0 1\n",
                "column: index 0",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 NaN\n",
                "value: value `NaN` is not finite",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1\n",
                "expected 3 fields",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1 1\n",
                "expected 3 fields",
            ),
            (
                "%%MatrixMarket matrix coordinate real general\n2 2 1\n-1 1 1\n",
                "row: expected a non-negative integer",
            ),
        ];
        for (text, want) in cases {
            let e = err(text);
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }
}
