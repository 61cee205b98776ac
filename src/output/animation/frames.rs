//! The animation's frames: body poses at a sequence of times, in single precision as the
//! file keeps them, pushed row by row from a run or read from its CSV.

use super::{BYTES_PER_BODY_FRAME, rotation_f32};
use crate::math::{Euler321, Mat3, Vec3};
use crate::model::Model;
use crate::observe::Observation;
use nalgebra::{Rotation3, UnitQuaternion};
use std::path::Path;

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

/// The rotation `[N b]` of 3-2-1 angles `θ_{b/N}` as a quaternion (w, x, y, z): for CSVs
/// written before the quaternion columns.
fn quaternion_of_angles(theta: &Euler321) -> [f64; 4] {
    let dcm_n_b: Mat3 = theta.to_dcm().transpose();
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(dcm_n_b));
    [q.w, q.i, q.j, q.k]
}

/// A CSV of `foldsim run`: its header and rows, every field a number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows of values.
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// Reads `path`; a field that is not a number is named by row and column.
    pub fn read(path: &Path) -> Result<Self, String> {
        let mut reader = csv::Reader::from_path(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let header: Vec<String> = reader
            .headers()
            .map_err(|e| format!("{}: {e}", path.display()))?
            .iter()
            .map(|h| h.trim().to_string())
            .collect();
        let mut rows = Vec::new();
        for (line, record) in reader.records().enumerate() {
            let record = record.map_err(|e| format!("{}: {e}", path.display()))?;
            let row = record
                .iter()
                .zip(&header)
                .map(|(field, name)| {
                    field.trim().parse::<f64>().map_err(|_| {
                        format!(
                            "{}: row {} column '{name}': '{}' is not a number",
                            path.display(),
                            line + 2,
                            field.trim()
                        )
                    })
                })
                .collect::<Result<Vec<f64>, String>>()?;
            rows.push(row);
        }
        Ok(Self { header, rows })
    }

    /// The index of column `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }
}

/// The frames of a finished run from its CSV (every body's `_R_x/y/z` and `_q_w/x/y/z`
/// columns, or `_yaw/_pitch/_roll` in a CSV written before the quaternions), about `fps` per
/// second if given; the rows they came from; and warnings (columns the scenario does not
/// make: the CSV may be another scenario's). Times must be finite and increase, poses be
/// finite: the first row that is not is named.
pub fn frames_from_table(
    model: &Model,
    table: &Table,
    fps: Option<f64>,
) -> Result<(Frames, Vec<usize>, Vec<String>), String> {
    let t_col = table.column("t").ok_or("no column 't'")?;
    let known: std::collections::HashSet<String> =
        crate::observe::catalogue(model).into_iter().map(|c| c.name).collect();
    let foreign: Vec<&str> = table.header.iter().filter(|h| !known.contains(*h)).map(String::as_str).collect();
    let mut warnings = Vec::new();
    if !foreign.is_empty() {
        warnings.push(format!(
            "{} column(s) of the CSV are not outputs of this scenario (e.g. {}): is it another scenario's run?",
            foreign.len(),
            foreign.iter().take(4).copied().collect::<Vec<_>>().join(", ")
        ));
    }
    let quaternions = model.bodies.iter().all(|b| table.column(&format!("{}_q_w", b.name)).is_some());
    let parts: &[&str] = if quaternions {
        &["_R_x", "_R_y", "_R_z", "_q_w", "_q_x", "_q_y", "_q_z"]
    } else {
        &["_R_x", "_R_y", "_R_z", "_yaw", "_pitch", "_roll"]
    };
    let mut cols = Vec::new();
    let mut missing = Vec::new();
    for b in &model.bodies {
        let names: Vec<String> = parts.iter().map(|s| format!("{}{s}", b.name)).collect();
        let found: Vec<Option<usize>> = names.iter().map(|n| table.column(n)).collect();
        missing.extend(names.iter().zip(&found).filter(|(_, f)| f.is_none()).map(|(n, _)| n.clone()));
        cols.push(found.into_iter().flatten().collect::<Vec<usize>>());
    }
    if !missing.is_empty() {
        let shown: Vec<&str> = missing.iter().take(6).map(String::as_str).collect();
        return Err(format!(
            "the animation needs every body's position and attitude; missing {} column(s), e.g. {} (rerun with the default columns, or add *_R_* and *_q_*)",
            missing.len(),
            shown.join(", ")
        ));
    }
    let mut frames = Frames::new(model.bodies.len(), fps);
    let mut kept = Vec::new();
    let mut previous: Option<f64> = None;
    for (k, row) in table.rows.iter().enumerate() {
        let line = k + 2;
        let t = row[t_col];
        if !t.is_finite() {
            return Err(format!("line {line}: t = {t} is not a finite time"));
        }
        if let Some(p) = previous
            && t <= p
        {
            return Err(format!(
                "line {line}: t = {t} s does not come after the previous row's {p} s; the rows must be in increasing time"
            ));
        }
        previous = Some(t);
        if let Some(c) = cols.iter().flatten().find(|&&c| !row[c].is_finite()) {
            return Err(format!("line {line}: {} = {} is not finite", table.header[*c], row[*c]));
        }
        let r: Vec<Vec3> = cols.iter().map(|c| Vec3::new(row[c[0]], row[c[1]], row[c[2]])).collect();
        let q: Vec<[f64; 4]> = cols
            .iter()
            .map(|c| {
                if quaternions {
                    [row[c[3]], row[c[4]], row[c[5]], row[c[6]]]
                } else {
                    quaternion_of_angles(&Euler321::new(row[c[3]], row[c[4]], row[c[5]]))
                }
            })
            .collect();
        if let Some((b, _)) = q.iter().enumerate().find(|(_, q)| q.iter().map(|x| x * x).sum::<f64>() < 1e-12) {
            return Err(format!("line {line}: {}'s quaternion is zero", model.bodies[b].name));
        }
        let before = frames.times.len();
        frames.push_poses(t, &r, &q);
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
