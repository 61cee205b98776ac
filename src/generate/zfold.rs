//! A z-folded chain of panels off the hub.

use super::params::{Params, header, hinge, panel};
use std::fmt::Write;

/// A hub and a chain of `n` panels, each hinged at the previous one's far edge, stowed with
/// folds of ±`fold_deg` alternating, released at rest.
pub fn zfold(n: usize, p: &Params) -> String {
    let mut s = String::new();
    header(&mut s, &format!("z-folded chain of {n} panels"), p);
    for k in 1..=n {
        panel(&mut s, &format!("p{k}"), p);
    }
    let half = 0.5 * p.panel_length;
    for k in 1..=n {
        let parent = if k == 1 { "hub".to_string() } else { format!("p{}", k - 1) };
        let a0 = format!("{{ position = [{:?}, 0.0, 0.0] }}", if k == 1 { 1.0 } else { half });
        hinge(&mut s, &format!("h{k}"), &parent, &format!("p{k}"), &a0, [half, 0.0, 0.0], p);
    }
    for k in 1..=n {
        let sign = if k % 2 == 1 { 1.0 } else { -1.0 };
        let _ = writeln!(s, "[initial.hinge.h{k}]\nyaw_deg = {:?}\n", sign * p.fold_deg);
    }
    s
}
