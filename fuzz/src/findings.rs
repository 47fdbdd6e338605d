//! Findings: the tally of a campaign, the reproducers of its defects ([`Reproducer`]) —
//! for a scene, a file `<class>-<formulation>-<hash>.ron`: the mutant exactly as it ran,
//! so that its line numbers are those of the errors and of the mutations, then a newline
//! and a footer of `// fuzz:` comment lines; for a reader, a directory
//! ([`crate::readers::reproducer`]) — and how a scene reproducer is read back for
//! `--replay`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use flexmbd::model::FormulationKind;

use crate::execute::{CLASSES, Class, Outcome, formulation_from_name, formulation_name};
use crate::mutate::Mutant;
use crate::rng::fnv1a;

/// The prefix of a reproducer's footer lines.
const FOOTER: &str = "// fuzz: ";

/// What starts the footer: a newline (added after the mutant) and the formulation line.
const FOOTER_START: &str = "\n// fuzz: formulation=";

/// What a defect's reproducer is made from: one execution of a campaign.
pub trait Reproducer {
    /// What signatures and file names call the execution: the formulation of a scene,
    /// the entry point of a reader.
    fn label(&self) -> String;
    /// Where its reproducer goes in `dir`: named after `class`, the label and a hash of
    /// the input, so the same input found twice is one reproducer.
    fn path(&self, dir: &Path, class: Class) -> PathBuf;
    /// Write the reproducer to `path`; `context` says which campaign and mutant it is.
    fn write(&self, path: &Path, outcome: &Outcome, context: &str) -> std::io::Result<()>;
}

/// A scene mutant run in one formulation.
#[derive(Clone, Debug)]
pub struct SceneExecution {
    /// The mutant.
    pub mutant: Mutant,
    /// The formulation it ran in.
    pub formulation: FormulationKind,
}

impl Reproducer for SceneExecution {
    fn label(&self) -> String {
        formulation_name(self.formulation).to_string()
    }

    fn path(&self, dir: &Path, class: Class) -> PathBuf {
        reproducer_path(dir, &self.mutant, self.formulation, class)
    }

    fn write(&self, path: &Path, outcome: &Outcome, context: &str) -> std::io::Result<()> {
        write_reproducer(path, &self.mutant, self.formulation, outcome, context)
    }
}

/// The reproducers kept per signature (a defect seen more often is still counted).
pub const FILES_PER_SIGNATURE: usize = 3;

/// A reproducer kept for a signature: the execution it records and its file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Kept {
    /// The mutant's index and the formulation's rank: the smallest are kept, so the
    /// files a campaign leaves do not depend on which worker finished first.
    pub order: (u64, usize),
    /// The file.
    pub path: PathBuf,
}

/// The tally of a campaign.
#[derive(Debug, Default)]
pub struct Tally {
    /// Executions per class.
    pub counts: BTreeMap<Class, u64>,
    /// Defects per signature (class, formulation, detail with its numbers blanked), with
    /// the reproducers kept for it.
    pub signatures: BTreeMap<String, (u64, Vec<Kept>)>,
}

impl Tally {
    /// All executions.
    pub fn executions(&self) -> u64 {
        self.counts.values().sum()
    }

    /// The defects.
    pub fn defects(&self) -> u64 {
        self.counts
            .iter()
            .filter(|(c, _)| c.is_defect())
            .map(|(_, n)| n)
            .sum()
    }

    /// Count the outcome of `execution`, mutant `index` of campaign `seed`, `rank` its
    /// place among the executions of that mutant (the formulation's); for a defect, keep
    /// its reproducer in `dir` if it is among the [`FILES_PER_SIGNATURE`] first
    /// executions (by index and rank) of its signature, removing the one it displaces.
    pub fn record(
        &mut self,
        execution: &dyn Reproducer,
        (seed, index, rank): (u64, u64, usize),
        outcome: &Outcome,
        dir: &Path,
    ) -> std::io::Result<()> {
        *self.counts.entry(outcome.class).or_default() += 1;
        if !outcome.class.is_defect() {
            return Ok(());
        }
        let (count, kept) = self
            .signatures
            .entry(signature(&execution.label(), outcome))
            .or_default();
        *count += 1;
        let order = (index, rank);
        let last = kept
            .iter()
            .enumerate()
            .max_by_key(|(_, k)| k.order)
            .map(|(i, k)| (i, k.order));
        let path = execution.path(dir, outcome.class);
        let room = kept.len() < FILES_PER_SIGNATURE || last.is_some_and(|(_, o)| order < o);
        if !room || kept.iter().any(|k| k.path == path) {
            return Ok(());
        }
        if kept.len() == FILES_PER_SIGNATURE
            && let Some((i, _)) = last
        {
            remove_reproducer(&kept.remove(i).path)?;
        }
        let context = format!("seed {seed}, mutant {index}");
        execution.write(&path, outcome, &context)?;
        kept.push(Kept { order, path });
        Ok(())
    }

    /// The summary lines: counts per class, then the defects by signature.
    pub fn summary(&self) -> Vec<String> {
        let counts: Vec<String> = CLASSES
            .iter()
            .map(|c| format!("{} {}", c.name(), self.counts.get(c).copied().unwrap_or(0)))
            .collect();
        let mut lines = vec![format!("outcomes: {}", counts.join(", "))];
        let mut by_count: Vec<_> = self.signatures.iter().collect();
        by_count.sort_by(|a, b| b.1.0.cmp(&a.1.0).then(a.0.cmp(b.0)));
        for (signature, (count, files)) in by_count {
            lines.push(format!("{count:>7} × {signature}"));
            if let Some(first) = files.iter().min_by_key(|k| k.order) {
                lines.push(format!("          e.g. {}", first.path.display()));
            }
        }
        lines
    }
}

/// A reproducer displaced by an earlier one: a file, or a directory of files.
fn remove_reproducer(path: &Path) -> std::io::Result<()> {
    if path.is_dir() {
        std::fs::remove_dir_all(path)
    } else {
        std::fs::remove_file(path)
    }
}

/// What groups defects: class, label (formulation or reader) and the detail with digits
/// blanked (but a panic's location kept whole).
fn signature(label: &str, outcome: &Outcome) -> String {
    let d = &outcome.detail;
    let (kept, rest) = match d.split_once(": ") {
        Some((location, rest)) if d.starts_with("panicked at ") => (location, rest),
        _ => ("", d.as_str()),
    };
    let blanked: String = rest
        .chars()
        .map(|c| if c.is_ascii_digit() { '#' } else { c })
        .take(140)
        .collect();
    let separator = if kept.is_empty() { "" } else { ": " };
    format!(
        "{} {label}: {kept}{separator}{blanked}",
        outcome.class.name()
    )
}

/// The file of a reproducer: its class, formulation and a hash of its text, so the same
/// mutant found twice is one file.
fn reproducer_path(
    dir: &Path,
    mutant: &Mutant,
    formulation: FormulationKind,
    class: Class,
) -> PathBuf {
    let f = formulation_name(formulation);
    let hash = fnv1a(format!("{f}\n{}", mutant.text).as_bytes());
    dir.join(format!("{}-{f}-{hash:016x}.ron", class.name()))
}

/// Write the reproducer of a defect to `path`: the mutant, then the footer.
fn write_reproducer(
    path: &Path,
    mutant: &Mutant,
    formulation: FormulationKind,
    outcome: &Outcome,
    context: &str,
) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let f = formulation_name(formulation);
    let mut text = mutant.text.clone();
    text.push_str(&format!("{FOOTER_START}{f}\n"));
    text.push_str(&format!(
        "{FOOTER}class={} detail={}\n",
        outcome.class.name(),
        outcome.detail
    ));
    text.push_str(&format!("{FOOTER}from {} ({context})\n", mutant.seed_scene));
    for m in &mutant.mutations {
        text.push_str(&format!("{FOOTER}mutation: {m}\n"));
    }
    text.push_str(&format!(
        "{FOOTER}replay: flexmbd-fuzz --replay {}\n",
        path.display()
    ));
    text.push_str(&format!(
        "{FOOTER}or: flexmbd simulate {} --formulation {f}\n",
        path.display()
    ));
    std::fs::write(path, text)
}

/// A reproducer read back: the formulation its footer names and the mutant's text (the
/// footer removed); a file without a footer is all mutant, of no formulation.
pub fn read_reproducer(text: &str) -> (Option<FormulationKind>, &str) {
    match text.rfind(FOOTER_START) {
        Some(at) => {
            let name = text[at + FOOTER_START.len()..].lines().next().unwrap_or("");
            (formulation_from_name(name.trim()), &text[..at])
        }
        None => (None, text),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("flexmbd-fuzz-{name}-{}", std::process::id()))
    }

    fn mutant(text: &str) -> Mutant {
        Mutant {
            seed_scene: "models/x.ron".into(),
            text: text.into(),
            mutations: vec!["line 1: `1` -> `NaN`".into()],
        }
    }

    #[test]
    fn a_reproducer_reads_back_as_the_mutant_and_its_formulation() {
        let dir = temp_dir("read-back");
        let mutant = mutant("// a comment\n(name: \"x\"");
        let outcome = Outcome::new(Class::Panic, "panicked at a.rs:3: boom");
        let mut tally = Tally::default();
        let relative = FormulationKind::Relative;
        let execution = SceneExecution {
            mutant: mutant.clone(),
            formulation: relative,
        };
        tally.record(&execution, (1, 2, 1), &outcome, &dir).unwrap();
        let (_, kept) = tally.signatures.values().next().unwrap();
        let name = kept[0]
            .path
            .file_name()
            .unwrap()
            .to_str()
            .unwrap()
            .to_string();
        assert!(name.starts_with("panic-relative-"), "{name}");
        let written = std::fs::read_to_string(&kept[0].path).unwrap();
        assert!(
            written.starts_with(&mutant.text),
            "the mutant keeps its line numbers"
        );
        assert!(written.contains("(seed 1, mutant 2)"), "{written}");
        assert_eq!(
            read_reproducer(&written),
            (Some(relative), mutant.text.as_str())
        );
        assert_eq!(read_reproducer("(a: 1)\n"), (None, "(a: 1)\n"));
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!((tally.executions(), tally.defects()), (1, 1));
    }

    #[test]
    fn the_files_kept_are_the_earliest_executions_whatever_the_arrival_order() {
        let outcome = Outcome::new(Class::Hang, "no outcome within 5 s (worker killed)");
        let f = FormulationKind::Absolute;
        let mut left = Vec::new();
        for (run, arrival) in [[5u64, 1, 4, 2, 3, 0], [0, 1, 2, 3, 4, 5]]
            .iter()
            .enumerate()
        {
            let dir = temp_dir(&format!("order-{run}"));
            let mut tally = Tally::default();
            for &index in arrival {
                let execution = SceneExecution {
                    mutant: mutant(&format!("mutant {index}")),
                    formulation: f,
                };
                tally
                    .record(&execution, (1, index, f as usize), &outcome, &dir)
                    .unwrap();
            }
            let mut files: Vec<String> = std::fs::read_dir(&dir)
                .unwrap()
                .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap())
                .map(|text| read_reproducer(&text).1.to_string())
                .collect();
            files.sort();
            std::fs::remove_dir_all(&dir).unwrap();
            assert_eq!(tally.signatures.values().next().unwrap().0, 6);
            left.push(files);
        }
        assert_eq!(left[0], ["mutant 0", "mutant 1", "mutant 2"]);
        assert_eq!(left[0], left[1]);
    }

    #[test]
    fn defects_differing_only_in_numbers_share_a_signature() {
        let a = Outcome::new(Class::Panic, "panicked at a.rs:3: index 5 out of range");
        let b = Outcome::new(Class::Panic, "panicked at a.rs:3: index 7 out of range");
        assert_eq!(signature("absolute", &a), signature("absolute", &b));
        assert_ne!(signature("absolute", &a), signature("relative", &a));
        let elsewhere = Outcome::new(Class::Panic, "panicked at a.rs:4: index 5 out of range");
        assert_ne!(signature("absolute", &a), signature("absolute", &elsewhere));
    }
}
