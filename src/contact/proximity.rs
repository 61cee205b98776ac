//! Which samples can touch soon: a proximity list kept across steps (a "Verlet list", kept
//! per sample point), so that a right-hand side probes only the samples that may be in
//! contact, not every sample of every pair whose boxes overlap.
//!
//! Built at a reference state: for every pair whose bounding boxes, grown by half the
//! `skin`, overlap, the samples of each (crease samples left out) within [`COVER`] skins of
//! the other's solid, with their gaps `d − ρ` there. A sample's centre moves, in the other
//! body's frame, by at most `|Δr| + 2 sin(θ/2) |p|` from the reference (`Δr` the change of
//! its body's origin there, `θ` the angle of the change of their relative attitude, `p` the
//! sample in its body's frame), and its distance from the other's solid by no more (the
//! distance is 1-Lipschitz): a sample whose gap exceeds that cannot touch and is skipped.
//! Hinged neighbours, whose samples next to the crease sit millimetres apart, are thus
//! probed only when their relative pose changes by that much, not whenever the structure
//! moves.
//!
//! Samples left out of the list (farther than `skin`) cannot touch while every body has
//! moved less than half the skin relative to the first body (the hub): distances do not
//! change under a rigid motion of the whole structure, so each body's motion is measured in
//! the first body's frame, its centre's displacement plus its reach times the chord of its
//! rotation. The two bodies' motions so measured also bound their relative motion: a pair
//! whose motions add up to less than its least gap is skipped before its relative pose is
//! formed. Beyond half the skin the list is rebuilt (at an accepted step: each pair's side
//! kept if its body has moved little in the other's frame since it was listed,
//! [`Proximity::rebuild`]) or, at a trial state, every pair is probed. Skipping never
//! changes a result: only samples not in contact
//! are skipped, and the rest are probed in the full search's order.
//!
//! At every accepted step the gaps of the samples that may be probed are measured again
//! there and their motion counted from there ([`Proximity::rereference`]): the bound then
//! grows with one step's motion, not with all the motion since the build, and a trial
//! state probes about the samples within a step's reach of the other body (on the 5 × 2
//! thick flasher 680 per right-hand side against 5,000, of which 262 touch).
//!
//! A side passed over there (nothing of it within reach) keeps a bound of its motion from
//! its reference to that accepted state (`NearSide::stale`), and each body's motion since the
//! last accepted state is measured once per right-hand side (in the first body's frame, as
//! above): a side whose gap exceeds the two is skipped before its bodies' relative pose is
//! formed (the distance from a moving solid changes by no more than the motions of the point
//! and of the solid's points). On the thick flasher example a right-hand side formed 218
//! relative poses to find the 54 sides it probes; with the bound 89 (callgrind: the run's
//! instructions −3.1 %, the same output to the byte).

use super::wall::NO_WALL;
use super::{ContactMemory, ContactPoint, ContactSet, Frame, PointKey, Workspace};
use crate::math::{Mat3, Vec3};

/// A margin for the rounding of two distances in the list's bounds, m.
const SLACK: f64 = 1e-9;

/// How far a side's samples are listed when the side is made, in skins: beyond the skin, so
/// that at a rebuild a side whose two bodies have moved little relative to each other since
/// (hinged neighbours, layers of a stowed stack) can be kept, its reach less that motion
/// still a skin ([`Proximity::rebuild`]). Under callgrind 1.5 took 0.9 % fewer instructions
/// than 1.25 on the thick flasher example (0.5 % on the 6 × 3's first second), 2 0.6 % more.
pub const COVER: f64 = 1.5;

/// The motion since the build, in skins, past which an accepted state rebuilds the list
/// (below the half skin where it stops covering every pair). On the 5 × 2 thick flasher,
/// 0.5 left 934 trial states to the full search (a third of the samples probed), 0.35 one
/// (4.5 s against 5.2 s), 0.25 as many as 0.35 at more builds.
pub const REBUILD: f64 = 0.35;

impl ContactSet {
    /// As [`ContactSet::evaluate`], probing only the samples `near` says may touch (the same
    /// points in the same order, found faster; every pair when the bodies have moved beyond
    /// the list's reach).
    pub fn evaluate_near(
        &self,
        frames: &[Frame],
        memory: &ContactMemory,
        near: &Proximity,
        ws: &mut Workspace,
        out: &mut Vec<ContactPoint>,
    ) {
        let mut points = Points { set: self, frames, out, side: None };
        if !near.scan(frames, &mut ws.motion, &mut points) {
            self.evaluate(frames, memory, ws, out);
        }
    }
}

/// What a scan of the list ([`Proximity::scan`]) does with the samples it cannot skip.
pub(crate) trait Visit {
    /// A side begins: the samples of `bodies.0` (pose `frames.0`) in the solid of
    /// `bodies.1` (`frames.1`), the body's attitude in the other's frame and its origin
    /// there (m).
    fn begin(&mut self, bodies: (usize, usize), frames: (&Frame, &Frame), pose: (Mat3, Vec3));
    /// A sample of the side begun, with a bound on how far it has moved in the other's frame
    /// since the list's reference (m): its lateral distance in the other's solid now is at
    /// most `sample.lateral` plus that (see [`super::solid::Solid::face_distance`]), and its
    /// wall ([`NearSample::wall`]) still answers it while that is less than its margin.
    fn sample(&mut self, sample: &NearSample, moved: f64);
    /// The side begun is done.
    fn end(&mut self);
}

/// The points of a scan, in order ([`ContactSet::evaluate_near`]).
struct Points<'a> {
    set: &'a ContactSet,
    frames: &'a [Frame],
    out: &'a mut Vec<ContactPoint>,
    /// The side begun: (body, other) and the body's pose in the other's frame.
    side: Option<((usize, usize), (Mat3, Vec3))>,
}

impl Visit for Points<'_> {
    fn begin(&mut self, bodies: (usize, usize), _: (&Frame, &Frame), pose: (Mat3, Vec3)) {
        self.side = Some((bodies, pose));
    }

    fn sample(&mut self, s: &NearSample, moved: f64) {
        let Some((bodies, (dcm_b_a, r_ab))) = &self.side else { return };
        self.set.probe_near(s, *bodies, self.frames, (dcm_b_a, r_ab), moved, self.out);
    }

    fn end(&mut self) {
        self.side = None;
    }
}

impl ContactSet {
    /// The near sample `s` of the side `(body, other)` probed as [`ContactSet::probe_sample`]
    /// does, at the poses `frames` with `body`'s pose in `other`'s frame `(dcm_b_a, r_ab)`
    /// (m), having moved at most `moved` (m) there since the list's reference (its lateral
    /// bound and wall from that: [`Visit::sample`]), its points appended to `out`.
    pub(super) fn probe_near(
        &self,
        s: &NearSample,
        (body, other): (usize, usize),
        frames: &[Frame],
        pose: (&Mat3, &Vec3),
        moved: f64,
        out: &mut Vec<ContactPoint>,
    ) {
        let key = PointKey { body: body as u32, other: other as u32, sample: s.index };
        let impact = || (!s.impact.is_nan()).then_some(s.impact);
        let wall = if moved < s.wall_margin { s.wall } else { NO_WALL };
        self.probe_sample(key, (&frames[body], &frames[other]), pose, (s.lateral + moved, wall), impact, out);
    }
}

impl Proximity {
    /// Visits, side by side, the samples that may touch at the poses `frames` (in the full
    /// search's order), each with its lateral bound; false, visiting nothing, when the
    /// bodies have moved beyond the list's reach (`motion` is scratch).
    pub(crate) fn scan(&self, frames: &[Frame], motion: &mut Vec<f64>, visit: &mut impl Visit) -> bool {
        if !self.motion(frames, motion) {
            return false;
        }
        let (motion, step) = motion.split_at(frames.len());
        for pair in &self.pairs {
            // The two bodies' motions relative to the first body bound their relative one.
            if motion[pair.a] + motion[pair.b] + SLACK < pair.gap {
                continue;
            }
            for (body, other, side) in [(pair.a, pair.b, &pair.a_in_b), (pair.b, pair.a, &pair.b_in_a)] {
                if side.samples.is_empty() {
                    continue;
                }
                // Its motion since its reference is at most that up to the last accepted
                // state and each body's since.
                if side.gap >= side.stale + step[body] + step[other] + SLACK {
                    continue;
                }
                let (fa, fb) = (&frames[body], &frames[other]);
                let (dcm_b_a, r_ab) = fa.in_frame_of(fb);
                let (shift, chord) = side.motion(&dcm_b_a, &r_ab);
                // A sample has moved by at most |Δr| + chord |p| in `other`'s frame.
                if side.gap >= shift + chord * side.reach + SLACK {
                    continue;
                }
                visit.begin((body, other), (fa, fb), (dcm_b_a, r_ab));
                let runs = side.samples.chunks(RUN).zip(side.bounds.chunks(RUN)).zip(&side.runs);
                for ((samples, bounds), &[least, farthest]) in runs {
                    if least >= shift + chord * farthest + SLACK {
                        continue;
                    }
                    for (s, &[gap, r]) in samples.iter().zip(bounds) {
                        if gap >= shift + chord * r + SLACK {
                            continue;
                        }
                        visit.sample(s, shift + chord * s.reach + SLACK);
                    }
                }
                visit.end();
            }
        }
        true
    }
}

/// A sample in the list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearSample {
    /// Its index in its body's solid.
    pub index: u32,
    /// Its gap `d − ρ` from the other body's solid at the reference, m (≤ 0 in contact).
    pub gap: f64,
    /// Its centre's lateral distance in the other body's solid at the reference (or an upper
    /// bound of it), m: see [`super::solid::Solid::face_distance`]. A sample well inside a
    /// face's outline (as the stowed wrap's layers lie on each other) is then probed against
    /// that face alone, not the outline's every edge.
    pub lateral: f64,
    /// Its centre's distance from its body's origin, m.
    pub reach: f64,
    /// Its impact speed if it was in contact at the last accepted state, m/s (NaN if not):
    /// the contact memory's entry, kept here by [`Proximity::remember`] so that a probe
    /// needs no look-up in the memory's map (a quarter of the stowed thick starshade's
    /// right-hand side went to those look-ups).
    pub impact: f64,
    /// The other solid's wall that answered its lateral distance at the reference
    /// ([`super::wall::Wall`]; [`super::wall::NO_WALL`] for none).
    pub wall: u32,
    /// How far it may move since the reference with that wall still the answer, m (less its
    /// motion since an older reference, where its gap was kept as a bound).
    pub wall_margin: f64,
}

/// One body's samples that may enter the other's solid.
#[derive(Clone, Debug)]
pub struct NearSide {
    /// The samples, in index order (the order the full search probes them in).
    pub samples: Vec<NearSample>,
    /// The least of their gaps, m (∞ for none).
    pub gap: f64,
    /// The largest of their reaches, m.
    pub reach: f64,
    /// Each sample's `[gap, reach]` (m), in `samples`' order: all that a right-hand side's
    /// scan for the samples to probe reads, packed. On the thick flasher example a right-hand
    /// side scans ~6,500 samples to probe ~320 (perf: the scan over the whole 40-byte records
    /// was ~6 % of the run's samples; packed, the run is 1–2 % faster, within the noise).
    bounds: Vec<[f64; 2]>,
    /// Per run of [`RUN`] consecutive samples: the least gap and the largest reach (m), so
    /// that a scan passes over a run far from the other body in one test (samples in index
    /// order lie along their outline, and their gaps change little from one to the next).
    runs: Vec<[f64; 2]>,
    /// At the reference: the body's attitude in the other's frame and its origin there (m).
    reference: (Mat3, Vec3),
    /// The places in `samples` whose `impact` is set (not NaN).
    remembered: Vec<u32>,
    /// The body's pose in the other's frame when its list was last made or kept: the
    /// attitude and the origin (m).
    based: (Mat3, Vec3),
    /// How far from the other's solid every sample not listed was then, at least, m.
    cover: f64,
    /// The places in `samples` whose gap is at most [`SLACK`] (in contact, or within rounding
    /// of it, at the reference): what [`Proximity::remember`] looks up, rather than every
    /// sample.
    touching: Vec<u32>,
    /// How far its samples may have moved towards the other's solid from the reference to
    /// the last accepted state, at most, m (0 where it was brought up to date there).
    stale: f64,
}

/// Each sample's `[gap, reach]`.
fn bounds_of(samples: &[NearSample]) -> Vec<[f64; 2]> {
    samples.iter().map(|s| [s.gap, s.reach]).collect()
}

/// Samples per run of [`NearSide::runs`]. On the thick flasher example, a right-hand side
/// scanned ~6,500 listed samples one by one to probe ~680 (5 % of the run).
const RUN: usize = 8;

/// Per run of [`RUN`] of `bounds`: the least gap and the largest reach, written to `runs`.
fn runs_of(bounds: &[[f64; 2]], runs: &mut Vec<[f64; 2]>) {
    runs.clear();
    runs.extend(
        bounds
            .chunks(RUN)
            .map(|run| run.iter().fold([f64::INFINITY, 0.0], |[g, r], &[gap, reach]| [g.min(gap), r.max(reach)])),
    );
}

/// The places in `samples` whose gap is at most [`SLACK`].
fn touching_of(samples: &[NearSample]) -> Vec<u32> {
    samples.iter().enumerate().filter(|(_, s)| s.gap <= SLACK).map(|(i, _)| i as u32).collect()
}

impl NearSide {
    /// `samples` of the body at `fa` against the body at `fb`, every sample within `cover`
    /// (m) of the other's solid among them.
    fn new(samples: Vec<NearSample>, fa: &Frame, fb: &Frame, cover: f64) -> Self {
        let gap = samples.iter().map(|s| s.gap).fold(f64::INFINITY, f64::min);
        let reach = samples.iter().map(|s| s.reach).fold(0.0, f64::max);
        let touching = touching_of(&samples);
        let bounds = bounds_of(&samples);
        let mut runs = Vec::new();
        runs_of(&bounds, &mut runs);
        let reference = fa.in_frame_of(fb);
        Self {
            samples,
            gap,
            reach,
            bounds,
            runs,
            reference,
            remembered: Vec::new(),
            touching,
            based: reference,
            cover,
            stale: 0.0,
        }
    }

    /// How far the body has moved in the other's frame since the reference, given its
    /// attitude `dcm_other_body` and origin `r_in_other` (m) there now: the origin's
    /// displacement (m) and the chord `2 sin(θ/2)` of the relative rotation (a sample at
    /// distance `p` from the origin moves at most `shift + chord p`).
    pub fn motion(&self, dcm_other_body: &Mat3, r_in_other: &Vec3) -> (f64, f64) {
        ((r_in_other - self.reference.1).norm(), chord(&self.reference.0, dcm_other_body))
    }
}

/// A pair of bodies that may touch, with the samples of each that may.
#[derive(Clone, Debug)]
pub struct NearPair {
    /// The lower body index.
    pub a: usize,
    /// The higher.
    pub b: usize,
    /// The least gap of any sample of either, m.
    pub gap: f64,
    /// `a`'s samples that may enter `b`.
    pub a_in_b: NearSide,
    /// `b`'s samples that may enter `a`.
    pub b_in_a: NearSide,
}

impl NearSide {
    /// Takes the pose `(dcm_b_a, r_ab)` of the body in the other's frame as the side's new
    /// reference, the side having moved `(shift, chord)` since the old one ([`Self::motion`];
    /// `solid` the other body's, `samples` the body's own). A sample's gap is measured again
    /// there if it may come near soon; one farther than `FAR` times its motion since the old
    /// reference keeps its old gap less that motion, a lower bound of its distance now (the
    /// distance is 1-Lipschitz), to be measured when it comes nearer.
    fn rereference(
        &mut self,
        samples: &[super::solid::Sample],
        solid: &super::solid::Solid,
        (dcm_b_a, r_ab): (&Mat3, &Vec3),
        (shift, chord): (f64, f64),
    ) {
        const FAR: f64 = 4.0;
        let mut least = f64::INFINITY;
        for (s, packed) in self.samples.iter_mut().zip(&mut self.bounds) {
            let moved = shift + chord * s.reach;
            let bound = s.gap - moved;
            if bound > FAR * moved {
                s.gap = bound;
                s.lateral += moved;
                s.wall_margin -= moved;
            } else {
                let sample = &samples[s.index as usize];
                let p = dcm_b_a * sample.point_in_body + r_ab;
                // The wall noted is kept while it has room for more motion than this (as a
                // gap is). A sample its lateral bound settles on a face, or its wall kept
                // answers, is measured by that alone (the same distance to the bit), its
                // lateral distance kept as a bound; any other in full, its wall noted again.
                let keep_wall = s.wall != NO_WALL && s.wall_margin - moved > FAR * moved;
                let lateral_bound = s.lateral + moved;
                if let Some((d, _)) = solid.known_distance(&p, lateral_bound, if keep_wall { s.wall } else { NO_WALL })
                {
                    (s.gap, s.lateral) = (d - sample.radius, lateral_bound);
                    s.wall_margin -= moved;
                } else {
                    let (d, lateral) = solid.distance_and_lateral(&p);
                    (s.gap, s.lateral) = (d - sample.radius, lateral);
                    if keep_wall {
                        s.wall_margin -= moved;
                    } else {
                        let wall = solid.wall_near(&p, (d, lateral), sample.radius);
                        (s.wall, s.wall_margin) = (wall.index, wall.margin);
                    }
                }
            }
            packed[0] = s.gap;
            least = least.min(s.gap);
        }
        self.gap = least;
        runs_of(&self.bounds, &mut self.runs);
        self.touching = touching_of(&self.samples);
        self.reference = (*dcm_b_a, *r_ab);
        self.stale = 0.0;
    }

    /// The side kept at `frames` (of `body` against `other`; `reach`, m, the farthest
    /// any of the body's samples is from its origin), if the body has moved so little in
    /// the other's frame since the side's samples were listed that the samples left out
    /// are still farther than `skin` (m) from the other's solid: its gaps brought up to date
    /// there, that pose its new base and its cover reduced by the motion. `None` if not.
    fn kept(
        mut self,
        set: &ContactSet,
        (body, other): (usize, usize),
        frames: &[Frame],
        reach: f64,
        skin: f64,
    ) -> Option<Self> {
        let (dcm_b_a, r_ab) = frames[body].in_frame_of(&frames[other]);
        let moved = (r_ab - self.based.1).norm() + chord(&self.based.0, &dcm_b_a) * reach;
        let cover = self.cover - moved - SLACK;
        if cover < skin {
            return None;
        }
        if !self.samples.is_empty() {
            let (Some(sa), Some(sb)) = (&set.solids[body], &set.solids[other]) else { return None };
            let motion = self.motion(&dcm_b_a, &r_ab);
            self.rereference(&sa.samples, sb, (&dcm_b_a, &r_ab), motion);
        }
        self.reference = (dcm_b_a, r_ab);
        (self.based, self.cover, self.stale) = ((dcm_b_a, r_ab), cover, 0.0);
        Some(self)
    }
}

/// The chord `2 sin(θ/2)` of the rotation `θ` that takes attitude `from` to `to` (the
/// largest distance a point at unit distance from the origin moves): `‖to − from‖_F / √2`,
/// as the difference of a rotation and the identity has singular values 2 sin(θ/2) twice and
/// 0. Formed from the entries' differences, it keeps its accuracy at small angles, where
/// `√(3 − tr(fromᵀ to))` loses it to rounding (an error of 3e-8 in the chord at any angle).
fn chord(from: &Mat3, to: &Mat3) -> f64 {
    (to - from).norm() * std::f64::consts::FRAC_1_SQRT_2
}

/// The proximity list at a reference state.
#[derive(Clone, Debug)]
pub struct Proximity {
    /// Per body at the reference: its centre and attitude in the first body's frame.
    ref_position: Vec<Vec3>,
    ref_dcm: Vec<Mat3>,
    /// The same at the last accepted state the list was brought up to date at.
    accepted_position: Vec<Vec3>,
    accepted_dcm: Vec<Mat3>,
    /// Per body: the farthest point of its samples (with their radii) and of its solid's
    /// bounding box from its centre, m.
    reach: Vec<f64>,
    /// Pairs with a sample within the skin (lower index first, in order).
    pub pairs: Vec<NearPair>,
    /// The skin, m.
    skin: f64,
    /// How many sides [`Proximity::rebuild`] kept from the list before.
    pub kept: usize,
}

impl Proximity {
    /// The list at `frames` for `set` with `skin` (m).
    pub fn build(set: &ContactSet, frames: &[Frame], skin: f64) -> Self {
        Self::rebuild(None, set, frames, skin)
    }

    /// The list at `frames` for `set` with `skin` (m), keeping from `old` (a list for the
    /// same set) each side whose body has moved so little in the other's frame since its
    /// samples were listed that every sample left out is still farther than the skin from
    /// the other's solid (its cover less that motion; see [`COVER`]); its gaps are brought up
    /// to date (as at an accepted step, [`Proximity::rereference`]). The other sides are
    /// listed afresh. The list is then as a fresh build's for every purpose (which samples
    /// may touch), found for less: over the 6 × 3 thick flasher's first second 77 % of the
    /// sides were kept (hinged neighbours and stacked layers, which move little against each
    /// other between rebuilds).
    pub fn rebuild(old: Option<Self>, set: &ContactSet, frames: &[Frame], skin: f64) -> Self {
        let reach: Vec<f64> = set
            .solids
            .iter()
            .map(|s| {
                s.as_ref().map_or(0.0, |s| {
                    let bound = s.bound_center_in_body.abs() + s.bound_half_in_body;
                    let samples = s.samples.iter().map(|p| p.point_in_body.norm() + p.radius).fold(0.0, f64::max);
                    bound.norm().max(samples)
                })
            })
            .collect();
        let (ref_position, ref_dcm) = relative(frames);
        let cover = COVER * skin;
        let mut old = old.filter(|o| o.skin == skin).map(|o| o.pairs.into_iter()).into_iter().flatten().peekable();
        let (mut pairs, mut kept) = (Vec::new(), 0);
        for (a, b) in set.candidate_pairs(frames, 0.5 * skin) {
            while old.next_if(|p| (p.a, p.b) < (a, b)).is_some() {}
            let before = old.next_if(|p| (p.a, p.b) == (a, b));
            let (old_a, old_b) = before.map_or((None, None), |p| (Some(p.a_in_b), Some(p.b_in_a)));
            let mut side = |body: usize, other: usize, old: Option<NearSide>| match old
                .and_then(|k| k.kept(set, (body, other), frames, reach[body], skin))
            {
                Some(side) => {
                    kept += 1;
                    side
                }
                None => {
                    NearSide::new(set.near_samples(body, other, frames, cover), &frames[body], &frames[other], cover)
                }
            };
            let a_in_b = side(a, b, old_a);
            let b_in_a = side(b, a, old_b);
            if a_in_b.samples.is_empty() && b_in_a.samples.is_empty() {
                continue;
            }
            pairs.push(NearPair { a, b, gap: a_in_b.gap.min(b_in_a.gap), a_in_b, b_in_a });
        }
        let (accepted_position, accepted_dcm) = (ref_position.clone(), ref_dcm.clone());
        Self { ref_position, ref_dcm, accepted_position, accepted_dcm, reach, pairs, skin, kept }
    }

    /// At an accepted state `frames`: if every body has moved less than [`REBUILD`] skins
    /// since the build, brings the samples' gaps up to date for every side of a pair whose
    /// bound lets some of its samples be probed (`NearSide::rereference`), so that the
    /// right-hand sides of the steps that follow probe only the samples that can reach the
    /// other body within them (a sample's gap at any reference, less its motion since,
    /// bounds its distance; which samples are in the list stays the build's), and returns
    /// true; else false, changing nothing: the caller rebuilds the list (rebuilt before the
    /// half skin is reached, the trial states of the next step seldom leave its reach, where
    /// every pair would be probed).
    pub fn rereference(&mut self, set: &ContactSet, frames: &[Frame], motion: &mut Vec<f64>) -> bool {
        let n = frames.len();
        if !self.motion(frames, motion) || motion[..n].iter().any(|&m| m >= REBUILD * self.skin) {
            return false;
        }
        let (motion, step) = motion.split_at(n);
        for pair in &mut self.pairs {
            let skipped = motion[pair.a] + motion[pair.b] + SLACK < pair.gap;
            for (body, other, side) in [(pair.a, pair.b, &mut pair.a_in_b), (pair.b, pair.a, &mut pair.b_in_a)] {
                if skipped {
                    side.stale += step[body] + step[other];
                    continue;
                }
                let (Some(sa), Some(sb)) = (&set.solids[body], &set.solids[other]) else { continue };
                if side.samples.is_empty() {
                    continue;
                }
                let (dcm_b_a, r_ab) = frames[body].in_frame_of(&frames[other]);
                let (shift, chord) = side.motion(&dcm_b_a, &r_ab);
                if side.gap >= shift + chord * side.reach + SLACK {
                    side.stale = shift + chord * side.reach;
                    continue;
                }
                side.rereference(&sa.samples, sb, (&dcm_b_a, &r_ab), (shift, chord));
            }
        }
        (self.accepted_position, self.accepted_dcm) = relative(frames);
        true
    }

    /// Copies the contact memory's impact speeds into the list's samples (NaN for a sample
    /// not in it): after every change of the memory, before the next probe.
    ///
    /// A point in contact at an accepted state has a gap ≤ 0 in the list there (the list was
    /// built there, or its side brought up to date there: a side not brought up to date has
    /// nothing in contact, and a gap kept as a lower bound is positive): only those samples
    /// are looked up, unless some of the memory's points were not found so (then every
    /// sample is).
    pub fn remember(&mut self, memory: &ContactMemory) {
        let mut found = 0;
        for pair in &mut self.pairs {
            for (body, other, side) in [(pair.a, pair.b, &mut pair.a_in_b), (pair.b, pair.a, &mut pair.b_in_a)] {
                for &i in &side.remembered {
                    side.samples[i as usize].impact = f64::NAN;
                }
                side.remembered.clear();
                for &i in &side.touching {
                    let s = &mut side.samples[i as usize];
                    let key = PointKey { body: body as u32, other: other as u32, sample: s.index };
                    if let Some(&v) = memory.get(&key) {
                        s.impact = v;
                        side.remembered.push(i);
                        found += 1;
                    }
                }
            }
        }
        if found == memory.len() {
            return;
        }
        for pair in &mut self.pairs {
            for (body, other, side) in [(pair.a, pair.b, &mut pair.a_in_b), (pair.b, pair.a, &mut pair.b_in_a)] {
                side.remembered.clear();
                for (i, s) in side.samples.iter_mut().enumerate() {
                    let key = PointKey { body: body as u32, other: other as u32, sample: s.index };
                    s.impact = memory.get(&key).copied().unwrap_or(f64::NAN);
                    if !s.impact.is_nan() {
                        side.remembered.push(i as u32);
                    }
                }
            }
        }
    }

    /// Per body, how far any of its points may have moved since the reference (m, in the
    /// first body's frame), written to `motion`; false if some body moved half the skin or
    /// more (the list no longer covers every pair that may touch).
    pub fn motion(&self, frames: &[Frame], motion: &mut Vec<f64>) -> bool {
        let n = frames.len();
        motion.clear();
        motion.resize(2 * n, 0.0);
        let f0 = &frames[0];
        let dcm_0n = f0.dcm_n_b.transpose();
        let mut valid = true;
        for (i, f) in frames.iter().enumerate() {
            let r = dcm_0n * (f.position_in_n - f0.position_in_n);
            let dcm = dcm_0n * f.dcm_n_b;
            let m = (r - self.ref_position[i]).norm() + self.reach[i] * chord(&self.ref_dcm[i], &dcm);
            valid &= m < 0.5 * self.skin;
            motion[i] = m;
            motion[n + i] = (r - self.accepted_position[i]).norm() + self.reach[i] * chord(&self.accepted_dcm[i], &dcm);
        }
        valid
    }
}

/// Every body's centre and attitude in the first body's frame.
fn relative(frames: &[Frame]) -> (Vec<Vec3>, Vec<Mat3>) {
    let f0 = &frames[0];
    let dcm_0n = f0.dcm_n_b.transpose();
    frames.iter().map(|f| (dcm_0n * (f.position_in_n - f0.position_in_n), dcm_0n * f.dcm_n_b)).unzip()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A side the list's upkeep passes over keeps count of its motion: two 1-cm plates 3 cm
    /// apart close between accepted states where the list is brought up to date and the side
    /// passed over, and at a trial state 4 mm into each other a scan through the list finds
    /// exactly the points a full search finds (none missed because only the motion since the
    /// last accepted state was counted against the 3-cm gap). Passed over at its pair (the
    /// bodies moved less than the gap since the build: 8 mm closer at each of three states),
    /// and at its side (both plates 2 cm sideways, which the pair's bound cannot tell from
    /// motion towards each other, then 1 and 2 cm closer).
    #[test]
    fn motion_passed_over_at_accepted_states_still_counts() {
        use super::super::law::ContactLaw;
        use super::super::solid::Solid;
        let square = [
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(0.5, -0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(-0.5, 0.5, 0.0),
        ];
        let plate = || Some(Solid::plate(&square, 0.01, 0.01).unwrap());
        let law = ContactLaw::new(1e8, 1.5, 0.5, 0.2, 1e-3, 1e-3, 0.0);
        // Body 0, far off, is the frame the bodies' motions are measured in.
        let set = ContactSet::new(law, vec![None, plate(), plate()]);
        // Plate 2 (m) sideways and down from 4 cm over plate 1, plate 1 sideways with it.
        let at = |x: f64, down: f64| {
            let frame = |x: f64, z: f64| Frame { position_in_n: Vec3::new(x, 0.0, z), ..Frame::default() };
            vec![frame(10.0, 0.0), frame(x, 0.0), frame(x, 0.04 - down)]
        };
        let paths: [&[(f64, f64)]; 2] = [&[(0.0, 0.008), (0.0, 0.016), (0.0, 0.024)], &[(0.02, 0.01), (0.02, 0.02)]];
        for (path, accepted) in paths.iter().enumerate() {
            // Faces 3 cm apart: within the list's cover (1.5 skins of 12.5 cm).
            let mut near = Proximity::build(&set, &at(0.0, 0.0), set.skin());
            assert_eq!(near.pairs.len(), 1);
            assert!((near.pairs[0].gap - 0.03).abs() < 1e-12, "gap {}", near.pairs[0].gap);
            let mut motion = Vec::new();
            for &(x, down) in accepted.iter() {
                assert!(near.rereference(&set, &at(x, down), &mut motion), "path {path}: rebuilt");
                let side = &near.pairs[0].a_in_b;
                assert!(side.gap > 0.029, "path {path}: the side was passed over (its gap {} kept)", side.gap);
            }
            let trial = at(accepted[accepted.len() - 1].0, 0.034);
            let mut full = Vec::new();
            set.evaluate(&trial, &ContactMemory::default(), &mut Workspace::default(), &mut full);
            assert!(full.len() > 100, "path {path}: {} points in the full search", full.len());
            let mut listed = Vec::new();
            set.evaluate_near(&trial, &ContactMemory::default(), &near, &mut Workspace::default(), &mut listed);
            assert!(listed == full, "path {path}: {} points through the list, {} in full", listed.len(), full.len());
        }
    }

    /// The chord of a rotation by θ is 2 sin(θ/2), to rounding, down to the smallest angles
    /// (the trace's form gave 0 or 3e-8 below about 1e-8 rad, and the proximity list then
    /// missed contacts that came within 1e-8 m).
    #[test]
    fn chord_is_accurate_at_small_angles() {
        let from = crate::math::dcm_from_quat(&[0.5, -0.5, 0.5, 0.5]);
        for theta in [1e-12_f64, 1e-9, 1e-6, 1e-3, 1.0, 3.0] {
            let turn =
                nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(Vec3::new(1.0, 2.0, -0.5)), theta);
            let to = from * turn.matrix();
            let exact = 2.0 * (theta / 2.0).sin();
            // Rounding of the entries (1e-16 each) against the chord itself.
            assert!((chord(&from, &to) - exact).abs() <= 1e-15 + 1e-14 * exact, "θ = {theta}: {}", chord(&from, &to));
        }
    }
}
