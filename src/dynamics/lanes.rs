//! Dual numbers of one body's 13 state numbers in its own 13 lanes, and their place in a
//! hinge's or a contact pair's 26 (the exact Jacobian's, [`super::jacobian`]).

use crate::state::BODY_STATE_LEN as B;
use nalgebra::SMatrix;

/// Dual numbers of one body's 13 state numbers (the hinge laws' [`crate::law::JacobianDual`]).
pub(super) type D13 = crate::law::JacobianDual;

/// Dual numbers of two bodies' 26 state numbers (a contact pair's, a locked hinge's).
pub(super) type D26 = num_dual::DualSVec64<26>;

/// One body's 13 state numbers seeded in its own 13 lanes.
pub(super) fn seeded13(s: &[f64]) -> [D13; B] {
    std::array::from_fn(|k| D13::from_re(s[k]).derivative(k))
}

/// A one-body dual number in a hinge's (or pair's) 26 lanes, its 13 at `first..first + 13`.
pub(super) fn widen(x: D13, first: usize) -> D26 {
    let mut eps = SMatrix::<f64, 26, 1>::zeros();
    if let Some(g) = x.eps.0 {
        eps.fixed_rows_mut::<13>(first).copy_from(&g);
    }
    D26::new(x.re, num_dual::Derivative::some(eps))
}
