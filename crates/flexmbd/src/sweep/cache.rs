//! A sweep's reference, computed once and kept on disk (issue 27 item 4): repeated
//! tunings and sweeps of the same scene do not pay for it again.
//!
//! An entry is keyed by everything the reference depends on: the kind asked for, the
//! judged sensors, the scene as run (its RON text, overrides applied), the grid's richest
//! point (the reference where the scene has no large-deformation model), and the program
//! that computes it (the crate's version, and the size and modification time of the
//! running executable, so that a rebuilt program does not read an older one's numbers).
//! The FE files of imported and solid bodies are in the key by path, size and modification
//! time, as the program is: an export written again changes the key.
//! The key's FNV-1a hash names the file; the file holds the whole key, compared on
//! reading, so a hash collision is a miss, never a wrong reference. The numbers are
//! written in RON, which reads every `f64` back exactly.
//!
//! Reading and writing are best effort: an unreadable, malformed or stale entry is a miss,
//! and a cache that cannot be written only costs the next run the reference again.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{ReferenceKind, ReferenceTable, SensorError};

/// The version of the entries' layout: entries of another version are misses.
const LAYOUT: u32 = 1;

/// A resolved reference, as kept.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct Entry {
    key: String,
    pub label: String,
    pub kind: ReferenceKind,
    pub fallback: Option<String>,
    pub margin: Option<Vec<SensorError>>,
    pub t: Vec<f64>,
    pub names: Vec<String>,
    pub columns: Vec<Vec<f64>>,
}

impl Entry {
    /// The entry of `table` and what goes with it, under `key`.
    pub fn new(
        key: &str,
        table: &ReferenceTable,
        kind: ReferenceKind,
        fallback: Option<String>,
        margin: Option<Vec<SensorError>>,
    ) -> Entry {
        Entry {
            key: key.to_string(),
            label: table.origin.clone(),
            kind,
            fallback,
            margin,
            t: table.t.clone(),
            names: table.names.clone(),
            columns: table.columns.clone(),
        }
    }

    /// The table kept (checked again as any table is).
    pub fn table(&self) -> Option<ReferenceTable> {
        ReferenceTable::new(
            self.label.clone(),
            self.t.clone(),
            self.names.clone(),
            self.columns.clone(),
        )
        .ok()
    }
}

/// The key of a reference: the parts named in the module documentation, one per line.
pub(super) fn key(
    kind: &str,
    sensors: &[String],
    scene_ron: &str,
    richest: &str,
    fe_files: &[PathBuf],
) -> String {
    let program = std::env::current_exe().map_or_else(|_| "unknown".into(), |p| stamp(&p));
    let files: String = fe_files
        .iter()
        .map(|f| format!("file {}: {}\n", f.display(), stamp(f)))
        .collect();
    format!(
        "layout {LAYOUT}\nflexmbd {}\nprogram {program}\n{files}reference {kind}\nsensors {}\nrichest {richest}\nscene {scene_ron}",
        env!("CARGO_PKG_VERSION"),
        sensors.join(",")
    )
}

/// A file's size and modification time (ns since the epoch), or `unknown`.
fn stamp(path: &Path) -> String {
    std::fs::metadata(path).map_or_else(
        |_| "unknown".into(),
        |m| {
            let modified = m
                .modified()
                .ok()
                .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
                .map_or(0, |d| d.as_nanos());
            format!("{} bytes, modified {modified}", m.len())
        },
    )
}

/// FNV-1a, 64 bits.
fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fn file_of(dir: &Path, key: &str) -> PathBuf {
    dir.join(format!("reference-{:016x}.ron", fnv1a(key)))
}

/// The entry kept under `key` in `dir`, if there is one for exactly that key.
pub(super) fn load(dir: &Path, key: &str) -> Option<Entry> {
    let text = std::fs::read_to_string(file_of(dir, key)).ok()?;
    let entry: Entry = ron::from_str(&text).ok()?;
    (entry.key == key).then_some(entry)
}

/// Keep `entry` in `dir` (made if missing), written to a temporary file and renamed, so a
/// reader never sees half an entry.
pub(super) fn store(dir: &Path, entry: &Entry) {
    let write = || -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        let text = ron::to_string(entry).map_err(std::io::Error::other)?;
        let path = file_of(dir, &entry.key);
        let temporary = path.with_extension(format!("tmp{}", std::process::id()));
        std::fs::write(&temporary, text)?;
        std::fs::rename(&temporary, &path)
    };
    let _ = write();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_reads_back_bit_for_bit_and_only_under_its_own_key() {
        let dir = std::env::temp_dir().join(format!("flexmbd-cache-{}", std::process::id()));
        let table = ReferenceTable::new(
            "ANCF",
            vec![0.0, 0.1, 0.2],
            vec!["tip".into()],
            vec![vec![0.1 + 0.2, -1e-300, std::f64::consts::PI]],
        )
        .unwrap();
        let margin = Some(vec![SensorError {
            sensor: "tip".into(),
            max_abs: 1.0 / 3.0,
            rms: 2e-7,
        }]);
        let key = key("faithful", &["tip".into()], "(name: \"a\")", "", &[]);
        let entry = Entry::new(&key, &table, ReferenceKind::LargeDeformation, None, margin);
        store(&dir, &entry);
        let read = load(&dir, &key).expect("kept");
        assert_eq!(read.table().unwrap(), table);
        assert_eq!(read.margin, entry.margin);
        assert_eq!(read.kind, ReferenceKind::LargeDeformation);
        let other = key.replace("(name: \"a\")", "(name: \"b\")");
        assert!(load(&dir, &other).is_none());
        // The same file under a colliding name but another key is a miss.
        std::fs::rename(file_of(&dir, &key), file_of(&dir, &other)).unwrap();
        assert!(load(&dir, &other).is_none());
        std::fs::remove_dir_all(&dir).ok();
    }

    /// An FE export written again (another size or time) is another key: the reference of
    /// the old export is not read for the new one.
    #[test]
    fn an_fe_file_written_again_changes_the_key() {
        let dir = std::env::temp_dir().join(format!("flexmbd-cache-fe-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let export = dir.join("part_STIF1.mtx");
        std::fs::write(&export, "1 1 1.0\n").unwrap();
        let keyed = || {
            key(
                "faithful",
                &["tip".into()],
                "(name: \"a\")",
                "",
                std::slice::from_ref(&export),
            )
        };
        let before = keyed();
        assert_eq!(before, keyed());
        assert!(before.contains("part_STIF1.mtx: 8 bytes"), "{before}");
        std::fs::write(&export, "1 1 2.50\n").unwrap();
        assert_ne!(keyed(), before);
        std::fs::remove_dir_all(&dir).ok();
    }
}
