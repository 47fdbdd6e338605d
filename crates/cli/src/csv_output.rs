//! The CSV output of `flexmbd simulate --output`: the path checked before the run starts,
//! the file replaced only when the run writes its header, and each row written whole and
//! flushed as soon as it is computed, so that an interrupted or killed run leaves a header
//! and whole rows.

use std::fmt::Write as _;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use flexmbd::output::RowSink;

/// A [`RowSink`] writing CSV to a file: the header as the `csv` crate writes it (quoted
/// where a name needs it), each row as `{:?}` of its values (the shortest representation
/// that reads back bit for bit), comma-separated, `\n`-terminated, formatted into a line
/// buffer that is reused (no allocation per row once it has grown to a row's length) and
/// written with one `write_all`.
pub struct CsvFile {
    path: PathBuf,
    file: Option<File>,
    line: String,
}

impl CsvFile {
    /// Check that `path` can take the CSV of a run of the scene at `scene`, without touching
    /// it: not the scene itself, not a directory, in a directory that exists, and, when it
    /// exists, writable (and not read-only, for root as for anyone). The file is created or
    /// emptied by [`RowSink::header`].
    pub fn check(path: &Path, scene: &Path) -> Result<CsvFile, String> {
        let refuse = |why: &str| format!("--output {}: {why}", path.display());
        if let (Ok(a), Ok(b)) = (path.canonicalize(), scene.canonicalize())
            && a == b
        {
            return Err(refuse("is the scene file itself; refusing to overwrite it"));
        }
        match std::fs::metadata(path) {
            Ok(meta) if meta.is_dir() => return Err(refuse("is a directory")),
            Ok(meta) if meta.permissions().readonly() => {
                return Err(refuse("is read-only; refusing to replace it"));
            }
            Ok(_) => {
                // Opened for writing without truncating: the permission is checked, the
                // contents are left as they are.
                std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| refuse(&format!("cannot be written: {e}")))?;
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let dir = match path.parent() {
                    Some(d) if !d.as_os_str().is_empty() => d,
                    _ => Path::new("."),
                };
                if !dir.is_dir() {
                    return Err(refuse(&format!(
                        "directory {} does not exist",
                        dir.display()
                    )));
                }
            }
            Err(e) => return Err(refuse(&format!("cannot be examined: {e}"))),
        }
        Ok(CsvFile {
            path: path.to_path_buf(),
            file: None,
            line: String::new(),
        })
    }

    /// The error of a failed write, naming the file.
    fn error(&self, source: std::io::Error) -> flexmbd::Error {
        flexmbd::Error::Output {
            path: self.path.clone(),
            source,
        }
    }

    /// Write `bytes` to the file with one `write_all`, then flush.
    fn write(&mut self, bytes: &[u8]) -> Result<(), flexmbd::Error> {
        let file = self
            .file
            .as_mut()
            .expect("CsvFile: the header is written before the rows");
        let written = file.write_all(bytes).and_then(|()| file.flush());
        written.map_err(|e| self.error(e))
    }
}

impl RowSink for CsvFile {
    /// Create (or empty) the file and write the header, flushed: a file that cannot take it
    /// (`/dev/full`, a read-only directory) is refused here, before the first step.
    fn header(&mut self, columns: &[String], _rows: usize) -> Result<(), flexmbd::Error> {
        let mut header = csv::Writer::from_writer(Vec::new());
        header
            .write_record(columns)
            .map_err(|e| self.error(e.into()))?;
        let bytes = header
            .into_inner()
            .map_err(|e| self.error(std::io::Error::other(e.to_string())))?;
        self.file = Some(File::create(&self.path).map_err(|e| self.error(e))?);
        self.write(&bytes)
    }

    fn row(&mut self, values: &[f64]) -> Result<(), flexmbd::Error> {
        let mut line = std::mem::take(&mut self.line);
        line.clear();
        for (i, v) in values.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            write!(line, "{v:?}").expect("formatting into a String does not fail");
        }
        line.push('\n');
        let written = self.write(line.as_bytes());
        self.line = line;
        written
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
        let mut sink = CsvFile::check(&path, Path::new("no-scene.ron")).unwrap();
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
