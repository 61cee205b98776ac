//! Time integration and output streaming.
//!
//! The integrators are in [`crate::integrate`] (DOP853 and Dormand–Prince 5(4) with dense
//! output, classical RK4 with a fixed step). Output rows are
//! produced from the dense output at each output time and handed to a sink as they are made,
//! so memory does not grow with the length of a run.
//!
//! - [`settings`]: what a run is asked to do ([`RunSettings`], [`Integrator`]);
//! - [`run`]: [`simulate`], which streams rows to a [`Sink`];
//! - [`accuracy`]: a run held to a tolerance in the bodies' positions (`run.position_tolerance`), by running it again tighter;
//! - [`stepper`]: a run advanced piece by piece ([`Stepper`]), for a controller outside;
//! - [`stream`]: the step handler a run and a stepped run share;
//! - [`stopped`]: why an integration stopped, in the user's terms;
//! - [`switching`]: `integrator = "auto"`, DOP853 and an implicit method (generalized-α, SDIRK4 with contact) each where it pays;
//! - [`pace`]: what the progress callback is told ([`Progress`]), and what holds a run's steps back;
//! - [`report`]: what it reports ([`RunReport`], [`Drift`]) or why it stopped ([`SimError`]);
//! - [`estimate`]: a run's wall time, projected from a short trial of it.

pub mod accuracy;
mod contact_entry;
pub mod estimate;
pub mod pace;
pub mod report;
mod rerun;
pub mod run;
pub mod settings;
pub mod stepper;
pub mod stopped;
pub mod stream;
pub mod switching;

pub use accuracy::simulate;
pub use pace::Progress;
pub use report::{Drift, MethodSpan, PositionAccuracy, RunReport, SimError};
pub use run::{Sink, simulate_at};
pub use settings::{Integrator, RunSettings};
pub use stepper::Stepper;
