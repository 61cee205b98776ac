//! Contact between bodies (docs/contact.md): geometry ([`solid`]: each body's solid and its
//! sample points; the pair search in [`ContactSet::evaluate`], parry's bounding-volume
//! hierarchy as the broad phase) and the compliant law ([`law`]). The dynamics calls
//! [`ContactSet::evaluate`] with the bodies' poses and applies the forces; nothing here knows
//! of hinges or of the state vector.

pub mod episodes;
pub mod law;
pub mod proximity;
pub mod solid;
pub mod wall;
pub mod wrench;

use crate::math::{Mat3, Real, Vec3, re, real};
use law::ContactLaw;
use nalgebra::{Matrix3, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as PVec;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use proximity::NearSample;
use solid::{Sample, Solid};
use std::collections::{HashMap, HashSet};

/// A body's pose and velocity as contact needs them (generic over the scalar for the exact
/// Jacobian; f64 otherwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame<T: nalgebra::Scalar = f64> {
    /// Centre of mass, m, N frame.
    pub position_in_n: Vector3<T>,
    /// Attitude: body → N.
    pub dcm_n_b: Matrix3<T>,
    /// Velocity of the centre of mass, m/s, N frame.
    pub velocity_in_n: Vector3<T>,
    /// Angular velocity, rad/s, N frame.
    pub omega_in_n: Vector3<T>,
}

impl Default for Frame {
    fn default() -> Self {
        Self {
            position_in_n: Vec3::zeros(),
            dcm_n_b: Mat3::identity(),
            velocity_in_n: Vec3::zeros(),
            omega_in_n: Vec3::zeros(),
        }
    }
}

impl Frame {
    /// Body A's (this frame's) attitude in body B's frame (`fb`; A → B) and A's origin there
    /// (m): a point `p` of A is at `dcm_b_a p + r_ab` in B.
    pub fn in_frame_of(&self, fb: &Frame) -> (Mat3, Vec3) {
        (fb.dcm_n_b.transpose() * self.dcm_n_b, fb.dcm_n_b.transpose() * (self.position_in_n - fb.position_in_n))
    }

    /// The point fixed in this body at `p_in_body` (m, body frame), in body B's frame (`fb`),
    /// m.
    fn point_in_frame_of(&self, p_in_body: &Vec3, fb: &Frame) -> Vec3 {
        fb.dcm_n_b.transpose() * (self.position_in_n + self.dcm_n_b * p_in_body - fb.position_in_n)
    }

    /// The velocity of this body's material point at `point_in_n` (m, N frame) against body
    /// B's (`fb`) material point there, m/s, B frame.
    fn velocity_against(&self, fb: &Frame, point_in_n: &Vec3) -> Vec3 {
        fb.dcm_n_b.transpose() * (self.velocity_at(point_in_n) - fb.velocity_at(point_in_n))
    }
}

impl<T: Real> Frame<T> {
    /// Velocity of the body's material point at `p_in_n` (m, N), m/s, N frame.
    fn velocity_at(&self, p_in_n: &Vector3<T>) -> Vector3<T> {
        self.velocity_in_n + self.omega_in_n.cross(&(p_in_n - self.position_in_n))
    }
}

/// One sample's contact, in any scalar: where the forces act and what they are.
#[derive(Clone, Copy, Debug)]
pub struct PointForce<T: nalgebra::Scalar> {
    /// The sample's centre, m, N frame.
    pub point_in_n: Vector3<T>,
    /// The other body's outward normal there, N frame.
    pub normal_in_n: Vector3<T>,
    /// Penetration, m.
    pub depth: T,
    /// Its rate, m/s (> 0 approaching).
    pub rate: T,
    /// Force on the sample's body, N, N frame.
    pub force_in_n: Vector3<T>,
    /// Power dissipated by damping and friction, W.
    pub dissipation: T,
}

/// One sample's contact in the frame of the body it penetrates (B), in any scalar.
#[derive(Clone, Copy, Debug)]
pub struct LocalForce<T: nalgebra::Scalar> {
    /// B's outward normal at the sample, B frame.
    pub normal_in_b: Vector3<T>,
    /// Penetration, m.
    pub depth: T,
    /// Its rate, m/s (> 0 approaching).
    pub rate: T,
    /// Force on the sample's body, N, B frame.
    pub force_in_b: Vector3<T>,
    /// Power dissipated by damping and friction, W.
    pub dissipation: T,
}

/// Which sample of which body is inside which other body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PointKey {
    /// The body whose sample it is.
    pub body: u32,
    /// The body whose solid it is in.
    pub other: u32,
    /// The sample's index in `body`'s solid.
    pub sample: u32,
}

/// One contact point and what the law makes of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Which sample in which body.
    pub key: PointKey,
    /// The sample's centre, where both forces act, m, N frame.
    pub point_in_n: Vec3,
    /// The other body's outward surface normal there (pushes `key.body` out), N frame.
    pub normal_in_n: Vec3,
    /// Penetration δ, m (> 0).
    pub depth: f64,
    /// Its rate δ̇, m/s (> 0 approaching).
    pub rate: f64,
    /// Force on `key.body` (the other body gets its opposite at the same point), N, N frame.
    pub force_in_n: Vec3,
    /// Elastic energy stored, J.
    pub energy: f64,
    /// Power dissipated by damping and friction, W (≥ 0).
    pub dissipation: f64,
}

/// Per contact point in contact at the last accepted state: its approach speed when it came
/// into contact, m/s (the law's v₀).
pub type ContactMemory = HashMap<PointKey, f64, std::hash::BuildHasherDefault<KeyHasher>>;

/// A hasher for [`PointKey`]s: the keys are small integers that need no protection from
/// chosen collisions, and the default SipHash took 5 % of a contact-heavy run. A
/// multiply-rotate mix of the three numbers (as rustc's FxHash does).
#[derive(Default)]
pub struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_u32(&mut self, n: u32) {
        self.write_u64(u64::from(n));
    }
    fn write_u64(&mut self, n: u64) {
        self.0 = (self.0.rotate_left(5) ^ n).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

/// Every contact body's geometry, the pairs that may touch, and the law.
#[derive(Clone, Debug)]
pub struct ContactSet {
    /// The law.
    pub law: ContactLaw,
    /// Per body (model order): its solid, or `None` for a body that takes part in no contact.
    pub solids: Vec<Option<Solid>>,
    /// Body pairs (lower index first) that never touch.
    excluded: HashSet<(usize, usize)>,
    /// Per (body, other): which of `body`'s samples are on the crease it shares with `other`
    /// (excluded against it).
    crease: HashMap<(usize, usize), Vec<bool>>,
}

/// Scratch space for [`ContactSet::evaluate`].
#[derive(Default)]
pub struct Workspace {
    aabbs: Vec<Aabb>,
    bodies: Vec<usize>,
    pairs: Vec<(usize, usize)>,
    bvh: BvhWorkspace,
    /// Per body, its motion since the proximity list's reference.
    motion: Vec<f64>,
    /// A side's points on a face or a wall ([`wrench`]).
    faced: Vec<wrench::Faced>,
    /// A sample's points when probed in full, as it is summed ([`wrench`]).
    probed: Vec<ContactPoint>,
}

impl std::fmt::Debug for Workspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workspace").field("bodies", &self.bodies).finish_non_exhaustive()
    }
}

impl ContactSet {
    /// Contact among `solids` under `law`, no pair excluded.
    pub fn new(law: ContactLaw, solids: Vec<Option<Solid>>) -> Self {
        Self { law, solids, excluded: HashSet::new(), crease: HashMap::new() }
    }

    /// The proximity list's skin (see [`proximity`]), m: a quarter of the smallest body's
    /// largest half extent, so that the list is rebuilt after a small fraction of a body's
    /// size of motion relative to the hub.
    pub fn skin(&self) -> f64 {
        0.25 * self.solids.iter().flatten().map(|s| s.bound_half_in_body.max()).fold(f64::INFINITY, f64::min)
    }

    /// Bodies `a` and `b` never touch.
    pub fn exclude(&mut self, a: usize, b: usize) {
        self.excluded.insert((a.min(b), a.max(b)));
    }

    /// Whether the pair is excluded.
    pub fn is_excluded(&self, a: usize, b: usize) -> bool {
        self.excluded.contains(&(a.min(b), a.max(b)))
    }

    /// Bodies `a` and `b` are joined by a hinge: with `b` placed at `b_in_a` (its centre of
    /// mass, m, and attitude b → a, in `a`'s frame) in the hinge's undeformed state, the
    /// samples of each that touch the other (within `margin` or 1 µm) are a crease if they
    /// lie on one line (two plates side by side along their shared edge), and then never
    /// count against the other. Samples touching over an area (a block resting on a slab
    /// with a spring between them) are no crease: they keep their contact. Returns how many
    /// samples that excludes.
    pub fn mark_crease(&mut self, a: usize, b: usize, b_in_a: (Vec3, Mat3)) -> usize {
        let (r, c) = b_in_a;
        let tol = self.law.margin.max(1e-6);
        let mut count = 0;
        for (owner, other, to_other) in [(a, b, (r, c)), (b, a, (-(c.transpose() * r), c.transpose()))] {
            let (Some(so), Some(sb)) = (&self.solids[owner], &self.solids[other]) else { continue };
            // A sample of `owner` in `other`'s frame: `to_other.1ᵀ (p − to_other.0)`.
            let marks: Vec<bool> = so
                .samples
                .iter()
                .map(|s| {
                    let p = to_other.1.transpose() * (s.point_in_body - to_other.0);
                    sb.signed_distance(&p).0 < s.radius + tol
                })
                .collect();
            let touching: Vec<Vec3> =
                so.samples.iter().zip(&marks).filter(|(_, m)| **m).map(|(s, _)| s.point_in_body).collect();
            // A thin plate's crease samples are its rim spheres (radius t/2, on the mid-plane)
            // and, at a sharp tip, points on both faces: a line within the plate's thickness.
            let width = 2.0 * so.samples.iter().map(|s| s.radius).fold(0.0, f64::max);
            if !collinear(&touching, width) {
                continue;
            }
            count += touching.len();
            let entry = self.crease.entry((owner, other)).or_insert_with(|| vec![false; marks.len()]);
            for (e, m) in entry.iter_mut().zip(marks) {
                *e |= m;
            }
        }
        count
    }

    /// Every contact point at the poses `frames` (one per body, model order), appended to
    /// `out`: each body's samples against every other body's solid within the broad phase's
    /// reach (their bounding boxes, grown by the margin, overlap), the crease samples and
    /// excluded pairs left out. `memory` gives the points already in contact their impact
    /// speed; a new point's is its approach speed now.
    pub fn evaluate(&self, frames: &[Frame], memory: &ContactMemory, ws: &mut Workspace, out: &mut Vec<ContactPoint>) {
        self.find_pairs(frames, self.law.margin, ws);
        for &(a, b) in ws.pairs.iter() {
            self.probe(a, b, frames, memory, out);
            self.probe(b, a, frames, memory, out);
        }
    }

    /// The pairs (lower index first, in order, excluded pairs left out) whose bounding boxes,
    /// each grown by `grow` m, overlap at `frames`.
    pub fn candidate_pairs(&self, frames: &[Frame], grow: f64) -> Vec<(usize, usize)> {
        let mut ws = Workspace::default();
        self.find_pairs(frames, grow, &mut ws);
        ws.pairs
    }

    /// `body`'s samples (crease samples left out) that come within `cap` m of `other`'s solid
    /// at `frames`, in index order: each one's index, its gap `d − ρ` (m; ≤ 0 in contact) and
    /// its centre's distance from `body`'s origin (m). A sample group whose sphere is `cap`
    /// or more from the solid is not opened (the distance is 1-Lipschitz).
    pub fn near_samples(&self, body: usize, other: usize, frames: &[Frame], cap: f64) -> Vec<NearSample> {
        let (Some(sa), Some(sb)) = (&self.solids[body], &self.solids[other]) else { return Vec::new() };
        let (fa, fb) = (&frames[body], &frames[other]);
        let crease = self.crease.get(&(body, other));
        let (dcm_b_a, r_ab) = fa.in_frame_of(fb);
        let mut near = Vec::new();
        for (run, centre, radius) in &sa.groups {
            if sb.signed_distance(&(dcm_b_a * centre + r_ab)).0 - radius >= cap {
                continue;
            }
            for k in run.clone() {
                if crease.is_some_and(|c| c[k]) {
                    continue;
                }
                let s = &sa.samples[k];
                let p = dcm_b_a * s.point_in_body + r_ab;
                let (d, lateral) = sb.distance_and_lateral(&p);
                let gap = d - s.radius;
                if gap < cap {
                    let wall = sb.wall_near(&p, (d, lateral), s.radius);
                    near.push(NearSample {
                        index: k as u32,
                        wall: wall.index,
                        gap,
                        lateral,
                        reach: s.point_in_body.norm(),
                        impact: f64::NAN,
                        wall_margin: wall.margin,
                    });
                }
            }
        }
        near
    }

    /// Fills `ws.pairs` with the candidate pairs at `frames`, boxes grown by `grow`.
    fn find_pairs(&self, frames: &[Frame], grow: f64, ws: &mut Workspace) {
        ws.aabbs.clear();
        ws.bodies.clear();
        ws.pairs.clear();
        for (i, s) in self.solids.iter().enumerate() {
            let Some(s) = s else { continue };
            let f = &frames[i];
            let c = f.position_in_n + f.dcm_n_b * s.bound_center_in_body;
            let h = f.dcm_n_b.abs() * s.bound_half_in_body + Vec3::repeat(grow);
            ws.aabbs.push(Aabb::new(
                PVec::new(c.x - h.x, c.y - h.y, c.z - h.z),
                PVec::new(c.x + h.x, c.y + h.y, c.z + h.z),
            ));
            ws.bodies.push(i);
        }
        if ws.bodies.len() < 2 {
            return;
        }
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &ws.aabbs);
        let (bodies, pairs) = (&ws.bodies, &mut ws.pairs);
        bvh.traverse_bvtt_single_tree::<false>(&mut ws.bvh, &mut |i, j| {
            let (a, b) = (bodies[i as usize], bodies[j as usize]);
            pairs.push((a.min(b), a.max(b)));
        });
        // The hierarchy's order depends on its build; contacts are summed in pair order, so
        // that the forces' rounding does not depend on it.
        pairs.sort_unstable();
        pairs.retain(|&(a, b)| !self.excluded.contains(&(a, b)));
    }

    /// `body`'s samples against `other`'s solid.
    fn probe(&self, body: usize, other: usize, frames: &[Frame], memory: &ContactMemory, out: &mut Vec<ContactPoint>) {
        let (Some(sa), Some(sb)) = (&self.solids[body], &self.solids[other]) else { return };
        let (fa, fb) = (&frames[body], &frames[other]);
        let crease = self.crease.get(&(body, other));
        let (dcm_b_a, r_ab) = fa.in_frame_of(fb);
        // A group whose sphere is outside `other`'s solid (its distance above the sphere's
        // radius) holds no sample in contact: the distance is 1-Lipschitz.
        let open = |centre: &Vec3, radius: f64| {
            let c = dcm_b_a * centre + r_ab;
            let q = (c - sb.bound_center_in_body).abs() - sb.bound_half_in_body;
            q.max() <= radius && sb.signed_distance(&c).0 <= radius
        };
        for (run, centre, radius) in &sa.groups {
            if !open(centre, *radius) {
                continue;
            }
            for k in run.clone() {
                if crease.is_some_and(|c| c[k]) {
                    continue;
                }
                let key = PointKey { body: body as u32, other: other as u32, sample: k as u32 };
                let unknown = (f64::INFINITY, wall::NO_WALL);
                self.probe_sample(key, (fa, fb), (&dcm_b_a, &r_ab), unknown, || memory.get(&key).copied(), out);
            }
        }
    }

    /// Sample `key.sample` of `key.body` against `key.other`'s solid (see [`Self::probe`];
    /// not a crease sample), with `impact` its impact speed if it was in contact at the last
    /// accepted state (m/s; asked only of a sample that penetrates, as most probed do not)
    /// and `(lateral_bound, wall)` a bound on its lateral distance in the solid (m, ∞ for
    /// none; see [`Solid::face_distance`]) and the wall that answers it ([`wall::NO_WALL`] for
    /// none known; see [`Solid::wall_distance`]).
    pub(crate) fn probe_sample(
        &self,
        key: PointKey,
        (fa, fb): (&Frame, &Frame),
        (dcm_b_a, r_ab): (&Mat3, &Vec3),
        known: (f64, u32),
        impact: impl FnOnce() -> Option<f64>,
        out: &mut Vec<ContactPoint>,
    ) {
        let k = key.sample as usize;
        let (Some(sa), Some(sb)) = (&self.solids[key.body as usize], &self.solids[key.other as usize]) else { return };
        let s = &sa.samples[k];
        let p = dcm_b_a * s.point_in_body + r_ab;
        // Quick rejection by `other`'s bounding box.
        let q = (p - sb.bound_center_in_body).abs() - sb.bound_half_in_body;
        if q.max() > s.radius {
            return;
        }
        let Some(f) = self.point_force_at(s, sb, fa, fb, &p, known, impact) else { return };
        out.push(ContactPoint {
            key,
            point_in_n: f.point_in_n,
            normal_in_n: f.normal_in_n,
            depth: f.depth,
            rate: f.rate,
            force_in_n: f.force_in_n,
            energy: self.law.energy(f.depth),
            dissipation: f.dissipation,
        });
    }

    /// The contact of `sample` (of the body at `fa`) in `solid` (of the body at `fb`), if it
    /// penetrates: the law at the sample's centre, for a point that came into contact at
    /// `impact_speed` (m/s; `None`: its approach speed now). The law itself is
    /// [`ContactSet::local_force`], in the probed body's frame.
    pub fn point_force(
        &self,
        sample: &Sample,
        solid: &Solid,
        fa: &Frame,
        fb: &Frame,
        impact_speed: Option<f64>,
    ) -> Option<PointForce<f64>> {
        let point_in_b = fa.point_in_frame_of(&sample.point_in_body, fb);
        self.point_force_at(sample, solid, fa, fb, &point_in_b, (f64::INFINITY, wall::NO_WALL), || impact_speed)
    }

    /// [`ContactSet::point_force`] with the sample's centre in `fb`'s body frame given (m),
    /// a bound on its lateral distance in `solid` (m; see [`Solid::face_distance`], ∞ for
    /// none) and the wall that answers it (see [`ContactSet::probe_sample`]).
    #[allow(clippy::too_many_arguments)]
    fn point_force_at(
        &self,
        sample: &Sample,
        solid: &Solid,
        fa: &Frame,
        fb: &Frame,
        point_in_b: &Vec3,
        (lateral_bound, wall): (f64, u32),
        impact_speed: impl FnOnce() -> Option<f64>,
    ) -> Option<PointForce<f64>> {
        let (d, normal_in_b) =
            solid.known_distance(point_in_b, lateral_bound, wall).unwrap_or_else(|| solid.signed_distance(point_in_b));
        let depth = sample.radius - d;
        if depth <= 0.0 {
            return None;
        }
        let impact_speed = impact_speed();
        let point = fb.position_in_n + fb.dcm_n_b * point_in_b;
        let velocity_in_b = fa.velocity_against(fb, &point);
        let f = self.law_at(depth, normal_in_b, &velocity_in_b, impact_speed);
        Some(PointForce {
            point_in_n: point,
            normal_in_n: fb.dcm_n_b * normal_in_b,
            depth,
            rate: f.rate,
            force_in_n: fb.dcm_n_b * f.force_in_b,
            dissipation: f.dissipation,
        })
    }

    /// The contact of `sample` (of body A) in `solid` (of body B) from where the sample's
    /// centre is in B (`point_in_b`, m, B frame) and how fast it moves against B's material
    /// point there (`velocity_in_b`, m/s, B frame), if it penetrates; for a point that came
    /// into contact at `impact_speed` (m/s; `None`: its approach speed now). Generic over the
    /// scalar: the exact Jacobian differentiates this same code in these six inputs (with the
    /// impact speed held).
    pub fn local_force<T: Real>(
        &self,
        sample: &Sample,
        solid: &Solid,
        point_in_b: &Vector3<T>,
        velocity_in_b: &Vector3<T>,
        impact_speed: Option<f64>,
    ) -> Option<LocalForce<T>> {
        let (d, normal_in_b) = solid.signed_distance(point_in_b);
        let depth = real::<T>(sample.radius) - d;
        if re(depth) <= 0.0 {
            return None;
        }
        Some(self.law_at(depth, normal_in_b, velocity_in_b, impact_speed))
    }

    /// The law at penetration `depth` (m) along B's outward normal `normal_in_b` for a
    /// sample moving at `velocity_in_b` against B (see [`ContactSet::local_force`]).
    #[inline]
    fn law_at<T: Real>(
        &self,
        depth: T,
        normal_in_b: Vector3<T>,
        velocity_in_b: &Vector3<T>,
        impact_speed: Option<f64>,
    ) -> LocalForce<T> {
        let rate = -normal_in_b.dot(velocity_in_b);
        let nf = self.law.normal(depth, rate, impact_speed);
        let slip = velocity_in_b + normal_in_b * rate;
        let friction = self.law.friction_force(nf.normal, &slip);
        LocalForce {
            normal_in_b,
            depth,
            rate,
            force_in_b: normal_in_b * nf.normal + friction,
            dissipation: nf.damping_power - friction.dot(&slip),
        }
    }

    /// The penetration of the sample `key` names into its other body at the poses `fa` (its
    /// body) and `fb` (the other), m: positive in contact, negative apart (the gap between
    /// the sample's sphere and the solid). NaN for a key that names no sample.
    pub fn depth(&self, key: &PointKey, fa: &Frame, fb: &Frame) -> f64 {
        let Some((sample, solid)) = self.sample_and_solid(key) else { return f64::NAN };
        let point_in_b = fa.point_in_frame_of(&sample.point_in_body, fb);
        sample.radius - solid.signed_distance(&point_in_b).0
    }

    /// The approach rate of the sample `key` names against its other body at the poses and
    /// velocities `fa` (its body) and `fb` (the other), m/s: the rate of its penetration
    /// (> 0 approaching) along the other solid's outward normal at the sample's centre, as
    /// the law takes it. NaN for a key that names no sample.
    pub fn approach_rate(&self, key: &PointKey, fa: &Frame, fb: &Frame) -> f64 {
        let Some((sample, solid)) = self.sample_and_solid(key) else { return f64::NAN };
        let point_in_b = fa.point_in_frame_of(&sample.point_in_body, fb);
        let normal_in_b = solid.signed_distance(&point_in_b).1;
        let point = fa.position_in_n + fa.dcm_n_b * sample.point_in_body;
        -normal_in_b.dot(&fa.velocity_against(fb, &point))
    }

    /// The sample `key` names and the solid it probes.
    pub fn sample_and_solid(&self, key: &PointKey) -> Option<(&Sample, &Solid)> {
        let sa = self.solids[key.body as usize].as_ref()?;
        let sb = self.solids[key.other as usize].as_ref()?;
        Some((sa.samples.get(key.sample as usize)?, sb))
    }
}

/// Whether `points` lie on one line, to 1 µm plus 1e-9 of their spread plus `width` (m).
fn collinear(points: &[Vec3], width: f64) -> bool {
    let Some(&a) = points.first() else { return true };
    let Some(&b) = points.iter().max_by(|p, q| (*p - a).norm().total_cmp(&(*q - a).norm())) else { return true };
    let Some(dir) = (b - a).try_normalize(0.0) else { return true };
    let tol = 1e-6 + 1e-9 * (b - a).norm() + width;
    points.iter().all(|p| {
        let w = p - a;
        (w - dir * w.dot(&dir)).norm() <= tol
    })
}

/// Contact over a run, as seen at its accepted steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactRecord {
    /// The first accepted state with a point in contact: time (s) and the pair (sample's
    /// body, other body) of its deepest point.
    pub first: Option<(f64, usize, usize)>,
    /// Deepest penetration (m), when (s), and the pair.
    pub deepest: (f64, f64, usize, usize),
    /// Largest total force between two bodies (N), when (s), and the pair.
    pub force_max: (f64, f64, usize, usize),
}

impl ContactRecord {
    /// Takes in the accepted state at time `t` (s) with contact points `points`.
    pub fn record(&mut self, t: f64, points: &[ContactPoint]) {
        if points.is_empty() {
            return;
        }
        let s = ContactSummary::of(points);
        if self.first.is_none() {
            self.first = Some((t, s.deepest.1, s.deepest.2));
        }
        if s.deepest.0 > self.deepest.0 {
            self.deepest = (s.deepest.0, t, s.deepest.1, s.deepest.2);
        }
        if s.force_max > self.force_max.0 {
            self.force_max = (s.force_max, t, s.force_pair.0, s.force_pair.1);
        }
    }
}

/// What the contact points of one state add up to, for the output columns and the report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactSummary {
    /// Body pairs with at least one point in contact.
    pub pairs: usize,
    /// Sample points in contact.
    pub points: usize,
    /// Deepest penetration, m (0 without contact), and its pair (sample's body, other body).
    pub deepest: (f64, usize, usize),
    /// Largest total force between two bodies, N.
    pub force_max: f64,
    /// The pair it acts between (lower body index first).
    pub force_pair: (usize, usize),
    /// Elastic energy stored in every contact, J.
    pub energy: f64,
}

impl ContactSummary {
    /// The summary of `points` (as [`ContactSet::evaluate`] leaves them: grouped by pair).
    pub fn of(points: &[ContactPoint]) -> Self {
        let mut s = Self::default();
        let mut pair_force: HashMap<(u32, u32), Vec3> = HashMap::new();
        for p in points {
            s.energy += p.energy;
            if p.depth > s.deepest.0 {
                s.deepest = (p.depth, p.key.body as usize, p.key.other as usize);
            }
            let (a, b) = (p.key.body.min(p.key.other), p.key.body.max(p.key.other));
            let sign = if p.key.body == a { 1.0 } else { -1.0 };
            *pair_force.entry((a, b)).or_insert_with(Vec3::zeros) += p.force_in_n * sign;
        }
        s.pairs = pair_force.len();
        s.points = points.len();
        for (&(a, b), f) in &pair_force {
            let f = f.norm();
            if f > s.force_max || (f == s.force_max && (a as usize, b as usize) < s.force_pair) {
                s.force_max = f;
                s.force_pair = (a as usize, b as usize);
            }
        }
        s
    }
}
