//! One FMU instance: the scenario text with its parameters, the inputs as set, the session
//! once the run has started, and the host's logger.

use crate::{ERROR, Logger, OK, Status};
use foldsim::export::fmu::{SCENARIO_FILE, VARIABLES_FILE, Variables};
use foldsim::scenario::{ScenarioText, SetValue};
use foldsim::session::{Session, parameters};
use std::ffi::{CString, c_char, c_void};
use std::path::PathBuf;

/// Where an instance is in FMI 2.0's co-simulation state machine (section 4.2.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// After fmi2Instantiate or fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    Initialization,
    /// Stepping.
    StepMode,
    /// After fmi2Terminate.
    Terminated,
    /// After an error: only reset, free and getters.
    Failed,
}

/// One FMU instance.
pub struct Instance {
    name: String,
    logger: Option<Logger>,
    env: *mut c_void,
    /// Whether the host asked for debug messages.
    pub logging_on: bool,
    /// The scenario as the FMU carries it (table paths relative to the resources).
    text: ScenarioText,
    variables: Variables,
    /// Parameter values as set (their start values until set).
    parameters: Vec<f64>,
    /// Input values as set (0 until set).
    inputs: Vec<f64>,
    /// Each FMU input's index among the session's inputs, each output's among its outputs.
    input_index: Vec<usize>,
    output_index: Vec<usize>,
    tolerance: Option<f64>,
    /// The host's start time, s: the run's t = 0.
    start: f64,
    stop: Option<f64>,
    session: Option<Session>,
    /// Where the instance is.
    pub phase: Phase,
}

/// Calls the host's logger with `message` (passed through `%s`, so no `%` in it is read as a
/// format).
pub fn log(logger: Option<Logger>, env: *mut c_void, name: &str, status: Status, message: &str) {
    let Some(logger) = logger else { return };
    let clean = |s: &str| CString::new(s.replace('\0', " ")).unwrap_or_default();
    let (name, message) = (clean(name), clean(message));
    let category: &std::ffi::CStr = if status >= ERROR { c"logStatusError" } else { c"logAll" };
    // SAFETY: the host's logger, called as FMI 2.0 section 2.1.5 defines it: every string
    // NUL-terminated and alive for the call, the format "%s" with one string argument.
    unsafe { logger(env, name.as_ptr(), status, category.as_ptr(), c"%s".as_ptr(), message.as_ptr() as *const c_char) };
}

/// The directory of a `file:` URI (`file:///a/b`, `file:/a/b`, percent-encoded).
fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let rest = uri
        .strip_prefix("file://localhost")
        .or_else(|| uri.strip_prefix("file://"))
        .or_else(|| uri.strip_prefix("file:"))
        .ok_or_else(|| format!("the resource location {uri:?} is not a file: URI"))?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        let hex =
            |k: usize| std::str::from_utf8(&bytes[k + 1..k + 3]).ok().and_then(|h| u8::from_str_radix(h, 16).ok());
        if let Some(b) = (bytes[k] == b'%' && k + 2 < bytes.len()).then(|| hex(k)).flatten() {
            out.push(b);
            k += 3;
            continue;
        }
        out.push(bytes[k]);
        k += 1;
    }
    let path = String::from_utf8(out).map_err(|_| format!("the resource location {uri:?} is not UTF-8"))?;
    Ok(PathBuf::from(path))
}

impl Instance {
    /// Reads the FMU's resources and checks the scenario builds.
    pub fn new(
        name: &str,
        guid: Option<&str>,
        location: Option<&str>,
        logger: Option<Logger>,
        env: *mut c_void,
        logging_on: bool,
    ) -> Result<Self, String> {
        let dir =
            resource_dir(location.ok_or("no resource location given: the FMU's resources/ directory is needed")?)?;
        let vars_path = dir.join(VARIABLES_FILE);
        let vars_text =
            std::fs::read_to_string(&vars_path).map_err(|e| format!("cannot read {}: {e}", vars_path.display()))?;
        let variables: Variables = toml::from_str(&vars_text).map_err(|e| format!("{}: {e}", vars_path.display()))?;
        if guid != Some(variables.guid.as_str()) {
            return Err(format!(
                "the GUID {:?} is not this FMU's ({}): the model description and the binary come from different exports",
                guid.unwrap_or(""),
                variables.guid
            ));
        }
        let text = ScenarioText::from_file(&dir.join(SCENARIO_FILE)).map_err(|e| e.to_string())?;
        let mut probe = text.build().map_err(|e| e.to_string())?;
        probe.model.commandable = true;
        let session_inputs = foldsim::session::Inputs::of(&probe.model);
        let input_index = variables.inputs.iter().map(|n| session_inputs.index(n)).collect::<Result<Vec<_>, _>>()?;
        let columns: Vec<String> = foldsim::observe::catalogue(&probe.model).into_iter().map(|c| c.name).collect();
        let output_index = variables
            .outputs
            .iter()
            .map(|n| columns.iter().position(|c| c == n).ok_or_else(|| format!("output {n} is not the scenario's")))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            name: name.to_string(),
            logger,
            env,
            logging_on,
            text,
            parameters: variables.parameters.iter().map(|p| p.start).collect(),
            inputs: vec![0.0; variables.inputs.len()],
            variables,
            input_index,
            output_index,
            tolerance: None,
            start: 0.0,
            stop: None,
            session: None,
            phase: Phase::Instantiated,
        })
    }

    /// Logs `message` as an error, marks the instance failed and returns `fmi2Error`.
    pub fn fail(&mut self, message: &str) -> Status {
        log(self.logger, self.env, &self.name, ERROR, message);
        self.phase = Phase::Failed;
        ERROR
    }

    /// Refuses a call made in the wrong phase.
    fn expect(&mut self, call: &str, allowed: &[Phase]) -> Result<(), Status> {
        if allowed.contains(&self.phase) {
            Ok(())
        } else {
            Err(self.fail(&format!("{call} is not allowed now (the instance is {:?})", self.phase)))
        }
    }

    /// `fmi2SetupExperiment`.
    pub fn setup(&mut self, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> Status {
        if let Err(s) = self.expect("fmi2SetupExperiment", &[Phase::Instantiated]) {
            return s;
        }
        if !start.is_finite() {
            return self.fail(&format!("fmi2SetupExperiment: the start time must be finite, got {start}"));
        }
        if let Some(t) = tolerance.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return self.fail(&format!("fmi2SetupExperiment: the tolerance must be a finite number > 0, got {t}"));
        }
        if let Some(s) = stop.filter(|s| !(s.is_finite() && *s > start)) {
            return self.fail(&format!(
                "fmi2SetupExperiment: the stop time must be finite and after the start time {start}, got {s}"
            ));
        }
        self.tolerance = tolerance;
        self.start = start;
        self.stop = stop;
        OK
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization(&mut self) -> Status {
        match self.expect("fmi2EnterInitializationMode", &[Phase::Instantiated]) {
            Ok(()) => {
                self.phase = Phase::Initialization;
                OK
            }
            Err(s) => s,
        }
    }

    /// `fmi2ExitInitializationMode`: starts the run.
    pub fn exit_initialization(&mut self) -> Status {
        if let Err(s) = self.expect("fmi2ExitInitializationMode", &[Phase::Initialization]) {
            return s;
        }
        if let Err(m) = self.ensure_session() {
            return self.fail(&m);
        }
        self.phase = Phase::StepMode;
        OK
    }

    /// `fmi2Reset`.
    pub fn reset(&mut self) -> Status {
        self.session = None;
        self.parameters = self.variables.parameters.iter().map(|p| p.start).collect();
        self.inputs.iter_mut().for_each(|v| *v = 0.0);
        self.tolerance = None;
        self.start = 0.0;
        self.stop = None;
        self.phase = Phase::Instantiated;
        OK
    }

    /// The host's time reached, s.
    pub fn time(&self) -> f64 {
        self.start + self.session.as_ref().map_or(0.0, |s| s.time())
    }

    /// Builds and starts the run with the parameters and the host's horizon, and sets every
    /// input (a motor's or actuator's replaces its drive from the start).
    fn ensure_session(&mut self) -> Result<(), String> {
        if self.session.is_some() {
            return Ok(());
        }
        let mut text = self.text.clone();
        for (p, v) in self.variables.parameters.iter().zip(&self.parameters) {
            if *v != p.start {
                parameters::set(&mut text, &p.path, *v)?;
            }
        }
        if let Some(stop) = self.stop {
            // The host's horizon; the FMU's outputs are read at its communication points and
            // it keeps no rows, so `run.output_step` is set to the horizon: a day-long
            // co-simulation of a scenario written with 5-ms rows is not refused for its row
            // count.
            text.set("run.duration", &SetValue::Number(stop - self.start))?;
            text.set("run.output_step", &SetValue::Number(stop - self.start))?;
        }
        if let Some(tol) = self.tolerance {
            text.set("run.rtol", &SetValue::Number(tol))?;
        }
        let scenario = text.build().map_err(|e| e.to_string())?;
        let mut session = Session::start(scenario)?;
        for (k, v) in self.input_index.iter().zip(&self.inputs) {
            session.set_input(*k, *v)?;
        }
        self.session = Some(session);
        Ok(())
    }

    /// `fmi2GetReal`.
    pub fn get_real(&mut self, vr: &[u32], out: &mut [f64]) -> Status {
        let (no, ni) = (self.variables.outputs.len(), self.variables.inputs.len());
        let needs_outputs = vr.iter().any(|&r| (r as usize) < no);
        if needs_outputs && self.session.is_none() {
            if self.phase == Phase::Instantiated {
                return self.fail("fmi2GetReal: outputs are known from initialization mode on");
            }
            if let Err(m) = self.ensure_session() {
                return self.fail(&m);
            }
        }
        for (r, o) in vr.iter().zip(out.iter_mut()) {
            let r = *r as usize;
            *o = if r < no {
                let index = self.output_index[r];
                match self.session.as_mut().map(|s| s.output(index)) {
                    Some(Ok(v)) => v,
                    Some(Err(m)) => return self.fail(&m),
                    None => return self.fail("fmi2GetReal: the run has not started"),
                }
            } else if r < no + ni {
                self.inputs[r - no]
            } else if let Some(p) = self.parameters.get(r - no - ni) {
                *p
            } else {
                return self.fail(&format!("fmi2GetReal: no variable has value reference {r}"));
            };
        }
        OK
    }

    /// `fmi2SetReal`.
    pub fn set_real(&mut self, vr: &[u32], values: &[f64]) -> Status {
        if let Err(s) = self.expect("fmi2SetReal", &[Phase::Instantiated, Phase::Initialization, Phase::StepMode]) {
            return s;
        }
        let (no, ni) = (self.variables.outputs.len(), self.variables.inputs.len());
        for (r, v) in vr.iter().zip(values) {
            let r = *r as usize;
            if !v.is_finite() {
                let name = self.name_of(r);
                return self.fail(&format!("fmi2SetReal: {name} must be a finite number, got {v}"));
            }
            if r < no {
                let name = self.name_of(r);
                return self.fail(&format!("fmi2SetReal: {name} is an output; only inputs and parameters are set"));
            } else if r < no + ni {
                self.inputs[r - no] = *v;
                let index = self.input_index[r - no];
                if let Some(Err(m)) = self.session.as_mut().map(|s| s.set_input(index, *v)) {
                    return self.fail(&m);
                }
            } else if r - no - ni < self.parameters.len() {
                if self.phase == Phase::StepMode {
                    let name = self.name_of(r);
                    return self.fail(&format!("fmi2SetReal: parameter {name} is fixed once the run has started"));
                }
                self.parameters[r - no - ni] = *v;
                self.session = None;
            } else {
                return self.fail(&format!("fmi2SetReal: no variable has value reference {r}"));
            }
        }
        OK
    }

    /// A variable's name by value reference.
    fn name_of(&self, r: usize) -> String {
        let v = &self.variables;
        v.outputs
            .iter()
            .chain(&v.inputs)
            .chain(v.parameters.iter().map(|p| &p.path))
            .nth(r)
            .cloned()
            .unwrap_or_else(|| format!("value reference {r}"))
    }

    /// `fmi2DoStep`.
    pub fn do_step(&mut self, current: f64, step: f64) -> Status {
        if let Err(s) = self.expect("fmi2DoStep", &[Phase::StepMode]) {
            return s;
        }
        let reached = self.time();
        if !(current.is_finite() && (current - reached).abs() <= 1e-9 * reached.abs().max(1.0)) {
            return self.fail(&format!(
                "fmi2DoStep: the communication point {current} s is not the time this FMU has reached, {reached} s"
            ));
        }
        let Some(session) = self.session.as_mut() else { return self.fail("fmi2DoStep: the run has not started") };
        match session.advance(step) {
            Ok(()) => OK,
            Err(m) => {
                let t = self.time();
                self.fail(&format!("fmi2DoStep from {current} s by {step} s failed (the run stands at {t} s): {m}"))
            }
        }
    }
}
