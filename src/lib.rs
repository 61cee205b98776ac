//! # foldsim
//!
//! Deployment dynamics of folded spacecraft structures: a rigid hub and rigid panels joined
//! by flexible hinges that bend, twist and stretch in all six directions (the model of
//! `docs/model.md`, after Fulton & Schaub, AAS 17-747).
//!
//! Bodies are integrated in maximal coordinates (pose and twist of each body) and every
//! hinge, tree or loop, is a force element between two bodies (`docs/architecture.md`).
//! The paper's relative coordinates (δ, θ per hinge) are the language of input and output.
//!
//! Layers, lowest first; a module uses only modules above it in this list:
//! [`math`] (rotations) → [`integrate`] (generic integrators) → [`law`] (hinge laws) →
//! [`contact`] → [`loads`] (external loads, motors, control) →
//! [`model`] (static description) → [`state`] (the state vector) → [`kinematics`] (hinge
//! relative states, initial conditions) → [`dynamics`] (equations of motion, locks, the
//! exact Jacobian, the hinge-graph Newton matrix) → [`observe`] (outputs) → [`simulate`]
//! (a run) → [`linear`] (linear models and modes) → [`scenario`] (TOML files) → [`session`] (a run stepped by name: the
//! C library's, the FMU's) → [`output`] (CSV, plots) → [`verify`] (checks of a run from its
//! outputs alone) → [`generate`] (scenario generators) →
//! [`sweep`] (many runs of a scenario, summarised) → [`fit`] (scenario values fitted to
//! measurements) → [`export`] (the FMU archive). `tests/layers.rs`
//! checks it.

#![warn(missing_docs)]

pub mod contact;
pub mod dynamics;
pub mod export;
pub mod fit;
pub mod generate;
pub mod integrate;
pub mod kinematics;
pub mod law;
pub mod linear;
pub mod loads;
pub mod math;
pub mod model;
pub mod observe;
pub mod output;
pub mod scenario;
pub mod session;
pub mod simulate;
pub mod state;
pub mod sweep;
pub mod verify;
