//! foldsim's C library (docs/interop.md; header `include/foldsim.h`): load a scenario from a
//! file or text, change its numbers by key path, start, set inputs by name, advance, read
//! outputs by name, the last error as text, free. A thin face of
//! [`foldsim::session::Session`]: inputs are named as `foldsim linearize` names them, outputs
//! as the CSV columns (docs/outputs.md).
//!
//! Every call checks its arguments (null pointers, unknown names, values that are not
//! finite, calls in the wrong order) and returns a [`FoldsimStatus`]; the reason is kept for
//! [`foldsim_last_error`]. Nothing unwinds across the boundary: a panic (a bug) is caught and
//! returned as [`FoldsimStatus::FoldsimErrorInternal`].

use foldsim::model::inputs::Input;
use foldsim::observe::catalogue;
use foldsim::scenario::ScenarioText;
use foldsim::session::{Session, parameters};
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

/// What a call returns.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FoldsimStatus {
    /// Done.
    FoldsimOk = 0,
    /// A pointer argument was null.
    FoldsimErrorNull = 1,
    /// An argument was wrong: an unknown name, a value that is not finite, an index out of
    /// range, text that is not UTF-8.
    FoldsimErrorArgument = 2,
    /// The call is not allowed now (a parameter after the start, an advance before it).
    FoldsimErrorState = 3,
    /// The scenario is not valid, or the run failed (its message says why).
    FoldsimErrorRun = 4,
    /// A bug in foldsim (please report it with the message).
    FoldsimErrorInternal = 5,
}

use FoldsimStatus::*;

/// A scenario loaded, and once started, its run (opaque to C).
pub struct FoldsimSimulation {
    text: ScenarioText,
    inputs: Vec<Input>,
    input_names: Vec<CString>,
    output_names: Vec<CString>,
    /// Inputs set before the start, applied when it starts.
    pending: Vec<Option<f64>>,
    session: Option<Session>,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(message: &str) {
    let c = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// An error: its status and its message.
type Failure = (FoldsimStatus, String);

/// Runs `f`, catching panics; a failure's message becomes the last error.
fn guard<T>(fallback: T, f: impl FnOnce() -> Result<T, Failure>) -> T {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(v)) => v,
        Ok(Err((_, message))) => {
            set_error(&message);
            fallback
        }
        Err(p) => {
            let what = p.downcast_ref::<String>().cloned().or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()));
            set_error(&format!("internal error (a bug in foldsim: please report it): {}", what.unwrap_or_default()));
            fallback
        }
    }
}

/// Runs a call that returns a status: its failure's code, with the message kept for
/// [`foldsim_last_error`]; a panic is `FoldsimErrorInternal`.
fn status(f: impl FnOnce() -> Result<(), Failure>) -> FoldsimStatus {
    guard(FoldsimErrorInternal, || {
        Ok(match f() {
            Ok(()) => FoldsimOk,
            Err((code, message)) => {
                set_error(&message);
                code
            }
        })
    })
}

/// A C string argument as `&str`.
///
/// # Safety
/// `p` is null or NUL-terminated and outlives the call.
unsafe fn arg<'a>(p: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if p.is_null() {
        return Err((FoldsimErrorNull, format!("{what} is a null pointer")));
    }
    // SAFETY: the caller's promise.
    unsafe { CStr::from_ptr(p) }.to_str().map_err(|_| (FoldsimErrorArgument, format!("{what} is not UTF-8 text")))
}

/// The simulation behind a handle.
///
/// # Safety
/// `sim` is null or a handle from `foldsim_load_*` not yet freed, used by one thread at a
/// time.
unsafe fn handle<'a>(sim: *mut FoldsimSimulation, call: &str) -> Result<&'a mut FoldsimSimulation, Failure> {
    // SAFETY: the caller's promise.
    unsafe { sim.as_mut() }.ok_or_else(|| (FoldsimErrorNull, format!("{call}: the simulation is a null pointer")))
}

fn load(text: ScenarioText) -> Result<*mut FoldsimSimulation, Failure> {
    let mut scenario = text.build().map_err(|e| (FoldsimErrorRun, e.to_string()))?;
    scenario.model.commandable = true;
    let inputs = foldsim::session::Inputs::of(&scenario.model).list().to_vec();
    let c = |s: &str| CString::new(s).unwrap_or_default();
    let input_names = inputs.iter().map(|i| c(&i.name)).collect();
    let output_names = catalogue(&scenario.model).iter().map(|o| c(&o.name)).collect();
    let pending = vec![None; inputs.len()];
    let sim = FoldsimSimulation { text, inputs, input_names, output_names, pending, session: None };
    Ok(Box::into_raw(Box::new(sim)))
}

/// Loads the scenario file `path` (TOML, docs/scenario.md; its table files relative to it)
/// and checks it. Returns the simulation, or null with the reason in [`foldsim_last_error`].
///
/// # Safety
/// `path` is null or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_load_file(path: *const c_char) -> *mut FoldsimSimulation {
    guard(std::ptr::null_mut(), || {
        // SAFETY: the caller's promise.
        let path = unsafe { arg(path, "foldsim_load_file: path") }?;
        let text = ScenarioText::from_file(Path::new(path)).map_err(|e| (FoldsimErrorRun, e.to_string()))?;
        load(text)
    })
}

/// Loads a scenario from its TOML text; `base_dir` (may be null: the current directory) is
/// where its table files are read from. Returns the simulation, or null with the reason in
/// [`foldsim_last_error`].
///
/// # Safety
/// `toml` and `base_dir` are null or NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_load_text(toml: *const c_char, base_dir: *const c_char) -> *mut FoldsimSimulation {
    guard(std::ptr::null_mut(), || {
        // SAFETY: the caller's promise.
        let toml = unsafe { arg(toml, "foldsim_load_text: toml") }?;
        let base = if base_dir.is_null() { "" } else { unsafe { arg(base_dir, "foldsim_load_text: base_dir") }? };
        let text = ScenarioText::new(toml, "<scenario text>", Path::new(base))
            .map_err(|e| (FoldsimErrorRun, e.to_string()))?;
        load(text)
    })
}

/// Sets the scenario's number at `key_path` (docs/scenario.md, "Key paths"; `*` sets every
/// list entry it matches) to `value`, before [`foldsim_start`]. The parameters are the
/// numbers the file writes as single values outside `[run]`; the changed scenario is checked
/// at once (a negative mass is refused here, and the change undone).
///
/// # Safety
/// `sim` is a live handle; `key_path` is null or NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_set_parameter(
    sim: *mut FoldsimSimulation,
    key_path: *const c_char,
    value: f64,
) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_set_parameter") }?;
        let path = unsafe { arg(key_path, "foldsim_set_parameter: key_path") }?;
        if s.session.is_some() {
            return Err((
                FoldsimErrorState,
                format!("foldsim_set_parameter({path}): the run has started; parameters are set before foldsim_start"),
            ));
        }
        let mut text = s.text.clone();
        parameters::set(&mut text, path, value).map_err(|e| (FoldsimErrorArgument, e))?;
        text.build().map_err(|e| (FoldsimErrorArgument, format!("foldsim_set_parameter({path} = {value}): {e}")))?;
        s.text = text;
        Ok(())
    })
}

/// Starts the run at t = 0: the scenario built with its parameters, the inputs set so far
/// applied. Fails if already started, or as a run's start fails.
///
/// # Safety
/// `sim` is a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_start(sim: *mut FoldsimSimulation) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_start") }?;
        if s.session.is_some() {
            return Err((FoldsimErrorState, "foldsim_start: the run has already started".into()));
        }
        let scenario = s.text.build().map_err(|e| (FoldsimErrorRun, e.to_string()))?;
        let mut session = Session::start(scenario).map_err(|e| (FoldsimErrorRun, e))?;
        for (k, v) in s.pending.iter().enumerate() {
            if let Some(v) = v {
                session.set_input(k, *v).map_err(|e| (FoldsimErrorArgument, e))?;
            }
        }
        s.session = Some(session);
        Ok(())
    })
}

/// The number of inputs (every body's six, every motor's, every actuator's); 0 for null.
///
/// # Safety
/// `sim` is null or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_input_count(sim: *const FoldsimSimulation) -> usize {
    // SAFETY: the caller's promise.
    unsafe { sim.as_ref() }.map_or(0, |s| s.inputs.len())
}

/// Input `index`'s name (`hub_T_z`), or null out of range; valid while the simulation lives.
///
/// # Safety
/// `sim` is null or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_input_name(sim: *const FoldsimSimulation, index: usize) -> *const c_char {
    // SAFETY: the caller's promise.
    unsafe { sim.as_ref() }.and_then(|s| s.input_names.get(index)).map_or(std::ptr::null(), |n| n.as_ptr())
}

/// The number of outputs (the CSV columns, docs/outputs.md); 0 for null.
///
/// # Safety
/// `sim` is null or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_output_count(sim: *const FoldsimSimulation) -> usize {
    // SAFETY: the caller's promise.
    unsafe { sim.as_ref() }.map_or(0, |s| s.output_names.len())
}

/// Output `index`'s name (`H_z`), or null out of range; valid while the simulation lives.
///
/// # Safety
/// `sim` is null or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_output_name(sim: *const FoldsimSimulation, index: usize) -> *const c_char {
    // SAFETY: the caller's promise.
    unsafe { sim.as_ref() }.and_then(|s| s.output_names.get(index)).map_or(std::ptr::null(), |n| n.as_ptr())
}

fn find(names: &[CString], name: &str, what: &str, call: &str) -> Result<usize, Failure> {
    names.iter().position(|n| n.as_bytes() == name.as_bytes()).ok_or_else(|| {
        let some: Vec<String> = names.iter().take(8).map(|n| n.to_string_lossy().into_owned()).collect();
        (
            FoldsimErrorArgument,
            format!(
                "{call}: no {what} named {name:?} (they are {}{})",
                some.join(", "),
                if names.len() > 8 { ", …" } else { "" }
            ),
        )
    })
}

/// Sets the input `name` (its unit: N, N·m; forces and torques in the body's own frame) to
/// `value` from now on, held until set again. Before the start it is applied at the start.
///
/// # Safety
/// `sim` is a live handle; `name` is null or NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_set_input(
    sim: *mut FoldsimSimulation,
    name: *const c_char,
    value: f64,
) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_set_input") }?;
        let name = unsafe { arg(name, "foldsim_set_input: name") }?;
        let k = find(&s.input_names, name, "input", "foldsim_set_input")?;
        set_input(s, k, value)
    })
}

/// As [`foldsim_set_input`], by the input's index (faster in a loop).
///
/// # Safety
/// `sim` is a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_set_input_at(sim: *mut FoldsimSimulation, index: usize, value: f64) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_set_input_at") }?;
        if index >= s.inputs.len() {
            return Err((
                FoldsimErrorArgument,
                format!("foldsim_set_input_at: index {index} is out of range: there are {} inputs", s.inputs.len()),
            ));
        }
        set_input(s, index, value)
    })
}

fn set_input(s: &mut FoldsimSimulation, k: usize, value: f64) -> Result<(), Failure> {
    if !value.is_finite() {
        return Err((
            FoldsimErrorArgument,
            format!(
                "input {}: the value must be a finite number ({}), got {value}",
                s.inputs[k].name,
                s.inputs[k].unit()
            ),
        ));
    }
    match s.session.as_mut() {
        Some(session) => session.set_input(k, value).map_err(|e| (FoldsimErrorArgument, e)),
        None => {
            s.pending[k] = Some(value);
            Ok(())
        }
    }
}

/// Integrates to exactly t + `dt` (s) with the scenario's integrator, the inputs held.
/// Fails for `dt` ≤ 0 or not finite, past `run.duration` (the run's horizon), before the
/// start, or as a run fails (the message says why; the state stays where it stopped).
///
/// # Safety
/// `sim` is a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_advance(sim: *mut FoldsimSimulation, dt: f64) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_advance") }?;
        let session = s
            .session
            .as_mut()
            .ok_or_else(|| (FoldsimErrorState, "foldsim_advance: call foldsim_start first".to_string()))?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err((FoldsimErrorArgument, format!("foldsim_advance: dt must be a finite number > 0 s, got {dt}")));
        }
        session.advance(dt).map_err(|e| (FoldsimErrorRun, e))
    })
}

/// Writes the time reached (s) to `*t`.
///
/// # Safety
/// `sim` is a live handle; `t` is null or points at a double.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_time(sim: *mut FoldsimSimulation, t: *mut f64) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_time") }?;
        let out =
            unsafe { t.as_mut() }.ok_or_else(|| (FoldsimErrorNull, "foldsim_time: t is a null pointer".to_string()))?;
        *out = s.session.as_ref().map_or(0.0, |s| s.time());
        Ok(())
    })
}

fn started<'a>(s: &'a mut FoldsimSimulation, call: &str) -> Result<&'a mut Session, Failure> {
    s.session.as_mut().ok_or_else(|| (FoldsimErrorState, format!("{call}: call foldsim_start first")))
}

/// Writes the output `name` at the time reached to `*value`.
///
/// # Safety
/// `sim` is a live handle; `name` is null or NUL-terminated; `value` is null or points at a
/// double.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_get_output(
    sim: *mut FoldsimSimulation,
    name: *const c_char,
    value: *mut f64,
) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_get_output") }?;
        let name = unsafe { arg(name, "foldsim_get_output: name") }?;
        let out = unsafe { value.as_mut() }
            .ok_or_else(|| (FoldsimErrorNull, "foldsim_get_output: value is a null pointer".to_string()))?;
        let k = find(&s.output_names, name, "output", "foldsim_get_output")?;
        *out = started(s, "foldsim_get_output")?.output(k).map_err(|e| (FoldsimErrorInternal, e))?;
        Ok(())
    })
}

/// Writes every output at the time reached to `values` (`count` must be
/// [`foldsim_output_count`]), in [`foldsim_output_name`]'s order.
///
/// # Safety
/// `sim` is a live handle; `values` is null or points at `count` doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_get_outputs(
    sim: *mut FoldsimSimulation,
    values: *mut f64,
    count: usize,
) -> FoldsimStatus {
    status(|| {
        // SAFETY: the caller's promise.
        let s = unsafe { handle(sim, "foldsim_get_outputs") }?;
        if values.is_null() {
            return Err((FoldsimErrorNull, "foldsim_get_outputs: values is a null pointer".into()));
        }
        let n = s.output_names.len();
        if count != n {
            return Err((
                FoldsimErrorArgument,
                format!("foldsim_get_outputs: count is {count}, but there are {n} outputs (foldsim_output_count)"),
            ));
        }
        let row = started(s, "foldsim_get_outputs")?.outputs();
        // SAFETY: the caller's promise: `values` holds `count` = n doubles.
        unsafe { std::slice::from_raw_parts_mut(values, n) }.copy_from_slice(row);
        Ok(())
    })
}

/// The last error's message on this thread (empty if none); valid until the next failing
/// call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn foldsim_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Frees a simulation (null is ignored).
///
/// # Safety
/// `sim` is null or a handle not yet freed; it is not used again.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn foldsim_free(sim: *mut FoldsimSimulation) {
    if !sim.is_null() {
        // SAFETY: the caller's promise; a drop that panicked would be a bug, kept from the host.
        let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(sim) })));
    }
}

/// foldsim's version ("0.1.0").
#[unsafe(no_mangle)]
pub extern "C" fn foldsim_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr() as *const c_char
}
