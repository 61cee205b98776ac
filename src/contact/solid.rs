//! One body's contact geometry (docs/contact.md §1): its solid, as a signed distance exact
//! inside the solid, and the sample points with which it probes other solids.
//!
//! A contact is a sample point (a sphere of radius ρ about a point fixed in one body) inside
//! another body's solid: penetration δ = ρ − d, with d the signed distance of the point from
//! the solid's surface (negative inside). Both are functions of the two bodies' poses alone,
//! so the contact's elastic energy is a potential: the force along the distance's gradient,
//! applied at the sample point to both bodies, conserves energy, P and H exactly.

use crate::math::{Mat3, Real, Vec3, lift, re, real};
use nalgebra::{Matrix3, Vector3};

/// A solid in its own frame.
#[derive(Clone, Debug, PartialEq)]
pub enum SolidKind {
    /// A simple polygon (counter-clockwise, x and y in the solid frame, m) extruded
    /// ±`half_thickness` along z (m): a plate of any outline, convex or not.
    Prism {
        /// Its edges in order (each starting at a vertex), with what [`polygon_distance`]
        /// needs of each formed once.
        edges: Vec<Edge>,
        /// Whether the outline is strictly convex (every turn to the left, by more than
        /// 1e-9 rad), which lets [`outline_distance`] take the farthest edge line (see there).
        convex: bool,
        /// Half the thickness, m (> 0).
        half_thickness: f64,
        /// Radius of the rim's rounding, m (0 ≤ it < `half_thickness`): the edges between
        /// the faces and the side walls are quarter cylinders of this radius (a thin plate's:
        /// half its half thickness; a thick one's: 0, sharp). Inside the solid within it of
        /// both a face and a wall the nearest surface is the rounding, so the normal turns
        /// smoothly from the face's to the wall's instead of jumping where the two are
        /// equally near (docs/contact.md §1).
        rim_radius: f64,
    },
    /// A box centred on the origin with its edges along the axes.
    Cuboid {
        /// Half the edge lengths, m.
        half: Vec3,
    },
    /// A circular cylinder about z, centred on the origin.
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Half the height, m.
        half_height: f64,
    },
}

/// A point fixed in a body that probes other bodies' solids, with its radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Centre, m, body frame.
    pub point_in_body: Vec3,
    /// Radius ρ, m (0 for a point).
    pub radius: f64,
}

/// A body's contact geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// The solid frame's origin, m, body frame.
    pub origin_in_body: Vec3,
    /// Rotation from the body frame to the solid frame: `p_s = dcm_s_b (p_b − origin)`.
    pub dcm_s_b: Mat3,
    /// The solid in its frame.
    pub kind: SolidKind,
    /// Its sample points.
    pub samples: Vec<Sample>,
    /// Centre of a box about the solid and its samples, m, body frame.
    pub bound_center_in_body: Vec3,
    /// Half extents of that box (body axes), m.
    pub bound_half_in_body: Vec3,
    /// Runs of at most [`GROUP`] consecutive samples with a sphere about them (centre m, body
    /// frame; radius m, the samples' own radii included): a sphere's distance from a solid
    /// bounds its samples' from below.
    pub groups: Vec<(std::ops::Range<usize>, Vec3, f64)>,
}

/// Samples per group (see [`Solid::groups`]).
pub const GROUP: usize = 16;

/// The most sample points one body may have: beyond it a run would spend its time probing.
pub const MAX_SAMPLES: usize = 20_000;

impl Solid {
    /// A plate: `vertices` (m, body frame, one plane, either way round) extruded by
    /// `thickness` (m, > 0) about their plane. A thin plate (thickness at most half its
    /// longest edge, and its outline moved in by half the thickness still a polygon) probes with spheres of radius thickness/2 along its outline, inset so
    /// that they touch its faces and sides, one per thickness of outline, and with points on
    /// its faces' edges at an acute corner, where the rounded rim leaves the tip out; a thick one (a hub
    /// prism) with points on its top and bottom outlines and side edges, `spacing` m apart.
    pub fn plate(vertices: &[Vec3], thickness: f64, spacing: f64) -> Result<Self, String> {
        let n = vertices.len();
        // Newell's normal and the centroid of the vertices.
        let mut normal = Vec3::zeros();
        for i in 0..n {
            let (a, b) = (vertices[i], vertices[(i + 1) % n]);
            normal += a.cross(&b);
        }
        let origin = vertices.iter().sum::<Vec3>() / n as f64;
        let z = normal.try_normalize(0.0).ok_or("the polygon has no area")?;
        let x = (vertices[1] - vertices[0]).try_normalize(0.0).ok_or("two vertices coincide")?;
        let x = (x - z * z.dot(&x)).normalize();
        let y = z.cross(&x);
        let dcm_s_b = Mat3::from_rows(&[x.transpose(), y.transpose(), z.transpose()]);
        let polygon: Vec<[f64; 2]> = vertices
            .iter()
            .map(|v| {
                let p = dcm_s_b * (v - origin);
                [p.x, p.y]
            })
            .collect();
        let h = 0.5 * thickness;
        let longest = (0..n).map(|i| dist2(polygon[i], polygon[(i + 1) % n])).fold(0.0, f64::max);
        let mut samples = Vec::new();
        let inset = if thickness <= 0.5 * longest { inset_polygon(&polygon, h) } else { None };
        let thin = inset.is_some();
        let to_body = |p: [f64; 2], zz: f64| origin + dcm_s_b.transpose() * Vec3::new(p[0], p[1], zz);
        match inset {
            Some(inner) => {
                for i in 0..n {
                    let (a, b) = (inner[i], inner[(i + 1) % n]);
                    let k = parts(dist2(a, b), thickness)?;
                    for j in 0..k {
                        let t = j as f64 / k as f64;
                        let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                        samples.push(Sample { point_in_body: to_body(p, 0.0), radius: h });
                    }
                }
                for p in tip_points(&polygon, h, thickness) {
                    samples.push(Sample { point_in_body: to_body([p[0], p[1]], p[2]), radius: 0.0 });
                }
            }
            None => {
                for i in 0..n {
                    let (a, b) = (polygon[i], polygon[(i + 1) % n]);
                    for zz in [-h, h] {
                        let k = parts(dist2(a, b), spacing)?;
                        for j in 0..k {
                            let t = j as f64 / k as f64;
                            let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                            samples.push(Sample { point_in_body: to_body(p, zz), radius: 0.0 });
                        }
                    }
                    let k = parts(thickness, spacing)?;
                    for j in 1..k {
                        let zz = -h + thickness * j as f64 / k as f64;
                        samples.push(Sample { point_in_body: to_body(a, zz), radius: 0.0 });
                    }
                }
            }
        }
        // A thin plate's rim is rounded (see `SolidKind::Prism::rim_radius`); a thick plate
        // (a hub) keeps its sharp edges.
        let rim_radius = if thin { 0.5 * h } else { 0.0 };
        let kind =
            SolidKind::Prism { edges: Edge::of(&polygon), convex: is_convex(&polygon), half_thickness: h, rim_radius };
        Self::finish(origin, dcm_s_b, kind, samples)
    }

    /// A box of edge lengths `size` (m) centred at `center` (m, body frame), edges along the
    /// body axes, probing with its 8 corners and points along its edges at most `spacing` m
    /// apart (each edge in equal parts).
    pub fn cuboid(size: Vec3, center: Vec3, spacing: f64) -> Result<Self, String> {
        let half = size * 0.5;
        let mut samples: Vec<Sample> = (0..8)
            .map(|c| Sample {
                point_in_body: center + half.component_mul(&Vec3::new(sign(c & 1), sign(c & 2), sign(c & 4))),
                radius: 0.0,
            })
            .collect();
        for axis in 0..3 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let k = parts(size[axis], spacing)?;
            for su in [-1.0, 1.0] {
                for sv in [-1.0, 1.0] {
                    for j in 1..k {
                        let mut p = Vec3::zeros();
                        p[u] = su * half[u];
                        p[v] = sv * half[v];
                        p[axis] = -half[axis] + size[axis] * j as f64 / k as f64;
                        samples.push(Sample { point_in_body: center + p, radius: 0.0 });
                    }
                }
            }
        }
        Self::finish(center, Mat3::identity(), SolidKind::Cuboid { half }, samples)
    }

    /// A cylinder of `radius` and `height` (m) about the body's z axis, centred on the origin,
    /// probing with points round its two rims `spacing` m apart (at least 16 per rim).
    pub fn cylinder(radius: f64, height: f64, spacing: f64) -> Result<Self, String> {
        let k = parts(std::f64::consts::TAU * radius, spacing)?.max(16);
        let mut samples = Vec::new();
        for zz in [-0.5 * height, 0.5 * height] {
            for j in 0..k {
                let a = std::f64::consts::TAU * j as f64 / k as f64;
                samples.push(Sample { point_in_body: Vec3::new(radius * a.cos(), radius * a.sin(), zz), radius: 0.0 });
            }
        }
        let kind = SolidKind::Cylinder { radius, half_height: 0.5 * height };
        Self::finish(Vec3::zeros(), Mat3::identity(), kind, samples)
    }

    fn finish(origin: Vec3, dcm_s_b: Mat3, kind: SolidKind, samples: Vec<Sample>) -> Result<Self, String> {
        if samples.len() > MAX_SAMPLES {
            return Err(format!(
                "its outline needs {} contact sample points, more than {MAX_SAMPLES}: give a larger contact.spacing",
                samples.len()
            ));
        }
        // Bounding box of the solid's corners (a cylinder's box) and the samples' spheres.
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        let mut grow = |p: Vec3, r: f64| {
            lo = lo.inf(&(p - Vec3::repeat(r)));
            hi = hi.sup(&(p + Vec3::repeat(r)));
        };
        let to_body = |p: Vec3| origin + dcm_s_b.transpose() * p;
        match &kind {
            SolidKind::Prism { edges, half_thickness, .. } => {
                for p in edges.iter().map(|e| e.a) {
                    for zz in [-half_thickness, *half_thickness] {
                        grow(to_body(Vec3::new(p[0], p[1], zz)), 0.0);
                    }
                }
            }
            SolidKind::Cuboid { half } => {
                for c in 0..8 {
                    let s = Vec3::new(sign(c & 1), sign(c & 2), sign(c & 4));
                    grow(to_body(half.component_mul(&s)), 0.0);
                }
            }
            SolidKind::Cylinder { radius, half_height } => {
                for c in 0..8 {
                    let s = Vec3::new(sign(c & 1), sign(c & 2), sign(c & 4));
                    grow(to_body(Vec3::new(*radius, *radius, *half_height).component_mul(&s)), 0.0);
                }
            }
        }
        for s in &samples {
            grow(s.point_in_body, s.radius);
        }
        let groups = (0..samples.len())
            .step_by(GROUP)
            .map(|start| {
                let run = start..(start + GROUP).min(samples.len());
                let centre = samples[run.clone()].iter().map(|s| s.point_in_body).sum::<Vec3>() / run.len() as f64;
                let radius = samples[run.clone()]
                    .iter()
                    .map(|s| (s.point_in_body - centre).norm() + s.radius)
                    .fold(0.0, f64::max);
                (run, centre, radius)
            })
            .collect();
        Ok(Self {
            groups,
            origin_in_body: origin,
            dcm_s_b,
            kind,
            samples,
            bound_center_in_body: (lo + hi) * 0.5,
            bound_half_in_body: (hi - lo) * 0.5,
        })
    }

    /// Signed distance of `p_in_body` (m, body frame) from the solid's surface, m (negative
    /// inside; exact inside and out), and the surface's outward unit normal nearest the
    /// point, body frame. Generic over the scalar: the exact Jacobian runs it in dual
    /// numbers (the branches are chosen on the real parts).
    pub fn signed_distance<T: Real>(&self, p_in_body: &Vector3<T>) -> (T, Vector3<T>) {
        let dcm: Matrix3<T> = lift(&self.dcm_s_b);
        let p = dcm * (p_in_body - self.origin_in_body.map(real::<T>));
        let (d, n) = match &self.kind {
            SolidKind::Prism { edges, convex, half_thickness, rim_radius } => {
                let (d2, g2) = outline_distance(edges, *convex, [p.x, p.y]);
                extrude(d2, g2, p.z, *half_thickness, *rim_radius)
            }
            SolidKind::Cylinder { radius, half_height } => {
                let r = (p.x * p.x + p.y * p.y).sqrt();
                let g2 = if re(r) > 0.0 { [p.x / r, p.y / r] } else { [real(1.0), real(0.0)] };
                extrude(r - real(*radius), g2, p.z, *half_height, 0.0)
            }
            SolidKind::Cuboid { half } => {
                let q = Vector3::from_fn(|k, _| p[k].abs() - real(half[k]));
                let s = Vector3::from_fn(|k, _| if re(p[k]) < 0.0 { real::<T>(-1.0) } else { real(1.0) });
                let out = Vector3::from_fn(|k, _| if re(q[k]) > 0.0 { q[k] } else { real(0.0) });
                let len = out.norm();
                if re(len) > 0.0 {
                    (len, (out / len).component_mul(&s))
                } else {
                    let k = (0..3).max_by(|&a, &b| re(q[a]).total_cmp(&re(q[b]))).unwrap_or(0);
                    let mut n = Vector3::zeros();
                    n[k] = s[k];
                    (q[k], n)
                }
            }
        };
        (d, dcm.transpose() * n)
    }
}

impl Solid {
    /// The signed distance of `p_in_body` (m, body frame; see [`Self::signed_distance`]) and
    /// its lateral part (m): for an extruded solid (prism, cylinder) the 2-D signed distance
    /// from its outline in its plane, whatever the height (negative inside the outline); +∞
    /// for a box (no shortcut by [`Self::face_distance`]).
    pub fn distance_and_lateral(&self, p_in_body: &Vec3) -> (f64, f64) {
        let p = self.dcm_s_b * (p_in_body - self.origin_in_body);
        match &self.kind {
            SolidKind::Prism { edges, convex, half_thickness, rim_radius } => {
                let (d2, g2) = outline_distance(edges, *convex, [p.x, p.y]);
                (extrude(d2, g2, p.z, *half_thickness, *rim_radius).0, d2)
            }
            SolidKind::Cylinder { radius, half_height } => {
                let d2 = (p.x * p.x + p.y * p.y).sqrt() - radius;
                (extrude(d2, [0.0, 0.0], p.z, *half_height, 0.0).0, d2)
            }
            SolidKind::Cuboid { .. } => (self.signed_distance(p_in_body).0, f64::INFINITY),
        }
    }

    /// [`Self::signed_distance`] of `p_in_body` (m, body frame) for a point known to be at
    /// least `-lateral_bound` m inside an extruded solid's outline (its lateral distance, see
    /// [`Self::distance_and_lateral`], at most `lateral_bound`), when that makes the nearest
    /// face its top or bottom: the distance is then `|z| − h` along ±z, without the outline's
    /// edges (the same arithmetic as the full computation, to the last bit). `None` when the
    /// bound does not settle it.
    pub fn face_distance(&self, p_in_body: &Vec3, lateral_bound: f64) -> Option<(f64, Vec3)> {
        let (h, r) = match &self.kind {
            SolidKind::Prism { half_thickness, rim_radius, .. } => (*half_thickness, *rim_radius),
            SolidKind::Cylinder { half_height, .. } => (*half_height, 0.0),
            SolidKind::Cuboid { .. } => return None,
        };
        if lateral_bound >= 0.0 {
            return None;
        }
        let p = self.dcm_s_b * (p_in_body - self.origin_in_body);
        let dz = p.z.abs() - h;
        if !on_face(lateral_bound, dz, r) {
            return None;
        }
        let sz = if p.z < 0.0 { -1.0 } else { 1.0 };
        Some((dz, self.dcm_s_b.transpose() * Vec3::new(0.0, 0.0, sz)))
    }
}

/// Whether a point whose lateral distance is at most `lateral_bound` (m) and whose height
/// over the nearer face is `dz` (m) is answered by that face in the extrusion with rim
/// radius `r` (`extrude`'s face case: not within `r` of both, and the side no nearer).
pub(super) fn on_face(lateral_bound: f64, dz: f64, r: f64) -> bool {
    (lateral_bound <= -r || dz <= -r) && lateral_bound < dz
}

/// Parts of at most `spacing` in a length, at least 1; an error past [`MAX_SAMPLES`] (before
/// anything is allocated).
fn parts(length: f64, spacing: f64) -> Result<usize, String> {
    let k = (length / spacing).ceil();
    if k.is_nan() || k > MAX_SAMPLES as f64 {
        return Err(format!(
            "a {} m edge in parts of {} m needs more than {MAX_SAMPLES} contact sample points: give a larger contact.spacing",
            crate::math::short(length),
            crate::math::short(spacing)
        ));
    }
    Ok((k as usize).max(1))
}

fn sign(bit: usize) -> f64 {
    if bit == 0 { -1.0 } else { 1.0 }
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// A 2-D signed distance `d2` (gradient `g2`) extruded ±`h` along z, the edges between the
/// faces and the side rounded with radius `r` (< `h`): the 3-D signed distance and its
/// gradient (Quílez's extrusion of the section, rounded as he rounds: the section's corner
/// between face and side a quarter circle). Within `r` of both a face and a side (`d2 > −r`,
/// `dz > −r`) the nearest surface is the rounding, whose normal turns smoothly from the
/// side's to the face's: with `r = 0` that region is outside the solid only, and inside it
/// the normal jumps where the side and the face are equally near. Exact with `r = 0`, and
/// with `r > 0` inside the solid and wherever the outline's nearest feature is an edge;
/// outside, within `r` of the rim near a vertex of the outline, it lies between the sharp
/// solid's distance and (√2 − 1) `r` more (its gradient still of unit length).
/// (`solid/tests.rs`, `signed_distance_against_surface_points`.)
fn extrude<T: Real>(d2: T, g2: [T; 2], z: T, h: f64, r: f64) -> (T, Vector3<T>) {
    let dz = z.abs() - real(h);
    let sz: T = if re(z) < 0.0 { real(-1.0) } else { real(1.0) };
    let zero = real::<T>(0.0);
    if re(d2) > -r && re(dz) > -r {
        let (a, b) = (d2 + real(r), dz + real(r));
        let len = (a * a + b * b).sqrt();
        (len - real(r), Vector3::new(g2[0] * a / len, g2[1] * a / len, sz * b / len))
    } else if re(d2) > re(dz) {
        (d2, Vector3::new(g2[0], g2[1], zero))
    } else {
        (dz, Vector3::new(zero, zero, sz))
    }
}

/// An edge of a polygon's outline from vertex `a` to vertex `b` (m, the solid's plane), with
/// the numbers [`polygon_distance`] needs of it formed once rather than at every probe (the
/// probe of a sample near an outline was a fifth of a stowed thick flasher's run, two
/// divisions per edge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// Its start and end, m (the end as given, not `a + e`: the crossing test compares
    /// the vertices' own coordinates, so that neighbouring edges agree on a vertex).
    a: [f64; 2],
    b: [f64; 2],
    /// `b − a`, m.
    e: [f64; 2],
    /// `1 / |b − a|²`, 1/m².
    inv_length2: f64,
    /// `|b − a|`, m.
    length: f64,
    /// The outward unit normal `(e_y, −e_x) / |e|` (the outline counter-clockwise).
    normal: [f64; 2],
    /// `(b_x − a_x) / (b_y − a_y)` (infinite for an edge along x, where the crossing test
    /// never asks for it).
    slope_x_per_y: f64,
}

impl Edge {
    /// The edges of `polygon` (counter-clockwise), the last closing it.
    pub fn of(polygon: &[[f64; 2]]) -> Vec<Edge> {
        let n = polygon.len();
        (0..n)
            .map(|i| {
                let (a, b) = (polygon[i], polygon[(i + 1) % n]);
                let e = [b[0] - a[0], b[1] - a[1]];
                let l = e[0].hypot(e[1]);
                Edge {
                    a,
                    b,
                    e,
                    inv_length2: 1.0 / (e[0] * e[0] + e[1] * e[1]),
                    length: l,
                    normal: [e[1] / l, -e[0] / l],
                    slope_x_per_y: e[0] / e[1],
                }
            })
            .collect()
    }

    /// The signed distance of `p` (m, the outline's plane) from the edge's line, positive
    /// outside: `n · (p − a)`.
    #[inline]
    pub fn line(&self, p: [f64; 2]) -> f64 {
        (p[0] - self.a[0]) * self.normal[0] + (p[1] - self.a[1]) * self.normal[1]
    }

    /// Where the foot of `p` (m) on the edge's line lies: 0 at its start, 1 at its end.
    pub fn along(&self, p: [f64; 2]) -> f64 {
        ((p[0] - self.a[0]) * self.e[0] + (p[1] - self.a[1]) * self.e[1]) * self.inv_length2
    }

    /// Its length, m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Its outward unit normal.
    pub fn normal(&self) -> [f64; 2] {
        self.normal
    }
}

/// Whether the counter-clockwise simple `polygon` is strictly convex: a turn to the left
/// by more than 1e-9 rad at every vertex. (Two edges in line, or all but, leave the nearest
/// of their lines to rounding, and [`outline_distance`] would take the wrong corner.)
fn is_convex(polygon: &[[f64; 2]]) -> bool {
    let n = polygon.len();
    (0..n).all(|i| {
        let (a, b, c) = (polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n]);
        let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
        u[0] * v[1] - u[1] * v[0] > 1e-9 * u[0].hypot(u[1]) * v[0].hypot(v[1])
    })
}

/// [`polygon_distance`] of `p` (m) from an outline given by its [`Edge`]s, taking the short
/// way when the outline is `convex`: the signed distance from a convex polygon is the
/// largest of the signed distances from its edges' lines, `max_i n_i · (p − a_i)`, wherever
/// the foot of `p` on that line lies on the edge itself (inside the polygon always; outside
/// when `p` is across that edge rather than past a corner), and its gradient is that edge's
/// outward normal n_i (the support-function form of the distance from a convex set, Boyd &
/// Vandenberghe, *Convex Optimization*, §8.1); past a corner, the distance from the vertex
/// at the foot's end of that edge. One product pair per edge instead of the nearest point
/// and the crossing test. The same distance and gradient as [`polygon_distance`] to
/// rounding (`tests` below).
pub fn outline_distance<T: Real>(edges: &[Edge], convex: bool, p: [T; 2]) -> (T, [T; 2]) {
    if convex && let Some(first) = edges.first() {
        let (px, py) = (re(p[0]), re(p[1]));
        // The first largest (strictly larger replaces), chosen without branches in the loop.
        let (mut s, mut i) = (first.line([px, py]), 0);
        for (j, edge) in edges.iter().enumerate().skip(1) {
            let sj = edge.line([px, py]);
            let larger = sj > s;
            s = if larger { sj } else { s };
            i = if larger { j } else { i };
        }
        let edge = &edges[i];
        let t = edge.along([px, py]);
        if s <= 0.0 || (0.0..=1.0).contains(&t) {
            let [nx, ny] = edge.normal;
            let d = (p[0] - real(edge.a[0])) * real(nx) + (p[1] - real(edge.a[1])) * real(ny);
            return (d, [real(nx), real(ny)]);
        }
        // Past a corner: the nearest point is the vertex at that end of the edge (the
        // direction from it lies in the corner's normal cone, between this edge's normal
        // and its neighbour's, which makes this edge's line or its neighbour's the farthest).
        let v = if t < 0.0 { edge.a } else { edge.b };
        let (dx, dy) = (p[0] - real(v[0]), p[1] - real(v[1]));
        let d = (dx * dx + dy * dy).sqrt();
        return (d, [dx / d, dy / d]);
    }
    polygon_distance(edges, p)
}

/// Signed distance of `p` from a simple polygon's boundary (given by its [`Edge`]s; negative
/// inside) and its outward gradient: the nearest edge point, the side from the crossing-number
/// test on the vertices as given (both chosen on the real parts).
pub fn polygon_distance<T: Real>(edges: &[Edge], p: [T; 2]) -> (T, [T; 2]) {
    let (px, py) = (re(p[0]), re(p[1]));
    // The squared distance from edge `i` (one square root at the end) and the parameter of
    // its nearest point, and whether a ray from p along +x crosses it.
    let at = |edge: &Edge| {
        let (a, b, [ex, ey]) = (edge.a, edge.b, edge.e);
        let (wx, wy) = (px - a[0], py - a[1]);
        let t = ((wx * ex + wy * ey) * edge.inv_length2).clamp(0.0, 1.0);
        let (qx, qy) = (wx - t * ex, wy - t * ey);
        // Both tests evaluated, without a branch between them (the slope of an edge along
        // x is infinite, and the second test then false or NaN, but the first is false).
        let crosses = ((a[1] > py) != (b[1] > py)) & (px < a[0] + (py - a[1]) * edge.slope_x_per_y);
        (qx * qx + qy * qy, t, crosses)
    };
    let Some(first) = edges.first() else { return (real(f64::INFINITY), [real(0.0), real(0.0)]) };
    // The first nearest edge (strictly nearer replaces), chosen without branches in the loop:
    // which edge is nearest and where a ray crosses are data the branch predictor cannot
    // learn (this function is a fifth of the thick flasher example's run).
    let (mut d, mut t, mut inside) = at(first);
    let mut i = 0;
    for (j, edge) in edges.iter().enumerate().skip(1) {
        let (dj, tj, crosses) = at(edge);
        let nearer = dj < d;
        d = if nearer { dj } else { d };
        t = if nearer { tj } else { t };
        i = if nearer { j } else { i };
        inside ^= crosses;
    }
    let d = d.sqrt();
    let Edge { a, e: [ex, ey], inv_length2, .. } = edges[i];
    let (wx, wy) = (p[0] - real(a[0]), p[1] - real(a[1]));
    // The nearest point: inside the edge it moves with p (projection), at a vertex it stays.
    let tt: T = if t > 0.0 && t < 1.0 { (wx * real(ex) + wy * real(ey)) * real(inv_length2) } else { real(t) };
    let (dx, dy) = (wx - tt * real(ex), wy - tt * real(ey));
    let (dist, g) = if d > 0.0 {
        let dd = (dx * dx + dy * dy).sqrt();
        (dd, [dx / dd, dy / dd])
    } else {
        // On the boundary: the edge's outward normal (counter-clockwise polygon).
        let l = ex.hypot(ey);
        (real(0.0), [real(ey / l), real(-ex / l)])
    };
    if inside { (-dist, [-g[0], -g[1]]) } else { (dist, g) }
}

/// The sharp tips a thin plate's rounded rim leaves out (2-D polygon counter-clockwise,
/// half-thickness `h`, spacing `t`): at a convex corner of interior angle α < 90° the rim's
/// last sphere sits h / tan(α/2) from the vertex along each edge, so the tip before it is
/// covered by points (radius 0) on both faces' edges from the vertex, `t` apart, and the
/// vertex at mid-plane; returned as `[x, y, z]` in the polygon's plane frame.
fn tip_points(polygon: &[[f64; 2]], h: f64, t: f64) -> Vec<[f64; 3]> {
    let n = polygon.len();
    let mut out = Vec::new();
    for i in 0..n {
        let (prev, v, next) = (polygon[(i + n - 1) % n], polygon[i], polygon[(i + 1) % n]);
        let (u1, u2) = ([prev[0] - v[0], prev[1] - v[1]], [next[0] - v[0], next[1] - v[1]]);
        let (l1, l2) = (u1[0].hypot(u1[1]), u2[0].hypot(u2[1]));
        // Convex (counter-clockwise: next × prev > 0) and acute.
        let cross = u2[0] * u1[1] - u2[1] * u1[0];
        let cos = (u1[0] * u2[0] + u1[1] * u2[1]) / (l1 * l2);
        if cross <= 0.0 || cos <= 0.0 {
            continue;
        }
        let half_angle = 0.5 * cos.clamp(-1.0, 1.0).acos();
        let reach = h / half_angle.tan();
        // The vertex at mid-plane and on both faces, then each edge from one spacing out.
        out.extend([0.0, -h, h].map(|z| [v[0], v[1], z]));
        for (u, l) in [(u1, l1), (u2, l2)] {
            let mut x = t;
            while x < reach.min(l) {
                out.extend([-h, h].map(|z| [v[0] + x * u[0] / l, v[1] + x * u[1] / l, z]));
                x += t;
            }
        }
    }
    out
}

/// The polygon (counter-clockwise) with every edge moved inwards by `r`: the vertex where
/// two moved edges meet. `None` if an edge would turn round (the polygon is too small).
fn inset_polygon(polygon: &[[f64; 2]], r: f64) -> Option<Vec<[f64; 2]>> {
    let n = polygon.len();
    let inward = |i: usize| {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let l = ex.hypot(ey);
        [-ey / l, ex / l]
    };
    let mut out = vec![[0.0; 2]; n];
    for (i, (p, o)) in polygon.iter().zip(&mut out).enumerate() {
        let prev = (i + n - 1) % n;
        let (n1, n2) = (inward(prev), inward(i));
        let m = [n1[0] + n2[0], n1[1] + n2[1]];
        let c = n1[0] * n2[0] + n1[1] * n2[1];
        // The bisector, scaled so that both edges move by r: r (n1 + n2) / (1 + n1·n2).
        if 1.0 + c < 1e-6 {
            return None;
        }
        let s = r / (1.0 + c);
        *o = [p[0] + s * m[0], p[1] + s * m[1]];
    }
    // Every moved edge keeps its direction.
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        let (c, d) = (out[i], out[(i + 1) % n]);
        if (b[0] - a[0]) * (d[0] - c[0]) + (b[1] - a[1]) * (d[1] - c[1]) <= 0.0 {
            return None;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests;
