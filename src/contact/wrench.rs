//! The contact forces' totals on each body, for a right-hand side: the same points as
//! [`ContactSet::evaluate_near`] finds, summed as they are found rather than listed.
//!
//! A right-hand side needs of contact only each body's force and torque and the power
//! dissipated; the points themselves (their keys, depths, energies) serve the accepted
//! steps (the contact memory, the episodes, the output) and the Jacobian, which find them
//! again through [`ContactSet::evaluate_near`]. In a stowed thick flasher nearly every point
//! is a rim sample lying on the next layer's face (the thick starshade's packed start has
//! ~50,000 points in contact over ~350 body pairs at every right-hand side), and for those
//! the distance is the face's (`Solid::face_distance`), the normal one of the face's two,
//! and the sample's velocity against the other body an affine function of its place there:
//! each such point costs its place, its penetration, the law and two sums, not a listed
//! point with its energy and its force and normal turned into the inertial frame. A sample
//! against a convex prism's side wall (the stowed wrap's inner layer on the hub) is summed
//! the same way, its distance that wall's ([`super::wall`]). Every other sample is probed as
//! for the list and added the same way.
//!
//! The totals are those of the listed points to rounding: the same samples are in contact
//! (the penetration is computed with the same operations, to the bit), and each point's
//! force acts at its centre on both bodies, equal and opposite, so the total force on the
//! structure is zero and its moment about any point too (P and H hold as they do for the
//! points; `tests/contact.rs`, `proximity_list_finds_every_contact`, compares the two at
//! every output row of the contact z-fold).
//!
//! Measured (`cargo bench --bench contact`, Intel Xeon 2-core, load 1.1–1.5, alternated
//! with the listing right-hand side, 2026-11-30): one contact right-hand side at the thick
//! flasher example's stowed state 727–738 µs listed, 351–362 µs summed; the thick
//! starshade's first 0.07 s 26.1–26.3 s of wall time, 16.9–17.5 s.

use super::proximity::{NearSample, Proximity, Visit};
use super::solid::{Solid, SolidKind};
use super::{ContactPoint, ContactSet, Frame, Workspace};
use crate::math::{Mat3, Vec3};

impl ContactSet {
    /// The contact forces at the poses `frames` added to each body's force (N, N frame) and
    /// torque about its centre of mass (N·m, N frame), through the proximity list `near`;
    /// returns the power they dissipate (W), or `None`, adding nothing, when the bodies have
    /// moved beyond the list's reach (then list the points: [`ContactSet::evaluate`]).
    pub fn wrench_near(
        &self,
        frames: &[Frame],
        near: &Proximity,
        ws: &mut Workspace,
        (force_in_n, torque_in_n): (&mut [Vec3], &mut [Vec3]),
    ) -> Option<f64> {
        let mut sums = Sums {
            set: self,
            frames,
            force_in_n,
            torque_in_n,
            dissipation: 0.0,
            side: None,
            points: std::mem::take(&mut ws.probed),
            faced: std::mem::take(&mut ws.faced),
        };
        let scanned = near.scan(frames, &mut ws.motion, &mut sums);
        ws.faced = sums.faced;
        ws.probed = sums.points;
        scanned.then_some(sums.dissipation)
    }
}

/// Adds the force of `p` on its two bodies (at its centre, equal and opposite) to their
/// force and torque (N, N·m, N frame), as a right-hand side does with listed points.
pub fn add_point(p: &ContactPoint, frames: &[Frame], force_in_n: &mut [Vec3], torque_in_n: &mut [Vec3]) {
    let (a, b) = (p.key.body as usize, p.key.other as usize);
    force_in_n[a] += p.force_in_n;
    torque_in_n[a] += (p.point_in_n - frames[a].position_in_n).cross(&p.force_in_n);
    force_in_n[b] -= p.force_in_n;
    torque_in_n[b] -= (p.point_in_n - frames[b].position_in_n).cross(&p.force_in_n);
}

/// The sums of a scan ([`ContactSet::wrench_near`]).
struct Sums<'a> {
    set: &'a ContactSet,
    frames: &'a [Frame],
    force_in_n: &'a mut [Vec3],
    torque_in_n: &'a mut [Vec3],
    dissipation: f64,
    side: Option<Side<'a>>,
    /// Scratch for a sample probed as a listed point.
    points: Vec<ContactPoint>,
    /// The side's samples in contact with a face or a wall, for [`Sums::end`].
    faced: Vec<Faced>,
}

/// A sample in contact with a face or a side wall of the other body's solid: its centre
/// (m), the face's or wall's outward normal (B frame), its penetration (m) and its impact
/// speed (m/s, NaN for none).
#[derive(Clone, Copy, Debug)]
pub(super) struct Faced {
    p: Vec3,
    normal: Vec3,
    depth: f64,
    impact: f64,
}

/// A side being summed: the samples of body A in the solid of body B.
struct Side<'a> {
    /// (A, B).
    bodies: (usize, usize),
    /// A's attitude in B's frame and its origin there, m.
    dcm_b_a: Mat3,
    r_ab: Vec3,
    /// A's samples.
    samples: &'a [super::solid::Sample],
    /// B's solid.
    solid: &'a Solid,
    /// B's solid, when it has faces (a prism or a cylinder): its solid frame's origin in B
    /// (m), the third row of `dcm_s_b` (B's face normal), its half thickness (m) and its
    /// rim's radius (m).
    face: Option<(Vec3, Vec3, f64, f64)>,
    /// A sample's velocity against B at its place `p` in B's frame is `v0 + omega × p`
    /// (m/s, B frame; see [`Side::new`]).
    v0: Vec3,
    omega: Vec3,
    /// The force on A (N) and its moment about B's centre of mass (N·m), B frame.
    force: Vec3,
    moment: Vec3,
}

impl<'a> Side<'a> {
    /// The velocity of A's material point at `x` against B's, in B, is
    /// `[B N](v_A + ω_A × (x − r_A) − v_B − ω_B × (x − r_B))`; with `x − r_A = (x − r_B) +
    /// (r_B − r_A)` and `p = [B N](x − r_B)` it is `v0 + Ω × p`, `v0 = [B N](v_A − v_B + ω_A ×
    /// (r_B − r_A))`, `Ω = [B N](ω_A − ω_B)` (a rotation carries a cross product).
    fn new(
        set: &'a ContactSet,
        bodies: (usize, usize),
        (fa, fb): (&Frame, &Frame),
        pose: (Mat3, Vec3),
    ) -> Option<Self> {
        let (sa, sb) = (set.solids[bodies.0].as_ref()?, set.solids[bodies.1].as_ref()?);
        let dcm_b_n = fb.dcm_n_b.transpose();
        let rel = fb.position_in_n - fa.position_in_n;
        Some(Self {
            bodies,
            dcm_b_a: pose.0,
            r_ab: pose.1,
            samples: &sa.samples,
            solid: sb,
            face: faces(sb),
            v0: dcm_b_n * (fa.velocity_in_n - fb.velocity_in_n + fa.omega_in_n.cross(&rel)),
            omega: dcm_b_n * (fa.omega_in_n - fb.omega_in_n),
            force: Vec3::zeros(),
            moment: Vec3::zeros(),
        })
    }
}

/// A solid's face data for [`Side::face`].
fn faces(solid: &Solid) -> Option<(Vec3, Vec3, f64, f64)> {
    let (h, r) = match &solid.kind {
        SolidKind::Prism { half_thickness, rim_radius, .. } => (*half_thickness, *rim_radius),
        SolidKind::Cylinder { half_height, .. } => (*half_height, 0.0),
        SolidKind::Cuboid { .. } => return None,
    };
    Some((solid.origin_in_body, solid.dcm_s_b.row(2).transpose(), h, r))
}

impl<'a> Visit for Sums<'a> {
    fn begin(&mut self, bodies: (usize, usize), frames: (&Frame, &Frame), pose: (Mat3, Vec3)) {
        self.side = Side::new(self.set, bodies, frames, pose);
    }

    fn sample(&mut self, s: &NearSample, moved: f64) {
        let Some(side) = self.side.as_mut() else { return };
        let sample = &side.samples[s.index as usize];
        let lateral_bound = s.lateral + moved;
        if let Some((origin, normal, h, r)) = side.face
            && lateral_bound < 0.0
        {
            // `Solid::face_distance` with the same operations: the sample's centre in B, its
            // height over B's mid-plane and the face's distance.
            let p = side.dcm_b_a * sample.point_in_body + side.r_ab;
            let q = p - origin;
            let z = normal.x * q.x + normal.y * q.y + normal.z * q.z;
            let dz = z.abs() - h;
            if super::solid::on_face(lateral_bound, dz, r) {
                let depth = sample.radius - dz;
                if depth > 0.0 {
                    let normal = if z < 0.0 { -normal } else { normal };
                    self.faced.push(Faced { p, normal, depth, impact: s.impact });
                }
                return;
            }
        }
        // A sample whose wall still answers it: that wall's distance, or the face's.
        if moved < s.wall_margin {
            let p = side.dcm_b_a * sample.point_in_body + side.r_ab;
            if let Some((d, normal)) = side.solid.wall_distance(&p, s.wall) {
                let depth = sample.radius - d;
                if depth > 0.0 {
                    self.faced.push(Faced { p, normal, depth, impact: s.impact });
                }
                return;
            }
        }
        // Any other sample: probed and added as a listed point.
        self.points.clear();
        self.set.probe_near(s, side.bodies, self.frames, (&side.dcm_b_a, &side.r_ab), moved, &mut self.points);
        for p in &self.points {
            add_point(p, self.frames, self.force_in_n, self.torque_in_n);
            self.dissipation += p.dissipation;
        }
    }

    fn end(&mut self) {
        let Some(mut side) = self.side.take() else { return };
        // The law at the face and wall points, in one tight loop (the square roots and divisions of
        // one point overlap the next's).
        for f in self.faced.drain(..) {
            let v = side.v0 + side.omega.cross(&f.p);
            let impact = (!f.impact.is_nan()).then_some(f.impact);
            let law = self.set.law_at(f.depth, f.normal, &v, impact);
            side.force += law.force_in_b;
            side.moment += f.p.cross(&law.force_in_b);
            self.dissipation += law.dissipation;
        }
        let (a, b) = side.bodies;
        let fb = &self.frames[b];
        let force = fb.dcm_n_b * side.force;
        let moment_about_b = fb.dcm_n_b * side.moment;
        self.force_in_n[a] += force;
        self.torque_in_n[a] += moment_about_b + (fb.position_in_n - self.frames[a].position_in_n).cross(&force);
        self.force_in_n[b] -= force;
        self.torque_in_n[b] -= moment_about_b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The face's distance as the sums form it is `Solid::face_distance`'s to the bit (so
    /// the sums and the list find the same samples in contact, even at a gap of zero): a
    /// tilted plate (its solid frame turned against its body frame), points about its faces
    /// in every direction, each compared wherever the face settles it.
    #[test]
    fn the_face_distance_is_the_solids_to_the_bit() {
        let q = nalgebra::Vector4::new(0.9, 0.3, -0.2, 0.1).normalize();
        let turn = crate::math::dcm_from_quat(q.as_slice());
        let vertices = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.3, 0.1, 0.0), Vec3::new(0.4, 0.9, 0.0)]
            .map(|v| turn * v + Vec3::new(0.2, -0.1, 0.05));
        let solid = Solid::plate(&vertices, 0.01, 0.01).unwrap();
        let (origin, normal, h, _) = faces(&solid).unwrap();
        let mut compared = 0;
        for i in 0..2000 {
            let u = |k: usize| ((i * 7919 + k * 104_729) % 1000) as f64 / 1000.0;
            // Within the outline's box, heights across both faces.
            let p = turn * Vec3::new(1.3 * u(1), 0.9 * u(2), 0.012 * (2.0 * u(3) - 1.0)) + Vec3::new(0.2, -0.1, 0.05);
            let (_, lateral) = solid.distance_and_lateral(&p);
            let Some((d, n)) = solid.face_distance(&p, lateral) else { continue };
            let q = p - origin;
            let z = normal.x * q.x + normal.y * q.y + normal.z * q.z;
            assert_eq!(z.abs() - h, d, "point {p:?}");
            assert_eq!(if z < 0.0 { -normal } else { normal }, n, "point {p:?}");
            compared += 1;
        }
        assert!(compared > 500, "only {compared} points settled by a face");
    }
}
