//! The FMI 3.0 C API (co-simulation) of the FMU's shared library, over [`Instance`].
//!
//! The types are the header's (`fmi3PlatformTypes.h`, `fmi3FunctionTypes.h` of the FMI
//! 3.0 standard), declared here: an instance and an FMU state are opaque pointers, a
//! status is a C `int`, a Boolean a C `bool`, a value reference a `uint32_t`.
//!
//! Every exported function catches unwinding: a panic becomes `fmi3Fatal` with the
//! panic's message through the logger, never an unwind across the C boundary. A refused
//! call is `fmi3Error` with the reason through the logger (category `logStatusError`),
//! whether or not logging was switched on. Every function of the standard is exported
//! (importers look them all up); those of model exchange, scheduled execution, clocks,
//! the integer, Boolean, string and binary types and derivatives answer `fmi3Error` (or `fmi3OK` for an empty request of a type the FMU has none of).

use std::ffi::{c_char, c_int, c_void};
use std::path::PathBuf;

use crate::ffi::{self, FmuStates, Wrapper, c_message, category, slice, slice_mut, text};
use crate::instance::{CallError, Instance};

pub use crate::ffi::{ERROR, FATAL, OK, Status};

/// `fmi3LogMessageCallback`.
pub type LogMessage = Option<
    unsafe extern "C" fn(
        environment: *mut c_void,
        status: Status,
        category: *const c_char,
        message: *const c_char,
    ),
>;

/// What an `fmi3Instance` points to.
pub struct Fmi3Instance {
    instance: Instance,
    environment: *mut c_void,
    log: LogMessage,
    name: String,
}

impl Wrapper for Fmi3Instance {
    fn log(&self, status: Status, message: &str) {
        log_to(
            self.log,
            self.environment,
            status,
            &format!("{}: {message}", self.name),
        );
    }
}

fn log_to(log: LogMessage, environment: *mut c_void, status: Status, message: &str) {
    let Some(log) = log else { return };
    let text = c_message(message);
    // SAFETY: the importer's callback, called with the environment it gave and two valid
    // C strings that outlive the call.
    unsafe {
        log(
            environment,
            status,
            category(status).as_ptr(),
            text.as_ptr(),
        )
    };
}

/// [`ffi::with`] for FMI 3.0 instances.
fn with(
    instance: *mut c_void,
    call: &str,
    f: impl FnOnce(&mut Fmi3Instance) -> Result<(), CallError>,
) -> Status {
    // SAFETY: a non-null instance is one this library made (fmi3InstantiateCoSimulation)
    // and has not freed: the FMI standard requires the importer to pass only those.
    unsafe { ffi::with(instance, call, f) }
}

/// The FMU states, spelt as FMI 3.0 does in messages.
const STATES: FmuStates = FmuStates { name: "FMUState" };

/// `fmi3GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// `fmi3SetDebugLogging`: errors are logged whatever is asked; nothing else is.
///
/// # Safety
/// `instance` is one of this library's, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    instance: *mut c_void,
    _logging_on: bool,
    _n_categories: usize,
    _categories: *const *const c_char,
) -> Status {
    with(instance, "fmi3SetDebugLogging", |_| Ok(()))
}

/// `fmi3InstantiateCoSimulation`: read the scene from `resource_path` (the FMU's
/// `resources/` folder), check the token and start the simulation; null (with the reason
/// logged) when it cannot.
///
/// # Safety
/// The strings are valid C strings or null; `log_message` is the importer's callback.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name: *const c_char,
    instantiation_token: *const c_char,
    resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    _event_mode_used: bool,
    _early_return_allowed: bool,
    _required_intermediate_variables: *const u32,
    _n_required_intermediate_variables: usize,
    instance_environment: *mut c_void,
    log_message: LogMessage,
    _intermediate_update: *mut c_void,
) -> *mut c_void {
    let (name, result) = ffi::instantiate(|| {
        // SAFETY: the importer passes valid C strings or null.
        let (name, token, resources) = unsafe {
            (
                text(instance_name),
                text(instantiation_token),
                text(resource_path),
            )
        };
        let name = name.unwrap_or_else(|| "flexmbd".to_string());
        let result = match (token, resources) {
            (_, None) => Err(CallError(
                "no resource path: the FMU's resources/ folder holds the scene".into(),
            )),
            (None, _) => Err(CallError("no instantiation token".into())),
            (Some(token), Some(resources)) => {
                let path = resources.strip_prefix("file://").unwrap_or(&resources);
                Instance::from_resources(&PathBuf::from(path), &token)
            }
        };
        (name, result)
    });
    match result {
        Ok(instance) => Box::into_raw(Box::new(Fmi3Instance {
            instance,
            environment: instance_environment,
            log: log_message,
            name,
        }))
        .cast(),
        Err(e) => {
            log_to(
                log_message,
                instance_environment,
                ERROR,
                &format!("{name}: fmi3InstantiateCoSimulation: {e}"),
            );
            std::ptr::null_mut()
        }
    }
}

/// `fmi3FreeInstance`: everything the instance holds is released.
///
/// # Safety
/// `instance` is one of this library's not yet freed, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeInstance(instance: *mut c_void) {
    // SAFETY: made by Box::into_raw in fmi3InstantiateCoSimulation, freed once.
    unsafe { ffi::free::<Fmi3Instance>(instance) }
}

/// `fmi3EnterInitializationMode`.
///
/// # Safety
/// `instance` is one of this library's, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    instance: *mut c_void,
    _tolerance_defined: bool,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: bool,
    _stop_time: f64,
) -> Status {
    with(instance, "fmi3EnterInitializationMode", |w| {
        w.instance.enter_initialization(start_time)
    })
}

/// `fmi3ExitInitializationMode`.
///
/// # Safety
/// `instance` is one of this library's, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ExitInitializationMode(instance: *mut c_void) -> Status {
    with(instance, "fmi3ExitInitializationMode", |w| {
        w.instance.exit_initialization()
    })
}

/// `fmi3Terminate`.
///
/// # Safety
/// `instance` is one of this library's, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Terminate(instance: *mut c_void) -> Status {
    with(instance, "fmi3Terminate", |w| w.instance.terminate())
}

/// `fmi3Reset`.
///
/// # Safety
/// `instance` is one of this library's, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Reset(instance: *mut c_void) -> Status {
    with(instance, "fmi3Reset", |w| w.instance.reset())
}

/// `fmi3GetFloat64`.
///
/// # Safety
/// `instance` is one of this library's, or null; the arrays hold their counts.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: *mut c_void,
    value_references: *const u32,
    n_value_references: usize,
    values: *mut f64,
    n_values: usize,
) -> Status {
    with(instance, "fmi3GetFloat64", |w| {
        // SAFETY: the importer's arrays of the counts it gives.
        let (vrs, values) = unsafe {
            (
                slice(value_references, n_value_references, "valueReferences")?,
                slice_mut(values, n_values, "values")?,
            )
        };
        w.instance.get(vrs, values)
    })
}

/// `fmi3SetFloat64`.
///
/// # Safety
/// `instance` is one of this library's, or null; the arrays hold their counts.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: *mut c_void,
    value_references: *const u32,
    n_value_references: usize,
    values: *const f64,
    n_values: usize,
) -> Status {
    with(instance, "fmi3SetFloat64", |w| {
        // SAFETY: the importer's arrays of the counts it gives.
        let (vrs, values) = unsafe {
            (
                slice(value_references, n_value_references, "valueReferences")?,
                slice(values, n_values, "values")?,
            )
        };
        w.instance.set(vrs, values)
    })
}

/// `fmi3EnterStepMode`: co-simulation without event mode enters step mode on leaving
/// initialisation; nothing to do.
///
/// # Safety
/// `instance` is one of this library's, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterStepMode(instance: *mut c_void) -> Status {
    with(instance, "fmi3EnterStepMode", |_| Ok(()))
}

/// `fmi3DoStep` ([`Instance::do_step`]); `lastSuccessfulTime` is the time reached.
///
/// # Safety
/// `instance` is one of this library's, or null; the out-pointers are valid or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DoStep(
    instance: *mut c_void,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior_to_current_point: bool,
    event_handling_needed: *mut bool,
    terminate_simulation: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Status {
    with(instance, "fmi3DoStep", |w| {
        let result = w
            .instance
            .do_step(current_communication_point, communication_step_size);
        let reached = w.instance.simulation().time();
        // SAFETY: the importer's out-pointers, each valid or null.
        unsafe {
            for flag in [event_handling_needed, terminate_simulation, early_return] {
                if !flag.is_null() {
                    *flag = false;
                }
            }
            if !last_successful_time.is_null() {
                *last_successful_time = reached;
            }
        }
        result
    })
}

/// `fmi3GetFMUState`: a copy of the state; a non-null `*state` is overwritten.
///
/// # Safety
/// `instance` is one of this library's, or null; `state` is valid, and a non-null
/// `*state` one of this library's FMU states.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFMUState(instance: *mut c_void, state: *mut *mut c_void) -> Status {
    with(instance, "fmi3GetFMUState", |w| {
        // SAFETY: the importer's pointer to an FMU state of this library's, or to null.
        unsafe { STATES.store(state, w.instance.state()) }
    })
}

/// `fmi3SetFMUState`.
///
/// # Safety
/// `instance` is one of this library's, or null; `state` one of this library's FMU
/// states, or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFMUState(instance: *mut c_void, state: *mut c_void) -> Status {
    with(instance, "fmi3SetFMUState", |w| {
        // SAFETY: an FMU state made by fmi3GetFMUState and not freed, or null.
        w.instance.set_state(unsafe { STATES.read(state) }?)
    })
}

/// `fmi3FreeFMUState`: `*state` freed and set to null.
///
/// # Safety
/// `instance` is one of this library's, or null; `state` valid, `*state` one of this
/// library's FMU states or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: *mut c_void,
    state: *mut *mut c_void,
) -> Status {
    with(instance, "fmi3FreeFMUState", |_| {
        // SAFETY: the importer's pointer to a state made by fmi3GetFMUState, freed once.
        unsafe { STATES.free(state) };
        Ok(())
    })
}

/// `fmi3SerializedFMUStateSize`: the length of the state's bytes ([`crate::instance::FmuState::to_bytes`]).
///
/// # Safety
/// `instance` is one of this library's, or null; `state` one of this library's FMU states
/// or null; `size` valid or null.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: *mut c_void,
    state: *mut c_void,
    size: *mut usize,
) -> Status {
    with(instance, "fmi3SerializedFMUStateSize", |_| {
        // SAFETY: an FMU state of this library or null; the importer's out-pointer.
        unsafe { STATES.size(state, size) }
    })
}

/// `fmi3SerializeFMUState`: the state's bytes into `serialized_state` of `size` bytes (the
/// size `fmi3SerializedFMUStateSize` gave).
///
/// # Safety
/// `instance` is one of this library's, or null; `state` one of this library's FMU states
/// or null; `serialized_state` holds `size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: *mut c_void,
    state: *mut c_void,
    serialized_state: *mut u8,
    size: usize,
) -> Status {
    with(instance, "fmi3SerializeFMUState", |_| {
        // SAFETY: an FMU state of this library or null; the importer's `size` bytes.
        unsafe { STATES.serialize(state, serialized_state, size, "fmi3SerializedFMUStateSize") }
    })
}

/// `fmi3DeserializeFMUState`: a new FMU state (or `*state` overwritten) from bytes of
/// `fmi3SerializeFMUState`; other bytes are refused.
///
/// # Safety
/// `instance` is one of this library's, or null; `serialized_state` holds `size` bytes;
/// `state` valid, a non-null `*state` one of this library's FMU states.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: *mut c_void,
    serialized_state: *const u8,
    size: usize,
    state: *mut *mut c_void,
) -> Status {
    with(instance, "fmi3DeserializeFMUState", |_| {
        // SAFETY: the importer's `size` bytes and its pointer to a state or to null.
        unsafe { STATES.deserialize(serialized_state, size, state) }
    })
}

/// Functions of the standard this FMU does not support: exported with their C
/// signatures (importers look every one up), each refusing with a message.
macro_rules! unsupported {
    ($($name:ident($($arg:ident: $ty:ty),*) $why:literal;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: not supported (", $why, "); `fmi3Error`.")]
        ///
        /// # Safety
        /// `instance` is one of this library's, or null.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(instance: *mut c_void, $(_: $ty),*) -> Status {
            with(instance, stringify!($name), |_| {
                Err(CallError(concat!("not supported: ", $why).into()))
            })
        }
    )*};
}

/// Typed get and set of variable types the FMU has none of: an empty request is `fmi3OK`,
/// any value reference is unknown.
macro_rules! no_variables_of_type {
    ($($name:ident($vr:ident, $n:ident $(, $arg:ident: $ty:ty)*);)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: the FMU has no variable of this type.")]
        ///
        /// # Safety
        /// `instance` is one of this library's, or null.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            instance: *mut c_void,
            $vr: *const u32,
            $n: usize,
            $(_: $ty),*
        ) -> Status {
            with(instance, stringify!($name), |_| {
                if $n == 0 {
                    return Ok(());
                }
                // SAFETY: the importer's array of the count it gives.
                let vrs = unsafe { slice($vr, $n, "valueReferences")? };
                Err(CallError(format!(
                    "value reference {}: the FMU's variables are all Float64",
                    vrs[0]
                )))
            })
        }
    )*};
}

no_variables_of_type! {
    fmi3GetFloat32(vr, n, v: *mut f32, m: usize);
    fmi3GetInt8(vr, n, v: *mut i8, m: usize);
    fmi3GetUInt8(vr, n, v: *mut u8, m: usize);
    fmi3GetInt16(vr, n, v: *mut i16, m: usize);
    fmi3GetUInt16(vr, n, v: *mut u16, m: usize);
    fmi3GetInt32(vr, n, v: *mut i32, m: usize);
    fmi3GetUInt32(vr, n, v: *mut u32, m: usize);
    fmi3GetInt64(vr, n, v: *mut i64, m: usize);
    fmi3GetUInt64(vr, n, v: *mut u64, m: usize);
    fmi3GetBoolean(vr, n, v: *mut bool, m: usize);
    fmi3GetString(vr, n, v: *mut *const c_char, m: usize);
    fmi3GetBinary(vr, n, s: *mut usize, v: *mut *const u8, m: usize);
    fmi3GetClock(vr, n, v: *mut bool);
    fmi3SetFloat32(vr, n, v: *const f32, m: usize);
    fmi3SetInt8(vr, n, v: *const i8, m: usize);
    fmi3SetUInt8(vr, n, v: *const u8, m: usize);
    fmi3SetInt16(vr, n, v: *const i16, m: usize);
    fmi3SetUInt16(vr, n, v: *const u16, m: usize);
    fmi3SetInt32(vr, n, v: *const i32, m: usize);
    fmi3SetUInt32(vr, n, v: *const u32, m: usize);
    fmi3SetInt64(vr, n, v: *const i64, m: usize);
    fmi3SetUInt64(vr, n, v: *const u64, m: usize);
    fmi3SetBoolean(vr, n, v: *const bool, m: usize);
    fmi3SetString(vr, n, v: *const *const c_char, m: usize);
    fmi3SetBinary(vr, n, s: *const usize, v: *const *const u8, m: usize);
    fmi3SetClock(vr, n, v: *const bool);
    fmi3GetIntervalDecimal(vr, n, v: *mut f64, q: *mut c_int);
    fmi3GetIntervalFraction(vr, n, c: *mut u64, r: *mut u64, q: *mut c_int);
    fmi3GetShiftDecimal(vr, n, v: *mut f64);
    fmi3GetShiftFraction(vr, n, c: *mut u64, r: *mut u64);
    fmi3SetIntervalDecimal(vr, n, v: *const f64);
    fmi3SetIntervalFraction(vr, n, c: *const u64, r: *const u64);
    fmi3SetShiftDecimal(vr, n, v: *const f64);
    fmi3SetShiftFraction(vr, n, c: *const u64, r: *const u64);
}

unsupported! {
    fmi3EnterEventMode() "the FMU has no event mode";
    fmi3GetNumberOfVariableDependencies(vr: u32, n: *mut usize) "no dependency information";
    fmi3GetVariableDependencies(vr: u32, e: *mut usize, i: *mut u32, ei: *mut usize, k: *mut c_int, n: usize) "no dependency information";
    fmi3GetDirectionalDerivative(u: *const u32, nu: usize, k: *const u32, nk: usize, s: *const f64, ns: usize, r: *mut f64, nr: usize) "no directional derivatives";
    fmi3GetAdjointDerivative(u: *const u32, nu: usize, k: *const u32, nk: usize, s: *const f64, ns: usize, r: *mut f64, nr: usize) "no adjoint derivatives";
    fmi3EnterConfigurationMode() "the FMU has no structural parameters";
    fmi3ExitConfigurationMode() "the FMU has no structural parameters";
    fmi3EvaluateDiscreteStates() "the FMU has no event mode";
    fmi3UpdateDiscreteStates(a: *mut bool, b: *mut bool, c: *mut bool, d: *mut bool, e: *mut bool, t: *mut f64) "the FMU has no event mode";
    fmi3EnterContinuousTimeMode() "a co-simulation FMU only";
    fmi3CompletedIntegratorStep(a: bool, b: *mut bool, c: *mut bool) "a co-simulation FMU only";
    fmi3SetTime(t: f64) "a co-simulation FMU only";
    fmi3SetContinuousStates(x: *const f64, n: usize) "a co-simulation FMU only";
    fmi3GetContinuousStateDerivatives(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi3GetEventIndicators(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi3GetContinuousStates(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi3GetNominalsOfContinuousStates(x: *mut f64, n: usize) "a co-simulation FMU only";
    fmi3GetNumberOfEventIndicators(n: *mut usize) "a co-simulation FMU only";
    fmi3GetNumberOfContinuousStates(n: *mut usize) "a co-simulation FMU only";
    fmi3GetOutputDerivatives(vr: *const u32, n: usize, o: *const i32, v: *mut f64, m: usize) "no output derivatives (providesOutputDerivatives is false)";
    fmi3ActivateModelPartition(c: u32, t: f64) "a co-simulation FMU only";
}

/// `fmi3InstantiateModelExchange`: not supported (a co-simulation FMU only); null.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateModelExchange(
    _instance_name: *const c_char,
    _instantiation_token: *const c_char,
    _resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    _instance_environment: *mut c_void,
    _log_message: LogMessage,
) -> *mut c_void {
    std::ptr::null_mut()
}

/// `fmi3InstantiateScheduledExecution`: not supported (a co-simulation FMU only); null.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateScheduledExecution(
    _instance_name: *const c_char,
    _instantiation_token: *const c_char,
    _resource_path: *const c_char,
    _visible: bool,
    _logging_on: bool,
    _instance_environment: *mut c_void,
    _log_message: LogMessage,
    _clock_update: *mut c_void,
    _lock_preemption: *mut c_void,
    _unlock_preemption: *mut c_void,
) -> *mut c_void {
    std::ptr::null_mut()
}
