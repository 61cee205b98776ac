//! The `[contact]` table (docs/contact.md): the law's values checked, contact turned on in
//! the model, and the initial state checked for bodies that overlap.

use super::error::{Ctx, ScenarioError};
use super::raw::RawContact;
use super::values::positive;
use crate::contact::Frame;
use crate::contact::law::{ContactLaw, MIN_RESTITUTION};
use crate::kinematics::{InitialConditions, initial_state};
use crate::math::short;
use crate::model::Model;
use crate::state::BodyMotion;
use toml::Spanned;

/// Default exponent of the penetration (Hertz's).
pub const DEFAULT_EXPONENT: f64 = 1.5;
/// Default slip speed and least impact speed, m/s.
pub const DEFAULT_SLIP_SPEED: f64 = 1e-3;

/// The deepest overlap at t = 0 that is not refused, m: round-off, not a placement.
pub const OVERLAP_TOLERANCE: f64 = 1e-9;

/// `v` if in `[lo, hi]`, else a located error naming `key`.
fn within(ctx: &Ctx<'_>, v: &Spanned<f64>, key: &str, lo: f64, hi: f64, why: &str) -> Result<f64, ScenarioError> {
    let x = *v.get_ref();
    if (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(ctx.span(v, format!("'{key}' must be in [{}, {}]{why}, got {}", short(lo), short(hi), short(x))))
    }
}

/// Turns contact on in `model` as `[contact]` asks, and refuses an initial state in which
/// two bodies overlap (beyond their creases) unless the table allows it.
pub(super) fn enable(
    ctx: &Ctx<'_>,
    raw: &Spanned<RawContact>,
    model: &mut Model,
    ic: &InitialConditions,
) -> Result<(), ScenarioError> {
    let c = raw.get_ref();
    let shaped: Vec<&str> = model.bodies.iter().filter(|b| b.shape.is_some()).map(|b| b.name.as_str()).collect();
    if shaped.len() < 2 {
        return Err(ctx.span(
            raw,
            format!(
                "[contact]: contact acts between bodies with a 'shape', and {}; give at least two bodies a shape (docs/contact.md) or remove [contact]",
                match shaped.as_slice() {
                    [] => "no body has one".to_string(),
                    [one] => format!("only '{one}' has one"),
                    _ => unreachable!(),
                }
            ),
        ));
    }
    let stiffness = positive(ctx, &c.stiffness, "contact.stiffness", "N/m^exponent")?;
    let exponent = match &c.exponent {
        Some(v) => within(ctx, v, "contact.exponent", 1.0, 3.0, " (1 linear, 1.5 Hertz)")?,
        None => DEFAULT_EXPONENT,
    };
    let restitution = within(
        ctx,
        &c.restitution,
        "contact.restitution",
        MIN_RESTITUTION,
        1.0,
        " (below 0.01 the damping it needs grows without bound)",
    )?;
    let friction = match &c.friction {
        Some(v) => within(ctx, v, "contact.friction", 0.0, 10.0, " (Coulomb's μ)")?,
        None => 0.0,
    };
    let opt_positive = |v: &Option<Spanned<f64>>, key: &str, unit: &str, default: f64| match v {
        Some(v) => positive(ctx, v, key, unit),
        None => Ok(default),
    };
    let slip_speed = opt_positive(&c.slip_speed, "contact.slip_speed", "m/s", DEFAULT_SLIP_SPEED)?;
    let min_impact_speed = opt_positive(&c.min_impact_speed, "contact.min_impact_speed", "m/s", DEFAULT_SLIP_SPEED)?;
    let margin = match &c.margin {
        Some(v) => within(ctx, v, "contact.margin", 0.0, f64::MAX, " m")?,
        None => 0.0,
    };
    let spacing = c.spacing.as_ref().map(|v| positive(ctx, v, "contact.spacing", "m")).transpose()?;
    let mut excluded = Vec::new();
    for pair in c.exclude.iter().flat_map(|e| e.get_ref()) {
        let mut ids = [0; 2];
        for (k, name) in pair.iter().enumerate() {
            ids[k] = model
                .body_index(name.get_ref())
                .ok_or_else(|| ctx.span(name, format!("contact.exclude: no body named '{}'", name.get_ref())))?;
        }
        if ids[0] == ids[1] {
            return Err(ctx.span(
                &pair[1],
                format!(
                    "contact.exclude: the pair ['{0}', '{0}'] names one body twice; a body never touches itself",
                    pair[0].get_ref()
                ),
            ));
        }
        excluded.push((ids[0], ids[1]));
    }
    let law = ContactLaw::new(stiffness, exponent, restitution, friction, slip_speed, min_impact_speed, margin);
    model.enable_contact(law, spacing, &excluded).map_err(|e| ctx.span(raw, format!("[contact]: {}", e.message)))?;

    if c.allow_initial_overlap != Some(true) {
        let (y0, _) = initial_state(model, ic);
        let frames: Vec<Frame> = (0..model.bodies.len())
            .map(|i| {
                let m = BodyMotion::from_state(&y0, i);
                m.contact_frame()
            })
            .collect();
        // Round-off in placing the bodies along the tree leaves overlaps of ~1e-16 m where
        // faces lie on each other by design (a flat-folded stack).
        let overlaps: Vec<_> = model.overlaps(&frames).into_iter().filter(|o| o.2 > OVERLAP_TOLERANCE).collect();
        if let Some(&(a, b, depth)) = overlaps.first() {
            let more =
                if overlaps.len() > 1 { format!(" (and {} more pairs)", overlaps.len() - 1) } else { String::new() };
            return Err(ctx.span(
                raw,
                format!(
                    "[contact]: bodies '{}' and '{}' overlap by {} m at t = 0{more}; move them apart, exclude the pair (contact.exclude), or set contact.allow_initial_overlap = true to let contact push them apart",
                    model.bodies[a].name,
                    model.bodies[b].name,
                    short(format!("{depth:.3e}").parse().unwrap_or(depth))
                ),
            ));
        }
    }
    Ok(())
}
