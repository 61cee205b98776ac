//! Reduced state-space models (issue 33, item 20; docs/linear.md, *Reduced models*): the
//! rigid-body poles exactly at zero, and the reduced model's response against the full
//! model's, the independent computation being the full model itself.

mod common;

use foldsim::linear::modes::Modes;
use foldsim::linear::reduced::{Reduction, reduce};
use foldsim::linear::statespace::{StateSpace, state_space};
use foldsim::linear::{linearize_at, start_for};
use nalgebra::{Complex, DMatrix};

/// The deployed scenario at `path` (its design state), its full model (hub forces and
/// torques in; MRPs, rates and a hinge angle out), linearisation and every mode.
fn deployed(path: &str, outputs: &[&str]) -> (StateSpace, foldsim::linear::Linearization, Modes) {
    let mut s = common::scenario(path);
    s.initial = start_for(&s.model, &s.initial, &mut s.settings, 0.0, true).unwrap();
    s.model.commandable = true;
    let patterns: Vec<String> = outputs.iter().map(|o| o.to_string()).collect();
    let outputs = foldsim::linear::statespace::outputs_matching(&s.model, &patterns).unwrap();
    let full = state_space(&s.model, &s.initial, &s.settings, 0.0, &[0], &outputs).unwrap();
    let (lin, here) = linearize_at(&s.model, &s.initial, &s.settings, 0.0).unwrap();
    assert!(here.balanced.is_none() && here.unbalanced.is_none());
    let modes = Modes::of(&lin, &here.positions, &here.dcm_n_b).unwrap();
    (full, lin, modes)
}

/// `C (sI − A)⁻¹ B + D` at s (complex).
fn response(m: &StateSpace, s: Complex<f64>) -> DMatrix<Complex<f64>> {
    let n = m.a.nrows();
    let a = m.a.map(|x| Complex::new(x, 0.0));
    let shifted = DMatrix::<Complex<f64>>::identity(n, n) * s - a;
    let x = shifted.lu().solve(&m.b.map(|x| Complex::new(x, 0.0))).expect("s is no pole");
    m.c.map(|x| Complex::new(x, 0.0)) * x + m.d.map(|x| Complex::new(x, 0.0))
}

fn largest_difference(a: &DMatrix<Complex<f64>>, b: &DMatrix<Complex<f64>>) -> f64 {
    let scale = b.iter().map(|x| x.norm()).fold(0.0, f64::max);
    a.iter().zip(b.iter()).map(|(x, y)| (x - y).norm()).fold(0.0, f64::max) / scale
}

/// Kept to every mode, both reductions are the full model in other coordinates: their
/// frequency responses agree with the full model's at 0.05, 0.5 and 5 rad/s (below, at and
/// above the modes of the 3-panel z-fold, whose first is 0.22 rad/s) to 1e-7 of the largest
/// entry (measured 1.1e-8: the full model's own rigid stiffness, its poles at up to 2e-6
/// rad/s, against s² = 2.5e-3 at the lowest frequency, and the modes' round-off). The
/// rigid coordinates have exactly no stiffness and no damping (A's columns, checked to the
/// bit), so the 12 rigid-body poles are zero but for the eigen-solver's round-off on their
/// Jordan blocks: |λ| ≤ 1e-9, where the full model's are at up to 2e-6.
#[test]
fn reduced_models_with_every_mode_are_the_full_model() {
    let dir = common::tmp("reduced", "zfold");
    let path = dir.join("z.toml");
    let o = common::foldsim().args(["generate", "zfold", "--panels", "3", "-o"]).arg(&path).output().unwrap();
    assert!(o.status.success());
    let (full, lin, modes) = deployed(path.to_str().unwrap(), &["sigma_B_*", "w_B_*", "h2_yaw"]);
    let all = 6 * (lin.bodies - 1);
    for kind in [Reduction::FreeFree, Reduction::HubHeld] {
        let r = reduce(&full, &lin, &modes, all, kind).unwrap();
        let mut worst: f64 = 0.0;
        for w in [0.05, 0.5, 5.0] {
            worst = worst
                .max(largest_difference(&response(&r, Complex::new(0.0, w)), &response(&full, Complex::new(0.0, w))));
        }
        let eigen = r.a.complex_eigenvalues();
        let zeros = eigen.iter().filter(|e| e.norm() <= 1e-9).count();
        let full_rigid =
            full.a.complex_eigenvalues().iter().map(|e| e.norm()).filter(|&x| x < 1e-3).fold(0.0, f64::max);
        println!(
            "{kind:?}: {} states, response {worst:.2e} of the largest; {zeros} poles within 1e-9 of 0 (the full model's rigid poles up to {full_rigid:.1e})",
            r.a.nrows()
        );
        assert!(worst < 1e-7, "{kind:?}: {worst:e}");
        assert_eq!(zeros, 12, "{kind:?}: {eigen:?}");
        rigid_is_exact(&r);
    }
}

/// The rigid coordinates (the first six of each form) have exactly no stiffness and no
/// damping: A's columns for them in the accelerations' rows are zero to the bit.
fn rigid_is_exact(r: &StateSpace) {
    let m = r.a.nrows() / 2;
    for row in m..2 * m {
        for col in (0..6).chain(m..m + 6) {
            assert_eq!(r.a[(row, col)], 0.0, "A[{row}, {col}]");
        }
    }
}

/// Truncated to the 4 lowest flexible modes, the deployed small flasher's models (20 states
/// of 804) keep the low-frequency response: at 0.01 rad/s (its first mode is at 0.47) within
/// 1e-3 of the full model's (the left-out modes' static flexibility, (0.01/ω_k)² each:
/// measured 5.7e-4 free-free, 2.4e-6 hub-held, whose hub-held modes carry the appendages'
/// inertia into the rigid part exactly).
#[test]
fn truncated_models_keep_the_low_frequencies() {
    let (full, lin, modes) = deployed("examples/flasher-small.toml", &["sigma_B_*", "w_B_*"]);
    for kind in [Reduction::FreeFree, Reduction::HubHeld] {
        let r = reduce(&full, &lin, &modes, 4, kind).unwrap();
        for w in [0.01, 0.05] {
            let d = largest_difference(&response(&r, Complex::new(0.0, w)), &response(&full, Complex::new(0.0, w)));
            println!(
                "{kind:?}: {} states of {}, response at {w} rad/s {d:.2e} of the largest",
                r.a.nrows(),
                full.a.nrows()
            );
        }
        let d = largest_difference(&response(&r, Complex::new(0.0, 0.01)), &response(&full, Complex::new(0.0, 0.01)));
        assert_eq!(r.a.nrows(), 2 * (6 + 4));
        assert!(d < 1e-3, "{kind:?}: {d:e}");
        assert_eq!(r.a.complex_eigenvalues().iter().filter(|e| e.norm() <= 1e-9).count(), 12);
        rigid_is_exact(&r);
    }
}
