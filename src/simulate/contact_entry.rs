//! Contact points entering and leaving within an accepted step, found on the step's dense
//! output (docs/contact.md): the instant to end a step at when the run locates contact
//! changes ([`super::settings::LOCATE_CONTACT_RTOL`]), and, at every accepted step, the
//! speed at which each point entering contact crossed into it, which the contact law holds
//! as its impact speed.

use crate::contact::PointKey;
use crate::dynamics::Dynamics;
use crate::integrate::Step;
use crate::state::BODY_STATE_LEN;

/// The first instant inside the step at which a contact point enters or leaves contact,
/// if one does (s): the contact law's `K δⁿ` bends there (its higher derivatives jump),
/// which a step straddling it integrates at less than its order, unseen by the error
/// estimate. The step is retaken to end there, as at a law's event, so that the energy
/// balance E + D converges with the tolerance (docs/contact.md). Found by Illinois regula
/// falsi on each changed point's penetration along the dense output (its two bodies only);
/// the instant returned lies just past the earliest crossing, so that the point has its
/// new status at the end of the retaken step.
pub(super) fn locate_contact_change(dynamics: &Dynamics<'_>, step: &Step<'_>) -> Option<f64> {
    let h = step.t - step.t_prev;
    if h <= 0.0 || dynamics.model().contact.is_none() {
        return None;
    }
    let changed = dynamics.contact_changes(step.y);
    if changed.is_empty() {
        return None;
    }
    let mut y = vec![0.0; step.y.len()];
    let mut roots = Vec::with_capacity(changed.len());
    for key in &changed {
        // A point leaving: the crossing of its negative penetration.
        let leaving = dynamics.contact_memory().contains_key(key);
        if let Some(b) = crossing(dynamics, step, key, leaving, (1e-9 * h, 60), &mut y) {
            roots.push(b);
        }
    }
    let first = roots.iter().copied().fold(f64::INFINITY, f64::min);
    if !first.is_finite() {
        return None;
    }
    // Points of one face meet another face all but at once (1e-12 s apart): one landing
    // past every crossing within a tenth of the step of the first, not one tiny step
    // per point (which would drive the step size to the floor).
    let cluster = first + 0.1 * h;
    let last = roots.iter().copied().filter(|&r| r <= cluster).fold(first, f64::max);
    // Landed a millionth of the step past the root (the retaken step's own solution
    // differs from this dense output by its local error: ending just past the root, it
    // ends with the point's new status, and the next step does not find the crossing
    // again a round-off after its start). A crossing in the first tenth of the step is
    // left to it (the bend so near its start costs little, and landing there would
    // shrink the steps without end); one at its end needs no retaking.
    let land = last + 1e-6 * h;
    (first > step.t_prev + 0.1 * h && land < step.t - 1e-12 * step.t.abs().max(1.0)).then_some(land)
}

/// The approach speed of each point entering contact within the accepted `step`, at the
/// instant it crossed into contact on the step's dense output, handed to the dynamics for
/// its next `accept` ([`crate::dynamics::Dynamics::set_entry_speeds`]). The contact law's
/// damping divides by a point's impact speed for the whole of its contact; taken at the
/// step's end (as it was), it depended on how far into the contact the step happened to
/// end, so that runs differed by where their steps fell however tight the tolerance
/// (the contact z-fold's error stayed at 2–5 mm from rtol 1e-5 to 1e-9). Located to a
/// millionth of the step: the rate changes little over that.
pub(super) fn locate_entry_speeds(dynamics: &Dynamics<'_>, step: &Step<'_>) {
    let h = step.t - step.t_prev;
    if h <= 0.0 || dynamics.model().contact.is_none() {
        return;
    }
    let changed = dynamics.contact_changes(step.y);
    let entering: Vec<PointKey> = {
        let memory = dynamics.contact_memory();
        changed.into_iter().filter(|k| !memory.contains_key(k)).collect()
    };
    let mut speeds = Vec::with_capacity(entering.len());
    let mut y = vec![0.0; step.y.len()];
    for key in entering {
        let Some(t) = crossing(dynamics, step, &key, false, (1e-6 * h, 40), &mut y) else { continue };
        interpolate_pair(step, &key, t, &mut y);
        let rate = dynamics.contact_rate(&key, &y);
        if rate.is_finite() {
            speeds.push((key, rate));
        }
    }
    dynamics.set_entry_speeds(speeds);
}

/// The instant within `step` at which point `key` crosses into contact (out of it, if
/// `leaving`), on the step's dense output, located by [`illinois`] to `(tol s, iterations)`
/// (the end just after the crossing); `None` if its penetration does not change sign over
/// the step. `y` is work space of the state's length.
fn crossing(
    dynamics: &Dynamics<'_>,
    step: &Step<'_>,
    key: &PointKey,
    leaving: bool,
    (tol, iterations): (f64, usize),
    y: &mut [f64],
) -> Option<f64> {
    // g < 0 before the crossing, ≥ 0 after.
    let sign = if leaving { -1.0 } else { 1.0 };
    let mut g_at = |t: f64| {
        interpolate_pair(step, key, t, y);
        sign * dynamics.contact_depth(key, y)
    };
    let (ga, gb) = (g_at(step.t_prev), g_at(step.t));
    (ga < 0.0 && gb >= 0.0).then(|| illinois(&mut g_at, |g| g >= 0.0, (step.t_prev, ga), (step.t, gb), tol, iterations))
}

/// The dense-output state at `t` of the two bodies of point `key`, written into their
/// components of `y`.
fn interpolate_pair(step: &Step<'_>, key: &PointKey, t: f64, y: &mut [f64]) {
    step.interpolate_range(t, body_range(key.body), y);
    step.interpolate_range(t, body_range(key.other), y);
}

/// The state components of body `b`.
fn body_range(b: u32) -> std::ops::Range<usize> {
    BODY_STATE_LEN * b as usize..BODY_STATE_LEN * (b as usize + 1)
}

/// Illinois regula falsi (Dowell & Jarratt 1971) on a bracket whose end `(a, g(a))` lies
/// before a crossing and `(b, g(b))` after it (`after(g)` tells which side a value is on):
/// narrowed to `tol` (s) in at most `iterations` evaluations of `g`, it returns the end after
/// the crossing. A retained end's value is halved when the other moves twice running, so the
/// bracket closes from both sides.
pub(super) fn illinois(
    g: &mut impl FnMut(f64) -> f64,
    after: impl Fn(f64) -> bool,
    (mut a, mut ga): (f64, f64),
    (mut b, mut gb): (f64, f64),
    tol: f64,
    iterations: usize,
) -> f64 {
    let mut side = 0;
    for _ in 0..iterations {
        if b - a <= tol {
            break;
        }
        let mut c = b - gb * (b - a) / (gb - ga);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let gc = g(c);
        if after(gc) {
            (b, gb) = (c, gc);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        } else {
            (a, ga) = (c, gc);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        }
    }
    b
}
