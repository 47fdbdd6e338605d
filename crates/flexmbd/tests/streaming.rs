//! Runs through a `RowSink`: the rows streamed are `run`'s rows, a stop flag ends the run
//! between two steps with status "interrupted" and the rows so far, a streamed run
//! allocates nothing per row, and the sizes a run may take are bounded (steps; the memory
//! of an in-memory `History`) with refusals that state the numbers.

use std::sync::atomic::{AtomicBool, Ordering};

use flexmbd::model::ModelError;
use flexmbd::output::{Discard, History, RowSink};
use flexmbd::simulation::{MAX_STEPS, run, run_into};
use flexmbd::{Error, Simulation};
use flexmbd_test_support::scenes::model;

mod common;
use common::flexible_pendulums;

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

/// A sink that passes each row to `inner`, then to `watch` (which may set a stop flag or
/// count allocations).
struct Watched<S, F> {
    inner: S,
    watch: F,
}

impl<S: RowSink, F: FnMut(&[f64])> RowSink for Watched<S, F> {
    fn header(&mut self, columns: &[String], rows: usize) -> Result<(), Error> {
        self.inner.header(columns, rows)
    }

    fn row(&mut self, values: &[f64]) -> Result<(), Error> {
        self.inner.row(values)?;
        (self.watch)(values);
        Ok(())
    }
}

/// A stop flag set after the 7th row ends the run before the next step: status
/// "interrupted" with the time in its message, the 7 rows equal bit for bit to the first
/// 7 of an uninterrupted run, in both formulations.
#[test]
fn a_stop_flag_interrupts_the_run_between_steps() {
    for scene in flexible_pendulums(0.1, Some(0.01)) {
        let form = scene.solver.formulation;
        let (full, history) = run(&scene, |_| {}).unwrap();
        assert_eq!(full.status, "ok");
        let stop = AtomicBool::new(false);
        let mut rows = 0;
        let mut sink = Watched {
            inner: History::default(),
            watch: |_: &[f64]| {
                rows += 1;
                if rows == 7 {
                    stop.store(true, Ordering::Relaxed);
                }
            },
        };
        let summary = run_into(&scene, &mut sink, &stop, |_| {}).unwrap();
        let kept = sink.inner;
        assert_eq!(summary.status, "interrupted", "{form:?}");
        assert_eq!(summary.rows, 7);
        assert_eq!(kept.header, history.header);
        assert_eq!(kept.rows, history.rows[..7], "{form:?}");
        let t = kept.rows[6][0];
        assert_eq!(summary.simulated_seconds.to_bits(), t.to_bits(), "{form:?}");
        let message = summary.message.unwrap();
        assert!(message.contains(&format!("t = {t} s")), "{message}");
        assert!(summary.failed_at.is_none());
    }
}

/// The streaming loop adds no allocation to the steps': between two rows (one step each),
/// nothing is allocated once the first steps have sized everything (counted from the 4th
/// row on, the steps, the sensors and the sink included).
#[test]
fn a_streamed_run_allocates_nothing_per_row() {
    for scene in flexible_pendulums(0.03, None) {
        let (mut last, mut rows, mut most) = (0, 0, 0);
        let mut sink = Watched {
            inner: Discard,
            watch: |_: &[f64]| {
                let now = flexmbd_test_support::allocations();
                if rows >= 3 {
                    most = most.max(now - last);
                }
                rows += 1;
                last = now;
            },
        };
        let summary = run_into(&scene, &mut sink, &AtomicBool::new(false), |_| {}).unwrap();
        assert_eq!(summary.status, "ok");
        assert_eq!(rows, 31);
        let form = scene.solver.formulation;
        assert_eq!(most, 0, "{form:?}: allocations between two rows");
    }
}

/// Issue 12: `--duration 1e17` panicked with "capacity overflow" (the history was
/// pre-allocated for 10²⁰ steps). A run of more than MAX_STEPS steps is refused when the
/// scene is compiled, naming solver.duration, the number of steps and the limit.
#[test]
fn duration_1e17_is_refused_not_a_panic() {
    let mut scene = model("double_four_bar.ron");
    scene.solver.duration = 1e17;
    let refusal = |e: Error| {
        let Error::Model(model) = e else {
            panic!("not a refusal of the scene: {e}")
        };
        let ModelError::Invalid { error, .. } = *model else {
            panic!("not a refusal of solver.duration: {model}")
        };
        assert_eq!(error.field, "solver.duration");
        let text = error.to_string();
        assert!(
            text.contains("1e20 steps") && text.contains(&MAX_STEPS.to_string()),
            "{text}"
        );
    };
    refusal(Simulation::new(&scene).err().expect("refused"));
    refusal(run(&scene, |_| {}).expect_err("refused"));
    refusal(run_into(&scene, &mut Discard, &AtomicBool::new(false), |_| {}).expect_err("refused"));
}

/// Issue 12: `--duration 1e8` aborted trying to allocate 240 GB. A run within MAX_STEPS
/// whose in-memory history would exceed 4 GiB is refused before its first step, with rows ×
/// columns × 8 bytes stated; streamed, the same run starts (stopped here at once).
#[test]
fn history_over_the_memory_limit_is_refused_with_its_size() {
    let mut scene = model("double_four_bar.ron");
    scene.solver.duration = 2e5; // 2·10⁸ steps, a row each: 2·10⁸ × 4 × 8 B = 6.4 GB
    scene.solver.output_interval = None;
    match run(&scene, |_| {}) {
        Err(Error::HistoryTooLarge {
            rows,
            columns,
            bytes,
        }) => {
            assert_eq!((rows, columns), (200_000_002, 4));
            assert_eq!(bytes, 200_000_002 * 4 * 8);
        }
        other => panic!("not refused: {:?}", other.map(|(s, _)| s.status)),
    }
    let summary = run_into(&scene, &mut Discard, &AtomicBool::new(true), |_| {}).unwrap();
    assert_eq!(summary.status, "interrupted");
    assert_eq!((summary.steps, summary.rows), (0, 1));
}

/// Issue 12: the duration was rounded to whole steps without notice. A duration that is
/// not a whole number of steps, or an output interval likewise, is run as before but
/// named in the summary's warnings with the rounded values; whole ones give no warning.
#[test]
fn rounding_to_whole_steps_is_warned() {
    let mut scene = model("double_four_bar.ron");
    scene.solver.duration = 0.02;
    let (summary, _) = run(&scene, |_| {}).unwrap();
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    scene.solver.duration = 0.0206;
    scene.solver.output_interval = Some(0.0104);
    let (summary, history) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok");
    assert_eq!(summary.steps, 21);
    assert_eq!(history.rows.len(), 4, "t = 0, 0.01, 0.02 and the last step");
    assert_eq!(
        summary.warnings,
        [
            "solver.duration 0.0206 s is not a whole number of 0.001 s steps: the run is 21 steps, to t = 0.021 s",
            "solver.output_interval 0.0104 s is not a whole number of 0.001 s steps: a row every 10 steps (0.01 s)",
        ]
    );
}

/// Issue 26 item 5: a step far too large for the motion (the flexible pendulum at h = 2 s)
/// used to be accepted at the iteration limit — no constraints, so ‖Φ‖ = 0 — with tip
/// positions of 1e146 and an infinite energy, written as a row. The iterate is accepted only
/// when the last correction is small too, so the run fails at the first step, with its time
/// and the correction's size, and keeps the rows before it (the start).
#[test]
fn a_step_whose_newton_iteration_wanders_off_fails_the_run() {
    use flexmbd::model::FormulationKind;
    for f in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut scene = model("flexible_pendulum.ron");
        scene.solver.step = 2.0;
        scene.solver.duration = 4.0;
        scene.solver.formulation = f;
        let (summary, history) = run(&scene, |_| {}).unwrap();
        assert_eq!(summary.status, "failed", "{f:?}");
        assert_eq!(summary.failed_at, Some(2.0), "{f:?}");
        assert_eq!(summary.accepted_unconverged, 0, "{f:?}");
        let message = summary.message.unwrap();
        assert!(message.contains("did not converge"), "{f:?}: {message}");
        assert_eq!(history.rows.len(), 1, "{f:?}: only the start is kept");
        assert!(history.rows[0].iter().all(|v| v.is_finite()));
    }
}

/// Issue 12: a run whose steps were accepted unconverged reported a plain "ok". With one
/// Newton iteration per step, the four-bar accepts steps at the iteration limit: the status
/// stays "ok" (‖Φ‖ was small) and a warning counts them.
#[test]
fn steps_accepted_unconverged_are_warned() {
    let mut scene = model("double_four_bar.ron");
    scene.solver.duration = 0.2;
    let (summary, _) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.accepted_unconverged, 0);
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    scene.solver.max_iterations = 1;
    let (summary, _) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok");
    let n = summary.accepted_unconverged;
    assert!(n > 0);
    assert_eq!(
        summary.warnings,
        [format!(
            "{n} of 200 steps accepted at the iteration limit (‖Φ‖ small, residual not converged)"
        )]
    );
}
