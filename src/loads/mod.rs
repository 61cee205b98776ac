//! External loads on the bodies (docs/loads.md): a force at a point of a body and a torque,
//! each given in the inertial frame N or in the body's own frame, with a time profile
//! (constant or a table, linear between its points) and optional on/off windows.
//!
//! A layer of its own, below the model (which holds the loads) and the dynamics (which add
//! them to the bodies' wrenches): it knows frames and time, nothing of hinges or contact.
//! Evaluation is generic over the scalar so that the exact Jacobian can differentiate it.

pub mod breaks;
pub mod control;
pub mod motor;

use crate::math::{Real, Vec3, real};
use nalgebra::{Matrix3, Vector3};

/// The frame a load's vector is given in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadFrame {
    /// The inertial frame N: the vector keeps its direction in space.
    Inertial,
    /// The body's frame: the vector turns with the body.
    Body,
}

/// A value's time history: a vector (a load's force or torque) or a number (a motor's
/// effort or its servo's target).
#[derive(Clone, Debug, PartialEq)]
pub enum Profile<V = Vec3> {
    /// The same value at all times.
    Constant(V),
    /// Linear between `(times[k], values[k])` (times strictly increasing, s), held at the
    /// first and last values outside them.
    Table {
        /// Times, s.
        times: Vec<f64>,
        /// The value at each time (its unit).
        values: Vec<V>,
    },
}

impl<V> Profile<V>
where
    V: Copy + std::ops::Mul<f64, Output = V> + std::ops::Add<Output = V> + std::ops::Sub<Output = V>,
{
    /// The value at time `t` (s).
    pub fn at(&self, t: f64) -> V {
        match self {
            Profile::Constant(v) => *v,
            Profile::Table { times, values } => {
                let k = times.partition_point(|&x| x <= t);
                if k == 0 {
                    values[0]
                } else if k == times.len() {
                    values[k - 1]
                } else {
                    let s = (t - times[k - 1]) / (times[k] - times[k - 1]);
                    values[k - 1] * (1.0 - s) + values[k] * s
                }
            }
        }
    }

    /// The rate of change at time `t` (s): a table's slope between its points (the right-hand
    /// one at a point), zero outside them and for a constant.
    pub fn slope(&self, t: f64) -> V {
        match self {
            Profile::Constant(v) => *v * 0.0,
            Profile::Table { times, values } => {
                let k = times.partition_point(|&x| x <= t);
                if k == 0 || k == times.len() {
                    values[0] * 0.0
                } else {
                    (values[k] - values[k - 1]) * (1.0 / (times[k] - times[k - 1]))
                }
            }
        }
    }

    /// The times at which the profile's slope changes (s): a table's points.
    pub fn corners(&self) -> &[f64] {
        match self {
            Profile::Constant(_) => &[],
            Profile::Table { times, .. } => times,
        }
    }
}

/// A vector load: its profile and the frame it is given in.
#[derive(Clone, Debug, PartialEq)]
pub struct Vector {
    /// The vector's history (N for a force, N·m for a torque).
    pub profile: Profile,
    /// The frame its components are in.
    pub frame: LoadFrame,
}

/// Whether `t` (s) lies in one of `windows`: `[on, off)` intervals, sorted and disjoint
/// ([`union`] makes them so); none: always. Found by bisection: scanned, a load switched
/// every 10 ms for 20 s (1,000 windows) made every right-hand side of the three-panel case
/// cost twice its own work.
pub fn acts(windows: &[(f64, f64)], t: f64) -> bool {
    debug_assert!(windows.windows(2).all(|w| w[0].1 < w[1].0), "windows not sorted and disjoint: use loads::union");
    if windows.is_empty() {
        return true;
    }
    let k = windows.partition_point(|&(on, _)| on <= t);
    k > 0 && t < windows[k - 1].1
}

/// The union of `[on, off)` windows as sorted, disjoint windows (overlapping or touching
/// ones merged): the same instants on, found by bisection ([`acts`]).
pub fn union(mut windows: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    windows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(windows.len());
    for (on, off) in windows {
        match out.last_mut() {
            Some(last) if on <= last.1 => last.1 = last.1.max(off),
            _ => out.push((on, off)),
        }
    }
    out
}

/// One external load on one body.
#[derive(Clone, Debug, PartialEq)]
pub struct Load {
    /// Name, for messages and the report.
    pub name: String,
    /// Index of the body it acts on.
    pub body: usize,
    /// Where the force acts: from the body's centre of mass, m, body frame.
    pub point_in_body: Vec3,
    /// The force, N, if any.
    pub force: Option<Vector>,
    /// The torque, N·m, if any.
    pub torque: Option<Vector>,
    /// Intervals `[on, off)` (s) in which the load acts, sorted and disjoint ([`union`]);
    /// empty: at all times.
    pub windows: Vec<(f64, f64)>,
}

impl Load {
    /// Whether the load acts at time `t` (s).
    pub fn acts(&self, t: f64) -> bool {
        acts(&self.windows, t)
    }

    /// The force (N, N frame) and the torque about the body's centre of mass (N·m, N frame)
    /// at time `t` (s) on a body whose attitude is `dcm_n_b` (body → N); zero when off.
    pub fn wrench<T: Real>(&self, t: f64, dcm_n_b: &Matrix3<T>) -> (Vector3<T>, Vector3<T>) {
        let zero = Vector3::from_element(real::<T>(0.0));
        if !self.acts(t) {
            return (zero, zero);
        }
        let in_n = |v: &Vector| -> Vector3<T> {
            let x = v.profile.at(t).map(real::<T>);
            match v.frame {
                LoadFrame::Inertial => x,
                LoadFrame::Body => dcm_n_b * x,
            }
        };
        let force = self.force.as_ref().map_or(zero, in_n);
        let arm = dcm_n_b * self.point_in_body.map(real::<T>);
        let torque = arm.cross(&force) + self.torque.as_ref().map_or(zero, in_n);
        (force, torque)
    }

    /// The times at which the load switches or its profiles bend (s), sorted: the integrator
    /// ends a step at each so that no step straddles a kink.
    pub fn breaks(&self) -> Vec<f64> {
        let mut out: Vec<f64> = self.windows.iter().flat_map(|&(on, off)| [on, off]).collect();
        for v in [&self.force, &self.torque].into_iter().flatten() {
            out.extend_from_slice(v.profile.corners());
        }
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }
}

/// The power of a load's wrench on a body moving at `velocity_in_n` (m/s, centre of mass)
/// and `omega_in_n` (rad/s): F · v + τ · ω, W (τ about the centre of mass).
pub fn power(force_in_n: &Vec3, torque_in_n: &Vec3, velocity_in_n: &Vec3, omega_in_n: &Vec3) -> f64 {
    force_in_n.dot(velocity_in_n) + torque_in_n.dot(omega_in_n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Windows merge into a sorted union, which bisection reads as a scan of the list as
    /// written does.
    #[test]
    fn windows_merge_and_bisect() {
        let w = union(vec![(3.0, 4.0), (0.0, 1.0), (0.5, 2.0), (2.0, 2.5), (5.0, 6.0)]);
        assert_eq!(w, vec![(0.0, 2.5), (3.0, 4.0), (5.0, 6.0)]);
        for (t, on) in [
            (-1.0, false),
            (0.0, true),
            (2.49, true),
            (2.5, false),
            (3.5, true),
            (4.0, false),
            (5.99, true),
            (6.0, false),
        ] {
            assert_eq!(acts(&w, t), on, "t = {t}");
            // The scan of the windows as written says the same.
            let raw = [(3.0, 4.0), (0.0, 1.0), (0.5, 2.0), (2.0, 2.5), (5.0, 6.0)];
            assert_eq!(raw.iter().any(|&(a, b)| t >= a && t < b), on, "t = {t}");
        }
        assert!(acts(&[], 1e9));
    }

    /// A table interpolates linearly and holds its end values; windows switch the load.
    #[test]
    fn profiles_and_windows() {
        let p =
            Profile::Table { times: vec![1.0, 3.0], values: vec![Vec3::new(2.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 2.0)] };
        assert_eq!(p.at(0.0), Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(p.at(2.0), Vec3::new(3.0, 0.0, 1.0));
        assert_eq!(p.at(9.0), Vec3::new(4.0, 0.0, 2.0));
        let load = Load {
            name: "l".into(),
            body: 0,
            point_in_body: Vec3::new(1.0, 0.0, 0.0),
            force: Some(Vector { profile: Profile::Constant(Vec3::new(0.0, 1.0, 0.0)), frame: LoadFrame::Body }),
            torque: None,
            windows: vec![(0.5, 1.5)],
        };
        let turn = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0); // 90° about z
        assert_eq!(load.wrench(0.0, &turn).0, Vec3::zeros());
        let (f, tau) = load.wrench(1.0, &turn);
        // The body's y axis is N's −x; the arm (body x) is N's y: τ = y × (−x) = z.
        assert_eq!(f, Vec3::new(-1.0, 0.0, 0.0));
        assert_eq!(tau, Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(load.breaks(), vec![0.5, 1.5]);
    }
}
