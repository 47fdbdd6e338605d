//! Ctrl-C during a long call. Rust runs with the GIL released, so Python's signal handlers
//! (KeyboardInterrupt for SIGINT) would only run once it returns. So the calling thread
//! waits for the worker's answer in slices of [`POLL`], running the handlers between two;
//! the first exception one raises asks the worker to stop between two steps, and is raised
//! once the worker has answered (its answer, the rows or the state so far, is kept).

use std::sync::Mutex;
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::Duration;

use pyo3::prelude::*;

/// How long the GIL stays released between two looks at the signal handlers.
const POLL: Duration = Duration::from_millis(50);

/// Wait for the worker's answer on `answers`, the GIL released. The first exception a signal
/// handler raises calls `stop` and is returned beside the answer; `None` for the answer:
/// the worker ended without one.
pub(crate) fn wait_for_answer<T: Send>(
    py: Python<'_>,
    answers: &Mutex<Receiver<T>>,
    stop: impl Fn(),
) -> (Option<T>, Option<PyErr>) {
    let mut raised = None;
    loop {
        let polled = py.detach(|| match answers.lock() {
            Ok(answers) => answers.recv_timeout(POLL),
            Err(_) => Err(RecvTimeoutError::Disconnected),
        });
        match polled {
            Ok(answer) => return (Some(answer), raised),
            Err(RecvTimeoutError::Disconnected) => return (None, raised),
            Err(RecvTimeoutError::Timeout) => {
                if raised.is_none()
                    && let Err(e) = py.check_signals()
                {
                    stop();
                    raised = Some(e);
                }
            }
        }
    }
}
