//! The FMI 2.0 C API (co-simulation) of the FMU's shared library, over the same
//! [`Instance`] as [`crate::fmi3`]: most tools in use (Simulink, many Modelica tools,
//! driving simulators) still load 2.0. One library serves both versions (their symbols
//! differ: `fmi2…`, `fmi3…`).
//!
//! The types are `fmi2TypesPlatform.h`'s, declared here: a component and an FMU state are
//! opaque pointers, a status and a Boolean a C `int`, a value reference an `unsigned int`.
//! The resource location is a `file:` URI. The logger is variadic (printf-style): the
//! message is passed as the format, its `%` doubled. As in FMI 3.0, every exported function
//! catches unwinding, and a refused call is `fmi2Error` with its message logged.

use std::ffi::{CStr, c_char, c_int, c_uint, c_void};
use std::path::PathBuf;

use crate::ffi::{self, FmuStates, Wrapper, c_message, category, slice, slice_mut, text};
use crate::instance::{CallError, Instance};

use crate::ffi::ERROR;
pub use crate::ffi::Status;
/// `fmi2CoSimulation` of `fmi2Type`.
const CO_SIMULATION: c_int = 1;

/// `fmi2CallbackLogger`.
pub type Logger = Option<
    unsafe extern "C" fn(
        environment: *mut c_void,
        instance_name: *const c_char,
        status: Status,
        category: *const c_char,
        message: *const c_char,
        ...
    ),
>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    logger: Logger,
    allocate_memory: *mut c_void,
    free_memory: *mut c_void,
    step_finished: *mut c_void,
    component_environment: *mut c_void,
}

/// What an `fmi2Component` points to.
pub struct Fmi2Instance {
    instance: Instance,
    environment: *mut c_void,
    logger: Logger,
    name: std::ffi::CString,
}

impl Wrapper for Fmi2Instance {
    fn log(&self, status: Status, message: &str) {
        log_to(self.logger, self.environment, &self.name, status, message);
    }
}

fn log_to(logger: Logger, environment: *mut c_void, name: &CStr, status: Status, message: &str) {
    let Some(logger) = logger else { return };
    let text = c_message(&message.replace('%', "%%"));
    // SAFETY: the importer's logger, called with its environment and valid C strings
    // (the message is a format without conversions: its `%` are doubled).
    unsafe {
        logger(
            environment,
            name.as_ptr(),
            status,
            category(status).as_ptr(),
            text.as_ptr(),
        )
    };
}

/// [`ffi::with`] for FMI 2.0 components.
fn with(
    component: *mut c_void,
    call: &str,
    f: impl FnOnce(&mut Fmi2Instance) -> Result<(), CallError>,
) -> Status {
    // SAFETY: a non-null component is one this library made (fmi2Instantiate) and has not
    // freed, as the standard requires of the importer.
    unsafe { ffi::with(component, call, f) }
}

/// The FMU states, spelt as FMI 2.0 does in messages.
const STATES: FmuStates = FmuStates { name: "FMUstate" };

/// The local path of a `file:` URI (`file:///dir`, `file://localhost/dir`, `file:/dir`),
/// its `%XX` escapes decoded; a plain path is taken as it is.
pub fn path_of_uri(uri: &str) -> PathBuf {
    let path = match uri.strip_prefix("file:") {
        Some(rest) => match rest.strip_prefix("//") {
            Some(authority_path) => authority_path
                .find('/')
                .map_or(authority_path, |k| &authority_path[k..]),
            None => rest,
        },
        None => uri,
    };
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (bytes[k], bytes.get(k + 1), bytes.get(k + 2)) {
            (b'%', Some(&a), Some(&b)) if hex(a).is_some() && hex(b).is_some() => {
                out.push((hex(a).unwrap_or(0) * 16 + hex(b).unwrap_or(0)) as u8);
                k += 3;
            }
            (b, _, _) => {
                out.push(b);
                k += 1;
            }
        }
    }
    PathBuf::from(String::from_utf8_lossy(&out).into_owned())
}

/// `fmi2GetTypesPlatform`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `fmi2GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// `fmi2Instantiate`: co-simulation only; the scene read from the resource location URI,
/// checked against the GUID; null (the reason logged) when it cannot.
///
/// # Safety
/// The strings are valid C strings or null; `functions` is valid or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const CallbackFunctions,
    _visible: c_int,
    _logging_on: c_int,
) -> *mut c_void {
    // SAFETY: the importer's callback structure, valid or null.
    let (logger, environment) = match unsafe { functions.as_ref() } {
        Some(f) => (f.logger, f.component_environment),
        None => (None, std::ptr::null_mut()),
    };
    let (name, result) = ffi::instantiate(|| {
        // SAFETY: the importer passes valid C strings or null.
        let (name, guid, uri) =
            unsafe { (text(instance_name), text(guid), text(resource_location)) };
        let name = name.unwrap_or_else(|| "flexmbd".into());
        let result = if fmu_type != CO_SIMULATION {
            Err(CallError(
                "a co-simulation FMU only (fmuType must be fmi2CoSimulation)".into(),
            ))
        } else {
            match (guid, uri) {
                (_, None) => Err(CallError(
                    "no resource location: the FMU's resources/ folder holds the scene".into(),
                )),
                (None, _) => Err(CallError("no GUID".into())),
                (Some(guid), Some(uri)) => Instance::from_resources(&path_of_uri(&uri), &guid),
            }
        };
        (name, result)
    });
    let name = std::ffi::CString::new(name.replace('\0', " ")).unwrap_or_default();
    match result {
        Ok(instance) => Box::into_raw(Box::new(Fmi2Instance {
            instance,
            environment,
            logger,
            name,
        }))
        .cast(),
        Err(e) => {
            log_to(
                logger,
                environment,
                &name,
                ERROR,
                &format!("fmi2Instantiate: {e}"),
            );
            std::ptr::null_mut()
        }
    }
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// `c` is one of this library's components not yet freed, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: *mut c_void) {
    // SAFETY: made by Box::into_raw in fmi2Instantiate, freed once.
    unsafe { ffi::free::<Fmi2Instance>(c) }
}

/// `fmi2SetDebugLogging`: errors are logged whatever is asked.
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: *mut c_void,
    _logging_on: c_int,
    _n: usize,
    _categories: *const *const c_char,
) -> Status {
    with(c, "fmi2SetDebugLogging", |_| Ok(()))
}

/// `fmi2SetupExperiment`: the start time must be 0.
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: *mut c_void,
    _tolerance_defined: c_int,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: c_int,
    _stop_time: f64,
) -> Status {
    with(c, "fmi2SetupExperiment", |_| {
        if start_time != 0.0 {
            return Err(CallError(format!(
                "startTime = {start_time}: the scene's simulation starts at t = 0"
            )));
        }
        Ok(())
    })
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: *mut c_void) -> Status {
    with(c, "fmi2EnterInitializationMode", |w| {
        w.instance.enter_initialization(0.0)
    })
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: *mut c_void) -> Status {
    with(c, "fmi2ExitInitializationMode", |w| {
        w.instance.exit_initialization()
    })
}

/// `fmi2Terminate`.
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: *mut c_void) -> Status {
    with(c, "fmi2Terminate", |w| w.instance.terminate())
}

/// `fmi2Reset`.
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: *mut c_void) -> Status {
    with(c, "fmi2Reset", |w| w.instance.reset())
}

/// `fmi2GetReal`.
///
/// # Safety
/// `c` is one of this library's components, or null; the arrays hold `n` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: *mut c_void,
    vr: *const c_uint,
    n: usize,
    values: *mut f64,
) -> Status {
    with(c, "fmi2GetReal", |w| {
        // SAFETY: the importer's arrays of n elements.
        let (vrs, values) = unsafe { (slice(vr, n, "vr")?, slice_mut(values, n, "value")?) };
        w.instance.get(vrs, values)
    })
}

/// `fmi2SetReal`.
///
/// # Safety
/// `c` is one of this library's components, or null; the arrays hold `n` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: *mut c_void,
    vr: *const c_uint,
    n: usize,
    values: *const f64,
) -> Status {
    with(c, "fmi2SetReal", |w| {
        // SAFETY: the importer's arrays of n elements.
        let (vrs, values) = unsafe { (slice(vr, n, "vr")?, slice(values, n, "value")?) };
        w.instance.set(vrs, values)
    })
}

/// `fmi2DoStep` ([`Instance::do_step`]).
///
/// # Safety
/// `c` is one of this library's components, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: *mut c_void,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior_to_current_point: c_int,
) -> Status {
    with(c, "fmi2DoStep", |w| {
        w.instance
            .do_step(current_communication_point, communication_step_size)
    })
}

/// `fmi2GetFMUstate`: a copy of the state; a non-null `*state` is overwritten.
///
/// # Safety
/// `c` is one of this library's components, or null; `state` valid, a non-null `*state`
/// one of this library's FMU states.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: *mut c_void, state: *mut *mut c_void) -> Status {
    with(c, "fmi2GetFMUstate", |w| {
        // SAFETY: the importer's pointer to an FMU state of this library's, or to null.
        unsafe { STATES.store(state, w.instance.state()) }
    })
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// `c` is one of this library's components, or null; `state` one of this library's FMU
/// states, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: *mut c_void, state: *mut c_void) -> Status {
    with(c, "fmi2SetFMUstate", |w| {
        // SAFETY: an FMU state made by fmi2GetFMUstate and not freed, or null.
        w.instance.set_state(unsafe { STATES.read(state) }?)
    })
}

/// `fmi2FreeFMUstate`: `*state` freed and set to null.
///
/// # Safety
/// `c` is one of this library's components, or null; `state` valid or null, `*state` one
/// of this library's FMU states or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: *mut c_void, state: *mut *mut c_void) -> Status {
    with(c, "fmi2FreeFMUstate", |_| {
        // SAFETY: the importer's pointer to a state made by fmi2GetFMUstate, freed once.
        unsafe { STATES.free(state) };
        Ok(())
    })
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// `c` is one of this library's components, or null; `state` one of this library's FMU
/// states or null; `size` valid or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: *mut c_void,
    state: *mut c_void,
    size: *mut usize,
) -> Status {
    with(c, "fmi2SerializedFMUstateSize", |_| {
        // SAFETY: an FMU state of this library or null; the importer's out-pointer.
        unsafe { STATES.size(state, size) }
    })
}

/// `fmi2SerializeFMUstate`.
///
/// # Safety
/// `c` is one of this library's components, or null; `state` one of this library's FMU
/// states or null; `bytes` holds `size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: *mut c_void,
    state: *mut c_void,
    bytes: *mut c_char,
    size: usize,
) -> Status {
    with(c, "fmi2SerializeFMUstate", |_| {
        // SAFETY: an FMU state of this library or null; the importer's `size` bytes.
        unsafe { STATES.serialize(state, bytes.cast(), size, "fmi2SerializedFMUstateSize") }
    })
}

/// `fmi2DeSerializeFMUstate`.
///
/// # Safety
/// `c` is one of this library's components, or null; `bytes` holds `size` bytes; `state`
/// valid, a non-null `*state` one of this library's FMU states.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: *mut c_void,
    bytes: *const c_char,
    size: usize,
    state: *mut *mut c_void,
) -> Status {
    with(c, "fmi2DeSerializeFMUstate", |_| {
        // SAFETY: the importer's `size` bytes and its pointer to a state or to null.
        unsafe { STATES.deserialize(bytes.cast(), size, state) }
    })
}

/// Functions of the standard this FMU does not support: exported with their C signatures,
/// each refusing with a message.
macro_rules! unsupported {
    ($($name:ident($($arg:ident: $ty:ty),*) $why:literal;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: not supported (", $why, "); `fmi2Error`.")]
        ///
        /// # Safety
        /// `c` is one of this library's components, or null.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: *mut c_void, $(_: $ty),*) -> Status {
            with(c, stringify!($name), |_| {
                Err(CallError(concat!("not supported: ", $why).into()))
            })
        }
    )*};
}

/// Get and set of types the FMU has none of: an empty request is `fmi2OK`.
macro_rules! no_variables_of_type {
    ($($name:ident($v:ty);)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: the FMU has no variable of this type.")]
        ///
        /// # Safety
        /// `c` is one of this library's components, or null; `vr` holds `n` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: *mut c_void, vr: *const c_uint, n: usize, _: $v) -> Status {
            with(c, stringify!($name), |_| {
                if n == 0 {
                    return Ok(());
                }
                // SAFETY: the importer's array of n elements.
                let vrs = unsafe { slice(vr, n, "vr")? };
                Err(CallError(format!(
                    "value reference {}: the FMU's variables are all Real",
                    vrs[0]
                )))
            })
        }
    )*};
}

no_variables_of_type! {
    fmi2GetInteger(*mut c_int);
    fmi2GetBoolean(*mut c_int);
    fmi2GetString(*mut *const c_char);
    fmi2SetInteger(*const c_int);
    fmi2SetBoolean(*const c_int);
    fmi2SetString(*const *const c_char);
}

unsupported! {
    fmi2GetDirectionalDerivative(u: *const c_uint, nu: usize, k: *const c_uint, nk: usize, dk: *const f64, du: *mut f64) "no directional derivatives";
    fmi2EnterEventMode() "a co-simulation FMU only";
    fmi2NewDiscreteStates(e: *mut c_void) "a co-simulation FMU only";
    fmi2EnterContinuousTimeMode() "a co-simulation FMU only";
    fmi2CompletedIntegratorStep(a: c_int, b: *mut c_int, d: *mut c_int) "a co-simulation FMU only";
    fmi2SetTime(t: f64) "a co-simulation FMU only";
    fmi2SetContinuousStates(x: *const f64, n: usize) "a co-simulation FMU only";
    fmi2GetDerivatives(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi2GetEventIndicators(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi2GetContinuousStates(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi2GetNominalsOfContinuousStates(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi2SetRealInputDerivatives(vr: *const c_uint, n: usize, o: *const c_int, v: *const f64) "canInterpolateInputs is false";
    fmi2GetRealOutputDerivatives(vr: *const c_uint, n: usize, o: *const c_int, v: *mut f64) "maxOutputDerivativeOrder is 0";
    fmi2CancelStep() "doStep never returns fmi2Pending";
    fmi2GetStatus(k: c_int, v: *mut c_int) "doStep never returns fmi2Pending";
    fmi2GetRealStatus(k: c_int, v: *mut f64) "doStep never returns fmi2Pending";
    fmi2GetIntegerStatus(k: c_int, v: *mut c_int) "doStep never returns fmi2Pending";
    fmi2GetBooleanStatus(k: c_int, v: *mut c_int) "doStep never returns fmi2Pending";
    fmi2GetStringStatus(k: c_int, v: *mut *const c_char) "doStep never returns fmi2Pending";
}
