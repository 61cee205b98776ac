//! A `[[body]]`: its mass and inertia given, or following from its shape and a density, or
//! both, checked against each other.

use super::error::{Ctx, ScenarioError};
use super::raw::{RawBody, RawShape};
use super::values::matrix;
use crate::math::{Mat3, Vec3};
use crate::model::{Body, Shape};
use toml::Spanned;

/// Given and computed mass properties must agree to this, relative.
const AGREE: f64 = 1e-9;

pub(super) fn body(ctx: &Ctx<'_>, b: &RawBody) -> Result<Body, ScenarioError> {
    let name = b.name.get_ref();
    let here = |at: std::ops::Range<usize>, m: String| ctx.at(Some(at), format!("body '{name}': {m}"));
    let inertia = match &b.inertia {
        None => None,
        Some(v) => Some(
            matrix(v.get_ref())
                .filter(|_| !matches!(v.get_ref(), toml::Value::Float(_) | toml::Value::Integer(_)))
                .ok_or_else(|| here(v.span(), "'inertia' must be 3 principal values [I1, I2, I3] or a full 3×3 tensor [[..],[..],[..]] in kg·m², body frame".into()))?,
        ),
    };
    let shape = b.shape.as_ref().map(|s| shape(ctx, name, s)).transpose()?;
    let (mass, inertia) = match &shape {
        None => {
            if let Some(d) = &b.density {
                return Err(here(
                    d.span(),
                    "'density' needs a 'shape' (a plate, a box or a cylinder) to apply to".into(),
                ));
            }
            match (&b.mass, inertia) {
                (Some(m), Some(i)) => (*m.get_ref(), i),
                _ => {
                    return Err(ctx.span(
                        &b.name,
                        format!("body '{name}' needs 'mass' (kg) and 'inertia' (kg·m², body frame), or a 'shape' with a 'density'"),
                    ));
                }
            }
        }
        Some(s) => {
            let sp = b.shape.as_ref().expect("a shape");
            // I/m follows from the shape alone, whatever the density: the unit-density
            // properties, scaled by mass / unit mass.
            let unit = s.mass_properties(1.0);
            let size = s.outline().iter().map(|p| p.norm()).fold(0.0, f64::max);
            // A shape too large (or too small) for f64: its volume or inertia overflows, and
            // every check against it below would pass on NaN.
            if !(unit.mass > 0.0
                && unit.mass.is_finite()
                && unit.inertia_about_centroid.iter().all(|x| x.is_finite())
                && unit.inertia_about_centroid.trace() > 0.0)
            {
                return Err(here(
                    sp.span(),
                    format!(
                        "the shape (extent {size:e} m) has a volume or inertia beyond what f64 holds ({:e} per unit density): give its sizes in metres, between about 1e-30 and 1e30",
                        unit.mass
                    ),
                ));
            }
            if unit.centroid.norm() > AGREE * size {
                let c = unit.centroid;
                return Err(here(
                    sp.span(),
                    format!(
                        "the shape's centroid is at [{:e}, {:e}, {:e}] m, but a body frame's origin is its centre of mass: move the shape by [{:e}, {:e}, {:e}] m",
                        c.x, c.y, c.z, -c.x, -c.y, -c.z
                    ),
                ));
            }
            let mass = match (&b.density, &b.mass) {
                (Some(d), m) => {
                    let density = *d.get_ref();
                    if !(density > 0.0 && density.is_finite()) {
                        let unit = if matches!(s, Shape::Plate { .. }) { "kg/m²" } else { "kg/m³" };
                        return Err(here(
                            d.span(),
                            format!(
                                "'density' must be a finite number > 0 {unit}, got {}",
                                crate::math::short(density)
                            ),
                        ));
                    }
                    let from_shape = density * unit.mass;
                    if let Some(m) = m
                        && (m.get_ref() - from_shape).abs() > AGREE * from_shape
                    {
                        return Err(here(
                            m.span(),
                            format!(
                                "'mass' = {} kg disagrees with its shape and density ({from_shape} kg); give one of them",
                                m.get_ref()
                            ),
                        ));
                    }
                    from_shape
                }
                (None, Some(m)) => *m.get_ref(),
                (None, None) => {
                    return Err(here(
                        sp.span(),
                        "a shape needs a 'density' (kg/m² for a plate, kg/m³ for a box or a cylinder) or a 'mass' (kg)"
                            .into(),
                    ));
                }
            };
            let from_shape = unit.inertia_about_centroid * (mass / unit.mass);
            if !from_shape.iter().all(|x| x.is_finite()) || !mass.is_finite() {
                return Err(here(
                    sp.span(),
                    format!(
                        "the shape's mass {mass:e} kg and inertia are beyond what f64 holds: give a smaller density or size"
                    ),
                ));
            }
            if let (Some(i), Some(v)) = (inertia, &b.inertia)
                && (i - from_shape).abs().max() > AGREE * from_shape.abs().max()
            {
                return Err(here(
                    v.span(),
                    format!("'inertia' disagrees with its shape's ({}); give one of them", describe(&from_shape)),
                ));
            }
            (mass, inertia.unwrap_or(from_shape))
        }
    };
    let body = Body::new(name, mass, inertia).map_err(|m| match (&b.mass, &b.inertia) {
        (Some(ms), _) if !(mass > 0.0 && mass.is_finite()) => ctx.at(Some(ms.span()), m),
        (_, Some(i)) => ctx.at(Some(i.span()), m),
        _ => ctx.span(&b.name, m),
    })?;
    Ok(match shape {
        Some(s) => body.with_shape(s),
        None => body,
    })
}

/// The shape of `shape = { … }`, checked.
fn shape(ctx: &Ctx<'_>, name: &str, s: &Spanned<RawShape>) -> Result<Shape, ScenarioError> {
    let r = s.get_ref();
    let v = |p: [f64; 3]| Vec3::new(p[0], p[1], p[2]);
    let shape = match (&r.polygon, r.cuboid, r.cylinder) {
        (Some(vertices), None, None) => {
            Shape::Plate { vertices: vertices.iter().map(|p| v(p.0)).collect(), thickness: r.thickness.unwrap_or(0.0) }
        }
        (None, Some(size), None) if r.thickness.is_none() => Shape::Cuboid { size: v(size.0), center: Vec3::zeros() },
        (None, None, Some(c)) if r.thickness.is_none() => Shape::Cylinder { radius: c.radius, height: c.height },
        _ => {
            return Err(ctx.span(
                s,
                format!(
                    "body '{name}': a shape is one of {{ polygon = [[x, y, z], …], thickness = … }} (m, body frame), {{ box = [a, b, c] }} (m, edges along the body axes) or {{ cylinder = {{ radius = r, height = h }} }} (m, axis along the body's z axis)"
                ),
            ));
        }
    };
    shape.check().map_err(|m| ctx.span(s, format!("body '{name}' shape: {m}")))?;
    Ok(shape)
}

fn describe(m: &Mat3) -> String {
    format!(
        "[[{:e}, {:e}, {:e}], [{:e}, {:e}, {:e}], [{:e}, {:e}, {:e}]] kg·m²",
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)]
    )
}
