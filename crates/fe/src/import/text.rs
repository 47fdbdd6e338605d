//! Line and field helpers shared by the readers: 1-based line numbers, CRLF and a
//! leading byte-order mark tolerated, every refusal an [`FeError::Format`] naming the
//! file, the line, the field and what was found.

use crate::error::FeError;

/// Longest excerpt of offending text quoted in an error.
const QUOTE: usize = 40;

/// The lines of `text` with their 1-based numbers; `\r\n` endings and a leading BOM
/// are removed.
pub(crate) fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.strip_prefix('\u{feff}')
        .unwrap_or(text)
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
}

/// Quote at most [`QUOTE`] characters of `s` for an error message.
pub(crate) fn quote(s: &str) -> String {
    let mut q: String = s.chars().take(QUOTE).collect();
    if s.chars().count() > QUOTE {
        q.push('…');
    }
    format!("`{q}`")
}

/// A [`FeError::Format`].
pub(crate) fn format_error(file: &str, line: usize, field: &str, message: String) -> FeError {
    FeError::Format {
        file: file.to_string(),
        line,
        field: field.to_string(),
        message,
    }
}

/// A [`FeError::Import`].
pub(crate) fn import_error(file: &str, field: &str, message: String) -> FeError {
    FeError::Import {
        file: file.to_string(),
        field: field.to_string(),
        message,
    }
}

/// Where a field sits, for its error messages.
#[derive(Clone, Copy)]
pub(crate) struct At<'a> {
    /// File name.
    pub file: &'a str,
    /// 1-based line.
    pub line: usize,
}

impl At<'_> {
    /// A [`FeError::Format`] at this place.
    pub fn error(&self, field: &str, message: String) -> FeError {
        format_error(self.file, self.line, field, message)
    }

    /// A finite real number (Fortran `D` exponents accepted).
    pub fn real(&self, field: &str, s: &str) -> Result<f64, FeError> {
        let t = s.trim();
        let v = t
            .parse::<f64>()
            .or_else(|_| t.replace(['D', 'd'], "E").parse::<f64>())
            .map_err(|_| {
                self.error(field, format!("expected a real number, found {}", quote(t)))
            })?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(field, format!("value {} is not finite", quote(t))))
        }
    }

    /// A non-negative integer.
    pub fn count(&self, field: &str, s: &str) -> Result<usize, FeError> {
        let t = s.trim();
        t.parse::<usize>().map_err(|_| {
            self.error(
                field,
                format!("expected a non-negative integer, found {}", quote(t)),
            )
        })
    }

    /// A 1-based index in 1..=n, returned 0-based.
    pub fn index1(&self, field: &str, s: &str, n: usize) -> Result<usize, FeError> {
        let i = self.count(field, s)?;
        if i == 0 || i > n {
            return Err(self.error(field, format!("index {i} is outside 1..={n}")));
        }
        Ok(i - 1)
    }

    /// A signed integer (node labels).
    pub fn integer(&self, field: &str, s: &str) -> Result<i64, FeError> {
        let t = s.trim();
        t.parse::<i64>()
            .map_err(|_| self.error(field, format!("expected an integer, found {}", quote(t))))
    }

    /// The three fields of `line` (see [`fields`]), or an error naming how many it has.
    pub fn three<'t>(&self, line: &'t str, layout: &str) -> Result<[&'t str; 3], FeError> {
        three_fields(line).ok_or_else(|| {
            self.error(
                "line",
                format!("expected 3 fields ({layout}), found {}", fields(line).len()),
            )
        })
    }

    /// Exactly `n` fields, or an error naming what was found.
    pub fn expect_fields(&self, fields: &[&str], n: usize, layout: &str) -> Result<(), FeError> {
        if fields.len() != n {
            return Err(self.error(
                "line",
                format!("expected {n} fields ({layout}), found {}", fields.len()),
            ));
        }
        Ok(())
    }
}

/// Fields separated by commas and/or white space (empty fields dropped).
pub(crate) fn fields(line: &str) -> Vec<&str> {
    line.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .collect()
}

/// Exactly three fields separated by commas and/or white space (the hot loop of the
/// matrix readers: no allocation); None otherwise.
fn three_fields(line: &str) -> Option<[&str; 3]> {
    let mut it = line
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty());
    let f = [it.next()?, it.next()?, it.next()?];
    it.next().is_none().then_some(f)
}

/// Fields separated by commas only, trimmed (Abaqus data lines).
pub(crate) fn comma_fields(line: &str) -> Vec<&str> {
    let t = line.trim().trim_end_matches(',');
    if t.is_empty() {
        return Vec::new();
    }
    t.split(',').map(str::trim).collect()
}

/// Read a whole file to a string, or an [`FeError::Io`] naming it.
pub(crate) fn read_file(path: &std::path::Path) -> Result<String, FeError> {
    let bytes = std::fs::read(path).map_err(|source| FeError::Io {
        file: path.display().to_string(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        import_error(
            &path.display().to_string(),
            "encoding",
            format!(
                "the file is not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crlf_and_bom_are_removed() {
        let v: Vec<_> = numbered_lines("\u{feff}a\r\nb\r\n\r\nc").collect();
        assert_eq!(v, vec![(1, "a"), (2, "b"), (3, ""), (4, "c")]);
    }

    #[test]
    fn reals_refuse_nan_and_garbage() {
        let at = At { file: "f", line: 3 };
        assert_eq!(at.real("x", " 1.5D+02").unwrap(), 150.0);
        assert_eq!(at.real("x", "0.").unwrap(), 0.0);
        for bad in ["nan", "NaN", "inf", "-inf", "1e999", "abc", ""] {
            let e = at.real("x", bad).unwrap_err().to_string();
            assert!(e.starts_with("f:3: x: "), "{e}");
        }
        assert!(at.index1("row", "0", 5).is_err());
        assert!(at.index1("row", "6", 5).is_err());
        assert_eq!(at.index1("row", "5", 5).unwrap(), 4);
        assert!(at.count("n", "-1").is_err());
    }
}
