//! An output file of `flexmbd simulate` (`--output`, `--jsonl`): its path checked before
//! the run starts without touching it, the file created or emptied only when the run
//! writes its header, and each piece written with one `write_all` and flushed.

use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// A file a run writes its rows to.
pub struct OutputFile {
    path: PathBuf,
    file: Option<File>,
}

impl OutputFile {
    /// Check that `path` (given as `option`) can take a run's rows, without touching it:
    /// not one of `others` (what it is — the scene file, another output — and its path;
    /// compared with links and `..` resolved), not a
    /// directory, in a directory that exists, and, when it exists, writable (and not
    /// read-only, for root as for anyone).
    pub fn check(
        option: &'static str,
        path: &Path,
        others: &[(&str, &Path)],
    ) -> Result<Self, String> {
        let refuse = |why: &str| format!("{option} {}: {why}", path.display());
        for (what, other) in others {
            if resolved(path).is_some() && resolved(path) == resolved(other) {
                return Err(refuse(&format!(
                    "is {what} {}; refusing to overwrite it",
                    other.display()
                )));
            }
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
                let dir = parent(path);
                if !dir.is_dir() {
                    return Err(refuse(&format!(
                        "directory {} does not exist",
                        dir.display()
                    )));
                }
            }
            Err(e) => return Err(refuse(&format!("cannot be examined: {e}"))),
        }
        Ok(OutputFile {
            path: path.to_path_buf(),
            file: None,
        })
    }

    /// The error of a failed write, naming the file.
    pub fn error(&self, source: std::io::Error) -> flexmbd::Error {
        flexmbd::Error::Output {
            path: self.path.clone(),
            source,
        }
    }

    /// Create (or empty) the file and write `header` to it, flushed: a file that cannot
    /// take it (`/dev/full`, a read-only directory) is refused here, before the first step.
    pub fn create_with(&mut self, header: &[u8]) -> Result<(), flexmbd::Error> {
        self.file = Some(File::create(&self.path).map_err(|e| self.error(e))?);
        self.write(header)
    }

    /// Write `bytes` with one `write_all`, then flush.
    pub fn write(&mut self, bytes: &[u8]) -> Result<(), flexmbd::Error> {
        let file = self
            .file
            .as_mut()
            .expect("OutputFile: created (with the header) before the rows");
        let written = file.write_all(bytes).and_then(|()| file.flush());
        written.map_err(|e| self.error(e))
    }
}

/// The directory `path` is in (`.` for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// `path` with its directory canonicalised (links and `..` resolved), whether or not the
/// file exists; `None` when the directory does not exist.
fn resolved(path: &Path) -> Option<PathBuf> {
    path.canonicalize()
        .ok()
        .or_else(|| Some(parent(path).canonicalize().ok()?.join(path.file_name()?)))
}
