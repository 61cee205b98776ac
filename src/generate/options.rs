//! The generators' options with their defaults and checks, as the command line and the Python
//! package take them (`foldsim generate …`, `foldsim.generate.…`): one place that says what
//! each may be.

use super::flasher::{
    FlasherLaws, FlasherReport, FlasherShape, MAX_GORES, PanelModel, THICK_C_FOLD, THIN_C_FOLD, flasher_scenario,
};
use super::params::{MAX_PANELS, Params, RunText};
use super::sheet::{HingeAxes, SheetParams};
use crate::math::short;
use crate::simulate::settings::{MAX_OUTPUT_ROWS, MIN_RTOL};

/// A positive finite number, or an error naming the option (`name` turns an option's key
/// into the caller's spelling: `--k-fold` on the command line, `k_fold` in Python).
fn positive(v: f64, key: &str, unit: &str, name: &dyn Fn(&str) -> String) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{} must be a positive number in {unit}; got {}", name(key), short(v)))
    }
}

fn at_least_zero(v: f64, key: &str, unit: &str, name: &dyn Fn(&str) -> String) -> Result<f64, String> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{} must be a number ≥ 0 in {unit}; got {}", name(key), short(v)))
    }
}

/// Checks the run's options as the loader will check `[run]` (docs/scenario.md), naming the
/// options: positive times, at most [`MAX_OUTPUT_ROWS`] rows, a tolerance above round-off,
/// a release within the run.
fn run_checked(
    duration: f64,
    output_step: f64,
    tolerance: f64,
    release_at: Option<f64>,
    name: &dyn Fn(&str) -> String,
) -> Result<(), String> {
    positive(duration, "duration", "s", name)?;
    positive(output_step, "output_step", "s", name)?;
    if duration / output_step > MAX_OUTPUT_ROWS {
        return Err(format!(
            "{} / {} = {} rows of output, more than {}: raise {}",
            name("duration"),
            name("output_step"),
            short(duration / output_step),
            short(MAX_OUTPUT_ROWS),
            name("output_step")
        ));
    }
    positive(tolerance, "tolerance", "(relative)", name)?;
    if tolerance <= MIN_RTOL {
        return Err(format!(
            "{} = {} is below what f64 resolves: give more than {MIN_RTOL:.1e} (1e-13 or looser is usual)",
            name("tolerance"),
            short(tolerance)
        ));
    }
    if tolerance >= 1.0 {
        return Err(format!(
            "{} = {} is no accuracy at all: give less than 1 (1e-8 is usual)",
            name("tolerance"),
            short(tolerance)
        ));
    }
    if let Some(t) = release_at
        && !(t.is_finite() && t > 0.0 && t < duration)
    {
        return Err(format!(
            "{} must lie strictly between 0 and {} = {} s; got {}",
            name("release_at"),
            name("duration"),
            short(duration),
            short(t)
        ));
    }
    Ok(())
}

/// Builds generated scenario text as `foldsim run` will, so that a generator never writes
/// a scenario the loader refuses; the loader's words, without the line of a file the user
/// never saw, and the options that were given values other than their defaults (`changed`:
/// name and value), among which the culprit is.
pub fn loadable(text: &str, changed: &[(String, f64)]) -> Result<(), String> {
    crate::scenario::Scenario::from_toml(text, "generated").map(|_| ()).map_err(|e| {
        let given = if changed.is_empty() {
            "every option at its default".to_string()
        } else {
            let list: Vec<String> = changed.iter().map(|(k, v)| format!("{k} {}", short(*v))).collect();
            format!("the options given: {}", list.join(", "))
        };
        format!(
            "these options give a scenario that foldsim refuses: {} ({given}; check their sizes and units)",
            e.message
        )
    })
}

/// The options among `values` (key, value, default) that differ from their defaults, named.
fn changed(values: &[(&str, f64, f64)], name: &dyn Fn(&str) -> String) -> Vec<(String, f64)> {
    values.iter().filter(|(_, v, d)| v.to_bits() != d.to_bits()).map(|(k, v, _)| (name(k), *v)).collect()
}

/// A length within what a structure can be (1 µm to 1,000 km), or an error naming it: beyond,
/// f64 geometry loses the digits a panel needs.
fn length(v: f64, key: &str, name: &dyn Fn(&str) -> String) -> Result<f64, String> {
    positive(v, key, "m", name)?;
    if !(1e-6..=1e6).contains(&v) {
        return Err(format!("{} = {} m is not a structure's size: give 1e-6 to 1e6 m", name(key), short(v)));
    }
    Ok(v)
}

impl Params {
    /// The options that differ from [`Params::default`], named.
    pub fn changed(&self, name: &dyn Fn(&str) -> String) -> Vec<(String, f64)> {
        let d = Params::default();
        changed(
            &[
                ("panel_mass", self.panel_mass, d.panel_mass),
                ("panel_length", self.panel_length, d.panel_length),
                ("panel_width", self.panel_width, d.panel_width),
                ("k_translation", self.k_translation, d.k_translation),
                ("k_bending", self.k_bending, d.k_bending),
                ("k_fold", self.k_fold, d.k_fold),
                ("fold_deg", self.fold_deg, d.fold_deg),
                ("duration", self.duration, d.duration),
                ("output_step", self.output_step, d.output_step),
                ("tolerance", self.tolerance, d.tolerance),
            ],
            name,
        )
    }
}

impl Params {
    /// Checks every value (positive masses, lengths, times and tolerance; stiffnesses ≥ 0).
    pub fn check(&self, name: &dyn Fn(&str) -> String) -> Result<(), String> {
        positive(self.panel_mass, "panel_mass", "kg", name)?;
        length(self.panel_length, "panel_length", name)?;
        length(self.panel_width, "panel_width", name)?;
        run_checked(self.duration, self.output_step, self.tolerance, None, name)?;
        at_least_zero(self.k_translation, "k_translation", "N/m", name)?;
        at_least_zero(self.k_bending, "k_bending", "N·m/rad", name)?;
        at_least_zero(self.k_fold, "k_fold", "N·m/rad", name)?;
        if !(self.fold_deg.is_finite() && self.fold_deg.abs() <= 360.0) {
            return Err(format!(
                "{} must be an angle from -360 to 360 degrees; got {}",
                name("fold_deg"),
                short(self.fold_deg)
            ));
        }
        Ok(())
    }
}

/// A z-fold's scenario text, its size and values checked.
pub fn zfold_checked(panels: usize, p: &Params, name: &dyn Fn(&str) -> String) -> Result<String, String> {
    p.check(name)?;
    if !(1..=MAX_PANELS).contains(&panels) {
        return Err(format!("a z-fold needs 1 ≤ {} ≤ {MAX_PANELS}; got {panels}", name("panels")));
    }
    let text = super::zfold(panels, p);
    loadable(&text, &p.changed(name))?;
    Ok(text)
}

/// A grid's scenario text, its size and values checked.
pub fn grid_checked(rows: usize, cols: usize, p: &Params, name: &dyn Fn(&str) -> String) -> Result<String, String> {
    p.check(name)?;
    if rows < 2 || cols < 2 || rows.saturating_mul(cols) > MAX_PANELS {
        return Err(format!(
            "a grid needs {} ≥ 2 and {} ≥ 2 with rows × cols ≤ {MAX_PANELS}; got {rows} × {cols}",
            name("rows"),
            name("cols")
        ));
    }
    let text = super::grid(rows, cols, p);
    loadable(&text, &p.changed(name))?;
    Ok(text)
}

/// Everything that makes a flasher scenario, with the command line's defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct FlasherOptions {
    /// Number of gores N (sides of the hub), ≥ 3.
    pub gores: usize,
    /// Rings of panels, ≥ 1.
    pub rings: usize,
    /// Hub circumradius, m.
    pub hub_radius: f64,
    /// Panel thickness, m (mass properties and shapes).
    pub thickness: f64,
    /// Where the hinges' fold axes lie (thickness accommodation).
    pub hinge_axes: HingeAxes,
    /// Mass per unit area of the panels, kg/m².
    pub areal_density: f64,
    /// Hub mass, kg.
    pub hub_mass: f64,
    /// Hub principal inertia about its centroid (x, y in its plane, z its axis), kg·m²;
    /// `None`: a uniform disc of the hub's radius and mass.
    pub hub_inertia: Option<[f64; 3]>,
    /// Panel model.
    pub panels: PanelModel,
    /// Stiffness and damping per crease kind.
    pub laws: FlasherLaws,
    /// Initial hub spin about its axis, rev/min.
    pub spin_rpm: f64,
    /// Simulated time, s.
    pub duration: f64,
    /// Output step, s (`None`: duration / 1000).
    pub output_step: Option<f64>,
    /// Integrator tolerance (rtol = atol); `None`: [`THIN_RUN`]'s for thin panels, [`THICK_RUN`]'s
    /// for thick ones.
    pub tolerance: Option<f64>,
    /// `dop853`, `sdirk4` or `auto`; `None` as the tolerance.
    pub integrator: Option<String>,
    /// Hold the stowed state until this time, s.
    pub release_at: Option<f64>,
}

/// A thin flasher's integrator and tolerance unless given: DOP853 at 1e-8, as every generated
/// structure (the hinges' stiff vibrations resolved, the energy kept to ~1e-9).
pub const THIN_RUN: (&str, f64) = ("dop853", 1e-8);

/// A thick flasher's (its panels in contact) unless given: SDIRK4 at 1e-5. Contact stiffens
/// the stowed package beyond what explicit steps can take (the 6 × 3, 1 cm flasher under
/// DOP853 at 1e-8 was projected at 8 h); with its folds damped at [`THICK_C_FOLD`] it runs
/// its 5 s at 1e-5 in 18–22 s, the energy balanced to 3.4e-7 (at 1e-4 in ~12 s to 4e-6;
/// 2-core AMD EPYC, load 1–2; docs/flasher.md, *Thick panels*).
pub const THICK_RUN: (&str, f64) = ("sdirk4", 1e-5);

impl Default for FlasherOptions {
    fn default() -> Self {
        Self {
            gores: 6,
            rings: 3,
            hub_radius: 1.0,
            thickness: 0.0,
            hinge_axes: HingeAxes::Shifted,
            areal_density: 1.0,
            hub_mass: 100.0,
            hub_inertia: None,
            panels: PanelModel::Triangles,
            laws: FlasherLaws::default(),
            spin_rpm: 0.0,
            duration: 5.0,
            output_step: None,
            tolerance: None,
            integrator: None,
            release_at: None,
        }
    }
}

impl FlasherOptions {
    /// The numeric options that differ from [`FlasherOptions::default`], named.
    pub fn changed(&self, name: &dyn Fn(&str) -> String) -> Vec<(String, f64)> {
        let d = FlasherOptions::default();
        let (l, dl) = (&self.laws, &d.laws);
        let mut out = changed(
            &[
                ("hub_radius", self.hub_radius, d.hub_radius),
                ("thickness", self.thickness, d.thickness),
                ("areal_density", self.areal_density, d.areal_density),
                ("hub_mass", self.hub_mass, d.hub_mass),
                ("k_fold", l.k_fold, dl.k_fold),
                ("k_panel_bending", l.k_bending, dl.k_bending),
                ("c_panel_bending", l.c_bending, dl.c_bending),
                ("k_translation", l.k_translation, dl.k_translation),
                ("c_translation", l.c_translation, dl.c_translation),
                ("k_bending", l.k_rotation, dl.k_rotation),
                ("c_rotation", l.c_rotation, dl.c_rotation),
                ("k_stop", l.k_stop, dl.k_stop),
                ("membrane_bending", l.membrane_bending, dl.membrane_bending),
                ("membrane_damping_ratio", l.membrane_damping_ratio, dl.membrane_damping_ratio),
                ("spin_rpm", self.spin_rpm, d.spin_rpm),
                ("duration", self.duration, d.duration),
            ],
            name,
        );
        if let Some(w) = self.laws.membrane_width {
            out.push((name("membrane_width"), w));
        }
        if let Some(c) = self.laws.c_fold {
            out.push((name("c_fold"), c));
        }
        if let Some(t) = self.tolerance {
            out.push((name("tolerance"), t));
        }
        if let Some(v) = self.hub_inertia {
            out.extend(v.iter().enumerate().map(|(i, x)| (format!("{} component {}", name("hub_inertia"), i + 1), *x)));
        }
        if let Some(t) = self.output_step {
            out.push((name("output_step"), t));
        }
        if let Some(t) = self.release_at {
            out.push((name("release_at"), t));
        }
        out
    }

    /// Checks the options and writes the scenario text and the generator's report. `name`
    /// spells an option's key as the caller takes it (`--k-fold` or `k_fold`).
    pub fn scenario(&self, name: &dyn Fn(&str) -> String) -> Result<(String, FlasherReport), String> {
        if !(3..=MAX_GORES).contains(&self.gores) {
            return Err(format!("{} must be 3 to {MAX_GORES}; got {}", name("gores"), self.gores));
        }
        if self.rings < 1 {
            return Err(format!("{} must be at least 1; got {}", name("rings"), self.rings));
        }
        // Panels per gore and ring (hub excluded): 4 triangles, or 2 quadrilaterals (measured:
        // 20 × 20 gives 1,580 triangles, 820 quads, 800 ring-quads).
        let per = if self.panels == PanelModel::Triangles { 4 } else { 2 };
        let panels = self.gores.saturating_mul(self.rings).saturating_mul(per);
        if panels > MAX_PANELS {
            return Err(format!(
                "{} {} × {} {} would make about {panels} panels ({per} per gore and ring with the {} panel model), more than {MAX_PANELS}: lower {} or {}",
                name("gores"),
                self.gores,
                name("rings"),
                self.rings,
                self.panels.name(),
                name("gores"),
                name("rings")
            ));
        }
        length(self.hub_radius, "hub_radius", name)?;
        positive(self.areal_density, "areal_density", "kg/m²", name)?;
        positive(self.hub_mass, "hub_mass", "kg", name)?;
        at_least_zero(self.thickness, "thickness", "m", name)?;
        if !self.spin_rpm.is_finite() {
            return Err(format!("{} must be a finite number in rev/min", name("spin_rpm")));
        }
        let l = &self.laws;
        for (v, key, unit) in [
            (l.c_fold.unwrap_or(0.0), "c_fold", "N·m·s/rad"),
            (l.k_bending, "k_panel_bending", "N·m/rad"),
            (l.c_bending, "c_panel_bending", "N·m·s/rad"),
            (l.c_translation, "c_translation", "N·s/m"),
            (l.c_rotation, "c_rotation", "N·m·s/rad"),
            (l.k_stop, "k_stop", "N·m/rad"),
            (l.membrane_bending, "membrane_bending", "N·m"),
            (l.membrane_damping_ratio, "membrane_damping_ratio", "(a ratio)"),
            (l.k_translation, "k_translation", "N/m"),
            (l.k_rotation, "k_bending", "N·m/rad"),
            (l.k_fold, "k_fold", "N·m/rad"),
        ] {
            at_least_zero(v, key, unit, name)?;
        }
        if let Some(w) = l.membrane_width {
            positive(w, "membrane_width", "m", name)?;
        }
        let r = self.hub_radius;
        if self.thickness > 0.0 && self.thickness < 1e-6 * r {
            return Err(format!(
                "{} = {} m is below a millionth of the hub's radius ({} m): the panels' cut corners and the layers' offsets vanish in round-off; give 0 for panels without thickness (a membrane), or a thickness of at least {:e} m",
                name("thickness"),
                short(self.thickness),
                short(r),
                1e-6 * r
            ));
        }
        if self.thickness > 0.0 && self.panels == PanelModel::RingQuads {
            // Ring-quads are bent across the prism's edges when stowed: the nesting of the
            // layers (docs/flasher.md, *Thick panels*) is made for the panels that lie flat in
            // the wrap, and ring-quads there would overlap the hub and one another.
            return Err(format!(
                "{} = ring-quads with {} > 0: thick panels are stowed in nested layers for the triangle and quad models only (ring-quads are bent across the hub's edges in the wrap and would overlap it); give {} = triangles or quads",
                name("panels"),
                name("thickness"),
                name("panels")
            ));
        }
        if self.thickness > 0.0 && self.hub_inertia.is_some() {
            return Err(format!(
                "{} does not apply with {} > 0: the hub is then a solid prism over its polygon, as tall as the stowed wrap, and its inertia follows from {} and that shape",
                name("hub_inertia"),
                name("thickness"),
                name("hub_mass")
            ));
        }
        let hub_inertia = match self.hub_inertia {
            Some(v) => {
                for (i, &x) in v.iter().enumerate() {
                    positive(x, &format!("hub_inertia component {}", i + 1), "kg·m²", name)?;
                }
                let mut p = v;
                p.sort_by(f64::total_cmp);
                if p[2] > (p[0] + p[1]) * (1.0 + 1e-9) {
                    return Err(format!(
                        "{}: principal inertias {}, {}, {} kg·m² are not a body's: the largest may not exceed the sum of the other two",
                        name("hub_inertia"),
                        short(v[0]),
                        short(v[1]),
                        short(v[2])
                    ));
                }
                v
            }
            None => [self.hub_mass * r * r / 4.0, self.hub_mass * r * r / 4.0, self.hub_mass * r * r / 2.0],
        };
        let output_step = self.output_step.unwrap_or(self.duration / 1000.0);
        let (default_integrator, default_tolerance) = if self.thickness > 0.0 { THICK_RUN } else { THIN_RUN };
        let tolerance = self.tolerance.unwrap_or(default_tolerance);
        run_checked(self.duration, output_step, tolerance, self.release_at, name)?;
        let integrator = match self.integrator.as_deref().unwrap_or(default_integrator) {
            "dop853" => "dop853",
            "sdirk4" => "sdirk4",
            "auto" => "auto",
            other => return Err(format!("{} must be auto, dop853 or sdirk4; got '{other}'", name("integrator"))),
        };
        let run = RunText { duration: self.duration, output_step, tolerance, integrator, release_at: self.release_at };
        let shape = FlasherShape { gores: self.gores, rings: self.rings, hub_radius: r, model: self.panels };
        let params = SheetParams {
            title: format!("flasher, {} gores, {} rings, {}", self.gores, self.rings, self.panels.name()),
            areal_density: self.areal_density,
            thickness: self.thickness,
            hinge_axes: self.hinge_axes,
            hub_mass: self.hub_mass,
            hub_inertia,
            spin_rpm: self.spin_rpm,
            run,
        };
        let (text, mut report) = flasher_scenario(&shape, &self.laws, &params)?;
        loadable(&text, &self.changed(name))?;
        if self.thickness > 0.0 {
            if self.laws.c_fold.is_none() {
                report.thick_defaults.push(format!("fold damping {THICK_C_FOLD} N·m·s/rad (thin: {THIN_C_FOLD})"));
            }
            if self.integrator.is_none() && self.tolerance.is_none() {
                report.thick_defaults.push(format!("{} at rtol {tolerance:e}", integrator.to_uppercase()));
            } else if self.tolerance.is_none() {
                report.thick_defaults.push(format!("rtol {tolerance:e}"));
            } else if self.integrator.is_none() {
                report.thick_defaults.push(integrator.to_uppercase());
            }
        }
        Ok((text, report))
    }
}

/// The hinge axes named `name` (`shifted`, `mid-plane`).
pub fn hinge_axes(name: &str) -> Result<HingeAxes, String> {
    [HingeAxes::Shifted, HingeAxes::MidPlane]
        .into_iter()
        .find(|h| h.name() == name)
        .ok_or_else(|| format!("hinge axes '{name}': give shifted or mid-plane"))
}

/// The panel model named `name` (`triangles`, `quads`, `ring-quads`).
pub fn panel_model(name: &str) -> Result<PanelModel, String> {
    match name {
        "triangles" => Ok(PanelModel::Triangles),
        "quads" => Ok(PanelModel::Quads),
        "ring-quads" => Ok(PanelModel::RingQuads),
        other => Err(format!("panel model '{other}': give triangles, quads or ring-quads")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `[run]` lines a flasher's scenario gets.
    fn run_lines(o: &FlasherOptions) -> (String, String) {
        let (text, _) = o.scenario(&|k: &str| k.to_string()).unwrap();
        let line = |key: &str| text.lines().find(|l| l.starts_with(key)).unwrap().to_string();
        (line("integrator = "), line("rtol = "))
    }

    /// Thin flashers keep DOP853 at 1e-8 and folds damped at 0.05 N·m·s/rad; thick ones (in
    /// contact) get SDIRK4 at 1e-5 and folds at 1, and the report says so; what is given is
    /// kept either way, and then the report names no default it did not take.
    #[test]
    fn thick_flashers_default_to_the_implicit_run() {
        let thin = FlasherOptions { gores: 4, rings: 1, ..FlasherOptions::default() };
        assert_eq!(run_lines(&thin), ("integrator = \"dop853\"".into(), "rtol = 1e-8".into()));
        let thick = FlasherOptions { thickness: 0.01, ..thin.clone() };
        assert_eq!(run_lines(&thick), ("integrator = \"sdirk4\"".into(), "rtol = 1e-5".into()));
        let given = FlasherOptions { integrator: Some("auto".into()), tolerance: Some(1e-6), ..thick.clone() };
        assert_eq!(run_lines(&given), ("integrator = \"auto\"".into(), "rtol = 1e-6".into()));
        // The folding creases' damping (the diagonals keep c_panel_bending) in the text and
        // the defaults taken in the report.
        let fold_damping = |o: &FlasherOptions| {
            let (text, report) = o.scenario(&|k: &str| k.to_string()).unwrap();
            // Fold stiffness 1 (1e0): thick laws `rz = { k = 1e0, damping = c`, thin
            // `k_theta = [1e3, 1e3, 1e0], …, c_theta = [.., .., c]`.
            let mut c: Vec<String> = text
                .lines()
                .filter_map(|l| match l.split("rz = { k = 1e0, damping = ").nth(1) {
                    Some(rest) => Some(rest),
                    None if l.contains("1e0], c_f") => l.rsplit_once(", ").map(|x| x.1),
                    None => None,
                })
                .map(|v| v.split([',', ' ', '}', ']']).next().unwrap().to_string())
                .collect();
            c.sort();
            c.dedup();
            let line = report.text(false).contains("thick panels' defaults");
            (c, report.thick_defaults, line)
        };
        let (thin_c, thin_taken, thin_line) = fold_damping(&thin);
        assert!(thin_c == ["5e-2"], "{thin_c:?}");
        assert!(thin_taken.is_empty() && !thin_line);
        let (thick_c, taken, line) = fold_damping(&thick);
        assert!(thick_c == ["1e0"], "{thick_c:?}");
        assert_eq!(taken, ["fold damping 1 N·m·s/rad (thin: 0.05)", "SDIRK4 at rtol 1e-5"]);
        assert!(line);
        let damped = FlasherOptions { laws: FlasherLaws { c_fold: Some(0.3), ..thick.laws }, ..given };
        let (c, taken, line) = fold_damping(&damped);
        assert!(c == ["3e-1"], "{c:?}");
        assert!(taken.is_empty() && !line);
    }

    /// A thick flasher with shifted axes stops every folding crease at flat, free on its
    /// stowed fold's side, and the scenario loads; thin panels, axes in the mid-plane or
    /// `k_stop = 0` write no stop (and with no membrane law 2 as before).
    #[test]
    fn thick_creases_stop_at_flat_on_the_far_side_of_their_fold() {
        use crate::generate::crease::LEAST_STOPPED_FOLD;
        let thick = FlasherOptions { gores: 4, rings: 2, thickness: 0.01, ..FlasherOptions::default() };
        let (text, report) = thick.scenario(&|k: &str| k.to_string()).unwrap();
        let folding: Vec<_> = report.sheet.strains.iter().filter(|s| s.fold.abs() > LEAST_STOPPED_FOLD).collect();
        assert!(!folding.is_empty() && folding.len() < report.sheet.strains.len(), "the diagonals stay flat");
        assert_eq!(report.sheet.stops.len(), folding.len());
        for (f, (name, stop)) in folding.iter().zip(&report.sheet.stops) {
            assert_eq!(&f.hinge, name);
            assert_eq!(stop.free_above, f.fold > 0.0, "{name}");
            assert!(stop.damping > 0.0 && stop.stiffness == thick.laws.k_stop, "{name}: {stop:?}");
        }
        assert_eq!(text.matches("stop = { at_deg = 0.0").count(), folding.len());
        crate::scenario::Scenario::from_toml(&text, "thick").unwrap();
        // Each folding crease has its membrane (x and y), the diagonals none.
        assert_eq!(text.matches("free = \"within\"").count(), 2 * folding.len());
        assert_eq!(report.membrane.map(|m| m.1), Some(folding.len()));
        let none = [
            FlasherOptions { thickness: 0.0, ..thick.clone() },
            FlasherOptions { hinge_axes: HingeAxes::MidPlane, ..thick.clone() },
            FlasherOptions { laws: FlasherLaws { k_stop: 0.0, membrane_bending: 0.0, ..thick.laws }, ..thick.clone() },
        ];
        for o in none {
            let (text, report) = o.scenario(&|k: &str| k.to_string()).unwrap();
            assert!(report.sheet.stops.is_empty() && !text.contains("directional"), "{o:?}");
        }
        // Without stops the membranes stay (a directional law with no stop at flat).
        let membranes_only = FlasherOptions { laws: FlasherLaws { k_stop: 0.0, ..thick.laws }, ..thick.clone() };
        let (text, report) = membranes_only.scenario(&|k: &str| k.to_string()).unwrap();
        assert!(report.sheet.stops.is_empty() && !text.contains("at_deg = 0.0"));
        assert_eq!(text.matches("free = \"within\"").count(), 2 * folding.len());
    }
}
