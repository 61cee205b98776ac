//! Hinge laws from their `[hinge.law]` tables: the linear laws, and directional laws with
//! their tables, tape springs, stops, latches and locks.

use super::error::{Ctx, ScenarioError};
use super::raw::{DirectionEntry, RawLaw, RawTable, RawTable2};
use super::values::{matrix, one_angle, positive};
use crate::law::directional::{Angles, DIRECTION_NAMES, Direction, DirectionalLaw, Response, Stop, Table2, TapeSpring};
use crate::law::table::{Interpolation, Outside, Table};
use crate::law::{EulerPotential, HingeLaw, LinearGains, PaperLinear, RotationVectorLinear};
use crate::math::Mat3;
use toml::Spanned;

pub(super) fn law(ctx: &Ctx<'_>, hinge: &str, v: &Spanned<RawLaw>) -> Result<Box<dyn HingeLaw>, ScenarioError> {
    let l = v.get_ref();
    let kind = l.kind.get_ref().as_str();
    let directional_keys = [&l.x, &l.y, &l.z, &l.rx, &l.ry, &l.rz];
    if kind == "directional" {
        for (m, key) in [(&l.k_f, "k_f"), (&l.k_theta, "k_theta"), (&l.c_f, "c_f"), (&l.c_theta, "c_theta")] {
            if let Some(m) = m {
                return Err(ctx.span(
                    m,
                    format!("hinge '{hinge}': law.{key} does not apply to a directional law; give each direction its own response"),
                ));
            }
        }
        return directional(ctx, hinge, v);
    }
    if let Some(a) = &l.angles {
        return Err(ctx.span(a, format!("hinge '{hinge}': law.angles applies only to type = \"directional\"")));
    }
    if let Some((d, name)) = directional_keys.iter().zip(DIRECTION_NAMES).find_map(|(d, n)| d.as_ref().map(|d| (d, n)))
    {
        return Err(ctx.span(d, format!("hinge '{hinge}': law.{name} applies only to type = \"directional\"")));
    }
    let mat = |m: &Option<Spanned<toml::Value>>, key: &str, unit: &str, required: bool| match m {
        Some(m) => matrix(m.get_ref()).ok_or_else(|| {
            ctx.span(
                m,
                format!(
                    "hinge '{hinge}' law.{key} must be a number, 3 numbers (a diagonal) or a 3×3 matrix, in {unit}"
                ),
            )
        }),
        None if required => Err(ctx.span(v, format!("hinge '{hinge}': law needs '{key}' ({unit})"))),
        None => Ok(Mat3::zeros()),
    };
    let gains = LinearGains {
        k_f: mat(&l.k_f, "k_f", "N/m", true)?,
        k_theta: mat(&l.k_theta, "k_theta", "N·m/rad", true)?,
        c_f: mat(&l.c_f, "c_f", "N·s/m", false)?,
        c_theta: mat(&l.c_theta, "c_theta", "N·m·s/rad", false)?,
    };
    // One policy for every law: springs and dampers must not create energy. A stiffness or
    // damping matrix's symmetric part must be positive semidefinite (a directional law's k and
    // damping ≥ 0); a negative stiffness (snap-through, buckling) is a table's to describe.
    for (m, key, what, unit) in [
        (&gains.k_f, &l.k_f, "k_f", "N/m"),
        (&gains.k_theta, &l.k_theta, "k_theta", "N·m/rad"),
        (&gains.c_f, &l.c_f, "c_f", "N·s/m"),
        (&gains.c_theta, &l.c_theta, "c_theta", "N·m·s/rad"),
    ] {
        let sym = (m + m.transpose()) * 0.5;
        let lowest = sym.symmetric_eigenvalues().min();
        if lowest < -1e-12 * m.abs().max()
            && let Some(key) = key
        {
            return Err(ctx.span(
                key,
                format!(
                    "hinge '{hinge}': law.{what} must be positive semidefinite (its symmetric part's lowest eigenvalue is {lowest:e} {unit}): a negative spring or damper creates energy; describe a negative stiffness (snap-through) with a directional table"
                ),
            ));
        }
    }
    let symmetric = |what: &str| -> Result<(), ScenarioError> {
        for (m, key) in [(&gains.k_f, &l.k_f), (&gains.k_theta, &l.k_theta)] {
            if (m - m.transpose()).abs().max() > 1e-12 * m.abs().max() {
                let key = key.as_ref().expect("required above");
                return Err(ctx.span(
                    key,
                    format!(
                        "hinge '{hinge}': the {what} law needs symmetric stiffness matrices (a potential's Hessian)"
                    ),
                ));
            }
        }
        Ok(())
    };
    match kind {
        "paper-linear" => Ok(Box::new(PaperLinear { gains })),
        "euler-potential" => {
            symmetric("euler-potential")?;
            Ok(Box::new(EulerPotential { gains }))
        }
        "rotation-vector" => {
            symmetric("rotation-vector")?;
            Ok(Box::new(RotationVectorLinear { gains }))
        }
        other => Err(ctx.span(
            &l.kind,
            format!(
                "hinge '{hinge}': unknown law type '{other}'; valid: \"paper-linear\" (docs/model.md §4 law 1), \"euler-potential\" (law 2), \"rotation-vector\", \"directional\""
            ),
        )),
    }
}

fn directional(ctx: &Ctx<'_>, hinge: &str, v: &Spanned<RawLaw>) -> Result<Box<dyn HingeLaw>, ScenarioError> {
    let l = v.get_ref();
    let angles = match l.angles.as_ref().map(|a| (a, a.get_ref().as_str())) {
        Some((_, "euler")) => Angles::Euler,
        Some((_, "rotation-vector")) => Angles::RotationVector,
        Some((a, other)) => {
            return Err(ctx.span(
                a,
                format!("hinge '{hinge}': law.angles '{other}' is not one of \"euler\", \"rotation-vector\""),
            ));
        }
        None => {
            return Err(ctx.span(
                v,
                format!("hinge '{hinge}': a directional law needs angles = \"euler\" or \"rotation-vector\""),
            ));
        }
    };
    let raw = [&l.x, &l.y, &l.z, &l.rx, &l.ry, &l.rz];
    let mut dirs = Vec::with_capacity(6);
    for (i, (d, name)) in raw.iter().zip(DIRECTION_NAMES).enumerate() {
        let Some(d) = d else {
            return Err(ctx.span(
                v,
                format!(
                    "hinge '{hinge}': a directional law needs all six directions x, y, z, rx, ry, rz; '{name}' is missing (write {name} = {{ free = true }} for no force)"
                ),
            ));
        };
        dirs.push(direction(ctx, hinge, name, i >= 3, d)?);
    }
    let directions: [Direction; 6] = dirs.try_into().expect("six directions");
    if angles == Angles::RotationVector
        && let Some(i) = (3..6).find(|&i| directions[i].response == Response::Locked)
    {
        let d = raw[i].as_ref().expect("checked above");
        return Err(ctx.span(
            d,
            format!(
                "hinge '{hinge}' law.{}: rotational directions are locked as 3-2-1 Euler angles; use angles = \"euler\" for a law with locked rotations",
                DIRECTION_NAMES[i]
            ),
        ));
    }
    Ok(Box::new(DirectionalLaw { angles, directions }))
}

fn direction(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    rotational: bool,
    d: &Spanned<DirectionEntry>,
) -> Result<Direction, ScenarioError> {
    let r = &d.get_ref().0;
    let here = |m: String| ctx.span(d, format!("hinge '{hinge}' law.{name}: {m}"));
    let (unit, rate_unit) = if rotational { ("N·m/rad", "N·m·s/rad") } else { ("N/m", "N·s/m") };
    let unit_of_q = if rotational { "in rad (or band_deg in degrees)" } else { "in m" };
    let given = [
        r.free == Some(true),
        r.locked == Some(true),
        r.k.is_some(),
        r.table.is_some(),
        r.table2d.is_some(),
        r.tape_spring.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 || r.free == Some(false) || r.locked == Some(false) {
        return Err(here(format!(
            "give exactly one response: free = true, locked = true, k = <stiffness in {unit}>, table = {{ … }}, table2d = {{ … }} or tape_spring = {{ … }}"
        )));
    }
    if r.locked == Some(true) {
        if r.stop.is_some() || r.damping.is_some() || r.rest.is_some() || r.rest_deg.is_some() {
            return Err(here(
                "a locked direction is held at its initial value: it takes no stop, damping or rest".into(),
            ));
        }
        return Ok(Direction { response: Response::Locked, rest: 0.0, damping: 0.0, stop: None });
    }
    let angle = |rad: Option<f64>, deg: Option<f64>, key: &str| -> Result<Option<f64>, ScenarioError> {
        if !rotational && deg.is_some() {
            return Err(here(format!("'{key}_deg' applies only to rotational directions; use '{key}' in m")));
        }
        one_angle(key, rad, deg).map_err(&here)
    };
    let rest = angle(r.rest, r.rest_deg, "rest")?.unwrap_or(0.0);
    let damping = r.damping.unwrap_or(0.0);
    if damping < 0.0 {
        return Err(here(format!("damping must be ≥ 0 {rate_unit}, got {}", crate::math::short(damping))));
    }
    let response = if let Some(k) = r.k {
        if k < 0.0 {
            return Err(here(format!(
                "k must be ≥ 0 {unit}, got {k}: a negative spring creates energy; describe a negative stiffness (snap-through) with a table"
            )));
        }
        Response::Linear { k }
    } else if let Some(t) = &r.table {
        Response::Table(table(ctx, hinge, name, rotational, t)?)
    } else if let Some(t) = &r.table2d {
        Response::Table2(table2(ctx, hinge, name, rotational, t)?)
    } else if let Some(ts) = &r.tape_spring {
        let raw = ts.get_ref();
        let k0 = *raw.transition_stiffness.get_ref();
        if k0 <= 0.0 {
            return Err(ctx.span(
                &raw.transition_stiffness,
                format!("hinge '{hinge}' law.{name}: transition_stiffness must be > 0 {unit}"),
            ));
        }
        let increasing = table(ctx, hinge, name, rotational, &raw.increasing)?;
        let decreasing = table(ctx, hinge, name, rotational, &raw.decreasing)?;
        // The slip element needs the increasing branch on or above the decreasing one
        // everywhere. Both interpolants are checked at every data point of either table and,
        // for PCHIP, at 64 points inside each interval (cubics can cross between points);
        // beyond the data, as far again as the data span.
        let mut at: Vec<f64> = increasing.points().iter().chain(decreasing.points()).copied().collect();
        at.sort_by(f64::total_cmp);
        at.dedup();
        let span = at[at.len() - 1] - at[0];
        at.insert(0, at[0] - span);
        at.push(at[at.len() - 1] + span);
        let fine =
            increasing.interpolation() == Interpolation::Pchip || decreasing.interpolation() == Interpolation::Pchip;
        let per = if fine { 64 } else { 1 };
        for w in at.windows(2) {
            for k in 0..=per {
                let u = w[0] + (w[1] - w[0]) * k as f64 / per as f64;
                let (fi, fd) = (increasing.eval(u).0, decreasing.eval(u).0);
                if fi < fd - 1e-12 * fd.abs().max(1.0) {
                    return Err(ctx.span(
                        ts,
                        format!(
                            "hinge '{hinge}' law.{name}: the increasing branch lies below the decreasing one at {u:.6} ({fi:.6} < {fd:.6}); the branches must not cross (with pchip they can between data points: add points or use linear)"
                        ),
                    ));
                }
            }
        }
        Response::TapeSpring(TapeSpring::new(increasing, decreasing, k0))
    } else {
        Response::Free
    };
    let stop = match &r.stop {
        None => None,
        Some(st) => {
            let raw = st.get_ref();
            let at = angle(raw.at, raw.at_deg, "at")?.ok_or_else(|| {
                ctx.span(
                    st,
                    format!(
                        "hinge '{hinge}' law.{name}.stop needs 'at'{}",
                        if rotational { " or 'at_deg'" } else { "" }
                    ),
                )
            })?;
            let (free_above, within) = match raw.free.get_ref().as_str() {
                "above" => (true, false),
                "below" => (false, false),
                "within" => (true, true),
                other => {
                    return Err(ctx.span(
                        &raw.free,
                        format!("hinge '{hinge}' law.{name}.stop.free '{other}' must be \"above\" (the stop resists going below 'at'), \"below\" or \"within\" (free within at ± band)"),
                    ));
                }
            };
            let band = match (&raw.band, &raw.band_deg) {
                (Some(b), None) => Some((b, *b.get_ref())),
                (None, Some(b)) if rotational => Some((b, b.get_ref().to_radians())),
                (None, Some(b)) => {
                    return Err(ctx.span(
                        b,
                        format!("hinge '{hinge}' law.{name}.stop: 'band_deg' is for rotations; give 'band' in m"),
                    ));
                }
                (Some(b), Some(_)) => {
                    return Err(
                        ctx.span(b, format!("hinge '{hinge}' law.{name}.stop: give 'band' or 'band_deg', not both"))
                    );
                }
                (None, None) => None,
            };
            let band = match (within, band) {
                (true, Some((span, b))) => {
                    if !(b.is_finite() && b > 0.0) {
                        return Err(ctx.span(
                            span,
                            format!("hinge '{hinge}' law.{name}.stop.band must be a positive half-width {unit_of_q}; got {b}"),
                        ));
                    }
                    if raw.lock {
                        return Err(ctx.span(
                            span,
                            format!("hinge '{hinge}' law.{name}.stop: a latch (lock = true) holds at one stop; give free = \"above\" or \"below\", not \"within\""),
                        ));
                    }
                    b
                }
                (true, None) => {
                    return Err(ctx.span(
                        &raw.free,
                        format!("hinge '{hinge}' law.{name}.stop: free = \"within\" needs 'band', the half-width of the free band about 'at' {unit_of_q}"),
                    ));
                }
                (false, Some((span, _))) => {
                    return Err(ctx.span(
                        span,
                        format!("hinge '{hinge}' law.{name}.stop: 'band' goes with free = \"within\" (a one-sided stop has none)"),
                    ));
                }
                (false, None) => 0.0,
            };
            let stiffness = positive(ctx, &raw.stiffness, &format!("law.{name}.stop.stiffness"), unit)?;
            let damping = *raw.damping.get_ref();
            if damping < 0.0 {
                return Err(
                    ctx.span(&raw.damping, format!("hinge '{hinge}' law.{name}.stop.damping must be ≥ 0 {rate_unit}"))
                );
            }
            Some(Stop { at, free_above, band, stiffness, damping, lock: raw.lock })
        }
    };
    Ok(Direction { response, rest, damping, stop })
}

fn interpolation_and_outside(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    interpolation: &Spanned<String>,
    outside: &Spanned<String>,
) -> Result<(Interpolation, Outside), ScenarioError> {
    let i = match interpolation.get_ref().as_str() {
        "linear" => Interpolation::Linear,
        "pchip" => Interpolation::Pchip,
        other => {
            return Err(ctx.span(
                interpolation,
                format!("hinge '{hinge}' law.{name}: interpolation '{other}' must be \"linear\" or \"pchip\" (monotone C¹ cubic)"),
            ));
        }
    };
    let o = match outside.get_ref().as_str() {
        "error" => Outside::Error,
        "clamp" => Outside::Clamp,
        "extend" => Outside::Extend,
        other => {
            return Err(ctx.span(
                outside,
                format!("hinge '{hinge}' law.{name}: outside '{other}' must be \"error\", \"clamp\" or \"extend\""),
            ));
        }
    };
    Ok((i, o))
}

fn table2(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    rotational: bool,
    t: &Spanned<RawTable2>,
) -> Result<Table2, ScenarioError> {
    let r = t.get_ref();
    let here = |m: String| ctx.span(t, format!("hinge '{hinge}' law.{name} table2d: {m}"));
    let (interpolation, outside) = interpolation_and_outside(ctx, hinge, name, &r.interpolation, &r.outside)?;
    let Some(other) = DIRECTION_NAMES.iter().position(|d| *d == r.other.get_ref().as_str()) else {
        return Err(ctx.span(
            &r.other,
            format!(
                "hinge '{hinge}' law.{name}.table2d.other '{}' must be one of x, y, z, rx, ry, rz",
                r.other.get_ref()
            ),
        ));
    };
    if DIRECTION_NAMES[other] == name {
        return Err(ctx.span(&r.other, format!("hinge '{hinge}' law.{name}.table2d.other must be another direction")));
    }
    let path = ctx.base.join(&r.file);
    ctx.inputs.borrow_mut().push(path.clone());
    let grid = Table::read_grid_csv(&path).map_err(&here)?;
    if grid.u_angle != rotational || grid.v_angle != (other >= 3) {
        return Err(here(format!(
            "{}: the first column must be {} (direction {name}) and the second {} (direction {})",
            path.display(),
            if rotational { "an angle" } else { "a displacement" },
            if other >= 3 { "an angle" } else { "a displacement" },
            DIRECTION_NAMES[other]
        )));
    }
    let lines = grid
        .values
        .iter()
        .map(|vals| {
            let pts: Vec<(f64, f64)> = grid.u.iter().copied().zip(vals.iter().copied()).collect();
            Table::new(&pts, interpolation, outside)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(&here)?;
    Ok(Table2 { other, v: grid.v, lines, outside })
}

fn table(
    ctx: &Ctx<'_>,
    hinge: &str,
    name: &str,
    rotational: bool,
    t: &Spanned<RawTable>,
) -> Result<Table, ScenarioError> {
    let r = t.get_ref();
    let here = |m: String| ctx.span(t, format!("hinge '{hinge}' law.{name} table: {m}"));
    let (interpolation, outside) = interpolation_and_outside(ctx, hinge, name, &r.interpolation, &r.outside)?;
    let points = match (&r.file, &r.points) {
        (Some(file), None) => {
            let path = ctx.base.join(file);
            ctx.inputs.borrow_mut().push(path.clone());
            let (points, is_angle) = Table::read_csv(&path).map_err(&here)?;
            if is_angle != rotational {
                return Err(here(format!(
                    "{} has {} but direction {name} is {}",
                    path.display(),
                    if is_angle { "angles" } else { "displacements" },
                    if rotational {
                        "rotational (angle_rad or angle_deg, moment_Nm)"
                    } else {
                        "translational (displacement_m, force_N)"
                    }
                )));
            }
            points
        }
        (None, Some(p)) => p.iter().map(|p| (p[0], p[1])).collect(),
        _ => return Err(here("give either file = \"….csv\" or points = [[q, f], …] (SI units)".into())),
    };
    let points = match &r.scale {
        None => points,
        Some(scale) => {
            let k = *scale.get_ref();
            if !(k.is_finite() && k > 0.0) {
                return Err(ctx.span(
                    scale,
                    format!("hinge '{hinge}' law.{name} table: scale = {k} multiplies the table's values; give a finite number > 0"),
                ));
            }
            points.into_iter().map(|(q, f)| (q, k * f)).collect()
        }
    };
    Table::new(&points, interpolation, outside).map_err(here)
}
