//! The worker: the same program started with `--worker`, under a memory cap, reading
//! executions from stdin and writing one outcome line each on stdout. A panic is caught
//! and reported as an outcome (a silent hook keeps its message and location); a hang, an
//! abort or a crash ends the worker, which the supervisor sees ([`crate::supervise`]).
//!
//! Protocol. A scene request: one byte (0 absolute, 1 relative), the text's length as a
//! little-endian `u32`, the UTF-8 text. A reader request: the byte 2, the reader's tag,
//! the reduction (0 none, 1 clamped, 2 free-free), the number of files, then each file's
//! name and text, each a `u32` length and UTF-8. Reply: `CLASS<TAB>DETAIL<NEWLINE>`.

use std::io::{self, BufWriter, Read, Write};
use std::panic::{self, AssertUnwindSafe};
use std::sync::Mutex;

use flexmbd::model::FormulationKind;

use crate::execute::{Class, Outcome, execute};
use crate::readers::execute::execute_reader;
use crate::readers::{Reader, ReaderFile, ReaderInput, Reduction};

/// The tag of a reader request (0 and 1 are the scene's formulations).
const READER_TAG: u8 = 2;

/// What a worker runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Request {
    /// A scene in a formulation.
    Scene {
        /// The formulation.
        formulation: FormulationKind,
        /// The scene's text.
        text: String,
    },
    /// A reader execution.
    Reader(ReaderInput),
}

/// The last panic's message and location, kept by the silent hook.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Write one scene request.
pub fn write_request(
    out: &mut impl Write,
    formulation: FormulationKind,
    text: &str,
) -> io::Result<()> {
    let tag = match formulation {
        FormulationKind::Absolute => 0u8,
        FormulationKind::Relative => 1u8,
    };
    out.write_all(&[tag])?;
    write_text(out, text)?;
    out.flush()
}

/// Write one request of either kind.
pub fn write_any_request(out: &mut impl Write, request: &Request) -> io::Result<()> {
    match request {
        Request::Scene { formulation, text } => write_request(out, *formulation, text),
        Request::Reader(input) => {
            let reduction = match input.reduction {
                None => 0u8,
                Some(Reduction::Clamped) => 1,
                Some(Reduction::FreeFree) => 2,
            };
            let count =
                u8::try_from(input.files.len()).map_err(|_| io::Error::other("over 255 files"))?;
            out.write_all(&[READER_TAG, input.reader.tag(), reduction, count])?;
            for f in &input.files {
                write_text(out, &f.name)?;
                write_text(out, &f.text)?;
            }
            out.flush()
        }
    }
}

/// A text as its length (little-endian `u32`) and its bytes.
fn write_text(out: &mut impl Write, text: &str) -> io::Result<()> {
    let len = u32::try_from(text.len()).map_err(|_| io::Error::other("text over 4 GiB"))?;
    out.write_all(&len.to_le_bytes())?;
    out.write_all(text.as_bytes())
}

/// Read one request; `None` at the end of the input.
pub fn read_request(input: &mut impl Read) -> io::Result<Option<Request>> {
    let mut tag = [0u8; 1];
    match input.read_exact(&mut tag) {
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => return Ok(None),
        r => r?,
    }
    let formulation = match tag[0] {
        0 => FormulationKind::Absolute,
        1 => FormulationKind::Relative,
        READER_TAG => return read_reader_request(input).map(|r| Some(Request::Reader(r))),
        t => return Err(io::Error::other(format!("unknown request tag {t}"))),
    };
    let text = read_text(input)?;
    Ok(Some(Request::Scene { formulation, text }))
}

/// The rest of a reader request, after its tag.
fn read_reader_request(input: &mut impl Read) -> io::Result<ReaderInput> {
    let mut head = [0u8; 3];
    input.read_exact(&mut head)?;
    let [reader, reduction, count] = head;
    let reader = Reader::from_tag(reader)
        .ok_or_else(|| io::Error::other(format!("unknown reader tag {reader}")))?;
    let reduction = match reduction {
        0 => None,
        1 => Some(Reduction::Clamped),
        2 => Some(Reduction::FreeFree),
        r => return Err(io::Error::other(format!("unknown reduction {r}"))),
    };
    let files = (0..count)
        .map(|_| {
            let name = read_text(input)?;
            let text = read_text(input)?;
            Ok(ReaderFile { name, text })
        })
        .collect::<io::Result<Vec<_>>>()?;
    ReaderInput::new(reader, files, reduction).map_err(io::Error::other)
}

/// A text written by [`write_text`].
fn read_text(input: &mut impl Read) -> io::Result<String> {
    let mut len = [0u8; 4];
    input.read_exact(&mut len)?;
    let mut text = vec![0u8; u32::from_le_bytes(len) as usize];
    input.read_exact(&mut text)?;
    String::from_utf8(text).map_err(|e| io::Error::other(e.to_string()))
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
    install_panic_hook();
    let mut input = io::stdin().lock();
    let mut output = BufWriter::new(io::stdout().lock());
    while let Some(request) = read_request(&mut input)? {
        let outcome = run_request(&request, max_steps);
        output.write_all(reply_line(&outcome).as_bytes())?;
        output.flush()?;
    }
    Ok(())
}

/// Replace the panic hook by a silent one that keeps the panic's message and location
/// for [`catch`] (the worker's stderr stays free for an abort's message).
pub fn install_panic_hook() {
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
}

/// Run a request, its panic caught.
pub fn run_request(request: &Request, max_steps: usize) -> Outcome {
    match request {
        Request::Scene { formulation, text } => run_caught(text, *formulation, max_steps),
        Request::Reader(input) => catch(|| execute_reader(input)),
    }
}

/// [`execute`] with its panic caught and turned into an outcome.
pub fn run_caught(text: &str, formulation: FormulationKind, max_steps: usize) -> Outcome {
    catch(|| execute(text, formulation, max_steps))
}

/// `target`'s outcome, or a panic's (with the message and location the hook of
/// [`install_panic_hook`] kept).
pub fn catch(target: impl FnOnce() -> Outcome) -> Outcome {
    match panic::catch_unwind(AssertUnwindSafe(target)) {
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
        let reader = Request::Reader(ReaderInput {
            reader: Reader::Calculix,
            files: ["a.inp", "a.dof", "a.sti", "a.mas"]
                .map(|name| ReaderFile {
                    name: name.into(),
                    text: format!("*NODE ρ\r\n{name}"),
                })
                .to_vec(),
            reduction: Some(Reduction::FreeFree),
        });
        write_any_request(&mut buf, &reader).unwrap();
        let mut r = buf.as_slice();
        assert_eq!(
            read_request(&mut r).unwrap(),
            Some(Request::Scene {
                formulation: FormulationKind::Relative,
                text: "(a: \"ρ\")".to_string()
            })
        );
        assert_eq!(
            read_request(&mut r).unwrap(),
            Some(Request::Scene {
                formulation: FormulationKind::Absolute,
                text: String::new()
            })
        );
        assert_eq!(read_request(&mut r).unwrap(), Some(reader));
        assert_eq!(read_request(&mut r).unwrap(), None);
    }

    #[test]
    fn replies_round_trip_with_multiline_details_folded() {
        let o = Outcome::new(Class::Panic, "panicked at a.rs:1: x\ny");
        let line = reply_line(&o);
        assert_eq!(parse_reply(line.trim_end_matches('\n')), Some(o));
    }
}
