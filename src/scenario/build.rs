//! A scenario ready to run: read, checked and turned into a model, initial conditions and
//! run settings.

use super::bodies::body;
use super::error::{Ctx, ScenarioError, enclosing_item, in_user_words};
use super::laws::law;
use super::raw::{RawBody, RawFrame, RawHinge, RawRun, RawScenario};
use super::values::{angles, angular_rate, check_finite, check_name, positive, vec3};
use crate::dynamics::Dynamics;
use crate::integrate::ErrorNorm;
use crate::kinematics::{HingeInitial, InitialConditions, RelativeTwist, initial_state};
use crate::model::{HingeSpec, Model, ModelError, ParentFrame};
use crate::observe::{Selection, catalogue};
use crate::simulate::settings::{MAX_DEFAULT_STEP_BUDGET, MAX_OUTPUT_ROWS, MIN_STEP_OF_DURATION, default_step_budget};
use crate::simulate::{Integrator, RunSettings};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// A scenario ready to run.
#[derive(Debug)]
pub struct Scenario {
    /// Optional title from the file.
    pub title: Option<String>,
    /// The structure.
    pub model: Model,
    /// Initial conditions (relative coordinates).
    pub initial: InitialConditions,
    /// Duration, output step and integrator.
    pub settings: RunSettings,
    /// Output CSV path from `run.csv`, resolved against the scenario file's directory.
    pub csv: Option<PathBuf>,
    /// The output columns written (`run.columns`; the default set if not given).
    pub columns: Selection,
    /// The files read to make it: the scenario file (when read from one) and every table
    /// file. No output may be written over them.
    pub inputs: Vec<PathBuf>,
    /// Warnings about values that are valid but probably not meant (an angle in radians
    /// above a turn), located by file, line and column.
    pub warnings: Vec<String>,
}

// ---------------------------------------------------------------------------------------

impl Scenario {
    /// Reads and checks a scenario file.
    pub fn from_file(path: &Path) -> Result<Self, ScenarioError> {
        let text = read_file(path)?;
        let s = Self::from_toml_in(&text, &path.display().to_string(), path.parent().unwrap_or(Path::new("")))?;
        Ok(s.read_from(path))
    }

    /// The scenario as read from `path`: `run.csv` relative to the file's directory, the
    /// file first among the inputs.
    pub(super) fn read_from(mut self, path: &Path) -> Self {
        let base = path.parent().unwrap_or(Path::new(""));
        if let Some(csv) = &self.csv {
            self.csv = Some(base.join(csv));
        }
        self.inputs.insert(0, path.to_path_buf());
        self
    }

    /// Parses and checks scenario text; `file` labels error messages; relative table paths
    /// are resolved against the current directory.
    pub fn from_toml(text: &str, file: &str) -> Result<Self, ScenarioError> {
        Self::from_toml_in(text, file, Path::new(""))
    }

    /// As [`Scenario::from_toml`], resolving relative table paths against `base`.
    pub fn from_toml_in(text: &str, file: &str, base: &Path) -> Result<Self, ScenarioError> {
        let ctx = Ctx { file, text, base, inputs: Default::default(), warnings: Default::default() };
        let raw: RawScenario = parse_toml(&ctx)?;
        build(&ctx, raw)
    }
}

/// `ctx`'s text read into `T`, TOML errors worded for users and located, every number checked
/// finite (a scenario file, or a law file: `super::law_file`).
pub(super) fn parse_toml<T: serde::de::DeserializeOwned>(ctx: &Ctx<'_>) -> Result<T, ScenarioError> {
    let text = ctx.text;
    let raw: T = toml::from_str(text).map_err(|e| {
        let message = in_user_words(e.message().trim(), text, e.span());
        let message = match e.span().and_then(|span| enclosing_item(text, span.start)) {
            Some(item) => format!("{item}: {message}"),
            None => message,
        };
        ctx.at(e.span(), message)
    })?;
    check_finite(ctx)?;
    Ok(raw)
}

/// A scenario file's text; an error names the file.
pub(super) fn read_file(path: &Path) -> Result<String, ScenarioError> {
    std::fs::read_to_string(path).map_err(|e| ScenarioError {
        file: path.display().to_string(),
        location: None,
        message: format!("cannot read the scenario file: {e}"),
    })
}

use crate::simulate::settings::MIN_RTOL;

fn build(ctx: &Ctx<'_>, raw: RawScenario) -> Result<Scenario, ScenarioError> {
    // Run settings.
    let run = raw.run.get_ref();
    let duration = positive(ctx, &run.duration, "run.duration", "s")?;
    let output_step = positive(ctx, &run.output_step, "run.output_step", "s")?;
    if duration / output_step > MAX_OUTPUT_ROWS {
        return Err(ctx.span(
            &run.output_step,
            format!(
                "'run.output_step' = {output_step:e} s gives {:.1e} output rows over {duration} s; at most {MAX_OUTPUT_ROWS:e}: give at least {:.3e} s",
                duration / output_step,
                duration / MAX_OUTPUT_ROWS
            ),
        ));
    }
    // No integrator: "auto" (DOP853, and SDIRK4 where stiffness holds DOP853 back).
    let integrator_name = run.integrator.as_ref().map_or("auto", |s| s.get_ref().as_str());
    // run.position_tolerance sets rtol and atol itself (crate::simulate::accuracy).
    let position_tolerance = match &run.position_tolerance {
        Some(x) => Some(positive(ctx, x, "run.position_tolerance", "m")?),
        None => None,
    };
    let need = |v: &Option<Spanned<f64>>, key: &str, what: &str| -> Result<f64, ScenarioError> {
        match (v, position_tolerance) {
            (Some(x), Some(_)) if key == "run.rtol" || key == "run.atol" => Err(ctx.span(
                x,
                format!("'{key}' and 'run.position_tolerance' both given: the position tolerance sets rtol and atol itself; give one or the other"),
            )),
            // Replaced run by run; the first candidate's below, meanwhile (what a trial runs at).
            (None, Some(p)) if key == "run.rtol" || key == "run.atol" => Ok(p),
            (Some(x), _) => positive(ctx, x, key, ""),
            (None, _) => Err(ctx.span(&raw.run, format!("[run] needs '{key}' ({what}) for integrator '{integrator_name}'"))),
        }
    };
    if let Some(x) = &run.position_tolerance
        && (integrator_name == "rk4" || (integrator_name == "generalized-alpha" && run.step.is_some()))
    {
        return Err(ctx.span(
            x,
            format!("'run.position_tolerance' needs an adaptive integrator (\"auto\", \"dop853\", \"dopri5\", \"sdirk4\", or \"generalized-alpha\" without run.step); '{integrator_name}' at a fixed run.step has no tolerance to set"),
        ));
    }
    let forbid = |v: &Option<Spanned<f64>>, key: &str| -> Result<(), ScenarioError> {
        match v {
            Some(x) => Err(ctx.span(x, format!("'{key}' does not apply to integrator '{integrator_name}'"))),
            None => Ok(()),
        }
    };
    // By default "auto" steps over stiff vibrations; "sdirk4" keeps Hairer's norm, as it
    // always had, and so does "auto" with contact: impacts need their rates (restitution
    // acts on the impact velocity), and the thick flasher example under the displacement
    // norm projected 29 min against 39 s (docs/scenario.md says why both norms exist).
    // Generalized-α without a step is adaptive, and weighs its error as "auto" does.
    let adaptive_alpha = integrator_name == "generalized-alpha" && run.step.is_none();
    let error_norm = match run.error_norm.as_ref().map(|s| (s, s.get_ref().as_str())) {
        None if (integrator_name == "auto" || adaptive_alpha) && raw.contact.is_none() => ErrorNorm::Displacement,
        None => ErrorNorm::State,
        Some((_, "displacement")) => ErrorNorm::Displacement,
        Some((_, "state")) => ErrorNorm::State,
        Some((x, other)) => {
            return Err(ctx.span(
                x,
                format!("unknown run.error_norm '{other}'; valid: \"displacement\" (rates weighed by the step; the default of \"auto\"), \"state\" (every component as it is; the default of \"sdirk4\")"),
            ));
        }
    };
    if let (Some(x), "dop853" | "dopri5" | "rk4" | "generalized-alpha") = (&run.error_norm, integrator_name)
        && !adaptive_alpha
    {
        let why = if integrator_name == "generalized-alpha" {
            "at a fixed run.step it has no error control; leave run.step out for adaptive steps"
        } else {
            "its error control weighs every component as it is"
        };
        return Err(ctx.span(
            x,
            format!("'run.error_norm' applies to the implicit steps of integrator \"sdirk4\", \"auto\" or an adaptive \"generalized-alpha\", not to '{integrator_name}' ({why})"),
        ));
    }
    let integrator = match integrator_name {
        name @ ("dop853" | "dopri5" | "sdirk4" | "auto") => {
            forbid(&run.step, "run.step")?;
            forbid(&run.rho_inf, "run.rho_inf")?;
            let rtol = need(&run.rtol, "run.rtol", "relative tolerance, e.g. 1e-10")?;
            let atol = need(&run.atol, "run.atol", "absolute tolerance, e.g. 1e-10")?;
            check_rtol(ctx, run, rtol)?;
            match name {
                "dop853" => Integrator::Dop853 { rtol, atol },
                "dopri5" => Integrator::Dopri5 { rtol, atol },
                "auto" => Integrator::Auto { rtol, atol },
                _ => Integrator::Sdirk4 { rtol, atol },
            }
        }
        "rk4" => {
            forbid(&run.rtol, "run.rtol")?;
            forbid(&run.atol, "run.atol")?;
            forbid(&run.rho_inf, "run.rho_inf")?;
            Integrator::Rk4 { step: fixed_step(ctx, run, duration, need(&run.step, "run.step", "fixed step in s")?)? }
        }
        "generalized-alpha" => {
            // With run.step a fixed step (rtol and atol are Newton's); without, adaptive.
            let step = match &run.step {
                Some(x) => Some(fixed_step(ctx, run, duration, positive(ctx, x, "run.step", "")?)?),
                None => None,
            };
            let what = if step.is_some() { "of the Newton iterations" } else { "of each step's error" };
            let rtol = need(&run.rtol, "run.rtol", &format!("relative tolerance {what}, e.g. 1e-6"))?;
            check_rtol(ctx, run, rtol)?;
            let atol = need(&run.atol, "run.atol", &format!("absolute tolerance {what}, e.g. 1e-6"))?;
            let rho_inf = match &run.rho_inf {
                None => DEFAULT_RHO_INF,
                Some(x) if (0.0..=1.0).contains(x.get_ref()) => *x.get_ref(),
                Some(x) => {
                    return Err(ctx.span(
                        x,
                        format!(
                            "'run.rho_inf' = {} is not a spectral radius: give a number from 0 (the most numerical damping) to 1 (none)",
                            x.get_ref()
                        ),
                    ));
                }
            };
            Integrator::GeneralizedAlpha { step, rho_inf, rtol, atol }
        }
        other => {
            let message = format!(
                "unknown integrator '{other}'; valid: \"auto\" (the default), \"dop853\", \"dopri5\", \"sdirk4\", \"generalized-alpha\", \"rk4\""
            );
            return Err(match &run.integrator {
                Some(x) => ctx.span(x, message),
                None => ctx.span(&raw.run, message),
            });
        }
    };
    let integrator = match position_tolerance {
        Some(p) => crate::simulate::accuracy::with_tolerance(
            integrator,
            crate::simulate::accuracy::first_tolerance(integrator, p),
        ),
        None => integrator,
    };
    let max_steps = match &run.max_steps {
        None => None,
        Some(v) if *v.get_ref() > 0 => Some(*v.get_ref() as usize),
        Some(v) => return Err(ctx.span(v, format!("'run.max_steps' must be a whole number > 0, got {}", v.get_ref()))),
    };
    let release_at = match &run.release_at {
        None => None,
        Some(v) if *v.get_ref() > 0.0 && *v.get_ref() < duration => Some(*v.get_ref()),
        Some(v) => {
            return Err(ctx.span(
                v,
                format!(
                    "'run.release_at' must lie between 0 and run.duration = {} s, got {}",
                    crate::math::short(duration),
                    crate::math::short(*v.get_ref())
                ),
            ));
        }
    };
    let settings = RunSettings {
        duration,
        output_step,
        integrator,
        error_norm,
        engage_locks_at_start: false,
        max_steps,
        release_at,
        hinge_loads: false,
        position_tolerance,
    };

    // Bodies.
    if raw.bodies.is_empty() {
        return Err(ctx.at(None, "no [[body]] given; the first [[body]] is the hub"));
    }
    let mut body_index: HashMap<String, usize> = HashMap::new();
    let mut bodies = Vec::with_capacity(raw.bodies.len());
    for (i, b) in raw.bodies.iter().enumerate() {
        let name = b.name.get_ref();
        check_name(ctx, &b.name, "body")?;
        if body_index.insert(name.clone(), i).is_some() {
            return Err(ctx.span(&b.name, format!("duplicate body name '{name}'; body names must be unique")));
        }
        bodies.push(body(ctx, b)?);
    }

    // Hinges.
    let mut hinge_index: HashMap<String, usize> = HashMap::new();
    let mut specs = Vec::with_capacity(raw.hinges.len());
    for (i, h) in raw.hinges.iter().enumerate() {
        let name = h.name.get_ref();
        check_name(ctx, &h.name, "hinge")?;
        if hinge_index.insert(name.clone(), i).is_some() {
            return Err(ctx.span(&h.name, format!("duplicate hinge name '{name}'; hinge names must be unique")));
        }
        let lookup = |s: &Spanned<String>, key: &str| {
            body_index.get(s.get_ref()).copied().ok_or_else(|| {
                ctx.span(
                    s,
                    format!(
                        "hinge '{name}': {key} '{}' is not a body; bodies are: {}",
                        s.get_ref(),
                        names(&raw.bodies)
                    ),
                )
            })
        };
        let parent = lookup(&h.parent, "parent")?;
        let child = lookup(&h.child, "child")?;
        let parent_frame = parent_frame(ctx, name, &h.a0)?;
        let a = h.a.get_ref();
        let theta_c_a = angles(a.yaw, a.yaw_deg, a.pitch, a.pitch_deg, a.roll, a.roll_deg)
            .map_err(|m| ctx.span(&h.a, format!("hinge '{name}' a: {m}")))?
            .unwrap_or_default();
        let law = law(ctx, name, &h.law)?;
        let r_child_in_a = vec3(Some(a.child_com));
        let a0_offset = match &parent_frame {
            ParentFrame::Given { r_a0_in_parent, .. } => r_a0_in_parent.norm(),
            ParentFrame::Assembled => 0.0,
        };
        for (offset, body, what, span) in
            [(a0_offset, parent, "a0.position", h.a0.span()), (r_child_in_a.norm(), child, "a.child_com", h.a.span())]
        {
            let size = body_size(&bodies[body]);
            if offset > FAR_HINGE * size && offset > 1.0 {
                ctx.warn(
                    span,
                    format!(
                        "hinge '{name}': {what} puts the hinge {offset:.4} m from body '{}''s centre of mass, {:.0} times the body's size ({size:.3} m): a length in mm where m was meant?",
                        bodies[body].name,
                        offset / size
                    ),
                );
            }
        }
        specs.push(HingeSpec {
            name: name.clone(),
            parent,
            child,
            parent_frame,
            r_child_in_a,
            dcm_child_a: theta_c_a.to_dcm(),
            law,
        });
    }

    // Initial conditions.
    /// How closely `[initial.loop.NAME]` angles must match the bodies' poses, rad.
    const LOOP_ANGLE_AGREEMENT: f64 = 1e-6;
    let mut ic = InitialConditions {
        hinges: vec![None; specs.len()],
        body_attitudes: vec![None; bodies.len()],
        loop_angles: vec![None; specs.len()],
        ..Default::default()
    };
    if let Some(hub) = &raw.initial.hub {
        let r = hub.get_ref();
        ic.hub_position_in_n = vec3(r.position);
        ic.hub_velocity_in_n = vec3(r.velocity);
        ic.hub_omega_in_hub = angular_rate("omega", r.omega, r.omega_deg_s, r.omega_rpm)
            .map_err(|m| ctx.span(hub, format!("initial.hub: {m}")))?;
        ic.hub_attitude = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(hub, format!("initial.hub: {m}")))?
            .unwrap_or_default();
    }
    let mut preferred = Vec::new();
    for (key, v) in &raw.initial.hinge {
        let Some(&i) = hinge_index.get(key.get_ref()) else {
            return Err(ctx.span(
                key,
                format!(
                    "initial.hinge.{}: no hinge of that name; hinges are: {}",
                    key.get_ref(),
                    hinge_names(&raw.hinges)
                ),
            ));
        };
        let r = v.get_ref();
        let theta = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(v, format!("initial.hinge.{}: {m}", key.get_ref())))?;
        ic.hinges[i] = Some(HingeInitial {
            twist: RelativeTwist {
                delta_in_a0: vec3(r.delta),
                delta_rate_in_a0: vec3(r.delta_rate),
                omega_rel_in_a: angular_rate("omega_rel", r.omega_rel, r.omega_rel_deg_s, r.omega_rel_rpm)
                    .map_err(|m| ctx.span(v, format!("initial.hinge.{}: {m}", key.get_ref())))?,
            },
            theta,
        });
        preferred.push(i);
    }
    preferred.sort_unstable();
    let mut attitude_keys = HashMap::new();
    for (key, v) in &raw.initial.body {
        let Some(&i) = body_index.get(key.get_ref()) else {
            return Err(ctx.span(
                key,
                format!("initial.body.{}: no body of that name; bodies are: {}", key.get_ref(), names(&raw.bodies)),
            ));
        };
        if i == 0 {
            return Err(ctx.span(
                key,
                format!("initial.body.{}: that is the hub; give its attitude in [initial.hub]", key.get_ref()),
            ));
        }
        let r = v.get_ref();
        let att = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(v, format!("initial.body.{}: {m}", key.get_ref())))?;
        ic.body_attitudes[i] = att;
        attitude_keys.insert(i, key.span());
    }

    let mut loop_keys = Vec::new();
    for (key, v) in &raw.initial.loop_hinge {
        let Some(&i) = hinge_index.get(key.get_ref()) else {
            return Err(ctx.span(
                key,
                format!(
                    "initial.loop.{}: no hinge of that name; hinges are: {}",
                    key.get_ref(),
                    hinge_names(&raw.hinges)
                ),
            ));
        };
        let r = v.get_ref();
        let near = angles(r.yaw, r.yaw_deg, r.pitch, r.pitch_deg, r.roll, r.roll_deg)
            .map_err(|m| ctx.span(v, format!("initial.loop.{}: {m}", key.get_ref())))?
            .unwrap_or_default();
        if ic.hinges[i].is_some() {
            return Err(ctx.span(
                key,
                format!(
                    "initial.loop.{0}: hinge '{0}' also has [initial.hinge.{0}]; give a loop hinge's angles here, a tree hinge's there",
                    key.get_ref()
                ),
            ));
        }
        ic.loop_angles[i] = Some(near);
        loop_keys.push((i, v.span()));
    }

    let model = Model::new(bodies, specs, &preferred).map_err(|e| model_error(ctx, &raw, e))?;

    // A loop hinge's angles follow from the bodies; the ones given only pick the branch, so
    // they must agree with the bodies (modulo whole turns) to 1e-6 rad.
    if !loop_keys.is_empty() {
        let (_, refs) = crate::kinematics::initial_state(&model, &ic);
        for (i, span) in loop_keys {
            let name = &model.hinges[i].name;
            if model.is_tree_hinge[i] {
                return Err(ctx.at(
                    Some(span),
                    format!(
                        "initial.loop.{name}: hinge '{name}' is a tree hinge (its angles place a body); give its angles in [initial.hinge.{name}]"
                    ),
                ));
            }
            let (given, start) = (ic.loop_angles[i].unwrap_or_default(), refs[i]);
            let off = (given.yaw - start.yaw)
                .abs()
                .max((given.pitch - start.pitch).abs())
                .max((given.roll - start.roll).abs());
            if off.is_nan() || off > LOOP_ANGLE_AGREEMENT {
                return Err(ctx.at(
                    Some(span),
                    format!(
                        "initial.loop.{name}: the bodies put this loop hinge at yaw {:.9}, pitch {:.9}, roll {:.9} rad; the angles given ({:.9}, {:.9}, {:.9}) must agree to {LOOP_ANGLE_AGREEMENT:e} rad (they only choose between ±180° and add whole turns)",
                        start.yaw, start.pitch, start.roll, given.yaw, given.pitch, given.roll
                    ),
                ));
            }
        }
    }

    // A body attitude replaces the angles of the tree hinge that places that body.
    for e in &model.tree {
        if let (Some(span), Some(Some(HingeInitial { theta: Some(_), .. }))) =
            (attitude_keys.get(&e.to), ic.hinges.get(e.hinge))
        {
            return Err(ctx.at(
                Some(span.clone()),
                format!(
                    "initial.body.{} gives the attitude of a body whose tree hinge '{}' also has initial angles; give one or the other",
                    model.bodies[e.to].name, model.hinges[e.hinge].name
                ),
            ));
        }
    }

    let mut seen = std::collections::HashSet::new();
    for c in catalogue(&model).iter().map(|c| &c.name) {
        if !seen.insert(c.clone()) {
            return Err(ctx.at(
                None,
                format!("output column '{c}' would appear twice; rename the body or hinge whose name makes it"),
            ));
        }
    }

    let mut model = model;
    if let Some(c) = &raw.contact {
        super::contact::enable(ctx, c, &mut model, &ic)?;
    }
    super::loads::add(ctx, &raw.loads, &mut model, duration)?;
    super::actuators::add_motors(ctx, &raw.motors, &mut model, duration)?;
    if let Some(c) = &raw.control {
        super::actuators::add_control(ctx, c, &mut model, duration)?;
    }

    // Every run must end: an explicit method that must follow the fastest hinge for this
    // long would take more steps than any run should (the user may insist).
    if settings.max_steps.is_none()
        && !matches!(settings.integrator, Integrator::Sdirk4 { .. } | Integrator::Auto { .. })
        && default_step_budget(&model, duration) > MAX_DEFAULT_STEP_BUDGET
        && let Some(fastest) = model.fastest_hinge()
    {
        return Err(ctx.span(
            &raw.hinges[fastest.hinge].name,
            format!(
                "{}: following it with integrator '{}' for {duration} s takes about {:.1e} steps. Use integrator = \"sdirk4\" (it steps over stiff vibrations), make the hinge softer or its bodies heavier, or set run.max_steps to insist",
                fastest.describe(&model),
                settings.integrator.name(),
                duration * fastest.rate / 3.0
            ),
        ));
    }

    // The initial state's loads and accelerations must be finite (an overflow would
    // otherwise show only as a step size that collapses).
    {
        let (y0, refs) = initial_state(&model, &ic);
        let dynamics = Dynamics::new(&model, refs);
        dynamics.initialize_memory(&y0);
        if let Some(cause) = dynamics.non_finite_cause(&y0) {
            return Err(ctx.at(None, format!("the initial state: {cause}")));
        }
        if let Err((h, message)) = dynamics.check_locks(&y0) {
            return Err(ctx.span(&raw.hinges[h].name, message));
        }
    }

    let columns = match &run.columns {
        None => Selection::default_for(&model),
        Some(patterns) => Selection::matching(&model, patterns.get_ref())
            .map_err(|m| ctx.span(patterns, format!("run.columns: {m}")))?,
    };

    let settings = RunSettings { hinge_loads: columns.has_hinge_loads(), ..settings };
    Ok(Scenario {
        title: raw.title,
        model,
        initial: ic,
        settings,
        csv: run.csv.as_ref().map(PathBuf::from),
        columns,
        inputs: ctx.inputs.take(),
        warnings: ctx.warnings.take(),
    })
}

fn names(bodies: &[RawBody]) -> String {
    bodies.iter().map(|b| b.name.get_ref().as_str()).collect::<Vec<_>>().join(", ")
}

fn hinge_names(hinges: &[RawHinge]) -> String {
    hinges.iter().map(|h| h.name.get_ref().as_str()).collect::<Vec<_>>().join(", ")
}

/// A hinge this many times a body's size from its centre of mass draws a warning.
const FAR_HINGE: f64 = 100.0;

/// A body's size, m: the radius of its shape's outline, or at least its radius of gyration
/// `√(tr I / 2m)` (a body without a shape has only its inertia to go by).
fn body_size(b: &crate::model::Body) -> f64 {
    let gyration = (b.inertia_in_body.trace() / (2.0 * b.mass)).sqrt();
    let outline = b.shape.as_ref().map_or(0.0, |s| s.outline().iter().map(|p| p.norm()).fold(0.0, f64::max));
    gyration.max(outline)
}

fn parent_frame(ctx: &Ctx<'_>, hinge: &str, v: &Spanned<toml::Value>) -> Result<ParentFrame, ScenarioError> {
    let help = "a0 must be \"assembled\" or a table { position = [x, y, z] (m, parent frame), yaw_deg = .., pitch_deg = .., roll_deg = .. }";
    match v.get_ref() {
        toml::Value::String(s) if s == "assembled" => Ok(ParentFrame::Assembled),
        toml::Value::Table(_) => {
            let f: RawFrame = v.get_ref().clone().try_into().map_err(|e: toml::de::Error| {
                ctx.span(v, format!("hinge '{hinge}' a0: {}; {help}", e.message().trim()))
            })?;
            let position = f
                .position
                .ok_or_else(|| ctx.span(v, format!("hinge '{hinge}' a0: missing 'position' (m, parent frame)")))?;
            let theta = angles(f.yaw, f.yaw_deg, f.pitch, f.pitch_deg, f.roll, f.roll_deg)
                .map_err(|m| ctx.span(v, format!("hinge '{hinge}' a0: {m}")))?
                .unwrap_or_default();
            Ok(ParentFrame::Given { r_a0_in_parent: vec3(Some(position)), dcm_a0_parent: theta.to_dcm() })
        }
        _ => Err(ctx.span(v, format!("hinge '{hinge}': {help}"))),
    }
}

fn model_error(ctx: &Ctx<'_>, raw: &RawScenario, e: ModelError) -> ScenarioError {
    let span = match (e.hinge, e.body) {
        (Some(h), _) => raw.hinges.get(h).map(|h| h.name.span()),
        (None, Some(b)) => raw.bodies.get(b).map(|b| b.name.span()),
        _ => None,
    };
    ctx.at(span, e.message)
}

pub use crate::integrate::galpha::DEFAULT_RHO_INF;

/// `run.rtol` between 10 u (u the unit round-off) and 1: Hairer's codes refuse rtol ≤ 10 u
/// (no step can be that accurate in f64, and the step size would shrink until the run
/// stops); above 1 a relative tolerance asks for no digit at all.
fn check_rtol(ctx: &Ctx<'_>, run: &RawRun, rtol: f64) -> Result<(), ScenarioError> {
    let Some(x) = &run.rtol else { return Ok(()) };
    if rtol <= MIN_RTOL {
        return Err(ctx.span(
            x,
            format!("'run.rtol' = {rtol:e} is beyond what f64 resolves: give more than {MIN_RTOL:.1e} (1e-13 or looser is usual)"),
        ));
    }
    if rtol > 1.0 {
        return Err(ctx.span(
            x,
            format!("'run.rtol' = {rtol:e} asks for no correct digit: a relative tolerance is at most 1 (1e-6 to 1e-10 is usual)"),
        ));
    }
    Ok(())
}

/// A fixed step (`run.step`, s) checked against the run's duration and the step budget.
fn fixed_step(ctx: &Ctx<'_>, run: &RawRun, duration: f64, step: f64) -> Result<f64, ScenarioError> {
    if step > duration
        && let Some(x) = &run.step
    {
        return Err(ctx.span(
            x,
            format!("'run.step' = {step} s is longer than run.duration = {duration} s: give a step of at most the duration (a fixed-step run ends on a whole step)"),
        ));
    }
    let steps = duration / step;
    if (step < MIN_STEP_OF_DURATION * duration || steps > MAX_DEFAULT_STEP_BUDGET)
        && let Some(x) = &run.step
    {
        return Err(ctx.span(
            x,
            format!(
                "'run.step' = {step:e} s would take {steps:.3e} steps over run.duration = {duration} s; give a step of at least {:.3e} s ({MAX_DEFAULT_STEP_BUDGET:e} steps)",
                duration / MAX_DEFAULT_STEP_BUDGET
            ),
        ));
    }
    Ok(step)
}
