//! Locked hinge directions: holonomic constraints between two bodies, held exactly.
//!
//! A locked direction keeps one relative coordinate of a hinge at its initial value: a
//! component of δ (A0 components), or one 3-2-1 Euler angle of `[A A0]`. In maximal
//! coordinates each lock is a constraint row `J V = 0` on the two bodies' twists
//! (`V = (v, ω)`, N components), with the acceleration-level form `J V̇ + γ = 0`, `γ` the
//! velocity-product terms, derived exactly below. Each right-hand-side evaluation solves
//! `(J M⁻¹ Jᵀ) λ = −(J a_free + γ)` for the constraint multipliers: ideal (workless) wrench
//! pairs, equal and opposite at a common point, so energy and momentum are conserved. After
//! every accepted step the state is projected back onto the constraint manifold (positions,
//! then velocities, mass-weighted), which holds the locked coordinates to round-off.
//!
//! `J M⁻¹ Jᵀ` couples only locks whose hinges share a body; it is assembled hinge pair by
//! hinge pair and factored within its envelope (no fill outside it), which for a chain of
//! locked hinges is linear in their number.

pub mod hold;
pub mod rows;
pub mod solve;

pub use hold::{DRIFT_LIMIT, drift_mask, drifted, project};
pub use rows::{Lock, Row, euler_index, hinge_rows, rows};
pub use solve::{IDLE_RESIDUAL, Workspace, constrain_accelerations, independent};
