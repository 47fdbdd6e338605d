//! The reproducer of a reader defect: a directory `<class>-<reader>-<hash>/` holding the
//! files exactly as they ran, under their names, and `fuzz.txt`: the reader, the
//! reduction, the files in argument order, then the outcome, the seed and mutations, the
//! call and the replay command, one `key=value` or `key: value` line each.
//! `flexmbd-fuzz --replay DIR` reads it back ([`read_reader_reproducer`]).

use std::path::{Path, PathBuf};

use super::execute::reduction_spec;
use super::mutate::ReaderMutant;
use super::{Reader, ReaderFile, ReaderInput, Reduction};
use crate::execute::{Class, Outcome};
use crate::findings::Reproducer;
use crate::rng::fnv1a;

/// The manifest's name in a reproducer directory.
pub const MANIFEST: &str = "fuzz.txt";

impl Reproducer for ReaderMutant {
    fn label(&self) -> String {
        self.input.reader.name().to_string()
    }

    fn path(&self, dir: &Path, class: Class) -> PathBuf {
        let mut bytes = self.label().into_bytes();
        bytes.extend(reduction_name(self.input.reduction).bytes());
        for f in &self.input.files {
            bytes.extend(format!("\n{}\n{}", f.name, f.text).bytes());
        }
        let hash = fnv1a(&bytes);
        dir.join(format!("{}-{}-{hash:016x}", class.name(), self.label()))
    }

    fn write(&self, path: &Path, outcome: &Outcome, context: &str) -> std::io::Result<()> {
        std::fs::create_dir_all(path)?;
        for f in &self.input.files {
            std::fs::write(path.join(&f.name), &f.text)?;
        }
        std::fs::write(path.join(MANIFEST), self.manifest(path, outcome, context))
    }
}

impl ReaderMutant {
    /// The manifest of its reproducer at `path`.
    fn manifest(&self, path: &Path, outcome: &Outcome, context: &str) -> String {
        let input = &self.input;
        let names: Vec<&str> = input.files.iter().map(|f| f.name.as_str()).collect();
        let mut m = format!(
            "reader={}\nreduction={}\nfiles={}\n",
            input.reader.name(),
            reduction_name(input.reduction),
            names.join(" ")
        );
        m.push_str(&format!(
            "class={} detail={}\n",
            outcome.class.name(),
            outcome.detail
        ));
        m.push_str(&format!("from: {} ({context})\n", self.seed));
        for what in &self.mutations {
            m.push_str(&format!("mutation: {what}\n"));
        }
        let roles = input.reader.roles();
        let args: Vec<String> = roles
            .iter()
            .zip(&names)
            .map(|(role, name)| format!("{role} = {name}"))
            .collect();
        m.push_str(&format!(
            "call: {} with {}\n",
            input.reader.call(),
            args.join(", ")
        ));
        if let Some(r) = input.reduction {
            m.push_str(&format!(
                "then: flexmbd_fe::imported::reduce_imported(&spec, &model, \"bar\") with spec = {:?}\n",
                reduction_spec(r)
            ));
        }
        m.push_str(&format!(
            "replay: flexmbd-fuzz --replay {}\n",
            path.display()
        ));
        m
    }
}

/// The manifest's name of a reduction.
fn reduction_name(r: Option<Reduction>) -> &'static str {
    r.map_or("none", Reduction::name)
}

/// The input a reproducer directory records.
pub fn read_reader_reproducer(dir: &Path) -> Result<ReaderInput, String> {
    let manifest_path = dir.join(MANIFEST);
    let manifest = std::fs::read_to_string(&manifest_path)
        .map_err(|e| format!("cannot read {}: {e}", manifest_path.display()))?;
    let value = |key: &str| {
        manifest
            .lines()
            .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
            .ok_or_else(|| format!("{}: no `{key}=` line", manifest_path.display()))
    };
    let reader_name = value("reader")?;
    let reader = Reader::from_name(reader_name).ok_or_else(|| {
        format!(
            "{}: unknown reader `{reader_name}`",
            manifest_path.display()
        )
    })?;
    let reduction_name = value("reduction")?;
    let reduction = Reduction::from_name(reduction_name).ok_or_else(|| {
        format!(
            "{}: unknown reduction `{reduction_name}`",
            manifest_path.display()
        )
    })?;
    let files = value("files")?
        .split_whitespace()
        .map(|name| {
            let path = dir.join(name);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            Ok(ReaderFile {
                name: name.to_string(),
                text,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    ReaderInput::new(reader, files, reduction)
        .map_err(|e| format!("{}: {e}", manifest_path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::findings::Tally;
    use crate::readers::corpus::{default_import_data_dir, load_reader_corpus};
    use crate::readers::mutate::reader_mutant;

    #[test]
    fn a_reproducer_directory_reads_back_as_the_input() {
        let corpus = load_reader_corpus(&default_import_data_dir()).unwrap();
        let dir = std::env::temp_dir().join(format!("flexmbd-fuzz-readers-{}", std::process::id()));
        let mutant = (0..)
            .map(|i| reader_mutant(&corpus, 3, i))
            .find(|m| m.input.reduction.is_some())
            .unwrap();
        let outcome = Outcome::new(Class::Panic, "panicked at a.rs:1: boom");
        let mut tally = Tally::default();
        tally.record(&mutant, (3, 0, 0), &outcome, &dir).unwrap();
        let (_, kept) = tally.signatures.values().next().unwrap();
        let name = kept[0]
            .path
            .file_name()
            .unwrap()
            .to_string_lossy()
            .into_owned();
        assert!(
            name.starts_with(&format!("panic-{}-", mutant.input.reader.name())),
            "{name}"
        );
        assert_eq!(read_reader_reproducer(&kept[0].path).unwrap(), mutant.input);
        let manifest = std::fs::read_to_string(kept[0].path.join(MANIFEST)).unwrap();
        assert!(
            manifest.contains("call: flexmbd_fe::import::parse_"),
            "{manifest}"
        );
        assert!(
            manifest.contains("then: flexmbd_fe::imported::reduce_imported"),
            "{manifest}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
