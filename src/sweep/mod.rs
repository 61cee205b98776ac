//! Sweeps: many runs of one scenario with values drawn from distributions, each summarised in
//! one row of a table (docs/sweep.md).
//!
//! - [`spec`]: the `[sweep]` table: run count, seed, distributions on key paths, metrics;
//! - [`run`]: [`Sweep`]: the draws (one random stream per run, so a seed gives the same
//!   table on any number of workers), the runs over a thread pool, rows in run order;
//! - `metrics`: each run's metrics, taken from its rows as they stream and from its report;
//! - [`table`]: the summary table as CSV.

mod metrics;
pub mod run;
pub mod spec;
pub mod table;

pub use metrics::BUILT_IN;
pub use run::{Sweep, SweepRow};
pub use spec::{Distribution, Metric, Parameter, Statistic, SweepSpec};
pub use table::CsvTable;
