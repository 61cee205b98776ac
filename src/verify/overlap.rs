//! How deep any two bodies overlap over a run, measured from its output poses alone, apart
//! from the contact code (its solids, samples and distances are not used): each body's shape
//! as a convex solid for parry3d, the pairs whose bounding boxes meet at a row measured by
//! parry's GJK/EPA (`parry3d_f64::query::contact`), the deepest of each pair over the rows
//! kept.
//!
//! Thin plates are measured two ways ([`Solids`]): as the contact code's samples describe
//! them (docs/contact.md §1: the outline moved in by t/2 and swept by a ball of radius t/2,
//! flat faces and a rounded rim) and as sharp prisms, whose edges reach up to 0.41 t/2 past
//! the rounded rim. Two hinged plates meet along their crease by construction: for such a
//! pair each plate is taken without the strip of one thickness along the edge they share (in
//! the hinge's undeformed state), so that what remains overlaps only if one panel passes into
//! the other (the crease's own edges never push, docs/contact.md §1). Pairs the scenario's
//! `contact.exclude` names are left out.

use crate::math::Vec3;
use crate::model::Model;
use crate::model::shape::Shape;
use crate::output::table::Poses;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, Cylinder, SharedShape};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// How thin plates are taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solids {
    /// As the contact code's samples describe them: flat faces, the rim rounded with half the
    /// thickness (a plate thicker than half its longest edge, a hub prism, stays sharp).
    Sampled,
    /// As sharp prisms (the polygon extruded by its thickness).
    Sharp,
}

/// One pair's deepest overlap over the rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overlap {
    /// Penetration depth, m (parry's: the smallest translation that separates the two).
    pub depth: f64,
    /// The row's time, s.
    pub t: f64,
    /// The two bodies (model indices, the first the smaller).
    pub bodies: (usize, usize),
    /// `depth` over the thinner body's thickness (a plate's, a box's shortest edge, a
    /// cylinder's height).
    pub of_thickness: f64,
}

/// A body's solid for parry, its pose in the body frame, and its thickness (m).
pub type Solid = (SharedShape, Pose, f64);

/// The convex hull of `points`, or why not (a degenerate outline).
fn hull(points: &[Vector], what: &str) -> Result<ConvexPolyhedron, String> {
    ConvexPolyhedron::from_convex_hull(points).ok_or_else(|| format!("{what}: its outline has no convex hull"))
}

/// A plate's unit normal (its polygon's, by Newell's sum, `model::shape::newell`).
fn plate_normal(vertices: &[Vec3]) -> Vec3 {
    crate::model::shape::newell(vertices).normalize()
}

fn vector(p: &Vec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// `shape` as a solid of the kind asked for (a plate as the convex hull of its outline), or
/// why not, naming it `what`.
pub fn solid(shape: &Shape, kind: Solids, what: &str) -> Result<Solid, String> {
    match shape {
        Shape::Plate { vertices, thickness } => {
            let n = vertices.len();
            let normal = plate_normal(vertices);
            let longest = (0..n).map(|i| (vertices[(i + 1) % n] - vertices[i]).norm()).fold(0.0, f64::max);
            if kind == Solids::Sampled && *thickness <= 0.5 * longest {
                // The outline moved in by t/2 at each vertex (along the bisector), swept by a
                // ball of t/2: a sliver 2e-9 m thick (so that the hull is a solid) swept by
                // t/2 less 1e-9 m, so that the faces are where the plate's are.
                let h = 0.5 * thickness;
                let inward = |i: usize| normal.cross(&(vertices[(i + 1) % n] - vertices[i]).normalize());
                let pts: Vec<Vector> = (0..n)
                    .flat_map(|i| {
                        let (n1, n2) = (inward((i + n - 1) % n), inward(i));
                        let p = vertices[i] + (n1 + n2) * (h / (1.0 + n1.dot(&n2)));
                        [-1e-9, 1e-9].map(|f| vector(&(p + normal * f)))
                    })
                    .collect();
                let shape = SharedShape::round_convex_hull(&pts, h - 1e-9)
                    .ok_or_else(|| format!("{what}: its outline has no convex hull"))?;
                return Ok((shape, Pose::IDENTITY, *thickness));
            }
            let pts: Vec<Vector> =
                vertices.iter().flat_map(|v| [-0.5, 0.5].map(|s| vector(&(v + normal * (s * thickness))))).collect();
            Ok((SharedShape::new(hull(&pts, what)?), Pose::IDENTITY, *thickness))
        }
        Shape::Cuboid { size, center } => Ok((
            SharedShape::new(Cuboid::new(Vector::new(size.x / 2.0, size.y / 2.0, size.z / 2.0))),
            Pose::from_translation(vector(center)),
            size.min(),
        )),
        // parry's cylinder is about its y axis; ours about z.
        Shape::Cylinder { radius, height } => Ok((
            SharedShape::new(Cylinder::new(height / 2.0, *radius)),
            Pose::from_parts(Vector::ZERO, Rotation::from_rotation_x(std::f64::consts::FRAC_PI_2)),
            *height,
        )),
    }
}

/// For two plates joined by hinge `k`: each without the strip of one thickness along the
/// edge they share with the hinge undeformed (the longest overlap of an edge of one outline,
/// or of its faces' outlines, with one on the same line of the other's). `None` if they share
/// no edge. Returned in the order (parent, child).
fn crease_clipped(model: &Model, k: usize, kind: Solids) -> Result<Option<[Solid; 2]>, String> {
    let h = &model.hinges[k];
    let (Some(Shape::Plate { vertices: vp, thickness: tp }), Some(Shape::Plate { vertices: vc, thickness: tc })) =
        (&model.bodies[h.parent].shape, &model.bodies[h.child].shape)
    else {
        return Ok(None);
    };
    // The child's polygon in the parent's frame with the hinge undeformed (A = A0).
    let dcm_p_a0 = h.dcm_a0_parent.transpose();
    let child_in_p: Vec<Vec3> =
        vc.iter().map(|v| h.r_a0_in_parent + dcm_p_a0 * (h.r_child_in_a + h.dcm_child_a.transpose() * v)).collect();
    let on_line = |p: &Vec3, a: &Vec3, b: &Vec3| {
        let u = (b - a).normalize();
        let w = p - a;
        (w - u * w.dot(&u)).norm() < 1e-6
    };
    // Edges of a plate's mid-plane and of its two faces (a hub prism's panels hinge on a
    // face's outline), by the outline edge they belong to.
    let edges = |poly: &[Vec3], t: f64| -> Vec<(usize, Vec3, Vec3)> {
        let m = poly.len();
        let normal = plate_normal(poly);
        [0.0, 0.5, -0.5]
            .iter()
            .flat_map(|f| (0..m).map(move |k| (k, poly[k] + normal * (f * t), poly[(k + 1) % m] + normal * (f * t))))
            .collect()
    };
    let child_edges = edges(&child_in_p, *tc);
    let overlap = |a: &Vec3, b: &Vec3, c: &Vec3, d: &Vec3| {
        let u = (b - a).normalize();
        let (lo, hi) = ((c - a).dot(&u).min((d - a).dot(&u)), (c - a).dot(&u).max((d - a).dot(&u)));
        hi.min((b - a).norm()) - lo.max(0.0)
    };
    let Some((pk, ck, _)) = edges(vp, *tp)
        .into_iter()
        .flat_map(|(k, a, b)| {
            child_edges
                .iter()
                .filter(move |(_, c, d)| on_line(c, &a, &b) && on_line(d, &a, &b))
                .map(move |(m, c, d)| (k, *m, overlap(&a, &b, c, d)))
        })
        .filter(|e| e.2 > 0.0)
        .max_by(|x, y| x.2.total_cmp(&y.2))
    else {
        return Ok(None);
    };
    let w = tp.min(*tc);
    // The polygon on the inner side of the line p0–p1 moved in by w (Sutherland–Hodgman).
    let clip = |poly: &[Vec3], p0: Vec3, p1: Vec3| -> Vec<Vec3> {
        let centroid = poly.iter().sum::<Vec3>() / poly.len() as f64;
        let along = (p1 - p0).normalize();
        let inward = {
            let c = centroid - p0;
            (c - along * c.dot(&along)).normalize()
        };
        let f = |p: &Vec3| (p - p0).dot(&inward) - w;
        let mut out = Vec::new();
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            if f(&p) >= 0.0 {
                out.push(p);
            }
            if (f(&p) >= 0.0) != (f(&q) >= 0.0) {
                out.push(p + (q - p) * (f(&p) / (f(&p) - f(&q))));
            }
        }
        out
    };
    let parent = clip(vp, vp[pk], vp[(pk + 1) % vp.len()]);
    let child = clip(vc, vc[ck], vc[(ck + 1) % vc.len()]);
    let name = |i: usize| model.bodies[i].name.as_str();
    if parent.len() < 3 || child.len() < 3 {
        return Err(format!(
            "{} and {}: a plate lies within one thickness ({w} m) of the crease they share, so an overlap cannot be told from the crease (the check leaves that strip out)",
            name(h.parent),
            name(h.child)
        ));
    }
    let plate = |vertices: Vec<Vec3>, thickness: f64, what: &str| {
        solid(&Shape::Plate { vertices, thickness }, kind, &format!("{what} without its crease with the other"))
    };
    Ok(Some([plate(parent, *tp, name(h.parent))?, plate(child, *tc, name(h.child))?]))
}

/// A body's pose in N for parry from its centre of mass `r` (m, N components) and quaternion
/// `q` (w, x, y, z) of `[N i]`.
pub fn pose(r: &Vec3, q: &[f64; 4]) -> Pose {
    Pose::from_parts(vector(r), Rotation::from_xyzw(q[1], q[2], q[3], q[0]).normalize())
}

/// Each pair's deepest overlap over the rows of `poses` (those that overlap at some row),
/// deepest first; `progress` is told the rows done after each (from any thread). The rows
/// are measured on every core (rayon).
pub fn deepest_overlaps(
    model: &Model,
    poses: &Poses,
    kind: Solids,
    progress: Option<&(dyn Fn(usize) + Sync)>,
) -> Result<Vec<Overlap>, String> {
    let n = model.bodies.len();
    let solids: Vec<Option<Solid>> = model
        .bodies
        .iter()
        .map(|b| b.shape.as_ref().map(|s| solid(s, kind, &b.name)).transpose())
        .collect::<Result<_, _>>()?;
    let mut clipped = std::collections::HashMap::new();
    for (k, h) in model.hinges.iter().enumerate() {
        if let Some([p, c]) = crease_clipped(model, k, kind)? {
            let (a, b) = h.bodies_sorted();
            clipped.insert((a, b), if h.parent == a { [p, c] } else { [c, p] });
        }
    }
    let excluded = |a: usize, b: usize| model.contact.as_ref().is_some_and(|c| c.is_excluded(a, b));
    let done = AtomicUsize::new(0);
    // Per row: each overlapping pair's depth.
    let per_row = |row: usize| -> Result<Vec<Overlap>, String> {
        let (r, q) = (&poses.r_in_n[row], &poses.quat[row]);
        let mut found = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let (Some(si), Some(sj)) = (&solids[i], &solids[j]) else { continue };
                if excluded(i, j) {
                    continue;
                }
                let [(gi, li, ti), (gj, lj, tj)] = match clipped.get(&(i, j)) {
                    Some([a, b]) => [a, b],
                    None => [si, sj],
                };
                let (pi, pj) = (pose(&r[i], &q[i]) * *li, pose(&r[j], &q[j]) * *lj);
                // Bounding boxes apart: no overlap (exact).
                if !gi.compute_aabb(&pi).intersects(&gj.compute_aabb(&pj)) {
                    continue;
                }
                let c = parry3d_f64::query::contact(&pi, gi.as_ref(), &pj, gj.as_ref(), 0.0).map_err(|_| {
                    format!("parry cannot measure {} against {}", model.bodies[i].name, model.bodies[j].name)
                })?;
                if let Some(c) = c
                    && c.dist < 0.0
                {
                    let depth = -c.dist;
                    found.push(Overlap {
                        depth,
                        t: poses.times[row],
                        bodies: (i, j),
                        of_thickness: depth / ti.min(*tj),
                    });
                }
            }
        }
        if let Some(p) = progress {
            p(done.fetch_add(1, Ordering::Relaxed) + 1);
        }
        Ok(found)
    };
    let rows: Vec<Vec<Overlap>> = (0..poses.times.len()).into_par_iter().map(per_row).collect::<Result<_, _>>()?;
    let mut deepest: std::collections::BTreeMap<(usize, usize), Overlap> = std::collections::BTreeMap::new();
    for o in rows.into_iter().flatten() {
        let e = deepest.entry(o.bodies).or_insert(o);
        if o.depth > e.depth {
            *e = o;
        }
    }
    let mut out: Vec<Overlap> = deepest.into_values().collect();
    out.sort_by(|a, b| b.depth.total_cmp(&a.depth));
    Ok(out)
}
