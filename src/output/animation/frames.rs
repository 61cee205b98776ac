//! The animation's frames: body poses at a sequence of times, in single precision as the
//! file keeps them, pushed row by row from a run or read from its CSV.

use super::{BYTES_PER_BODY_FRAME, rotation_f32};
use crate::math::Vec3;
use crate::model::Model;
use crate::observe::Observation;
use crate::output::table::{Table, poses_from_table};

/// Body poses at a sequence of times, kept in single precision as the file stores them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frames {
    /// Bodies per frame.
    pub(super) bodies: usize,
    /// Keep a row only this long after the last kept one, s (0: every row).
    interval: f64,
    /// Times, s, increasing.
    pub times: Vec<f64>,
    /// Per frame then per body (model order): centre of mass in N, m.
    pub translations: Vec<[f32; 3]>,
    /// Per frame then per body: `[N i]` as a unit quaternion (x, y, z, w).
    pub rotations: Vec<[f32; 4]>,
    /// The last row seen, if it was not kept.
    pending: Option<(f64, Vec<Vec3>, Vec<[f64; 4]>)>,
    /// Per frame then per body, when the rows say (a run with contact): whether the body
    /// touched another from this frame until the next (STEP interpolation shows it over that
    /// interval). Empty otherwise.
    pub touched: Vec<bool>,
    /// The pending row's touches (for the last frame).
    touched_pending: Vec<bool>,
    /// Rows pushed so far, and the index of each kept one (as `times`): which rows of the
    /// run's table the frames show.
    rows: usize,
    /// See `rows`.
    pub kept: Vec<usize>,
    /// The index of the pending row.
    pending_row: usize,
}

impl Frames {
    /// Frames of `bodies` bodies, about `fps` per second of simulated time if given (else one
    /// per output row).
    pub fn new(bodies: usize, fps: Option<f64>) -> Self {
        Self { bodies, interval: fps.map_or(0.0, |f| 1.0 / f), ..Default::default() }
    }

    /// Adds the poses of one output row (if it is due), and which bodies touched since the
    /// row before (a run with contact).
    pub fn push(&mut self, o: &Observation) {
        // The row's touches (since the row before) belong to the interval that starts at the
        // last frame kept.
        let nb = o.touched.len();
        if nb > 0 && self.touched.len() >= nb {
            let last = self.touched.len() - nb;
            for (p, t) in self.touched[last..].iter_mut().zip(&o.touched) {
                *p |= t;
            }
        }
        let kept = self.times.len();
        self.push_poses(o.t, &o.body_r_in_n, &o.body_quat);
        if self.times.len() > kept {
            self.kept.push(self.rows);
            self.touched.extend_from_slice(&o.touched);
        } else {
            self.pending_row = self.rows;
            self.touched_pending.clone_from(&o.touched);
        }
        self.rows += 1;
    }

    /// Adds a frame from positions in N and attitude quaternions `β_{i/N}` (w, x, y, z; the
    /// rotation `[N i]` as an operator) if it is due: the first row, then rows at least the
    /// frame interval apart; [`Self::finish`] adds the last.
    pub fn push_poses(&mut self, t: f64, r_in_n: &[Vec3], quat: &[[f64; 4]]) {
        if let Some(&last) = self.times.last()
            && t < last + self.interval * (1.0 - 1e-9)
        {
            self.pending = Some((t, r_in_n.to_vec(), quat.to_vec()));
            return;
        }
        self.pending = None;
        self.times.push(t);
        self.translations.extend(r_in_n.iter().map(|r| [r.x as f32, r.y as f32, r.z as f32]));
        self.rotations.extend(quat.iter().map(rotation_f32));
    }

    /// Adds the last row if it was skipped, so the animation ends where the run did.
    pub fn finish(&mut self) {
        if let Some((t, r, q)) = self.pending.take() {
            self.interval = 0.0;
            self.push_poses(t, &r, &q);
            self.kept.push(self.pending_row);
            self.touched.append(&mut self.touched_pending);
        }
    }

    /// Bytes the frames take in the file.
    pub fn bytes(&self) -> usize {
        self.times.len() * (4 + self.bodies * BYTES_PER_BODY_FRAME)
    }
}

/// The frames of a finished run from its CSV (every body's pose, read by
/// [`crate::output::table::poses_from_table`]), about `fps` per second if given; the rows they
/// came from; and warnings (columns the scenario does not make: the CSV may be another
/// scenario's).
pub fn frames_from_table(
    model: &Model,
    table: &Table,
    fps: Option<f64>,
) -> Result<(Frames, Vec<usize>, Vec<String>), String> {
    let (poses, warnings) = poses_from_table(model, table)?;
    let mut frames = Frames::new(model.bodies.len(), fps);
    let mut kept = Vec::new();
    for (k, t) in poses.times.iter().enumerate() {
        let before = frames.times.len();
        frames.push_poses(*t, &poses.r_in_n[k], &poses.quat[k]);
        if frames.times.len() > before {
            kept.push(k);
        }
    }
    let before = frames.times.len();
    frames.finish();
    if frames.times.len() > before {
        kept.push(table.rows.len() - 1);
    }
    Ok((frames, kept, warnings))
}
