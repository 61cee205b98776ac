//! A body's geometry: a flat polygonal plate with a thickness, or a box, and the exact mass
//! properties that follow from it and a density. The shape changes nothing in the dynamics
//! beyond the mass properties; animation and contact use it.
//!
//! The plate's area, centroid and second moments are the closed forms of the shoelace
//! decomposition into triangles with the first vertex (Green's theorem over the boundary;
//! exact for any simple polygon, convex or not), computed about that vertex, in the plate's
//! own plane, so round-off stays relative to the plate's size, not its distance from the
//! body's origin. The thickness t adds `m t²/12` about the two in-plane axes (a slab of
//! uniform density).

use crate::math::{Mat3, Vec3};

/// A body's geometry, in its body frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A flat plate: a simple polygon (vertices in order, either way round, all in one
    /// plane; m, body frame) extruded by `thickness` (m, ≥ 0) along its normal, centred on
    /// the polygon's plane.
    Plate {
        /// The polygon's vertices, m, body frame.
        vertices: Vec<Vec3>,
        /// Thickness along the polygon's normal, m.
        thickness: f64,
    },
    /// A rectangular box with its edges along the body axes.
    Cuboid {
        /// Edge lengths along x, y, z, m.
        size: Vec3,
        /// Its centre, m, body frame.
        center: Vec3,
    },
    /// A solid circular cylinder with its axis along the body's z axis, centred on the origin
    /// (a hub, say).
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Height along z, m.
        height: f64,
    },
}

/// Points round a cylinder's rim in [`Shape::outline`] and facets of its display mesh.
pub const CYLINDER_SEGMENTS: usize = 32;

/// Mass, centre of mass and inertia of a shape of uniform density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, m, body frame.
    pub centroid: Vec3,
    /// Inertia about the centre of mass, kg·m², body frame.
    pub inertia_about_centroid: Mat3,
}

/// The plane of a plate: an orthonormal frame (u, v in the plane, n its normal) and the
/// vertices' coordinates in (u, v) relative to the first vertex.
struct PlaneFrame {
    u: Vec3,
    v: Vec3,
    n: Vec3,
    points: Vec<(f64, f64)>,
}

impl Shape {
    /// Checks the shape: finite numbers; a plate's vertices at least three, in one plane (to
    /// 1e-9 of its size), enclosing an area, its edges not crossing, its thickness ≥ 0; a
    /// box's edges > 0. The message says what is wrong and what would be valid.
    pub fn check(&self) -> Result<(), String> {
        match self {
            Shape::Plate { vertices, thickness } => {
                if vertices.len() < 3 {
                    return Err(format!("a plate needs at least 3 vertices, got {}", vertices.len()));
                }
                if vertices.iter().any(|p| !p.iter().all(|x| x.is_finite())) || !thickness.is_finite() {
                    return Err("a plate's vertices and thickness must be finite".into());
                }
                if *thickness < 0.0 {
                    return Err(format!("a plate's thickness must be ≥ 0 m, got {thickness}"));
                }
                let frame = plane_frame(vertices)?;
                let size = diameter(vertices);
                if let Some((i, d)) = vertices
                    .iter()
                    .enumerate()
                    .map(|(i, p)| (i, (p - vertices[0]).dot(&frame.n).abs()))
                    .find(|(_, d)| *d > 1e-9 * size)
                {
                    return Err(format!(
                        "a plate's vertices must lie in one plane: vertex {} is {d:e} m off the plane of the others",
                        i + 1
                    ));
                }
                if let Some((i, j)) = crossing_edges(&frame.points) {
                    return Err(format!(
                        "a plate's edges must not cross: edge {} (vertices {} to {}) crosses edge {} (vertices {} to {}); list the vertices in order round the polygon",
                        i + 1,
                        i + 1,
                        (i + 1) % vertices.len() + 1,
                        j + 1,
                        j + 1,
                        (j + 1) % vertices.len() + 1
                    ));
                }
                Ok(())
            }
            Shape::Cuboid { size, center } => {
                if !(size.iter().chain(center.iter()).all(|x| x.is_finite())) {
                    return Err("a box's size and centre must be finite".into());
                }
                if size.iter().any(|x| *x <= 0.0) {
                    return Err(format!("a box's edges must be > 0 m, got [{}, {}, {}]", size.x, size.y, size.z));
                }
                Ok(())
            }
            Shape::Cylinder { radius, height } => {
                if !(radius.is_finite() && height.is_finite() && *radius > 0.0 && *height > 0.0) {
                    return Err(format!(
                        "a cylinder's radius and height must be finite and > 0 m, got radius {}, height {}",
                        crate::math::short(*radius),
                        crate::math::short(*height)
                    ));
                }
                Ok(())
            }
        }
    }

    /// Mass properties at uniform `density`: kg/m² (mass per unit area of the plate,
    /// whatever its thickness) for a plate, kg/m³ for a box. The shape must have passed
    /// [`Self::check`].
    pub fn mass_properties(&self, density: f64) -> MassProperties {
        match self {
            Shape::Plate { vertices, thickness } => plate(vertices, *thickness, density),
            Shape::Cuboid { size, center } => {
                let mass = density * size.x * size.y * size.z;
                let (a2, b2, c2) = (size.x * size.x, size.y * size.y, size.z * size.z);
                let inertia = Mat3::from_diagonal(&Vec3::new(b2 + c2, a2 + c2, a2 + b2)) * (mass / 12.0);
                MassProperties { mass, centroid: *center, inertia_about_centroid: inertia }
            }
            Shape::Cylinder { radius, height } => {
                // Solid cylinder about its centroid: I_z = m r²/2, I_x = I_y = m (3r² + h²)/12.
                let mass = density * std::f64::consts::PI * radius * radius * height;
                let (r2, h2) = (radius * radius, height * height);
                let side = mass * (3.0 * r2 + h2) / 12.0;
                let inertia = Mat3::from_diagonal(&Vec3::new(side, side, mass * r2 / 2.0));
                MassProperties { mass, centroid: Vec3::zeros(), inertia_about_centroid: inertia }
            }
        }
    }

    /// Points that outline the shape, m, body frame: a plate's vertices (on its mid-plane),
    /// a box's eight corners, [`CYLINDER_SEGMENTS`] points round each rim of a cylinder.
    pub fn outline(&self) -> Vec<Vec3> {
        match self {
            Shape::Plate { vertices, .. } => vertices.clone(),
            Shape::Cuboid { size, center } => (0..8)
                .map(|k| {
                    let s = |bit: usize| if k & bit == 0 { -0.5 } else { 0.5 };
                    center + Vec3::new(s(1) * size.x, s(2) * size.y, s(4) * size.z)
                })
                .collect(),
            Shape::Cylinder { radius, height } => [-0.5, 0.5]
                .iter()
                .flat_map(|z| {
                    (0..CYLINDER_SEGMENTS).map(move |k| {
                        let a = 2.0 * std::f64::consts::PI * k as f64 / CYLINDER_SEGMENTS as f64;
                        Vec3::new(radius * a.cos(), radius * a.sin(), z * height)
                    })
                })
                .collect(),
        }
    }
}

/// The largest distance between two vertices, m.
fn diameter(vertices: &[Vec3]) -> f64 {
    vertices.iter().flat_map(|a| vertices.iter().map(move |b| (a - b).norm())).fold(0.0, f64::max)
}

/// Newell's sum for a polygon (m², body frame): twice its area along its normal, the side its
/// vertices turn anticlockwise about (robust for non-convex polygons).
pub fn newell(vertices: &[Vec3]) -> Vec3 {
    let p0 = vertices[0];
    let mut normal = Vec3::zeros();
    for (i, a) in vertices.iter().enumerate() {
        let b = vertices[(i + 1) % vertices.len()];
        normal += (a - p0).cross(&(b - p0));
    }
    normal
}

/// The plate's plane: its normal by Newell's method (robust for non-convex polygons), u along
/// the first edge, v = n × u, and the vertices' (u, v) coordinates from the first vertex.
fn plane_frame(vertices: &[Vec3]) -> Result<PlaneFrame, String> {
    let p0 = vertices[0];
    let normal = newell(vertices);
    let size = diameter(vertices);
    if normal.norm() <= 1e-12 * size * size || normal.norm().is_nan() {
        return Err("a plate's vertices enclose no area (they are collinear or repeat)".into());
    }
    let n = normal.normalize();
    let first = vertices.iter().skip(1).map(|p| p - p0).find(|e| e.norm() > 1e-12 * size).expect("an area");
    let u = (first - n * first.dot(&n)).normalize();
    let v = n.cross(&u);
    let points = vertices.iter().map(|p| ((p - p0).dot(&u), (p - p0).dot(&v))).collect();
    Ok(PlaneFrame { u, v, n, points })
}

/// The first pair of edges (by index) that cross or touch other than at a shared vertex.
fn crossing_edges(points: &[(f64, f64)]) -> Option<(usize, usize)> {
    let n = points.len();
    let orient = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
    for i in 0..n {
        for j in i + 1..n {
            // Neighbouring edges share a vertex.
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (a, b) = (points[i], points[(i + 1) % n]);
            let (c, d) = (points[j], points[(j + 1) % n]);
            let (d1, d2) = (orient(a, b, c), orient(a, b, d));
            let (d3, d4) = (orient(c, d, a), orient(c, d, b));
            if d1 * d2 <= 0.0 && d3 * d4 <= 0.0 && (d1 != 0.0 || d2 != 0.0 || d3 != 0.0 || d4 != 0.0) {
                return Some((i, j));
            }
        }
    }
    None
}

/// A plate's mass properties (see the module's notes).
fn plate(vertices: &[Vec3], thickness: f64, density: f64) -> MassProperties {
    let frame = plane_frame(vertices).expect("checked");
    let pts = &frame.points;
    // Shoelace sums over the edges, about the first vertex: area A, first moments (∫x, ∫y)
    // and second moments (∫x², ∫y², ∫xy).
    let (mut a, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, &(x0, y0)) in pts.iter().enumerate() {
        let (x1, y1) = pts[(i + 1) % pts.len()];
        let c = x0 * y1 - x1 * y0;
        a += c;
        sx += (x0 + x1) * c;
        sy += (y0 + y1) * c;
        sxx += (x0 * x0 + x0 * x1 + x1 * x1) * c;
        syy += (y0 * y0 + y0 * y1 + y1 * y1) * c;
        sxy += (x0 * y1 + 2.0 * x0 * y0 + 2.0 * x1 * y1 + x1 * y0) * c;
    }
    // Clockwise polygons give negative sums: every integral changes sign with the orientation.
    let sign = a.signum();
    let area = 0.5 * a * sign;
    let (ix, iy) = (sx * sign / 6.0, sy * sign / 6.0);
    let (ixx, iyy, ixy) = (sxx * sign / 12.0, syy * sign / 12.0, sxy * sign / 24.0);
    let (cx, cy) = (ix / area, iy / area);
    // Second moments about the centroid (parallel axes).
    let jxx = ixx - area * cx * cx;
    let jyy = iyy - area * cy * cy;
    let jxy = ixy - area * cx * cy;
    let mass = density * area;
    let slab = mass * thickness * thickness / 12.0;
    // In the plate's frame (u, v, n): I_uu = σ∫v² + m t²/12, I_vv = σ∫u² + m t²/12,
    // I_nn = σ∫(u² + v²), I_uv = −σ∫uv.
    let local = Mat3::new(
        density * jyy + slab,
        -density * jxy,
        0.0,
        -density * jxy,
        density * jxx + slab,
        0.0,
        0.0,
        0.0,
        density * (jxx + jyy),
    );
    let rotation = Mat3::from_columns(&[frame.u, frame.v, frame.n]);
    let inertia = rotation * local * rotation.transpose();
    MassProperties {
        mass,
        centroid: vertices[0] + frame.u * cx + frame.v * cy,
        inertia_about_centroid: (inertia + inertia.transpose()) * 0.5,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An independent computation: the polygon cut into triangles by ear clipping (no signed
    /// areas, no fan from one vertex), each integrated by the three-edge-midpoint rule, which
    /// is exact for the quadratic integrands of area, first and second moments. Returns the
    /// mass, the centroid and (∫x², ∫y², ∫xy) about the centroid, times the density.
    fn by_ears(points: &[(f64, f64)], density: f64) -> (f64, (f64, f64), [f64; 3]) {
        let cross = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        let mut ring: Vec<(f64, f64)> = points.to_vec();
        let signed: f64 = (0..ring.len()).map(|i| cross((0.0, 0.0), ring[i], ring[(i + 1) % ring.len()])).sum();
        if signed < 0.0 {
            ring.reverse();
        }
        let mut triangles = Vec::new();
        while ring.len() > 3 {
            let n = ring.len();
            let ear = (0..n)
                .find(|&i| {
                    let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
                    cross(a, b, c) > 0.0
                        && ring.iter().all(|&p| {
                            p == a
                                || p == b
                                || p == c
                                || !(cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0)
                        })
                })
                .expect("a simple polygon has an ear");
            triangles.push((ring[(ear + n - 1) % n], ring[ear], ring[(ear + 1) % n]));
            ring.remove(ear);
        }
        triangles.push((ring[0], ring[1], ring[2]));
        let integrate = |f: &dyn Fn(f64, f64) -> f64| -> f64 {
            triangles
                .iter()
                .map(|&(a, b, c)| {
                    let mid = |p: (f64, f64), q: (f64, f64)| f(0.5 * (p.0 + q.0), 0.5 * (p.1 + q.1));
                    0.5 * cross(a, b, c) / 3.0 * (mid(a, b) + mid(b, c) + mid(c, a))
                })
                .sum()
        };
        let area = integrate(&|_, _| 1.0);
        let (cx, cy) = (integrate(&|x, _| x) / area, integrate(&|_, y| y) / area);
        let jxx = integrate(&|x, _| (x - cx) * (x - cx));
        let jyy = integrate(&|_, y| (y - cy) * (y - cy));
        let jxy = integrate(&|x, y| (x - cx) * (y - cy));
        (density * area, (cx, cy), [density * jxx, density * jyy, density * jxy])
    }

    const POLYGONS: [&[(f64, f64)]; 4] = [
        &[(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)],
        // An L (non-convex), clockwise.
        &[(0.0, 0.0), (0.0, 2.0), (0.5, 2.0), (0.5, 0.5), (1.5, 0.5), (1.5, 0.0)],
        // A non-convex arrow far from the origin (an offset centroid).
        &[(40.0, 10.0), (43.0, 11.5), (40.0, 13.0), (41.0, 11.7)],
        // A triangle across the origin.
        &[(-1.0, -0.5), (1.5, -0.3), (0.25, 2.0)],
    ];

    /// Plates in the body's x–y plane, convex and not, near the origin and far from it: the
    /// closed forms against the ear-clipped quadrature, to 1e-12 (relative to the mass, the
    /// polygon's size and the largest moment: both are exact up to round-off).
    #[test]
    fn plate_mass_properties_match_an_independent_quadrature() {
        for pts in POLYGONS {
            let vertices: Vec<Vec3> = pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
            let size = diameter(&vertices);
            let shape = Shape::Plate { vertices, thickness: 0.0 };
            shape.check().expect("valid");
            let mp = shape.mass_properties(3.0);
            let (m, (cx, cy), [jxx, jyy, jxy]) = by_ears(pts, 3.0);
            let scale = jxx.abs().max(jyy.abs());
            assert!((mp.mass - m).abs() <= 1e-12 * m, "mass {} vs {m}", mp.mass);
            assert!((mp.centroid.x - cx).abs() <= 1e-12 * size, "cx {} vs {cx}", mp.centroid.x);
            assert!((mp.centroid.y - cy).abs() <= 1e-12 * size, "cy {} vs {cy}", mp.centroid.y);
            let i = mp.inertia_about_centroid;
            for (got, want) in [(i[(0, 0)], jyy), (i[(1, 1)], jxx), (i[(2, 2)], jxx + jyy), (i[(0, 1)], -jxy)] {
                assert!((got - want).abs() <= 1e-12 * scale, "{got} vs {want} ({pts:?})");
            }
        }
    }

    /// The same plates turned into a tilted plane, moved off the origin and given a thickness:
    /// `I = R (I_flat + m t²/12 on the in-plane axes) Rᵀ`, centroid `R c + offset`.
    #[test]
    fn tilted_thick_plates_turn_with_their_plane() {
        let rotation = crate::math::Euler321::new(0.7, -0.4, 1.1).to_dcm().transpose();
        let offset = Vec3::new(-3.0, 5.0, 2.5);
        let t = 0.05;
        for pts in POLYGONS {
            let flat: Vec<Vec3> = pts.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
            let f = Shape::Plate { vertices: flat.clone(), thickness: 0.0 }.mass_properties(2.0);
            let tilted: Vec<Vec3> = flat.iter().map(|p| rotation * p + offset).collect();
            let shape = Shape::Plate { vertices: tilted, thickness: t };
            shape.check().expect("valid");
            let g = shape.mass_properties(2.0);
            let slab = Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 0.0)) * (f.mass * t * t / 12.0);
            let expected = rotation * (f.inertia_about_centroid + slab) * rotation.transpose();
            let scale = expected.abs().max();
            assert!((g.mass - f.mass).abs() <= 1e-12 * f.mass);
            assert!((g.centroid - (rotation * f.centroid + offset)).norm() <= 1e-12 * (offset.norm() + 50.0));
            assert!((g.inertia_about_centroid - expected).abs().max() <= 1e-12 * scale, "{pts:?}");
        }
    }

    /// A solid cylinder's mass properties against a midpoint quadrature over its volume
    /// (400 radial × 400 angular × 200 axial cells: error ~1e-5 relative, so 1e-4 checks the
    /// closed form's every term), and bad sizes refused.
    #[test]
    fn cylinder_mass_properties_match_a_quadrature() {
        let (r, h, rho) = (0.8, 0.3, 1200.0);
        let p = Shape::Cylinder { radius: r, height: h }.mass_properties(rho);
        let (nr, na, nz) = (400, 400, 200);
        let (mut mass, mut ixx, mut izz) = (0.0, 0.0, 0.0);
        for i in 0..nr {
            let rr = r * (i as f64 + 0.5) / nr as f64;
            let dr = r / nr as f64;
            for j in 0..na {
                let a = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / na as f64;
                let da = 2.0 * std::f64::consts::PI / na as f64;
                for k in 0..nz {
                    let z = h * ((k as f64 + 0.5) / nz as f64 - 0.5);
                    let dm = rho * rr * dr * da * (h / nz as f64);
                    let (x, y) = (rr * a.cos(), rr * a.sin());
                    mass += dm;
                    ixx += dm * (y * y + z * z);
                    izz += dm * (x * x + y * y);
                }
            }
        }
        let rel = |a: f64, b: f64| (a - b).abs() / b;
        assert!(rel(p.mass, mass) < 1e-4 && rel(p.inertia_about_centroid[(0, 0)], ixx) < 1e-4);
        assert!(rel(p.inertia_about_centroid[(1, 1)], ixx) < 1e-4 && rel(p.inertia_about_centroid[(2, 2)], izz) < 1e-4);
        assert_eq!(p.centroid, Vec3::zeros());
        for (radius, height) in [(0.0, 1.0), (1.0, -1.0), (f64::NAN, 1.0), (1.0, f64::INFINITY)] {
            let e = Shape::Cylinder { radius, height }.check().unwrap_err();
            assert!(e.contains("cylinder's radius and height"), "{e}");
        }
        assert_eq!(Shape::Cylinder { radius: 1.0, height: 2.0 }.outline().len(), 2 * CYLINDER_SEGMENTS);
    }

    #[test]
    fn bad_plates_are_refused() {
        let bad = [
            (vec![Vec3::zeros(), Vec3::x()], 0.0, "at least 3"),
            (vec![Vec3::zeros(), Vec3::x(), Vec3::x() * 2.0], 0.0, "no area"),
            (vec![Vec3::zeros(), Vec3::x(), Vec3::new(1.0, 1.0, 0.1), Vec3::y()], 0.0, "one plane"),
            (
                vec![
                    Vec3::zeros(),
                    Vec3::x() * 4.0,
                    Vec3::new(4.0, 2.0, 0.0),
                    Vec3::new(1.0, -1.0, 0.0),
                    Vec3::y() * 2.0,
                ],
                0.0,
                "cross",
            ),
            (vec![Vec3::zeros(), Vec3::x(), Vec3::y()], -0.1, "thickness"),
        ];
        for (vertices, thickness, word) in bad {
            let e = Shape::Plate { vertices, thickness }.check().unwrap_err();
            assert!(e.contains(word), "{e}");
        }
    }
}
