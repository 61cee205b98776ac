//! A finished run read back from its CSV: the table of numbers, and every body's pose at each
//! row (for the animation and the viewer, and for checks made from the outputs alone, as
//! `verify::overlap`'s).

use crate::math::{Euler321, Mat3, Vec3};
use crate::model::Model;
use nalgebra::{Rotation3, UnitQuaternion};
use std::path::Path;

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

/// Every body's pose at every row of a run's CSV.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Poses {
    /// The rows' times, s, increasing.
    pub times: Vec<f64>,
    /// Per row, per body (model order): the centre of mass `R_i` in N, m.
    pub r_in_n: Vec<Vec<Vec3>>,
    /// Per row, per body: `[N i]` as a quaternion (w, x, y, z), of norm 1 to the CSV's digits.
    pub quat: Vec<Vec<[f64; 4]>>,
}

impl Poses {
    /// The poses of a run's observations (rows as `foldsim run` writes them).
    pub fn from_observations(rows: &[crate::observe::Observation]) -> Self {
        Self {
            times: rows.iter().map(|o| o.t).collect(),
            r_in_n: rows.iter().map(|o| o.body_r_in_n.clone()).collect(),
            quat: rows.iter().map(|o| o.body_quat.clone()).collect(),
        }
    }
}

/// The rotation `[N b]` of 3-2-1 angles `θ_{b/N}` as a quaternion (w, x, y, z): for CSVs
/// written before the quaternion columns.
fn quaternion_of_angles(theta: &Euler321) -> [f64; 4] {
    let dcm_n_b: Mat3 = theta.to_dcm().transpose();
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(dcm_n_b));
    [q.w, q.i, q.j, q.k]
}

/// Every body's pose at every row of `table` (the `<body>_R_x/y/z` and `<body>_q_w/x/y/z`
/// columns, or `_yaw/_pitch/_roll` in a CSV written before the quaternions), and warnings
/// (columns the scenario does not make: the CSV may be another scenario's). Times must be
/// finite and increase, poses be finite and quaternions of norm near 1 (0.5 to 2: the CSV
/// keeps them to its digits): the first row that is not is named by its line.
pub fn poses_from_table(model: &Model, table: &Table) -> Result<(Poses, Vec<String>), String> {
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
            "this needs every body's position and attitude; missing {} column(s), e.g. {} (rerun with the default columns, or add *_R_* and *_q_*)",
            missing.len(),
            shown.join(", ")
        ));
    }
    let mut poses = Poses::default();
    for (k, row) in table.rows.iter().enumerate() {
        let line = k + 2;
        let t = row[t_col];
        if !t.is_finite() {
            return Err(format!("line {line}: t = {t} is not a finite time"));
        }
        if let Some(&p) = poses.times.last()
            && t <= p
        {
            return Err(format!(
                "line {line}: t = {t} s does not come after the previous row's {p} s; the rows must be in increasing time"
            ));
        }
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
        if let Some((b, q)) = q.iter().enumerate().find(|(_, q)| !(0.25..=4.0).contains(&q.iter().map(|x| x * x).sum()))
        {
            let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            return Err(format!(
                "line {line}: {}'s quaternion has norm {norm:e}, not 1: is the CSV a run's output?",
                model.bodies[b].name
            ));
        }
        poses.times.push(t);
        poses.r_in_n.push(r);
        poses.quat.push(q);
    }
    Ok((poses, warnings))
}
