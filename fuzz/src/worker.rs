//! The worker: the same program started with `--worker`, under a memory cap, reading
//! executions from stdin and writing one outcome line each on stdout. A panic is caught
//! and reported as an outcome (a silent hook keeps its message and location); a hang, an
//! abort or a crash ends the worker, which the supervisor sees ([`crate::supervise`]).
//!
//! Protocol. Request: one byte (0 absolute, 1 relative), the text's length as a
//! little-endian `u32`, the UTF-8 text. Reply: `CLASS<TAB>DETAIL<NEWLINE>`.

use std::io::{self, BufWriter, Read, Write};
use std::panic::{self, AssertUnwindSafe};
use std::sync::Mutex;

use flexmbd::model::FormulationKind;

use crate::execute::{Class, Outcome, execute};

/// The last panic's message and location, kept by the silent hook.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Write one request.
pub fn write_request(
    out: &mut impl Write,
    formulation: FormulationKind,
    text: &str,
) -> io::Result<()> {
    let tag = match formulation {
        FormulationKind::Absolute => 0u8,
        FormulationKind::Relative => 1u8,
    };
    let len = u32::try_from(text.len()).map_err(|_| io::Error::other("mutant over 4 GiB"))?;
    out.write_all(&[tag])?;
    out.write_all(&len.to_le_bytes())?;
    out.write_all(text.as_bytes())?;
    out.flush()
}

/// Read one request; `None` at the end of the input.
pub fn read_request(input: &mut impl Read) -> io::Result<Option<(FormulationKind, String)>> {
    let mut tag = [0u8; 1];
    match input.read_exact(&mut tag) {
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => return Ok(None),
        r => r?,
    }
    let formulation = match tag[0] {
        0 => FormulationKind::Absolute,
        1 => FormulationKind::Relative,
        t => return Err(io::Error::other(format!("unknown formulation tag {t}"))),
    };
    let mut len = [0u8; 4];
    input.read_exact(&mut len)?;
    let mut text = vec![0u8; u32::from_le_bytes(len) as usize];
    input.read_exact(&mut text)?;
    let text = String::from_utf8(text).map_err(|e| io::Error::other(e.to_string()))?;
    Ok(Some((formulation, text)))
}

/// The reply line of an outcome.
pub fn reply_line(o: &Outcome) -> String {
    format!("{}\t{}\n", o.class.name(), o.detail)
}

/// Parse a reply line (without its newline).
pub fn parse_reply(line: &str) -> Option<Outcome> {
    let (class, detail) = line.split_once('\t')?;
    Some(Outcome::new(Class::from_name(class)?, detail))
}

/// The worker's main loop: cap the address space at `memory_mib` MiB, then serve requests
/// until stdin closes.
pub fn serve(memory_mib: u64, max_steps: usize) -> io::Result<()> {
    cap_address_space(memory_mib)?;
    panic::set_hook(Box::new(|info| {
        let location = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let payload = info.payload();
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "(non-text payload)".to_string());
        *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) =
            Some(format!("panicked{location}: {message}"));
    }));
    let mut input = io::stdin().lock();
    let mut output = BufWriter::new(io::stdout().lock());
    while let Some((formulation, text)) = read_request(&mut input)? {
        let outcome = run_caught(&text, formulation, max_steps);
        output.write_all(reply_line(&outcome).as_bytes())?;
        output.flush()?;
    }
    Ok(())
}

/// [`execute`] with its panic caught and turned into an outcome.
pub fn run_caught(text: &str, formulation: FormulationKind, max_steps: usize) -> Outcome {
    match panic::catch_unwind(AssertUnwindSafe(|| execute(text, formulation, max_steps))) {
        Ok(outcome) => outcome,
        Err(_) => {
            let message = LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()).take();
            Outcome::new(
                Class::Panic,
                message.unwrap_or_else(|| "panicked".to_string()),
            )
        }
    }
}

/// Limit this process's address space (RLIMIT_AS) to `mib` MiB: an allocation beyond it
/// fails, and Rust aborts with "memory allocation of N bytes failed".
#[allow(unsafe_code)]
fn cap_address_space(mib: u64) -> io::Result<()> {
    let bytes = mib.saturating_mul(1 << 20) as libc::rlim_t;
    let limit = libc::rlimit {
        rlim_cur: bytes,
        rlim_max: bytes,
    };
    // SAFETY: setrlimit reads the struct we pass by pointer and nothing else; the struct
    // lives on the stack for the duration of the call.
    let status = unsafe { libc::setrlimit(libc::RLIMIT_AS, &limit) };
    if status == 0 {
        Ok(())
    } else {
        Err(io::Error::last_os_error())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_round_trip_and_end_cleanly() {
        let mut buf = Vec::new();
        write_request(&mut buf, FormulationKind::Relative, "(a: \"ρ\")").unwrap();
        write_request(&mut buf, FormulationKind::Absolute, "").unwrap();
        let mut r = buf.as_slice();
        assert_eq!(
            read_request(&mut r).unwrap(),
            Some((FormulationKind::Relative, "(a: \"ρ\")".to_string()))
        );
        assert_eq!(
            read_request(&mut r).unwrap(),
            Some((FormulationKind::Absolute, String::new()))
        );
        assert_eq!(read_request(&mut r).unwrap(), None);
    }

    #[test]
    fn replies_round_trip_with_multiline_details_folded() {
        let o = Outcome::new(Class::Panic, "panicked at a.rs:1: x\ny");
        let line = reply_line(&o);
        assert_eq!(parse_reply(line.trim_end_matches('\n')), Some(o));
    }
}
