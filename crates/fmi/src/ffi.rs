//! What the FMI 2.0 and 3.0 C APIs ([`crate::fmi2`], [`crate::fmi3`]) share at the C
//! boundary: the status codes (the same numbers in both versions), the guarded call that
//! turns a refusal into `Error` and a panic into `Fatal` (never an unwind into the
//! importer), the importer's arrays and strings, and the FMU states (boxed
//! [`FmuState`]s behind opaque pointers, their bytes for serialisation).

use std::any::Any;
use std::ffi::{CStr, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};

use crate::instance::{CallError, FmuState, Instance};

/// `fmi2Status` / `fmi3Status`.
pub type Status = c_int;
/// `fmi2OK` / `fmi3OK`.
pub const OK: Status = 0;
/// `fmi2Error` / `fmi3Error`.
pub const ERROR: Status = 3;
/// `fmi2Fatal` / `fmi3Fatal`.
pub const FATAL: Status = 4;

/// The log category of a status.
pub(crate) fn category(status: Status) -> &'static CStr {
    if status == FATAL {
        c"logStatusFatal"
    } else {
        c"logStatusError"
    }
}

/// `message` as a C string (a NUL inside becomes a space).
pub(crate) fn c_message(message: &str) -> std::ffi::CString {
    std::ffi::CString::new(message.replace('\0', " "))
        .unwrap_or_else(|_| c"(message not representable)".to_owned())
}

/// What an instance pointer of either version points to: the [`Instance`] and the
/// importer's logger.
pub(crate) trait Wrapper {
    /// Tell the importer's logger `message` with `status`.
    fn log(&self, status: Status, message: &str);
}

/// The panic's message, for the logger.
pub(crate) fn panic_message(panic: Box<dyn Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Run `f` on the wrapper behind `instance`, catching a panic: a refusal is logged and
/// `Error`, a panic logged and `Fatal`; a null instance is `Error`.
///
/// # Safety
/// A non-null `instance` is a `W` this library made and has not freed (the standard
/// requires the importer to pass only those).
pub(crate) unsafe fn with<W: Wrapper>(
    instance: *mut c_void,
    call: &str,
    f: impl FnOnce(&mut W) -> Result<(), CallError>,
) -> Status {
    if instance.is_null() {
        return ERROR;
    }
    // SAFETY: as the caller promises.
    let wrapper = unsafe { &mut *instance.cast::<W>() };
    match catch_unwind(AssertUnwindSafe(|| f(wrapper))) {
        Ok(Ok(())) => OK,
        Ok(Err(e)) => {
            wrapper.log(ERROR, &format!("{call}: {e}"));
            ERROR
        }
        Err(panic) => {
            wrapper.log(
                FATAL,
                &format!("{call}: internal error: {}", panic_message(panic)),
            );
            FATAL
        }
    }
}

/// Make an [`Instance`] by `make` (which gives the instance's name and the result),
/// catching a panic as an internal error.
pub(crate) fn instantiate(
    make: impl FnOnce() -> (String, Result<Instance, CallError>),
) -> (String, Result<Instance, CallError>) {
    catch_unwind(AssertUnwindSafe(make)).unwrap_or_else(|panic| {
        (
            "flexmbd".into(),
            Err(CallError(format!(
                "internal error: {}",
                panic_message(panic)
            ))),
        )
    })
}

/// Free a wrapper made by `Box::into_raw`, catching a panic in its drop.
///
/// # Safety
/// `instance` is null or a `W` this library made and has not freed; it is freed once.
pub(crate) unsafe fn free<W>(instance: *mut c_void) {
    if instance.is_null() {
        return;
    }
    // SAFETY: as the caller promises.
    let boxed = unsafe { Box::from_raw(instance.cast::<W>()) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(boxed)));
}

/// A C string argument, `None` when null.
///
/// # Safety
/// A non-null `p` must be a valid NUL-terminated string.
pub(crate) unsafe fn text(p: *const c_char) -> Option<String> {
    // SAFETY: as the caller promises.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// The `n` elements at `p` (none when `n` is 0; a null `p` with `n > 0` is refused).
///
/// # Safety
/// `p` must point to `n` valid elements that outlive the borrow.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize, what: &str) -> Result<&'a [T], CallError> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err(CallError(format!("{what} is a null pointer")));
    }
    // SAFETY: as the caller promises.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// [`slice`], writable.
///
/// # Safety
/// As [`slice`], and nothing else may read or write the elements during the borrow.
pub(crate) unsafe fn slice_mut<'a, T>(
    p: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], CallError> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err(CallError(format!("{what} is a null pointer")));
    }
    // SAFETY: as the caller promises.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// The FMU-state calls, over boxed [`FmuState`]s behind opaque pointers; `name` is the
/// version's spelling of the type (`FMUstate` in 2.0, `FMUState` in 3.0), for messages.
pub(crate) struct FmuStates {
    pub name: &'static str,
}

impl FmuStates {
    fn null(&self) -> CallError {
        CallError(format!("{} is a null pointer", self.name))
    }

    /// Put `saved` behind `*state`: a new box when `*state` is null, else overwritten.
    ///
    /// # Safety
    /// `state` is valid or null; a non-null `*state` is one of this library's states.
    pub unsafe fn store(&self, state: *mut *mut c_void, saved: FmuState) -> Result<(), CallError> {
        if state.is_null() {
            return Err(self.null());
        }
        // SAFETY: the importer's pointer; a non-null *state was made by Box::into_raw here.
        unsafe {
            if (*state).is_null() {
                *state = Box::into_raw(Box::new(saved)).cast();
            } else {
                *(*state).cast::<FmuState>() = saved;
            }
        }
        Ok(())
    }

    /// The state behind `state`.
    ///
    /// # Safety
    /// `state` is null or one of this library's states, not freed during the borrow.
    pub unsafe fn read<'a>(&self, state: *mut c_void) -> Result<&'a FmuState, CallError> {
        if state.is_null() {
            return Err(self.null());
        }
        // SAFETY: as the caller promises.
        Ok(unsafe { &*state.cast::<FmuState>() })
    }

    /// Free `*state` and set it to null (nothing to do when either pointer is null).
    ///
    /// # Safety
    /// `state` is valid or null; `*state` one of this library's states or null, freed once.
    pub unsafe fn free(&self, state: *mut *mut c_void) {
        // SAFETY: as the caller promises.
        unsafe {
            if !state.is_null() && !(*state).is_null() {
                drop(Box::from_raw((*state).cast::<FmuState>()));
                *state = std::ptr::null_mut();
            }
        }
    }

    /// The length of the state's bytes ([`FmuState::to_bytes`]) into `*size`.
    ///
    /// # Safety
    /// As [`FmuStates::read`]; `size` valid or null.
    pub unsafe fn size(&self, state: *mut c_void, size: *mut usize) -> Result<(), CallError> {
        if size.is_null() {
            return Err(CallError(format!(
                "{} or size is a null pointer",
                self.name
            )));
        }
        // SAFETY: as the caller promises.
        let bytes = unsafe { self.read(state) }?.to_bytes()?;
        unsafe { *size = bytes.len() };
        Ok(())
    }

    /// The state's bytes into `out` of `size` bytes, the size `size_call` gave.
    ///
    /// # Safety
    /// As [`FmuStates::read`]; `out` holds `size` bytes.
    pub unsafe fn serialize(
        &self,
        state: *mut c_void,
        out: *mut u8,
        size: usize,
        size_call: &str,
    ) -> Result<(), CallError> {
        // SAFETY: as the caller promises.
        let bytes = unsafe { self.read(state) }?.to_bytes()?;
        let out = unsafe { slice_mut(out, size, "serializedState")? };
        if out.len() != bytes.len() {
            return Err(CallError(format!(
                "size = {size}, but the state takes {} bytes ({size_call})",
                bytes.len()
            )));
        }
        out.copy_from_slice(&bytes);
        Ok(())
    }

    /// A state read from `size` bytes at `bytes` (other bytes than a serialised state's are
    /// refused), stored behind `*state` as [`FmuStates::store`] does.
    ///
    /// # Safety
    /// `bytes` holds `size` bytes; `state` as for [`FmuStates::store`].
    pub unsafe fn deserialize(
        &self,
        bytes: *const u8,
        size: usize,
        state: *mut *mut c_void,
    ) -> Result<(), CallError> {
        if state.is_null() {
            return Err(self.null());
        }
        // SAFETY: as the caller promises.
        let read = FmuState::from_bytes(unsafe { slice(bytes, size, "serializedState")? })?;
        unsafe { self.store(state, read) }
    }
}
