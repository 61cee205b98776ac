//! What a run is asked to do: duration, output step and integrator.

/// Time integration method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Dormand–Prince 8(5,3), adaptive, 7th-order dense output.
    Dop853 {
        /// Relative tolerance per state component.
        rtol: f64,
        /// Absolute tolerance per state component (m, m/s, rad/s, quaternion units).
        atol: f64,
    },
    /// Dormand–Prince 5(4), adaptive, 4th-order dense output.
    Dopri5 {
        /// Relative tolerance per state component.
        rtol: f64,
        /// Absolute tolerance per state component.
        atol: f64,
    },
    /// SDIRK4, L-stable implicit (for stiff hinges), adaptive, with the hinge-graph-sparse
    /// Newton matrix of [`crate::dynamics::newton`]; cubic Hermite dense output.
    Sdirk4 {
        /// Relative tolerance per component.
        rtol: f64,
        /// Absolute tolerance per component.
        atol: f64,
    },
    /// Classical fourth-order Runge–Kutta with a fixed step.
    Rk4 {
        /// Step, s.
        step: f64,
    },
}

impl Integrator {
    /// Name as written in scenario files.
    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Dop853 { .. } => "dop853",
            Integrator::Dopri5 { .. } => "dopri5",
            Integrator::Sdirk4 { .. } => "sdirk4",
            Integrator::Rk4 { .. } => "rk4",
        }
    }
}

/// How long to run and how often to output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSettings {
    /// Simulated time, s (> 0).
    pub duration: f64,
    /// Interval between output rows, s (> 0). Rows are at `k · output_step` and at `duration`.
    pub output_step: f64,
    /// Integration method.
    pub integrator: Integrator,
    /// Solve for every lock from the start, rather than engaging each once it carries load
    /// (see [`crate::dynamics::Dynamics::disengage_locks`]): the same motion at a higher
    /// cost, for comparison. Not a scenario key; false from a scenario.
    pub engage_locks_at_start: bool,
}
