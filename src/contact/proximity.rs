//! Which pairs can touch soon: a proximity list kept across steps (a "Verlet list"), so that
//! a right-hand side probes only pairs that may be in contact, not every pair whose boxes
//! overlap.
//!
//! Built at a reference state: every pair whose bounding boxes, grown by half the `skin`,
//! overlap, with a lower bound on its gap (the least of `d − ρ` over the samples of each
//! against the other's solid, crease samples left out); pairs at least `skin` apart are left
//! out. Distances between bodies do not change under a rigid motion of the whole structure,
//! so each body's motion is measured in the first body's frame (the hub's): its centre's
//! displacement plus its reach times the chord of its rotation bounds how far any of its
//! points or its solid's surface has moved. A pair whose two motions add up to less than its
//! gap cannot touch: it is skipped. While every body has moved less than half the skin, a
//! pair left out cannot touch either; beyond that the list is rebuilt (at an accepted step)
//! or, at a trial state, every pair is probed. Skipping never changes a result: only pairs
//! with no point in contact are skipped.

use super::{ContactSet, Frame};
use crate::math::{Mat3, Vec3};

/// The proximity list at a reference state.
#[derive(Clone, Debug)]
pub struct Proximity {
    /// Per body at the reference: its centre and attitude in the first body's frame.
    ref_position: Vec<Vec3>,
    ref_dcm: Vec<Mat3>,
    /// Per body: the farthest point of its samples (with their radii) and of its solid's
    /// bounding box from its centre, m.
    reach: Vec<f64>,
    /// Pairs that may touch (lower index first, in order) and a lower bound on each one's
    /// gap at the reference, m (≤ 0 when in contact).
    pub pairs: Vec<(usize, usize, f64)>,
    /// The skin, m.
    skin: f64,
}

impl Proximity {
    /// The list at `frames` for `set` with `skin` (m).
    pub fn build(set: &ContactSet, frames: &[Frame], skin: f64) -> Self {
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
        let mut pairs = Vec::new();
        for (a, b) in set.candidate_pairs(frames, 0.5 * skin) {
            let gap = set.gap(a, b, frames, skin).min(set.gap(b, a, frames, skin));
            if gap < skin {
                pairs.push((a, b, gap));
            }
        }
        Self { ref_position, ref_dcm, reach, pairs, skin }
    }

    /// Per body, how far any of its points may have moved since the reference (m, in the
    /// first body's frame), written to `motion`; false if some body moved half the skin or
    /// more (the list no longer covers every pair that may touch).
    pub fn motion(&self, frames: &[Frame], motion: &mut Vec<f64>) -> bool {
        motion.clear();
        let f0 = &frames[0];
        let dcm_0n = f0.dcm_n_b.transpose();
        let mut valid = true;
        for (i, f) in frames.iter().enumerate() {
            let r = dcm_0n * (f.position_in_n - f0.position_in_n);
            // The chord of the rotation between the reference and now: 2 sin(θ/2) =
            // √(3 − tr(Rrefᵀ R)), with R = [0 i].
            let dcm_now = dcm_0n * f.dcm_n_b;
            let trace = self.ref_dcm[i].component_mul(&dcm_now).sum();
            let chord = (3.0 - trace).max(0.0).sqrt();
            let m = (r - self.ref_position[i]).norm() + self.reach[i] * chord;
            valid &= m < 0.5 * self.skin;
            motion.push(m);
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
