//! # foldsim
//!
//! Deployment dynamics of folded spacecraft structures: a rigid hub and rigid panels joined
//! by flexible hinges that bend, twist and stretch in all six directions (the model of
//! `MODEL.md`, after Fulton & Schaub, AAS 17-747).
//!
//! Bodies are integrated in maximal coordinates (pose and twist of each body) and every
//! hinge, tree or loop, is a force element between two bodies (`docs/architecture.md`).
//! The paper's relative coordinates (δ, θ per hinge) are the language of input and output.
//!
//! Layers: [`model`] (static description) → [`init`] (relative initial conditions to body
//! states) → [`dynamics`] (equations of motion) → [`simulate`] (integration, streaming) →
//! [`observe`] (outputs of MODEL.md §5). [`scenario`] reads TOML scenario files.

#![warn(missing_docs)]

pub mod constraints;
pub mod dynamics;
pub mod generate;
pub mod implicit;
pub mod init;
pub mod jacobian;
pub mod law;
pub mod math;
pub mod model;
pub mod observe;
pub mod ode;
pub mod output;
#[cfg(feature = "plot")]
pub mod plot;
pub mod scenario;
pub mod simulate;
pub mod sparse;
pub mod state;
