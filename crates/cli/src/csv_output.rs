//! The CSV output of `flexmbd simulate --output`: each row written whole and flushed as
//! soon as it is computed ([`OutputFile`]), so that an interrupted or killed run leaves a
//! header and whole rows.

use std::fmt::Write as _;

use flexmbd::output::RowSink;

use crate::output_file::OutputFile;

/// A [`RowSink`] writing CSV to a file: the header as the `csv` crate writes it (quoted
/// where a name needs it), each row as `{:?}` of its values (the shortest representation
/// that reads back bit for bit), comma-separated, `\n`-terminated, formatted into a line
/// buffer that is reused (no allocation per row once it has grown to a row's length) and
/// written with one `write_all`.
pub struct CsvFile {
    out: OutputFile,
    line: String,
}

impl CsvFile {
    /// A CSV sink into `out` (checked, not yet created).
    pub fn new(out: OutputFile) -> Self {
        CsvFile {
            out,
            line: String::new(),
        }
    }
}

impl RowSink for CsvFile {
    /// Create (or empty) the file and write the header, flushed.
    fn header(&mut self, columns: &[String], _rows: usize) -> Result<(), flexmbd::Error> {
        let mut header = csv::Writer::from_writer(Vec::new());
        header
            .write_record(columns)
            .map_err(|e| self.out.error(e.into()))?;
        let bytes = header
            .into_inner()
            .map_err(|e| self.out.error(std::io::Error::other(e.to_string())))?;
        self.out.create_with(&bytes)
    }

    fn row(&mut self, values: &[f64]) -> Result<(), flexmbd::Error> {
        self.line.clear();
        for (i, v) in values.iter().enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            write!(self.line, "{v:?}").expect("formatting into a String does not fail");
        }
        self.line.push('\n');
        self.out.write(self.line.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A CSV of `rows` as the program wrote it before rows were streamed: the csv crate,
    /// `{:?}` of each value.
    fn as_csv_crate_writes(columns: &[String], rows: &[Vec<f64>]) -> Vec<u8> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(columns).unwrap();
        for r in rows {
            w.write_record(r.iter().map(|v| format!("{v:?}"))).unwrap();
        }
        w.into_inner().unwrap()
    }

    /// The streamed CSV is byte for byte the csv crate's, quoting of odd sensor names and
    /// the extreme values included; once the line buffer has grown, a row allocates nothing.
    #[test]
    fn rows_are_the_csv_crates_bytes_and_allocate_nothing() {
        let dir = std::env::temp_dir().join(format!("flexmbd-csv-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.csv");
        let columns: Vec<String> = ["t", "tip x", "a,b", "say \"hi\""]
            .map(String::from)
            .to_vec();
        let rows = vec![
            vec![0.0, -0.0, 1.0 / 3.0, 5e-324],
            vec![0.001, f64::NAN, f64::INFINITY, f64::NEG_INFINITY],
            vec![1.0010000000000001, 1e300, -1.5e-7, 123456789.0],
        ];
        let mut sink = CsvFile::new(OutputFile::check("--output", &path, &[]).unwrap());
        sink.header(&columns, rows.len()).unwrap();
        let mut most = 0;
        for row in &rows {
            sink.row(row).unwrap(); // grows the line buffer to a row's length
            let made = flexmbd_test_support::allocations_in(|| sink.row(row).unwrap());
            most = most.max(made);
        }
        assert_eq!(most, 0, "allocations in a row");
        let doubled: Vec<Vec<f64>> = rows.iter().flat_map(|r| [r.clone(), r.clone()]).collect();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            as_csv_crate_writes(&columns, &doubled)
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
