//! The Newton matrix's factorization: our block elimination on the hinge graph
//! (`GraphNewton::refactor`, 6 × 6 blocks in a minimum-fill order) against faer's general
//! sparse LU (symbolic analysis once, then a numeric factorization per new hγ) on the same
//! matrix, the starshade example's `S = I − hγ ∂a/∂v − (hγ)² ∂a/∂x P ∂ẋ/∂v` at its stowed
//! state (229 bodies: 1,374 unknowns).
//!
//! Prints the load, each side's cost per factorization and per solve (medians of alternated
//! batches), and the residual of each solution. Behind the `faer-bench` feature (faer is a
//! large build): `cargo bench --features faer-bench --bench sparse_lu`.

use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{SparseColMat, Triplet};
use foldsim::dynamics::Dynamics;
use foldsim::dynamics::newton::GraphNewton;
use foldsim::integrate::{NewtonMatrix, OdeSystem};
use foldsim::kinematics::initial_state;
use foldsim::scenario::Scenario;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

mod common;
use common::load;

/// Median seconds per call of `f` over `batches` batches of `n` calls, alternated with `g`
/// batch by batch; returns both medians.
fn alternated(batches: usize, n: usize, mut f: impl FnMut(), mut g: impl FnMut()) -> (f64, f64) {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..batches {
        let t = Instant::now();
        for _ in 0..n {
            f();
        }
        a.push(t.elapsed().as_secs_f64() / n as f64);
        let t = Instant::now();
        for _ in 0..n {
            g();
        }
        b.push(t.elapsed().as_secs_f64() / n as f64);
    }
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    (a[a.len() / 2], b[b.len() / 2])
}

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/flasher-starshade.toml");
    let s = Scenario::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
    println!("load average before: {}", load());
    let (y, refs) = initial_state(&s.model, &s.initial);
    let dynamics = Dynamics::new(&s.model, refs);
    let mut f = vec![0.0; y.len()];
    OdeSystem::rhs(&dynamics, 0.0, &y, &mut f);
    let mut newton = GraphNewton::new_exact(&dynamics, &s.model, &dynamics);
    let h_gamma = 1e-3;
    assert!(newton.prepare(0.0, &y, h_gamma));
    let blocks = newton.twist_blocks(h_gamma);
    let n = 6 * blocks.len();
    let triplets: Vec<Triplet<usize, usize, f64>> = blocks
        .iter()
        .enumerate()
        .flat_map(|(i, row)| {
            row.iter().flat_map(move |(&j, b)| {
                (0..36).map(move |k| Triplet::new(6 * i + k / 6, 6 * j + k % 6, b[(k / 6, k % 6)]))
            })
        })
        .collect();
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).expect("a valid matrix");
    let t = Instant::now();
    let symbolic = SymbolicLu::try_new(a.symbolic()).expect("symbolic LU");
    let symbolic_time = t.elapsed().as_secs_f64();
    println!(
        "S: {n} unknowns, {} blocks ({} nonzeros); faer's symbolic LU once: {:.2} ms",
        blocks.iter().map(|r| r.len()).sum::<usize>(),
        triplets.len(),
        symbolic_time * 1e3
    );
    // Factorizations: ours (assembly from the Jacobian's blocks and elimination) against
    // faer's numeric LU on the assembled matrix (assembly into its CSC arrays not counted).
    let mut flip = false;
    let (ours, theirs) = alternated(
        7,
        20,
        || {
            flip = !flip;
            assert!(newton.refactor(if flip { 1.1e-3 } else { 1e-3 }));
        },
        || {
            black_box(Lu::try_new_with_symbolic(symbolic.clone(), a.as_ref()).expect("numeric LU"));
        },
    );
    println!(
        "factorization: ours {:.3} ms, faer {:.3} ms (faer / ours {:.2})",
        ours * 1e3,
        theirs * 1e3,
        theirs / ours
    );
    // Solves: ours on the whole 13-per-body system (the pose corrections in closed form
    // around the twist solve), faer on the twists alone.
    assert!(newton.refactor(h_gamma));
    let lu = Lu::try_new_with_symbolic(symbolic.clone(), a.as_ref()).expect("numeric LU");
    let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64 / 1000.0 - 0.5).collect();
    let mut full = f.clone();
    let mut x = Mat::<f64>::zeros(n, 1);
    let (ours, theirs) = alternated(
        7,
        200,
        || {
            full.copy_from_slice(&f);
            newton.solve(&mut full);
        },
        || {
            x = Mat::from_fn(n, 1, |i, _| b[i]);
            lu.solve_in_place(x.as_mut());
        },
    );
    println!("solve: ours {:.1} µs, faer {:.1} µs (faer / ours {:.2})", ours * 1e6, theirs * 1e6, theirs / ours);
    // faer's residual on S (ours solves the same S inside its solve; tests/ check it).
    let mut r = 0.0f64;
    for (i, row) in blocks.iter().enumerate() {
        for k in 0..6 {
            let mut acc = -b[6 * i + k];
            for (&j, blk) in row {
                for c in 0..6 {
                    acc += blk[(k, c)] * x[(6 * j + c, 0)];
                }
            }
            r = r.max(acc.abs());
        }
    }
    println!("faer's residual max |S x − b| = {r:.2e} (|b| ≤ 0.5); load after: {}", load());
}
