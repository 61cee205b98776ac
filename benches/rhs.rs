//! Cost of one right-hand-side evaluation against structure size: a straight chain of N
//! panels on six-direction hinges (law 2), N = 1 … 4096. Prints ns per hinge per evaluation
//! and the machine's load average, since these machines are shared.
//!
//! Run: `cargo bench --bench rhs`.

use foldsim::dynamics::Dynamics;
use foldsim::init::{InitialConditions, initial_state};
use foldsim::law::{EulerPotential, LinearGains};
use foldsim::math::{Mat3, Vec3};
use foldsim::model::{Body, HingeSpec, Model, ParentFrame};
use std::time::Instant;

fn chain(n: usize) -> Model {
    let mut bodies = vec![Body::new("hub", 100.0, Mat3::from_diagonal(&Vec3::new(50.0, 50.0, 50.0))).unwrap()];
    let mut hinges = Vec::new();
    for i in 1..=n {
        bodies.push(Body::new(&format!("p{i}"), 2.0, Mat3::from_diagonal(&Vec3::new(0.2, 0.2, 0.35))).unwrap());
        let gains = LinearGains {
            k_f: Mat3::identity() * 1e6,
            k_theta: Mat3::from_diagonal(&Vec3::new(1e3, 1e3, 1.0)),
            c_f: Mat3::zeros(),
            c_theta: Mat3::zeros(),
        };
        hinges.push(HingeSpec {
            name: format!("h{i}"),
            parent: i - 1,
            child: i,
            parent_frame: ParentFrame::Given {
                r_a0_in_parent: Vec3::new(if i == 1 { 1.0 } else { 0.5 }, 0.0, 0.0),
                dcm_a0_parent: Mat3::identity(),
            },
            r_child_in_a: Vec3::new(0.5, 0.0, 0.0),
            dcm_child_a: Mat3::identity(),
            law: Box::new(EulerPotential { gains }),
        });
    }
    Model::new(bodies, hinges, &[]).unwrap()
}

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

fn main() {
    // `cargo test --benches` runs benches with --bench absent; keep that quick.
    let quick = !std::env::args().any(|a| a == "--bench");
    println!("right-hand-side cost, straight chain, law 2 (load average {})", load());
    println!("{:>6} {:>10} {:>14} {:>14}", "panels", "evals", "µs/eval", "ns/hinge");
    for n in [1usize, 4, 16, 64, 256, 1024, 4096] {
        let model = chain(n);
        let ic = InitialConditions { hinges: vec![None; n], body_attitudes: vec![None; n + 1], ..Default::default() };
        let (mut y, refs) = initial_state(&model, &ic);
        // A deformed state, so every law term is live.
        for (i, v) in y.iter_mut().enumerate() {
            *v += 1e-3 * ((i * 7919) % 13) as f64;
        }
        let dynamics = Dynamics::new(&model, refs);
        let mut dydt = vec![0.0; y.len()];
        let budget = if quick { 0.01 } else { 0.5 };
        let mut evals = 0u64;
        let start = Instant::now();
        while start.elapsed().as_secs_f64() < budget {
            for _ in 0..16 {
                dynamics.rhs(&y, &mut dydt);
            }
            evals += 16;
        }
        let per_eval = start.elapsed().as_secs_f64() / evals as f64;
        println!("{:>6} {:>10} {:>14.3} {:>14.1}", n, evals, per_eval * 1e6, per_eval * 1e9 / n as f64);
        std::hint::black_box(&dydt);
    }
    println!("load average after: {}", load());
}
