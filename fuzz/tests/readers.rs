//! The reader targets end to end: a panicking target reported with its message and
//! location, a reader execution over the cap recorded as a hang with a reproducer
//! directory that reads back, and a short reader campaign through the real workers —
//! clean, and the same outcomes whatever the number of workers.

use std::path::PathBuf;
use std::time::Duration;

use flexmbd_fuzz::campaign::{self, Corpus, Plan};
use flexmbd_fuzz::execute::{Class, Outcome};
use flexmbd_fuzz::findings::Tally;
use flexmbd_fuzz::readers::corpus::{default_import_data_dir, load_reader_corpus};
use flexmbd_fuzz::readers::mutate::reader_mutant;
use flexmbd_fuzz::readers::reproducer::read_reader_reproducer;
use flexmbd_fuzz::supervise::{Supervisor, WorkerConfig};
use flexmbd_fuzz::worker::{self, Request};

fn config(timeout: Duration) -> WorkerConfig {
    WorkerConfig {
        program: env!("CARGO_BIN_EXE_flexmbd-fuzz").into(),
        memory_mib: 2048,
        max_steps: 2,
        timeout,
        directory: None,
    }
}

fn temp_dir(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("flexmbd-fuzz-{name}-{}", std::process::id()))
}

fn reader_corpus() -> Corpus {
    Corpus::Readers(load_reader_corpus(&default_import_data_dir()).unwrap())
}

/// The worker's guard around a target: a target that panics (as a reader with a
/// defect would) is a `panic` outcome naming the message and where it was raised.
#[test]
fn a_panicking_target_is_reported_with_its_message_and_location() {
    let previous = std::panic::take_hook();
    worker::install_panic_hook();
    let outcome = worker::catch(|| -> Outcome { panic!("a deliberate reader defect") });
    let clean = worker::catch(|| Outcome::new(Class::Refused, "bar_K.mtx:3: size"));
    std::panic::set_hook(previous);
    assert_eq!(outcome.class, Class::Panic);
    assert!(outcome.class.is_defect());
    assert!(
        outcome.detail.contains("a deliberate reader defect")
            && outcome.detail.contains("tests/readers.rs"),
        "{}",
        outcome.detail
    );
    assert_eq!(clean.class, Class::Refused);
}

/// A reader execution that gives no outcome within the cap is a hang (the worker is
/// killed); its reproducer is a directory that reads back as the input that ran.
#[test]
fn a_reader_execution_over_the_cap_is_a_hang_with_a_reproducer_directory() {
    let Corpus::Readers(seeds) = reader_corpus() else {
        unreachable!()
    };
    let mutant = reader_mutant(&seeds, 5, 0);
    // No reader answers within a nanosecond: the reply cannot have arrived.
    let mut s = Supervisor::new(config(Duration::from_nanos(1)));
    let outcome = s.run(&Request::Reader(mutant.input.clone()));
    assert_eq!(outcome.class, Class::Hang, "{}", outcome.detail);
    let dir = temp_dir("reader-hang");
    let mut tally = Tally::default();
    tally.record(&mutant, (5, 0, 0), &outcome, &dir).unwrap();
    let (_, kept) = tally.signatures.values().next().unwrap();
    assert_eq!(read_reader_reproducer(&kept[0].path).unwrap(), mutant.input);
    std::fs::remove_dir_all(&dir).unwrap();
    // The next execution gets a new worker and the seed reads cleanly.
    let mut s = Supervisor::new(config(Duration::from_secs(60)));
    let seed = seeds[0].clone();
    let input = flexmbd_fuzz::readers::ReaderInput::new(seed.reader, seed.files, None).unwrap();
    let ok = s.run(&Request::Reader(input));
    assert_eq!(ok.class, Class::Ok, "{}", ok.detail);
}

/// A short reader campaign, through the real workers, reports no defect, and gives
/// the same outcomes with one worker as with two (the mutants depend on the seed and
/// the index only). Seed 1: its first 400 mutants do not reach the non-finite
/// reductions found by seed 12 (docs/fuzzing.md, "Defects found in the readers"), which
/// a campaign must report, not this test.
#[test]
fn a_short_reader_campaign_runs_clean_and_deterministically() {
    let corpus = reader_corpus();
    let run = |workers: usize| {
        let findings = temp_dir(&format!("reader-campaign-{workers}"));
        let log = findings.with_extension("tsv");
        let plan = Plan {
            seed: 1,
            executions: Some(400),
            seconds: None,
            workers,
            worker: config(Duration::from_secs(60)),
            findings: findings.clone(),
            log: Some(log.clone()),
        };
        let report = campaign::run(&plan, &corpus, Duration::from_secs(600)).unwrap();
        let mut lines: Vec<String> = std::fs::read_to_string(&log)
            .unwrap()
            .lines()
            .map(|l| {
                // index, reader, milliseconds, class, detail: all but the time.
                let f: Vec<&str> = l.splitn(5, '\t').collect();
                format!("{}\t{}\t{}\t{}", f[0], f[1], f[3], f[4])
            })
            .collect();
        lines.sort();
        std::fs::remove_file(&log).unwrap();
        let _ = std::fs::remove_dir_all(&findings);
        (report, lines)
    };
    let (two, two_lines) = run(2);
    assert_eq!(two.tally.executions(), 400);
    assert_eq!(two.tally.defects(), 0, "{:#?}", two.tally.summary());
    for class in [Class::Refused, Class::Ok] {
        assert!(
            two.tally.counts.get(&class).is_some_and(|&n| n > 20),
            "{class:?}"
        );
    }
    assert!(
        two_lines.iter().any(|l| l.contains("reduction: ")),
        "no mutant was reduced"
    );
    let (one, one_lines) = run(1);
    assert_eq!(one.tally.counts, two.tally.counts);
    assert_eq!(one_lines, two_lines);
}
