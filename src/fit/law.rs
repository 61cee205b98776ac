//! A hinge law alone against a bench test (docs/fit.md, *A law alone*): moment–rotation (or
//! force–displacement) points of one direction, in the order the test took them (loading,
//! then unloading), against the law's quasi-static response driven through the same path.
//!
//! The drive: the direction's coordinate moves from point to point with every other
//! coordinate at rest, at a vanishing rate (1e-9 per second, whose sign says loading or
//! unloading), and the law's discrete memory (a tape spring's slip mode, a stop's contact, a
//! latch) changes as in a run: at every crossing of an event function, located by bisection
//! to 1e-13 of the coordinate, the law's own event is applied; its bookkeeping (which piece of
//! a table) is kept up to date at every point. The response is the law's restoring force or
//! moment on that coordinate (the table's convention: positive for a positive coordinate of a
//! spring).

use super::params::Free;
use super::{Column, Fitted};
use crate::law::directional::DIRECTION_NAMES;
use crate::law::{HingeLaw, HingeState, LawMemory};
use crate::math::{Euler321, Vec3};
use crate::scenario::{ScenarioText, SetValue, law_from_toml};

/// The coordinate's rate during the drive, per second: small enough that damping adds
/// nothing measurable (1e-9 × a damping of 1e4 is 1e-5 N·m), its sign the direction of travel.
pub const DRIVE_RATE: f64 = 1e-9;

/// The longest step of the drive between event checks (rad or m); crossings inside a step are
/// located by bisection.
pub const DRIVE_STEP: f64 = 1e-3;

/// A bench test: the coordinate and the measured force or moment, in the test's order.
#[derive(Clone, Debug, PartialEq)]
pub struct Bench {
    /// The file (or label).
    pub file: String,
    /// True for a rotation (angles, moments), false for a translation (m, N).
    pub rotational: bool,
    /// The coordinate in the file's unit (deg, rad or m), for plots.
    pub shown: Vec<f64>,
    /// Its unit's name in the file (`angle_deg`, …).
    pub shown_unit: &'static str,
    /// The coordinate, rad or m.
    pub coordinate: Vec<f64>,
    /// The measured force (N) or moment (N·m).
    pub measured: Vec<f64>,
    /// The measurement noise, if given (N or N·m).
    pub sigma: Option<f64>,
}

impl Bench {
    /// Parses a bench test's CSV: a header `angle_deg,moment_Nm`, `angle_rad,moment_Nm` or
    /// `displacement_m,force_N` (as a law's table files have it), then the points in the
    /// order taken; `#` lines are comments. Refused with the line named: another header, a
    /// cell that is not a finite number, a row of the wrong length, fewer than two rows.
    pub fn parse(text: &str, file: &str) -> Result<Self, String> {
        let err = |line: usize, m: String| format!("{file}:{line}: {m}");
        let mut lines = super::data::data_lines(text);
        let Some((hl, header)) = lines.next() else {
            return Err(format!("{file}: empty; a bench test has a header (angle_deg,moment_Nm) and rows"));
        };
        let names: Vec<&str> = header.split(',').map(|h| h.trim().trim_matches('"')).collect();
        let (rotational, shown_unit, factor) = match names.as_slice() {
            ["angle_deg", "moment_Nm"] => (true, "angle_deg", std::f64::consts::PI / 180.0),
            ["angle_rad", "moment_Nm"] => (true, "angle_rad", 1.0),
            ["displacement_m", "force_N"] => (false, "displacement_m", 1.0),
            _ => {
                return Err(err(
                    hl,
                    format!(
                        "header '{}': a bench test's columns are angle_deg,moment_Nm or angle_rad,moment_Nm (a rotation) or displacement_m,force_N (a translation), as a law's table files have them",
                        header.trim()
                    ),
                ));
            }
        };
        let (mut shown, mut measured) = (Vec::new(), Vec::new());
        for (line, row) in lines {
            let cells: Vec<&str> = row.split(',').map(str::trim).collect();
            if cells.len() != 2 {
                return Err(err(line, format!("{} cells; the header has 2", cells.len())));
            }
            let number =
                |k: usize| {
                    cells[k].parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                        err(line, format!("column '{}': '{}' is not a finite number", names[k], cells[k]))
                    })
                };
            shown.push(number(0)?);
            measured.push(number(1)?);
        }
        if shown.len() < 2 {
            return Err(format!("{file}: {} row(s); a fit needs at least two", shown.len()));
        }
        let coordinate = shown.iter().map(|q| q * factor).collect();
        Ok(Self { file: file.to_string(), rotational, shown, shown_unit, coordinate, measured, sigma: None })
    }
}

/// A law file's values fitted to a bench test of one of its directions.
#[derive(Clone, Debug)]
pub struct LawProblem {
    text: ScenarioText,
    /// The free values (key paths in the law file: `law.rz.tape_spring.increasing.scale`).
    pub free: Vec<Free>,
    /// The bench test.
    pub bench: Bench,
    /// The direction driven: 0–5 for x, y, z, rx, ry, rz.
    pub direction: usize,
}

impl LawProblem {
    /// The problem of fitting `free` of the law file `text` to `bench` in direction `name`
    /// (`x` … `rz`). Checks the direction against the test's kind and that the law builds.
    pub fn new(text: ScenarioText, free: Vec<Free>, bench: Bench, name: &str) -> Result<Self, String> {
        let direction = DIRECTION_NAMES
            .iter()
            .position(|d| *d == name)
            .ok_or_else(|| format!("--direction {name}: one of {}", DIRECTION_NAMES.join(", ")))?;
        if (direction >= 3) != bench.rotational {
            return Err(format!(
                "{}: the test is a {} but --direction {name} is a {}",
                bench.file,
                if bench.rotational {
                    "rotation (moment against angle)"
                } else {
                    "translation (force against displacement)"
                },
                if direction >= 3 { "rotation" } else { "translation" }
            ));
        }
        if bench.measured.len() <= free.len() {
            return Err(format!(
                "{}: {} points for {} free values; a fit needs more points than values",
                bench.file,
                bench.measured.len(),
                free.len()
            ));
        }
        let p = Self { text, free, bench, direction };
        p.law_at(&p.free.iter().map(|f| f.start).collect::<Vec<_>>())?;
        Ok(p)
    }

    /// The law file's text with the values `x` set.
    pub fn text_at(&self, x: &[f64]) -> Result<ScenarioText, String> {
        let mut t = self.text.clone();
        for (f, v) in self.free.iter().zip(x) {
            t.set(&f.path, &SetValue::Number(*v))?;
        }
        Ok(t)
    }

    fn law_at(&self, x: &[f64]) -> Result<Box<dyn HingeLaw>, String> {
        let t = self.text_at(x)?;
        let describe: Vec<String> =
            self.free.iter().zip(x).map(|(f, v)| format!("{} = {}", f.path, crate::math::short(*v))).collect();
        law_from_toml(&t.text(), &t.file, &t.base)
            .map(|(law, _)| law)
            .map_err(|e| format!("the law with {}: {e}", describe.join(", ")))
    }

    /// The law's quasi-static response at the test's points, driven through them in order.
    pub fn response(&self, x: &[f64]) -> Result<Vec<f64>, String> {
        let law = self.law_at(x)?;
        Ok(drive(law.as_ref(), self.direction, &self.bench.coordinate))
    }
}

/// The hinge state with coordinate `direction` at `q` moving at `rate`, the rest at rest.
fn state(direction: usize, q: f64, rate: f64) -> HingeState {
    let mut delta = Vec3::zeros();
    let mut theta = Euler321::default();
    match direction {
        0..=2 => delta[direction] = q,
        3 => theta.roll = q,
        4 => theta.pitch = q,
        _ => theta.yaw = q,
    }
    let mut s = HingeState::at(delta, theta);
    // With one angle turned, ω_rel in A is that angle's rate on its own axis.
    if direction < 3 {
        s.delta_rate_in_a0[direction] = rate;
    } else {
        s.omega_rel_in_a[direction - 3] = rate;
    }
    s
}

/// The restoring force or moment on coordinate `direction` of `law` at each of `path`'s
/// points, the coordinate driven through them in order (see the module documentation).
pub fn drive(law: &dyn HingeLaw, direction: usize, path: &[f64]) -> Vec<f64> {
    let n = law.event_count();
    let (mut g, mut g_new) = (vec![0.0; n], vec![0.0; n]);
    let mut q = path.first().copied().unwrap_or(0.0);
    let mut rate = if path.len() > 1 && path[1] < q { -DRIVE_RATE } else { DRIVE_RATE };
    let mut memory: LawMemory = law.initial_memory(&state(direction, q, rate));
    let component = |s: &HingeState, m: &LawMemory| {
        let w = law.wrench(s, m);
        if direction < 3 { w.force_in_a0[direction] } else { w.torque_in_a[direction - 3] }
    };
    let mut out = Vec::with_capacity(path.len());
    // Events whose function is negative at the current point are applied there (a reversal
    // of the rate, or a start past a crossing), at most a few times over.
    let settle = |q: f64, rate: f64, memory: &mut LawMemory, g: &mut Vec<f64>| {
        for _ in 0..8 {
            let s = state(direction, q, rate);
            law.sync_memory(&s, memory);
            law.event_values(&s, memory, g);
            let Some(k) = (0..n).find(|&k| g[k] < 0.0 && !law.bookkeeping_event(k)) else { return };
            law.apply_event(k, &s, memory);
        }
    };
    settle(q, rate, &mut memory, &mut g);
    out.push(component(&state(direction, q, rate), &memory));
    for &target in &path[1..] {
        if target != q {
            let new_rate = if target > q { DRIVE_RATE } else { -DRIVE_RATE };
            if new_rate != rate {
                rate = new_rate;
                settle(q, rate, &mut memory, &mut g);
            }
        }
        let steps = ((target - q).abs() / DRIVE_STEP).ceil().max(1.0) as usize;
        let start = q;
        for i in 1..=steps {
            let next = if i == steps { target } else { start + (target - start) * i as f64 / steps as f64 };
            // Crossings inside (q, next]: the earliest located by bisection, applied, and the
            // rest of the step gone over again.
            let mut guard = 0;
            loop {
                let s = state(direction, next, rate);
                law.event_values(&s, &memory, &mut g_new);
                let s0 = state(direction, q, rate);
                law.event_values(&s0, &memory, &mut g);
                let crossing = (0..n).find(|&k| g[k] >= 0.0 && g_new[k] < 0.0 && !law.bookkeeping_event(k));
                let Some(_) = crossing else { break };
                guard += 1;
                if guard > 16 {
                    break;
                }
                let (mut a, mut b) = (q, next);
                let mut k_hit = crossing.expect("found");
                while (b - a).abs() > 1e-13 * (1.0 + a.abs()) {
                    let m = 0.5 * (a + b);
                    law.event_values(&state(direction, m, rate), &memory, &mut g_new);
                    match (0..n).find(|&k| g_new[k] < 0.0 && g[k] >= 0.0 && !law.bookkeeping_event(k)) {
                        Some(k) => {
                            b = m;
                            k_hit = k;
                        }
                        None => a = m,
                    }
                }
                q = b;
                law.apply_event(k_hit, &state(direction, q, rate), &mut memory);
                law.sync_memory(&state(direction, q, rate), &mut memory);
            }
            q = next;
            law.sync_memory(&state(direction, q, rate), &mut memory);
        }
        out.push(component(&state(direction, q, rate), &memory));
    }
    out
}

impl Fitted for LawProblem {
    fn free(&self) -> &[Free] {
        &self.free
    }

    fn residuals(&self, x: &[f64]) -> Result<Vec<f64>, String> {
        let f = self.response(x)?;
        let w = 1.0 / self.bench.sigma.unwrap_or(1.0);
        let r: Vec<f64> = f.iter().zip(&self.bench.measured).map(|(a, b)| (a - b) * w).collect();
        if r.iter().all(|v| v.is_finite()) { Ok(r) } else { Err("the law's response is not finite at a point".into()) }
    }

    fn columns(&self, x: &[f64]) -> Result<Vec<Column>, String> {
        let (name, unit) = if self.bench.rotational { ("moment", "N·m") } else { ("force", "N") };
        Ok(vec![Column {
            name: name.into(),
            unit,
            abscissa: self.bench.shown.clone(),
            measured: self.bench.measured.iter().map(|v| Some(*v)).collect(),
            fitted: self.response(x)?,
            sigma: self.bench.sigma,
        }])
    }

    fn data_summary(&self) -> String {
        format!(
            "{} points of {} (direction {}, the law's quasi-static response along them)",
            self.bench.measured.len(),
            self.bench.file,
            DIRECTION_NAMES[self.direction]
        )
    }

    fn abscissa(&self) -> String {
        match self.bench.shown_unit {
            "angle_deg" => "angle (deg)".into(),
            "angle_rad" => "angle (rad)".into(),
            _ => "displacement (m)".into(),
        }
    }
}
