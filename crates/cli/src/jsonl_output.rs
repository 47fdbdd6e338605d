//! The JSON-lines output of `flexmbd simulate --jsonl`: one JSON object per row,
//! `{"t":…,"sensor":…}`, written whole and flushed as soon as it is computed
//! ([`OutputFile`]). A value is `{:?}` of the f64 (the shortest representation that reads
//! back bit for bit, a valid JSON number), or `null` when it is not finite (JSON has no
//! NaN or infinity). The file starts with no header line: every object names its fields.

use std::fmt::Write as _;

use flexmbd::output::RowSink;

use crate::output_file::OutputFile;

/// A [`RowSink`] writing JSON lines to a file, formatted into a reused line buffer.
pub struct JsonlFile {
    out: OutputFile,
    /// `"name":` of each column, JSON-escaped once.
    keys: Vec<String>,
    line: String,
}

impl JsonlFile {
    /// A JSON-lines sink into `out` (checked, not yet created).
    pub fn new(out: OutputFile) -> Self {
        JsonlFile {
            out,
            keys: Vec::new(),
            line: String::new(),
        }
    }
}

impl RowSink for JsonlFile {
    /// Create (or empty) the file; note the columns' keys.
    fn header(&mut self, columns: &[String], _rows: usize) -> Result<(), flexmbd::Error> {
        self.keys = columns
            .iter()
            .map(|c| serde_json::to_string(c).map(|k| k + ":"))
            .collect::<Result<_, _>>()
            .map_err(|e| self.out.error(e.into()))?;
        self.out.create_with(b"")
    }

    fn row(&mut self, values: &[f64]) -> Result<(), flexmbd::Error> {
        self.line.clear();
        self.line.push('{');
        for (i, (key, v)) in self.keys.iter().zip(values).enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            self.line.push_str(key);
            if v.is_finite() {
                write!(self.line, "{v:?}").expect("formatting into a String does not fail");
            } else {
                self.line.push_str("null");
            }
        }
        self.line.push_str("}\n");
        self.out.write(self.line.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each line parses as JSON with the columns as keys, the finite values written as
    /// `{:?}` (bit for bit) and null for the others; a row allocates nothing once the buffer
    /// has grown.
    #[test]
    fn rows_are_json_objects_with_the_values_as_written() {
        let dir = std::env::temp_dir().join(format!("flexmbd-jsonl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.jsonl");
        let columns: Vec<String> = ["t", "tip \"x\""].map(String::from).to_vec();
        let rows = [[0.0, 1.0 / 3.0], [1e-3, 5e-324], [1.5, f64::NAN]];
        let mut sink = JsonlFile::new(OutputFile::check("--jsonl", &path, &[]).unwrap());
        sink.header(&columns, rows.len()).unwrap();
        let mut most = 0;
        for row in &rows {
            sink.row(row).unwrap();
            most = most.max(flexmbd_test_support::allocations_in(|| {
                sink.row(row).unwrap()
            }));
        }
        assert_eq!(most, 0, "allocations in a row");
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 6);
        assert!(lines.iter().all(|l| l.as_object().unwrap().len() == 2));
        assert!(lines[4]["tip \"x\""].is_null());
        // The numbers as written (serde_json's default parser is not exact to the last bit).
        let written: Vec<&str> = text.lines().step_by(2).collect();
        assert_eq!(
            written,
            [
                r#"{"t":0.0,"tip \"x\"":0.3333333333333333}"#,
                r#"{"t":0.001,"tip \"x\"":5e-324}"#,
                r#"{"t":1.5,"tip \"x\"":null}"#,
            ]
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
