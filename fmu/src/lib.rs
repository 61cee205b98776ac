//! The FMU's binary: the FMI 2.0 co-simulation functions (FMI standard 2.0.4, chapter 4) of
//! a scenario exported by `foldsim export fmu` (docs/interop.md), over
//! [`foldsim::session::Session`]. The scenario, its table files and the variables chosen at
//! export are in the FMU's `resources/`; foldsim's own integrator steps between
//! communication points.
//!
//! Every function catches panics (nothing unwinds into the host) and reports errors through
//! the host's logger with `fmi2Error`; after an error an instance answers only `fmi2Reset`,
//! `fmi2FreeInstance` and getters of what it already holds.

mod instance;

use instance::{Instance, Phase};
use std::ffi::{CStr, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// `fmi2Status`.
pub type Status = c_int;
/// `fmi2OK`.
pub const OK: Status = 0;
/// `fmi2Warning`.
pub const WARNING: Status = 1;
/// `fmi2Discard`.
pub const DISCARD: Status = 2;
/// `fmi2Error`.
pub const ERROR: Status = 3;
/// `fmi2Fatal`.
pub const FATAL: Status = 4;

/// `fmi2CallbackLogger`: `(componentEnvironment, instanceName, status, category, message, ...)`
/// with `message` a printf format.
pub type Logger = unsafe extern "C" fn(*mut c_void, *const c_char, Status, *const c_char, *const c_char, ...);

/// `fmi2CallbackFunctions` (FMI 2.0 section 2.1.5).
#[repr(C)]
pub struct CallbackFunctions {
    /// The host's logger.
    pub logger: Option<Logger>,
    /// Not used (`canNotUseMemoryManagementFunctions = true`).
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// Not used.
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Not used (no asynchronous steps).
    pub step_finished: Option<unsafe extern "C" fn(*mut c_void, Status)>,
    /// Handed back to the logger.
    pub component_environment: *mut c_void,
}

/// Runs `f` on the instance `c`, catching panics; a null instance is an error.
fn with(c: *mut c_void, f: impl FnOnce(&mut Instance) -> Status) -> Status {
    if c.is_null() {
        return ERROR;
    }
    // SAFETY: a non-null component is one fmi2Instantiate returned (Box<Instance>::into_raw)
    // and fmi2FreeInstance has not freed: the FMI standard forbids calls on a freed
    // instance, and one instance is never used from two threads at once (section 2.1.4).
    let instance = unsafe { &mut *(c as *mut Instance) };
    match catch_unwind(AssertUnwindSafe(|| f(instance))) {
        Ok(s) => s,
        Err(p) => {
            let what = p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()));
            instance
                .fail(&format!("internal error (a bug in foldsim: please report it): {}", what.unwrap_or_default()));
            FATAL
        }
    }
}

/// A C string as `&str` (`None` for null or not UTF-8).
///
/// # Safety
/// `p` is null or a NUL-terminated string that outlives the call.
unsafe fn text<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        return None;
    }
    // SAFETY: the caller's promise.
    unsafe { CStr::from_ptr(p) }.to_str().ok()
}

/// `nvr` values of `vr` as slices (empty for 0, `None` for a null pointer with nvr > 0).
///
/// # Safety
/// Non-null pointers point at `nvr` elements each.
unsafe fn slices<'a, T>(vr: *const u32, nvr: usize, value: *const T) -> Option<(&'a [u32], &'a [T])> {
    if nvr == 0 {
        return Some((&[], &[]));
    }
    if vr.is_null() || value.is_null() {
        return None;
    }
    // SAFETY: the caller's promise.
    Some(unsafe { (std::slice::from_raw_parts(vr, nvr), std::slice::from_raw_parts(value, nvr)) })
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

/// `fmi2Instantiate`: reads the scenario and variables from the resources and checks the
/// scenario builds. Null (with the reason logged) for a model-exchange request, a wrong
/// GUID, unreadable resources or a scenario that does not build.
///
/// # Safety
/// The strings are null or NUL-terminated; `functions` is null or a valid callback table.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const CallbackFunctions,
    _visible: c_int,
    logging_on: c_int,
) -> *mut c_void {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the host's table, valid for the instance's life (FMI 2.0 section 2.1.5).
        let (logger, env) = match unsafe { functions.as_ref() } {
            Some(f) => (f.logger, f.component_environment),
            None => (None, std::ptr::null_mut()),
        };
        // SAFETY: the caller's promise.
        let name = unsafe { text(instance_name) }.unwrap_or("foldsim").to_string();
        let (guid, location) = unsafe { (text(guid), text(resource_location)) };
        let made = if fmu_type != 1 {
            Err("this FMU is for co-simulation only (fmuType must be fmi2CoSimulation)".to_string())
        } else {
            Instance::new(&name, guid, location, logger, env, logging_on != 0)
        };
        match made {
            Ok(i) => Box::into_raw(Box::new(i)) as *mut c_void,
            Err(message) => {
                instance::log(logger, env, &name, ERROR, &message);
                std::ptr::null_mut()
            }
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// `c` is null or an instance from fmi2Instantiate not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: *mut c_void) {
    if !c.is_null() {
        // SAFETY: as the function's contract says; dropping never panics into the host.
        let _ = catch_unwind(|| drop(unsafe { Box::from_raw(c as *mut Instance) }));
    }
}

/// `fmi2SetDebugLogging`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetDebugLogging(
    c: *mut c_void,
    logging_on: c_int,
    _n: usize,
    _categories: *const *const c_char,
) -> Status {
    with(c, |i| {
        i.logging_on = logging_on != 0;
        OK
    })
}

/// `fmi2SetupExperiment`: the host's start and stop time (the run's horizon becomes
/// `stop − start`) and tolerance (the run's rtol).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetupExperiment(
    c: *mut c_void,
    tolerance_defined: c_int,
    tolerance: f64,
    start_time: f64,
    stop_time_defined: c_int,
    stop_time: f64,
) -> Status {
    with(c, |i| {
        i.setup(
            (tolerance_defined != 0).then_some(tolerance),
            start_time,
            (stop_time_defined != 0).then_some(stop_time),
        )
    })
}

/// `fmi2EnterInitializationMode`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2EnterInitializationMode(c: *mut c_void) -> Status {
    with(c, |i| i.enter_initialization())
}

/// `fmi2ExitInitializationMode`: the run starts (parameters applied, inputs set).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2ExitInitializationMode(c: *mut c_void) -> Status {
    with(c, |i| i.exit_initialization())
}

/// `fmi2Terminate`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Terminate(c: *mut c_void) -> Status {
    with(c, |i| {
        i.phase = Phase::Terminated;
        OK
    })
}

/// `fmi2Reset`: back to as instantiated (parameters at their start values, inputs 0).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Reset(c: *mut c_void) -> Status {
    with(c, |i| i.reset())
}

/// `fmi2GetReal`.
///
/// # Safety
/// `vr` and `value` point at `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(c: *mut c_void, vr: *const u32, nvr: usize, value: *mut f64) -> Status {
    with(c, |i| {
        if nvr == 0 {
            return OK;
        }
        if vr.is_null() || value.is_null() {
            return i.fail("fmi2GetReal: a null array");
        }
        // SAFETY: the caller's promise.
        let (vr, out) = unsafe { (std::slice::from_raw_parts(vr, nvr), std::slice::from_raw_parts_mut(value, nvr)) };
        i.get_real(vr, out)
    })
}

/// `fmi2SetReal`: inputs at any time, parameters before the run starts.
///
/// # Safety
/// `vr` and `value` point at `nvr` elements.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(c: *mut c_void, vr: *const u32, nvr: usize, value: *const f64) -> Status {
    with(c, |i| match unsafe { slices(vr, nvr, value) } {
        Some((vr, values)) => i.set_real(vr, values),
        None => i.fail("fmi2SetReal: a null array"),
    })
}

/// No variables of this type: fails unless asked for none.
fn none_of(c: *mut c_void, nvr: usize, what: &str) -> Status {
    with(c, |i| if nvr == 0 { OK } else { i.fail(&format!("this FMU has no {what} variables (all are Real)")) })
}

/// `fmi2GetInteger` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetInteger(c: *mut c_void, _vr: *const u32, nvr: usize, _value: *mut c_int) -> Status {
    none_of(c, nvr, "Integer")
}
/// `fmi2GetBoolean` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetBoolean(c: *mut c_void, _vr: *const u32, nvr: usize, _value: *mut c_int) -> Status {
    none_of(c, nvr, "Boolean")
}
/// `fmi2GetString` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetString(c: *mut c_void, _vr: *const u32, nvr: usize, _value: *mut *const c_char) -> Status {
    none_of(c, nvr, "String")
}
/// `fmi2SetInteger` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetInteger(c: *mut c_void, _vr: *const u32, nvr: usize, _value: *const c_int) -> Status {
    none_of(c, nvr, "Integer")
}
/// `fmi2SetBoolean` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetBoolean(c: *mut c_void, _vr: *const u32, nvr: usize, _value: *const c_int) -> Status {
    none_of(c, nvr, "Boolean")
}
/// `fmi2SetString` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetString(c: *mut c_void, _vr: *const u32, nvr: usize, _value: *const *const c_char) -> Status {
    none_of(c, nvr, "String")
}

/// What this FMU does not offer, refused with its reason.
fn unsupported(c: *mut c_void, what: &str) -> Status {
    with(c, |i| i.fail(what))
}

/// `fmi2GetFMUstate` (not offered: `canGetAndSetFMUstate = false`).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetFMUstate(c: *mut c_void, _state: *mut *mut c_void) -> Status {
    unsupported(c, "fmi2GetFMUstate: this FMU cannot save its state (canGetAndSetFMUstate = false)")
}
/// `fmi2SetFMUstate` (not offered).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetFMUstate(c: *mut c_void, _state: *mut c_void) -> Status {
    unsupported(c, "fmi2SetFMUstate: this FMU cannot restore a state (canGetAndSetFMUstate = false)")
}
/// `fmi2FreeFMUstate` (not offered).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeFMUstate(c: *mut c_void, _state: *mut *mut c_void) -> Status {
    unsupported(c, "fmi2FreeFMUstate: this FMU has no saved states (canGetAndSetFMUstate = false)")
}
/// `fmi2SerializedFMUstateSize` (not offered).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SerializedFMUstateSize(c: *mut c_void, _state: *mut c_void, _size: *mut usize) -> Status {
    unsupported(c, "fmi2SerializedFMUstateSize: this FMU cannot serialize its state (canSerializeFMUstate = false)")
}
/// `fmi2SerializeFMUstate` (not offered).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SerializeFMUstate(
    c: *mut c_void,
    _state: *mut c_void,
    _bytes: *mut c_char,
    _size: usize,
) -> Status {
    unsupported(c, "fmi2SerializeFMUstate: this FMU cannot serialize its state (canSerializeFMUstate = false)")
}
/// `fmi2DeSerializeFMUstate` (not offered).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: *mut c_void,
    _bytes: *const c_char,
    _size: usize,
    _state: *mut *mut c_void,
) -> Status {
    unsupported(c, "fmi2DeSerializeFMUstate: this FMU cannot serialize its state (canSerializeFMUstate = false)")
}
/// `fmi2GetDirectionalDerivative` (not offered: `providesDirectionalDerivative = false`;
/// `foldsim linearize` gives the linear model).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetDirectionalDerivative(
    c: *mut c_void,
    _unknown: *const u32,
    _nu: usize,
    _known: *const u32,
    _nk: usize,
    _dv_known: *const f64,
    _dv_unknown: *mut f64,
) -> Status {
    unsupported(
        c,
        "fmi2GetDirectionalDerivative: not offered (providesDirectionalDerivative = false); foldsim linearize gives the linear model",
    )
}
/// `fmi2SetRealInputDerivatives` (not offered: `canInterpolateInputs = false`).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: *mut c_void,
    _vr: *const u32,
    _nvr: usize,
    _order: *const c_int,
    _value: *const f64,
) -> Status {
    unsupported(c, "fmi2SetRealInputDerivatives: inputs are held constant over a step (canInterpolateInputs = false)")
}
/// `fmi2GetRealOutputDerivatives` (not offered: `MaxOutputDerivativeOrder = 0`).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: *mut c_void,
    _vr: *const u32,
    _nvr: usize,
    _order: *const c_int,
    _value: *mut f64,
) -> Status {
    unsupported(c, "fmi2GetRealOutputDerivatives: not offered (MaxOutputDerivativeOrder = 0)")
}

/// `fmi2DoStep`: integrates from `current` to `current + step` with the inputs as set, held
/// constant (foldsim's own adaptive integrator, the scenario's `[run]` settings).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2DoStep(c: *mut c_void, current: f64, step: f64, _no_set_prior: c_int) -> Status {
    with(c, |i| i.do_step(current, step))
}

/// `fmi2CancelStep` (steps are never asynchronous).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2CancelStep(c: *mut c_void) -> Status {
    unsupported(c, "fmi2CancelStep: steps are not asynchronous here")
}

/// `fmi2GetStatus` (asynchronous steps only: none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStatus(c: *mut c_void, _kind: c_int, _value: *mut Status) -> Status {
    with(c, |_| DISCARD)
}
/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` (2) gives the time reached.
///
/// # Safety
/// `value` is null or points at a double.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(c: *mut c_void, kind: c_int, value: *mut f64) -> Status {
    with(c, |i| {
        if kind != 2 || value.is_null() {
            return DISCARD;
        }
        // SAFETY: the caller's promise.
        unsafe { *value = i.time() };
        OK
    })
}
/// `fmi2GetIntegerStatus` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetIntegerStatus(c: *mut c_void, _kind: c_int, _value: *mut c_int) -> Status {
    with(c, |_| DISCARD)
}
/// `fmi2GetBooleanStatus`: `fmi2Terminated` (3) is false (the FMU never ends a run itself).
///
/// # Safety
/// `value` is null or points at an int.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(c: *mut c_void, kind: c_int, value: *mut c_int) -> Status {
    with(c, |_| {
        if kind != 3 || value.is_null() {
            return DISCARD;
        }
        // SAFETY: the caller's promise.
        unsafe { *value = 0 };
        OK
    })
}
/// `fmi2GetStringStatus` (none).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStringStatus(c: *mut c_void, _kind: c_int, _value: *mut *const c_char) -> Status {
    with(c, |_| DISCARD)
}
