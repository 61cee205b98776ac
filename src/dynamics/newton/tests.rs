//! The hinge-graph Newton solve against the dense one, with and without locks.

use super::*;
use crate::dynamics::Dynamics;
use crate::integrate::DenseNewton;
use crate::kinematics::initial_state;
use crate::scenario::Scenario;

/// Minimum-fill elimination makes no fill on a tree (a z-fold chain: two factor blocks
/// per hinge, L and U) and a bounded amount on a grid (6×6: 264 blocks for 61 hinges,
/// 2.2× the no-fill count; bound 3×).
#[test]
fn elimination_fill_follows_the_hinge_graph() {
    use crate::generate::{Params, grid, zfold};
    for (text, tree) in [(zfold(32, &Params::default()), true), (grid(6, 6, &Params::default()), false)] {
        let s = Scenario::from_toml(&text, "generated").unwrap();
        let (y, refs) = initial_state(&s.model, &s.initial);
        let dynamics = Dynamics::new(&s.model, refs);
        dynamics.initialize_memory(&y);
        let mut f = vec![0.0; y.len()];
        crate::integrate::OdeSystem::rhs(&dynamics, 0.0, &y, &mut f);
        let mut newton = GraphNewton::new_exact(&dynamics, &s.model, &dynamics);
        assert!(newton.prepare(0.0, &y, 1e-3));
        assert_eq!(newton.jacobian_counts(), (1, 0), "exact Jacobian for law 2");
        let pairs = 2 * s.model.hinges.len();
        if tree {
            assert_eq!(newton.fill_blocks(), pairs);
        } else {
            assert!(newton.fill_blocks() < 3 * pairs, "{} blocks for {pairs}", newton.fill_blocks());
        }
    }
}

/// `GraphNewton`'s solve (with the exact Jacobian if `exact`) and `DenseNewton`'s
/// (forward differences of the right-hand side) of the same right-hand side at
/// scenario `s`'s initial state and `h_gamma`: (right-hand side, graph solution, largest
/// difference in the body rows, largest dense solution entry there).
fn graph_and_dense(s: &Scenario, h_gamma: f64, exact: bool) -> (Vec<f64>, Vec<f64>, f64, f64) {
    graph_and_dense_spinning(s, h_gamma, exact, [0.0; 3])
}

/// [`graph_and_dense`] with body 1 given an angular velocity `spin` (rad/s, body
/// components) at the start: about an axis out of a flat structure's plane and not
/// across its arms, the out-of-plane locks of a flat structure carry load (at rest, or
/// spinning about an in-plane axis across the arms, they are idle).
fn graph_and_dense_spinning(s: &Scenario, h_gamma: f64, exact: bool, spin: [f64; 3]) -> (Vec<f64>, Vec<f64>, f64, f64) {
    graph_and_dense_with(s, h_gamma, exact, &|y, _| {
        for (k, w) in spin.iter().enumerate() {
            y[B + OMEGA + k] += w;
        }
    })
}

/// [`graph_and_dense`] at the initial state as `setup` changes it (and the dynamics,
/// whose memory is set at the initial state first).
fn graph_and_dense_with(
    s: &Scenario,
    h_gamma: f64,
    exact: bool,
    setup: &dyn Fn(&mut Vec<f64>, &Dynamics),
) -> (Vec<f64>, Vec<f64>, f64, f64) {
    let (mut y, refs) = initial_state(&s.model, &s.initial);
    let dynamics = Dynamics::new(&s.model, refs);
    dynamics.initialize_memory(&y);
    setup(&mut y, &dynamics);
    assert!(dynamics.check_locks(&y).is_ok());
    let mut f = vec![0.0; y.len()];
    crate::integrate::OdeSystem::rhs(&dynamics, 0.0, &y, &mut f);
    let mut graph = if exact {
        GraphNewton::new_exact(&dynamics, &s.model, &dynamics)
    } else {
        GraphNewton::new(&dynamics, &s.model)
    };
    let mut dense = DenseNewton::new(&dynamics, y.len());
    assert!(graph.prepare(0.0, &y, h_gamma));
    assert_eq!(graph.jacobian_counts(), if exact { (1, 0) } else { (0, 1) });
    assert!(dense.prepare(0.0, &y, h_gamma));
    let b: Vec<f64> = (0..y.len()).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
    let (mut xg, mut xd) = (b.clone(), b.clone());
    graph.solve(&mut xg);
    dense.solve(&mut xd);
    let nb = 13 * s.model.bodies.len();
    let scale = xd[..nb].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = xg[..nb].iter().zip(&xd[..nb]).fold(0.0f64, |m, (a, c)| m.max((a - c).abs()));
    (b, xg, diff, scale)
}

/// The differenced graph solve against the dense one: both use forward-difference
/// Jacobians (steps differ), so agreement to 1e-5 relative is what the differencing
/// allows; a wrong block, colour or elimination step would be off by O(1).
fn graph_matches_dense(s: &Scenario) {
    let (_, _, diff, scale) = graph_and_dense(s, 0.05, false);
    assert!(diff <= 1e-5 * scale, "{:?}: graph vs dense: {diff:e} of {scale:e}", s.title);
}

/// On the 3-panel case (a loop hinge, so elimination makes fill), the graph-sparse solve
/// matches the dense one.
#[test]
fn graph_solve_matches_dense_solve() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/paper-3panel.toml")).unwrap();
    let s = Scenario::from_toml(&text, "p3").unwrap();
    graph_matches_dense(&s);
    let dynamics = Dynamics::new(&s.model, Vec::new());
    let graph = GraphNewton::new(&dynamics, &s.model);
    assert!(graph.colour_count() <= 4, "4 bodies need at most 4 colours");
}

/// With locked directions and the exact Jacobian, the constraints are rows of the Newton
/// matrix: on the z-fold example with its five off-axis directions locked, the solve
/// matches the dense one (forward differences of the constrained right-hand side).
#[test]
fn constraint_rows_solve_matches_dense_solve() {
    let s = crate::scenario::example_with("zfold-tape-latch.toml", &["x", "y", "z", "rx", "ry"], "\"locked\"");
    for h_gamma in [1e-4, 0.05] {
        let (_, _, diff, scale) = graph_and_dense(&s, h_gamma, true);
        eprintln!("hγ = {h_gamma}: constraint rows vs dense: {diff:e} of {scale:e}");
        assert!(diff <= 1e-5 * scale, "graph vs dense: {diff:e} of {scale:e}");
    }
}

/// Locks around loops (a 3×3 grid of panels, every hinge's z translation locked, the
/// rest stiff springs, one panel spinning so the locks carry load): the
/// rows' solve against the dense differenced one, as above (bound 2 hγ relative at
/// hγ = 1e-4), and the locked rows of the correction.
#[test]
fn constraint_rows_solve_on_loops() {
    use crate::generate::{Params, grid};
    let law = "law = { type = \"directional\", angles = \"euler\", x = { k = 1e6 }, y = { k = 1e6 }, z = \"locked\", rx = { k = 1e3 }, ry = { k = 1e3 }, rz = { k = 1.0 } }";
    let text: String = grid(3, 3, &Params::default())
        .lines()
        .map(|l| if l.starts_with("law = ") { law.to_string() } else { l.to_string() })
        .collect::<Vec<_>>()
        .join("\n");
    let s = Scenario::from_toml(&text, "locked grid").unwrap();
    let h_gamma = 1e-4;
    let (_, _, diff, scale) = graph_and_dense_spinning(&s, h_gamma, true, [0.3, 0.0, 0.5]);
    eprintln!("locked grid, constraint rows vs dense: {diff:e} of {scale:e}");
    assert!(diff <= 2.0 * h_gamma * scale, "graph vs dense: {diff:e} of {scale:e}");
}

/// Idle locks leave the Newton matrix: the z-fold example with z locked, folded at rest
/// (in-plane moments, so the locks carry nothing), solves exactly as with z free — the
/// same matrix, no lock nodes — while the same structure with one panel spinning (loaded
/// locks) keeps its rows and differs. A lock wrongly judged idle is caught by the two
/// tests above, whose locks carry load.
#[test]
fn idle_locks_leave_the_newton_matrix() {
    let locked = crate::scenario::example_with("zfold-tape-latch.toml", &["z"], "\"locked\"");
    let free = crate::scenario::example_with("zfold-tape-latch.toml", &["z"], "\"free\"");
    let (_, x_locked, _, _) = graph_and_dense(&locked, 0.05, true);
    let (_, x_free, _, _) = graph_and_dense(&free, 0.05, true);
    assert_eq!(x_locked, x_free, "idle locks changed the Newton solve");
    let (_, x_rolling_locked, _, _) = graph_and_dense_spinning(&locked, 0.05, true, [0.3, 0.0, 0.5]);
    let (_, x_rolling_free, _, _) = graph_and_dense_spinning(&free, 0.05, true, [0.3, 0.0, 0.5]);
    let diff = x_rolling_locked.iter().zip(&x_rolling_free).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff > 1e-6, "loaded locks must stay in the Newton matrix: {diff:e}");
}

/// Some hinges' locks engaged, the others not (a run engages each hinge's locks once they
/// drift): the Newton matrix carries the engaged hinges' rows only and matches the dense
/// solve of the same right-hand side, as in `constraint_rows_solve_matches_dense_solve`
/// (bound 1e-5 relative). The z-fold example with its five off-axis directions locked,
/// every lock disengaged, then the second panel moved 1 µm along N's x: three in-plane
/// translation locks of the two hinges at that panel drift and engage (they carry the
/// folded panels' spring loads, so their rows stay in the matrix), the other 17 stay
/// disengaged (the solve then differs from the all-engaged one). Idle engaged locks
/// leave the matrix, which the dense differences cannot follow (see
/// `idle_locks_leave_the_newton_matrix`).
#[test]
fn partly_engaged_locks_solve_matches_dense_solve() {
    let s = crate::scenario::example_with("zfold-tape-latch.toml", &["x", "y", "z", "rx", "ry"], "\"locked\"");
    let moved = |y: &mut Vec<f64>| y[2 * B] += 1e-6;
    let (_, x_part, diff, scale) = graph_and_dense_with(&s, 0.05, true, &|y, dynamics| {
        moved(y);
        dynamics.disengage_locks();
        let engaged: Vec<(usize, usize)> = dynamics
            .engage_drifted_locks(y)
            .iter()
            .map(|&k| (dynamics.locks()[k].hinge, dynamics.locks()[k].direction))
            .collect();
        // In-plane translations of the two hinges at the panel (h2's A0 is on the first
        // panel, turned 90° by h1's fold: its x axis is across N's x).
        assert_eq!(engaged, [(1, 1), (2, 0), (2, 1)], "in-plane translations at the panel");
    });
    eprintln!("partly engaged: constraint rows vs dense: {diff:e} of {scale:e}");
    assert!(diff <= 1e-5 * scale, "graph vs dense: {diff:e} of {scale:e}");
    let (_, x_all, _, _) = graph_and_dense_with(&s, 0.05, true, &|y, _| moved(y));
    let change = x_part.iter().zip(&x_all).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(change > 1e-6 * scale, "disengaged locks must leave the matrix: {change:e}");
}

/// With locked directions the multipliers couple every body of a locked chain, not only
/// neighbours: the z-fold example (hub and four panels in a chain) with its five off-axis
/// directions locked. Colouring by the hinge graph alone gives the hub and the third
/// panel one colour and puts the chain's far coupling into the wrong blocks (off by
/// O(1); SDIRK4's Newton iteration then failed on 6,040 of 11,515 steps).
#[test]
fn graph_solve_matches_dense_solve_with_locks() {
    let s = crate::scenario::example_with("zfold-tape-latch.toml", &["x", "y", "z", "rx", "ry"], "\"locked\"");
    graph_matches_dense(&s);
}
