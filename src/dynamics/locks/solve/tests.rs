//! The lock solves checked against each other and against the skipped (idle) solve.

use super::*;
use nalgebra::{DMatrix, DVector};

/// Elimination along the forest, the dense solve of `J M⁻¹ Jᵀ` on the stack and its
/// envelope solve give the same correction and multipliers (to 1e-12 of their size: all
/// are direct solves of well-conditioned systems, and a wrong term in any would be off by
/// O(1)), on a chain (the z-fold example with x, z and ry locked: inner bodies with
/// locked hinges further out, and a leaf) and a star (the 1-DOF example: two leaves on
/// the hub, five locks each).
#[test]
fn forest_dense_and_envelope_solves_agree() {
    use crate::dynamics::Dynamics;
    use crate::kinematics::initial_state;
    let zfold = crate::scenario::example_with("zfold-tape-latch.toml", &["x", "z", "ry"], "\"locked\"");
    let one_dof = crate::scenario::example_with("hinged-panels-1dof.toml", &[], "");
    for (s, chain) in [(zfold, true), (one_dof, false)] {
        let (y, refs) = initial_state(&s.model, &s.initial);
        let dynamics = Dynamics::new(&s.model, refs);
        dynamics.initialize_memory(&y);
        let nb = s.model.bodies.len();
        let motions: Vec<BodyMotion> = (0..nb).map(|i| BodyMotion::from_state(&y, i)).collect();
        let rows = rows(&s.model, &dynamics.locks(), &motions, &dynamics.theta_refs());
        let residual: Vec<f64> = (0..rows.len()).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        let mut work = Workspace::default();
        work.prepare(&s.model, &rows, &motions);
        let f = forest(&work.structure, nb).expect("the locked hinges form a tree");
        assert_eq!(f.leaf.iter().all(|l| *l), !chain);
        work.forest = Some(f);
        assert!(work.correct(&s.model, &rows, &residual));
        let by_forest = work.delta.clone();
        work.forest = None;
        assert!(rows.len() <= SMALL, "solved dense on the stack");
        assert!(work.correct(&s.model, &rows, &residual));
        let scale = work.delta.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff =
            by_forest.iter().flatten().zip(work.delta.iter().flatten()).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(scale > 0.0 && diff <= 1e-12 * scale, "forest vs dense: {diff:e} of {scale:e}");
        // The envelope solve (used above SMALL rows) gives the dense solve's multipliers.
        let dense = work.lambda.clone();
        work.envelope_terms(&rows);
        work.lambda = residual.iter().map(|r| -r).collect();
        assert!(work.factor_envelope());
        work.solve();
        let scale = dense.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = dense.iter().zip(&work.lambda).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(scale > 0.0 && diff <= 1e-12 * scale, "envelope vs dense: {diff:e} of {scale:e}");
    }
}

/// A lock the free accelerations already satisfy is not solved for, and one they miss by
/// a tiny amount is. The z-fold example with z locked, folded at rest: the tape springs'
/// moments act in the plane, so the out-of-plane locks carry nothing (residuals exactly
/// zero), and the structure of the solve is never even built. With one panel given an
/// out-of-plane rate of 1e-9 rad/s, the residuals are ~1.7e-10 m/s², all of the size of
/// their own terms, so the locks are solved for (an absolute threshold of 1e-9 would skip
/// them, and fails this test), and the corrected accelerations satisfy them to 1e-14 of
/// the terms (round-off: measured 1.0e-15).
#[test]
fn idle_locks_are_not_solved_for() {
    use crate::dynamics::Dynamics;
    use crate::kinematics::initial_state;
    let locked = crate::scenario::example_with("zfold-tape-latch.toml", &["z"], "\"locked\"");
    let free = crate::scenario::example_with("zfold-tape-latch.toml", &["z"], "\"free\"");
    let (mut y, refs) = initial_state(&locked.model, &locked.initial);
    let nb = locked.model.bodies.len();
    for tilted in [false, true] {
        if tilted {
            y[BODY_STATE_LEN * 2 + OMEGA] = 1e-9;
        }
        let locking = Dynamics::new(&locked.model, refs.clone());
        locking.initialize_memory(&y);
        let unlocked = Dynamics::new(&free.model, refs.clone());
        unlocked.initialize_memory(&y);
        let mut dydt = vec![0.0; y.len()];
        unlocked.rhs(&y, &mut dydt);
        let dydt_free = dydt.clone();
        let motions: Vec<BodyMotion> = (0..nb).map(|i| BodyMotion::from_state(&y, i)).collect();
        let rows = rows(&locked.model, &locking.locks(), &motions, &locking.theta_refs());
        let mut work = Workspace::default();
        assert!(constrain_accelerations(&locked.model, &rows, &motions, &mut dydt, &mut work));
        let largest = work.multipliers().iter().fold(0.0f64, |m, l| m.max(l.abs()));
        if !tilted {
            assert!(work.parts.is_empty(), "the solve was set up for idle locks");
            assert_eq!(largest, 0.0);
            assert_eq!(dydt, dydt_free);
            continue;
        }
        assert!(!work.parts.is_empty() && largest > 0.0, "locks missed by 1.7e-10 m/s² were not solved for");
        for r in &rows {
            let (p, c) = (twist6(&dydt, r.parent), twist6(&dydt, r.child));
            let (alpha_p, alpha_c) = (
                motions[r.parent].dcm_n_b * Vec3::new(p[3], p[4], p[5]),
                motions[r.child].dcm_n_b * Vec3::new(c[3], c[4], c[5]),
            );
            let terms = [
                r.gamma,
                r.lin_p.dot(&Vec3::new(p[0], p[1], p[2])),
                r.ang_p.dot(&alpha_p),
                r.lin_c.dot(&Vec3::new(c[0], c[1], c[2])),
                r.ang_c.dot(&alpha_c),
            ];
            let (value, scale) = (terms.iter().sum::<f64>(), terms.iter().map(|t| t.abs()).sum::<f64>());
            assert!(value.abs() <= 1e-14 * scale.max(1e-300), "residual {value:e} of {scale:e}");
        }
    }
}

/// The envelope Cholesky solve equals a dense solve on an SPD matrix with a staircase
/// envelope (rows zero left of `first`), like a chain of locked hinges'.
#[test]
fn envelope_cholesky_matches_dense() {
    let n = 9;
    let first = [0, 0, 0, 1, 1, 3, 3, 3, 6];
    // A = B Bᵀ + n I with B lower-banded inside the envelope: SPD, and zero outside.
    let b =
        DMatrix::from_fn(n, n, |i, j| if j <= i && j >= first[i] { 1.0 + ((i * 7 + j * 3) % 5) as f64 } else { 0.0 });
    let mut dense = &b * b.transpose() + DMatrix::identity(n, n) * n as f64;
    for i in 0..n {
        for j in 0..first[i] {
            dense[(i, j)] = 0.0;
            dense[(j, i)] = 0.0;
        }
    }
    let rhs = DVector::from_fn(n, |i, _| (i as f64).sin());
    let expected = dense.clone().cholesky().expect("SPD").solve(&rhs);
    let mut w = Workspace::default();
    for i in 0..n {
        w.first.push(first[i]);
        w.offset.push(w.matrix.len());
        for j in first[i]..=i {
            w.matrix.push(dense[(i, j)]);
        }
    }
    assert!(w.cholesky());
    w.lambda = rhs.iter().copied().collect();
    w.solve();
    let err = w.lambda.iter().zip(expected.iter()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-14, "{err}");
}
