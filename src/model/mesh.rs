//! A body's surface as triangles, for display: a plate's two faces (ear-clipped polygon) and
//! its rim, a box's six faces, and for a body without a shape the box of uniform density
//! with its mass and inertia (edges `a² = 6 (I_yy + I_zz − I_xx) / m` and so on, the inverse
//! of `I_xx = m (b² + c²) / 12`).

use super::body::Body;
use super::shape::Shape;
use crate::math::Vec3;

/// Triangles with flat normals, m, body frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, m, body frame.
    pub positions: Vec<Vec3>,
    /// Unit normal per vertex (the face's), body frame.
    pub normals: Vec<Vec3>,
    /// Vertex indices, three per triangle, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// True when the surface has no inside (a plate of zero thickness): draw both sides.
    pub two_sided: bool,
}

impl Mesh {
    /// Adds a planar face: `corners` in order round its outward normal `n`.
    fn face(&mut self, corners: &[Vec3], n: Vec3, triangles: &[[usize; 3]]) {
        let first = self.positions.len() as u32;
        self.positions.extend_from_slice(corners);
        self.normals.extend(std::iter::repeat_n(n, corners.len()));
        self.triangles.extend(triangles.iter().map(|t| t.map(|i| first + i as u32)));
    }
}

/// The surface of `body`: its shape's, or the box with its mass and inertia.
pub fn body_mesh(body: &Body) -> Mesh {
    match &body.shape {
        Some(Shape::Plate { vertices, thickness }) => plate(vertices, *thickness),
        Some(Shape::Cuboid { size, center }) => cuboid(*size, *center),
        Some(Shape::Cylinder { radius, height }) => cylinder(*radius, *height),
        None => {
            let i = body.inertia_in_body;
            let edge =
                |a: usize, b: usize, c: usize| (6.0 * (i[(b, b)] + i[(c, c)] - i[(a, a)]) / body.mass).max(0.0).sqrt();
            let mut size = Vec3::new(edge(0, 1, 2), edge(1, 0, 2), edge(2, 0, 1));
            // A flat or degenerate inertia still shows: no edge below 1 % of the longest.
            let floor = 0.01 * size.max().max(1e-3);
            size.iter_mut().for_each(|x| *x = x.max(floor));
            cuboid(size, Vec3::zeros())
        }
    }
}

/// A cylinder about z: [`super::shape::CYLINDER_SEGMENTS`] flat facets round its side
/// (each its own normal) and the two caps.
fn cylinder(radius: f64, height: f64) -> Mesh {
    let n = super::shape::CYLINDER_SEGMENTS;
    let h = height / 2.0;
    let at = |k: usize, z: f64| {
        let a = 2.0 * std::f64::consts::PI * (k % n) as f64 / n as f64;
        Vec3::new(radius * a.cos(), radius * a.sin(), z)
    };
    let mut m = Mesh::default();
    for k in 0..n {
        let mid = 2.0 * std::f64::consts::PI * (k as f64 + 0.5) / n as f64;
        let normal = Vec3::new(mid.cos(), mid.sin(), 0.0);
        m.face(&[at(k, -h), at(k + 1, -h), at(k + 1, h), at(k, h)], normal, &[[0, 1, 2], [0, 2, 3]]);
    }
    // Caps as fans, counter-clockwise about their outward normals.
    let fan: Vec<[usize; 3]> = (1..n - 1).map(|k| [0, k, k + 1]).collect();
    let top: Vec<Vec3> = (0..n).map(|k| at(k, h)).collect();
    m.face(&top, Vec3::z(), &fan);
    let bottom: Vec<Vec3> = (0..n).rev().map(|k| at(k, -h)).collect();
    m.face(&bottom, -Vec3::z(), &fan);
    m
}

/// A box with its edges along the body axes.
fn cuboid(size: Vec3, center: Vec3) -> Mesh {
    let mut m = Mesh::default();
    let h = size / 2.0;
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut n = Vec3::zeros();
            n[axis] = sign;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f64, b: f64| {
                let mut p = n.component_mul(&h);
                p[u] = a * h[u];
                p[v] = b * h[v];
                center + p
            };
            // Counter-clockwise about n: (u, v) is right-handed with n for sign +1.
            let mut corners = vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)];
            if sign < 0.0 {
                corners.reverse();
            }
            m.face(&corners, n, &[[0, 1, 2], [0, 2, 3]]);
        }
    }
    m
}

/// A plate: the polygon on both faces (±t/2 along its normal) and its rim; with t = 0, one
/// face to be drawn from both sides.
fn plate(vertices: &[Vec3], thickness: f64) -> Mesh {
    let count = vertices.len();
    // Newell's normal: the polygon's orientation, either way round.
    let n = (0..count).map(|i| vertices[i].cross(&vertices[(i + 1) % count])).sum::<Vec3>().normalize();
    let u = (vertices[1] - vertices[0]).normalize();
    let v = n.cross(&u);
    let flat: Vec<(f64, f64)> =
        vertices.iter().map(|p| ((p - vertices[0]).dot(&u), (p - vertices[0]).dot(&v))).collect();
    let ears = ear_clip(&flat);
    let mut m = Mesh::default();
    let offset = n * (thickness / 2.0);
    let top: Vec<Vec3> = vertices.iter().map(|p| p + offset).collect();
    m.face(&top, n, &ears);
    if thickness == 0.0 {
        m.two_sided = true;
        return m;
    }
    let bottom: Vec<Vec3> = vertices.iter().rev().map(|p| p - offset).collect();
    // The same triangles on the reversed list, wound the other way (about −n).
    let reversed: Vec<[usize; 3]> =
        ears.iter().map(|t| [count - 1 - t[2], count - 1 - t[1], count - 1 - t[0]]).collect();
    m.face(&bottom, -n, &reversed);
    for i in 0..count {
        let (a, b) = (vertices[i], vertices[(i + 1) % count]);
        let side = (b - a).cross(&n).normalize();
        m.face(&[a - offset, b - offset, b + offset, a + offset], side, &[[0, 1, 2], [0, 2, 3]]);
    }
    m
}

/// Triangles of a simple polygon given counter-clockwise in its plane (u, v), as vertex
/// indices, each counter-clockwise (ear clipping: O(n²), fine for panels).
fn ear_clip(points: &[(f64, f64)]) -> Vec<[usize; 3]> {
    let cross = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
    let mut ring: Vec<usize> = (0..points.len()).collect();
    let mut out = Vec::with_capacity(points.len().saturating_sub(2));
    while ring.len() > 3 {
        let n = ring.len();
        let is_ear = |i: usize| {
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (pa, pb, pc) = (points[a], points[b], points[c]);
            cross(pa, pb, pc) > 0.0
                && ring.iter().filter(|&&k| k != a && k != b && k != c).all(|&k| {
                    let p = points[k];
                    !(cross(pa, pb, p) >= 0.0 && cross(pb, pc, p) >= 0.0 && cross(pc, pa, p) >= 0.0)
                })
        };
        // A simple polygon always has an ear; round-off on a degenerate one may hide it, and
        // then the sharpest convex corner is cut.
        let ear = (0..n).find(|&i| is_ear(i)).unwrap_or(0);
        out.push([ring[(ear + n - 1) % n], ring[ear], ring[(ear + 1) % n]]);
        ring.remove(ear);
    }
    out.push([ring[0], ring[1], ring[2]]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cylinder's mesh is a closed, outward-wound prism: its volume by the divergence
    /// theorem (Σ a·(b×c)/6 over the triangles) is the inscribed 32-gon prism's,
    /// `n/2 · r² sin(2π/n) · h`, to round-off, and every triangle's winding agrees with the
    /// normal stored at its corners.
    #[test]
    fn a_cylinder_is_a_closed_outward_prism() {
        let (r, h) = (1.5, 0.4);
        let m = body_mesh(
            &Body::new("hub", 1.0, crate::math::Mat3::identity())
                .unwrap()
                .with_shape(Shape::Cylinder { radius: r, height: h }),
        );
        let volume: f64 = m
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        let n = crate::model::shape::CYLINDER_SEGMENTS as f64;
        let expected = n / 2.0 * r * r * (2.0 * std::f64::consts::PI / n).sin() * h;
        assert!((volume - expected).abs() < 1e-12 * expected, "{volume} vs {expected}");
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(&(c - a)).dot(&m.normals[t[0] as usize]) > 0.0);
        }
        assert!(!m.two_sided);
    }

    fn area(m: &Mesh) -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| m.positions[i as usize]);
                0.5 * (b - a).cross(&(c - a)).norm()
            })
            .sum()
    }

    /// Surface areas against closed forms (an L-shaped plate, non-convex, clockwise; a box),
    /// and every triangle's winding agreeing with its normal: to round-off (1e-12).
    #[test]
    fn meshes_cover_the_surface_facing_out() {
        let l = [(0.0, 0.0), (0.0, 2.0), (0.5, 2.0), (0.5, 0.5), (1.5, 0.5), (1.5, 0.0)];
        let vertices: Vec<Vec3> = l.iter().map(|&(x, y)| Vec3::new(x, y, 0.3)).collect();
        let (t, plate_area, perimeter) = (0.02, 1.5, 7.0);
        let m = plate(&vertices, t);
        assert!((area(&m) - (2.0 * plate_area + perimeter * t)).abs() < 1e-12, "{}", area(&m));
        let thin = plate(&vertices, 0.0);
        assert!(thin.two_sided && (area(&thin) - plate_area).abs() < 1e-12);
        let b = cuboid(Vec3::new(1.0, 2.0, 3.0), Vec3::new(5.0, 0.0, 0.0));
        assert!((area(&b) - 2.0 * (2.0 + 3.0 + 6.0)).abs() < 1e-12);
        for m in [&m, &b] {
            for t in &m.triangles {
                let [a, p, q] = t.map(|i| m.positions[i as usize]);
                let n = m.normals[t[0] as usize];
                assert!((p - a).cross(&(q - a)).normalize().dot(&n) > 1.0 - 1e-12, "a triangle faces inward");
            }
        }
    }
}
