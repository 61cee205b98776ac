//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod fuzz;

use foldsim::observe::{Observation, catalogue, row};
use foldsim::scenario::Scenario;
use foldsim::simulate::{RunReport, simulate};
use std::path::{Path, PathBuf};

/// The `foldsim` binary of this build.
pub fn foldsim() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_foldsim"))
}

/// A directory of its own for one test: `foldsim-<group>-<pid>-<name>` in the system's
/// temporary directory, created.
pub fn tmp(group: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foldsim-{group}-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Path of a file in the repository.
pub fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Loads a scenario from the repository.
pub fn scenario(path: &str) -> Scenario {
    Scenario::from_file(&repo(path)).unwrap_or_else(|e| panic!("{e}"))
}

/// The largest distance between two runs' body positions over their common rows, m.
pub fn largest_distance(a: &[Observation], b: &[Observation]) -> f64 {
    assert_eq!(a.len(), b.len(), "the same output rows");
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.body_r_in_n.iter().zip(&y.body_r_in_n).map(|(p, q)| (p - q).norm()))
        .fold(0.0, f64::max)
}

/// A table of named columns.
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    pub fn col(&self, name: &str) -> usize {
        self.columns.iter().position(|c| c == name).unwrap_or_else(|| panic!("no column {name}"))
    }
}

/// Runs a scenario and keeps every output row.
pub fn run(s: &Scenario) -> (Table, Vec<Observation>, RunReport) {
    let mut observations = Vec::new();
    let mut sink = |o: &Observation| -> Result<(), String> {
        observations.push(o.clone());
        Ok(())
    };
    let report = simulate(&s.model, &s.initial, &s.settings, &mut sink, None).unwrap_or_else(|e| panic!("{e}"));
    let columns = catalogue(&s.model).into_iter().map(|c| c.name).collect();
    let table = Table { columns, rows: observations.iter().map(row).collect() };
    (table, observations, report)
}

/// Reads a CSV with a header of column names and numeric rows.
pub fn read_csv(path: &Path) -> Table {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let columns = r.headers().unwrap().iter().map(|s| s.trim().to_string()).collect();
    let rows = r.records().map(|rec| rec.unwrap().iter().map(|x| x.trim().parse::<f64>().unwrap()).collect()).collect();
    Table { columns, rows }
}

/// Largest difference per shared column, rows matched by time, angle columns (ending in
/// _yaw, _pitch, _roll) compared modulo 2π: the rules of tools/compare_reference.py.
/// Returns (column, max |diff|) for every column of `reference` found in `ours`, and the
/// number of rows matched.
pub fn compare(reference: &Table, ours: &Table) -> (Vec<(String, f64)>, usize) {
    let (rt, ot) = (reference.col("t"), ours.col("t"));
    let mut worst: Vec<(String, f64)> = Vec::new();
    let shared: Vec<(usize, usize, &String)> = reference
        .columns
        .iter()
        .enumerate()
        .filter(|(_, c)| c.as_str() != "t")
        .filter_map(|(i, c)| ours.columns.iter().position(|o| o == c).map(|j| (i, j, c)))
        .collect();
    for (_, _, c) in &shared {
        worst.push(((*c).clone(), 0.0));
    }
    let mut matched = 0;
    for rrow in &reference.rows {
        let t = rrow[rt];
        let Some(orow) = ours.rows.iter().find(|o| (o[ot] - t).abs() < 1e-9) else { continue };
        matched += 1;
        for (k, (i, j, c)) in shared.iter().enumerate() {
            let mut d = (rrow[*i] - orow[*j]).abs();
            if c.ends_with("_yaw") || c.ends_with("_pitch") || c.ends_with("_roll") {
                d = ((d + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI).abs();
            }
            if d.is_nan() {
                d = f64::INFINITY;
            }
            worst[k].1 = worst[k].1.max(d);
        }
    }
    (worst, matched)
}

/// The shipped example `file` (in `examples/`) with every line whose key is in one of the
/// `replace` lists set to `key = value` for that list's value.
pub fn example_variant(file: &str, replace: &[(&[&str], &str)]) -> Scenario {
    let dir = repo("examples");
    let text = std::fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    let text: String = text
        .lines()
        .map(|l| {
            let key = l.split('=').next().unwrap_or("").trim();
            match replace.iter().find(|(keys, _)| keys.contains(&key)) {
                Some((_, value)) => format!("{key} = {value}"),
                None => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    Scenario::from_toml_in(&text, file, &dir).unwrap_or_else(|e| panic!("{e}"))
}

/// Largest difference between the dual-number Jacobian of the accelerations at `y` and
/// central differences of the right-hand side (step `h`), relative to the largest entry.
pub fn jacobian_mismatch_at(dynamics: &foldsim::dynamics::Dynamics, y: &[f64], h: f64) -> f64 {
    use foldsim::dynamics::jacobian::{ExactJacobian, PoseBlock, TwistBlock};
    const B: usize = 13;
    let nb = dynamics.model().bodies.len();
    let mut exact = std::collections::HashMap::new();
    assert!(dynamics.acceleration_jacobian(y, &mut |i, j, dx: &PoseBlock, dv: &TwistBlock| {
        let e = exact.entry((i, j)).or_insert((PoseBlock::zeros(), TwistBlock::zeros()));
        e.0 += dx;
        e.1 += dv;
    }));
    let n = y.len();
    let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for j in 0..nb {
        for k in 0..B {
            let (mut yp, mut ym) = (y.to_vec(), y.to_vec());
            yp[B * j + k] += h;
            ym[B * j + k] -= h;
            dynamics.rhs(&yp, &mut fp);
            dynamics.rhs(&ym, &mut fm);
            for i in 0..nb {
                let blocks = exact.get(&(i, j));
                for r in 0..6 {
                    let fd = (fp[B * i + 7 + r] - fm[B * i + 7 + r]) / (2.0 * h);
                    let ex = blocks.map_or(0.0, |(dx, dv)| if k < 7 { dx[(r, k)] } else { dv[(r, k - 7)] });
                    worst = worst.max((fd - ex).abs());
                    scale = scale.max(fd.abs());
                }
            }
        }
    }
    worst / scale
}

/// The hinge laws of `examples/flasher-starshade.toml`'s generator options (1e7 N/m and
/// 1e4 N·m/rad off the fold, 0.2 N·m/rad folds and panel bending, their dampings), the other
/// laws at the generator's defaults (membrane hinges with thick panels).
pub fn starshade_laws() -> foldsim::generate::flasher::FlasherLaws {
    foldsim::generate::flasher::FlasherLaws {
        k_translation: 1e7,
        k_rotation: 1e4,
        k_fold: 0.2,
        k_bending: 0.2,
        c_translation: 100.0,
        c_rotation: 1.0,
        c_fold: Some(1.0),
        c_bending: 1.0,
        ..Default::default()
    }
}
