//! A sample near a side wall of a convex prism (an edge of its outline, extruded) probed
//! against that wall alone, as a sample well inside a face's outline is probed against the
//! face alone ([`Solid::face_distance`]).
//!
//! The stowed wrap's innermost layer lies on the hub prism's side walls: in the thick
//! flasher example, two thirds of the samples a summing right-hand side probed in full (the
//! outline's every edge, the extrusion, then the law through the listed point's path) were
//! samples against the hub (counted, 2026-11-30: 4.2 million of 6.4 million).
//! A convex outline's signed distance is the largest of its edges' line distances where the
//! foot on that edge's line lies on the edge or the point is inside ([`super::solid::
//! outline_distance`]); the list ([`super::proximity`]) notes at each reference which edge
//! that is ([`Wall::of`]) and how far the sample may move with it still the answer (each
//! line distance, and the foot's place along the edge, move by at most the motion: the lines'
//! normals are unit vectors). Within that motion the distance is that edge line's, extruded,
//! formed with the full computation's operations ([`Solid::wall_distance`]): the same numbers
//! to the last bit (`tests` below).

use super::solid::{Edge, Solid, SolidKind};
use crate::math::Vec3;

/// No wall noted (the other solid not a convex prism): [`Wall::index`].
pub const NO_WALL: u32 = u32::MAX;

/// The edge of a convex outline whose line answers a point's lateral distance, and how far
/// the point may move and still be answered by it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// The edge's place in the outline ([`NO_WALL`] for none).
    pub index: u32,
    /// How far (m, in any direction) the point may move with that edge's line still the
    /// outline's distance: half its lead over the next farthest line, and the larger of its
    /// foot's distance from the edge's ends and its depth inside the outline (negative or
    /// −∞ for no such motion).
    pub margin: f64,
}

impl Wall {
    /// None noted.
    pub const NONE: Self = Self { index: NO_WALL, margin: f64::NEG_INFINITY };

    /// The wall of the convex outline `edges` (counter-clockwise, the solid's plane) that
    /// answers the point `p` (m, the solid's plane), as [`super::solid::outline_distance`]
    /// chooses it, and its margin.
    pub fn of(edges: &[Edge], p: [f64; 2]) -> Self {
        let (mut first, mut second, mut index) = (f64::NEG_INFINITY, f64::NEG_INFINITY, 0);
        for (j, edge) in edges.iter().enumerate() {
            let l = edge.line(p);
            if l > first {
                (second, first, index) = (first, l, j);
            } else if l > second {
                second = l;
            }
        }
        let Some(edge) = edges.get(index) else { return Self::NONE };
        let along = edge.along(p);
        let foot = along.min(1.0 - along) * edge.length();
        let margin = (0.5 * (first - second)).min(foot.max(-first));
        if margin.is_nan() { Self::NONE } else { Self { index: index as u32, margin } }
    }
}

impl Solid {
    /// The [`Wall`] that answers a sample's centre `p_in_body` (m, body frame), at signed
    /// distance `distance` (m) and lateral distance `lateral` (m) from the solid (as
    /// [`Solid::distance_and_lateral`] gives them) with radius `radius` (m), for the list
    /// ([`super::proximity`]) to note: only where the wall can serve (a convex prism, the
    /// sample within its radius of contact, and the distance a wall's, where the face's own
    /// shortcut does not serve); else [`Wall::NONE`]. (Noted for every listed sample, it cost
    /// more at the list's upkeep than it saved at the right-hand sides: callgrind on the
    /// thick flasher example.)
    pub fn wall_near(&self, p_in_body: &Vec3, (distance, lateral): (f64, f64), radius: f64) -> Wall {
        let SolidKind::Prism { edges, convex: true, .. } = &self.kind else { return Wall::NONE };
        // `extrude` returns the lateral distance itself where a wall is nearest.
        if distance - radius >= radius || distance != lateral {
            return Wall::NONE;
        }
        let p = self.dcm_s_b * (p_in_body - self.origin_in_body);
        Wall::of(edges, [p.x, p.y])
    }

    /// [`Solid::signed_distance`] of `p_in_body` (m, body frame) by what a listed sample
    /// knows of it: the face's alone where `lateral_bound` (m, a bound on its lateral
    /// distance) settles it on a face ([`Solid::face_distance`]), else the wall `wall`'s
    /// where one is noted and still answers ([`Solid::wall_distance`]; [`NO_WALL`] for none).
    /// `None` where neither serves: the full computation then. The same numbers to the bit.
    pub fn known_distance(&self, p_in_body: &Vec3, lateral_bound: f64, wall: u32) -> Option<(f64, Vec3)> {
        self.face_distance(p_in_body, lateral_bound).or_else(|| self.wall_distance(p_in_body, wall))
    }

    /// [`Solid::signed_distance`] of `p_in_body` (m, body frame) when the outline's edge
    /// `wall` (of a convex prism) answers the point's lateral distance (the caller knows it
    /// from a [`Wall`] and the point's motion since, within its margin): the wall's line
    /// distance or the face's, extruded, with the full computation's operations; `None`
    /// where the point is past both (the rounded edge between them: the full computation
    /// then).
    pub fn wall_distance(&self, p_in_body: &Vec3, wall: u32) -> Option<(f64, Vec3)> {
        let SolidKind::Prism { edges, half_thickness, rim_radius, .. } = &self.kind else { return None };
        let edge = edges.get(wall as usize)?;
        let p = self.dcm_s_b * (p_in_body - self.origin_in_body);
        let d2 = edge.line([p.x, p.y]);
        let dz = p.z.abs() - half_thickness;
        // `extrude`'s three cases: the rim (within its radius of both; not here), the wall,
        // the face.
        if d2 > -rim_radius && dz > -rim_radius {
            return None;
        }
        let n = if d2 > dz {
            let [nx, ny] = edge.normal();
            (d2, Vec3::new(nx, ny, 0.0))
        } else {
            (dz, Vec3::new(0.0, 0.0, if p.z < 0.0 { -1.0 } else { 1.0 }))
        };
        Some((n.0, self.dcm_s_b.transpose() * n.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;

    /// About a tilted convex prism (a pentagon 1.7 m thick, as the example's hub), points
    /// anywhere near its walls and faces, each moved at random within its wall's margin: the
    /// wall's distance is the full computation's to the last bit, wherever it answers, and
    /// it answers most of them. A margin twice as wide lets a moved point take another wall
    /// (checked: the test fails with it).
    #[test]
    fn the_walls_distance_is_the_solids_to_the_bit() {
        let turn = Mat3::new(0.6, -0.8, 0.0, 0.8, 0.6, 0.0, 0.0, 0.0, 1.0)
            * Mat3::new(1.0, 0.0, 0.0, 0.0, 0.8, -0.6, 0.0, 0.6, 0.8);
        let pentagon: Vec<Vec3> = (0..5)
            .map(|k| {
                let a = 2.0 * std::f64::consts::PI * k as f64 / 5.0;
                turn * Vec3::new(a.cos(), a.sin(), 0.0) + Vec3::new(0.3, -0.2, 0.1)
            })
            .collect();
        let hub = Solid::plate(&pentagon, 1.7, 0.05).unwrap();
        let SolidKind::Prism { edges, convex: true, .. } = &hub.kind else { panic!("a convex prism") };
        let mut seed = 4242_u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut answered, mut walls, mut tried) = (0, 0, 0);
        for _ in 0..20_000 {
            // A point within 0.2 m of the outline, at any height across the faces.
            let (a, r, z) = (2.0 * std::f64::consts::PI * rnd(), 0.6 + 0.6 * rnd(), 2.0 * rnd() - 1.0);
            let at = |p: Vec3| hub.dcm_s_b * (p - hub.origin_in_body);
            let p = hub.origin_in_body + hub.dcm_s_b.transpose() * Vec3::new(r * a.cos(), r * a.sin(), z);
            let q = at(p);
            let wall = Wall::of(edges, [q.x, q.y]);
            if wall.margin <= 0.0 {
                continue;
            }
            tried += 1;
            // Moved by less than the margin.
            let dir = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let moved = p + dir * (0.999 * wall.margin * rnd());
            if let Some(found) = hub.wall_distance(&moved, wall.index) {
                assert_eq!(found, hub.signed_distance(&moved), "at {moved:?}, wall {wall:?}");
                answered += 1;
                walls += usize::from(found.1.dot(&(hub.dcm_s_b.transpose() * Vec3::z())).abs() < 0.5);
            }
        }
        assert!(tried > 10_000 && answered > tried * 9 / 10 && walls > tried / 2, "{answered}, {walls} of {tried}");
    }
}
