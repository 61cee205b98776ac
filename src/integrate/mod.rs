//! Time integrators, generic over any first-order system `ẏ = f(t, y)`: they know nothing of
//! bodies or hinges.
//!
//! - [`step`]: the [`OdeSystem`] trait, the accepted [`Step`] with its dense output, the
//!   callback's [`Control`], [`Stats`] and [`OdeError`];
//! - [`explicit`]: DOP853, Dormand–Prince 5(4) and fixed-step RK4 ([`integrate`]), with the
//!   coefficients in `tableau`;
//! - [`sdirk4`]: the L-stable implicit SDIRK4 ([`integrate_sdirk4`]), which solves with a
//!   [`NewtonMatrix`] from [`newton`];
//! - [`galpha`]: the generalized-α method at fixed or adaptive steps ([`integrate_generalized_alpha`]),
//!   with the same Newton matrix.

mod anderson;
pub mod explicit;
pub mod galpha;
pub mod newton;
mod retries;
pub mod sdirk4;
pub mod step;
mod tableau;

pub use explicit::integrate;
pub use galpha::{AlphaSteps, integrate_generalized_alpha};
pub use newton::{DenseNewton, NewtonMatrix};
pub use sdirk4::integrate_sdirk4;
pub use step::{Control, ErrorNorm, Limits, Method, OdeError, OdeSystem, Stats, Step};
