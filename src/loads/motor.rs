//! Hinge motors (docs/loads.md, *Hinge motors*): a generalized force on one of a hinge's six
//! coordinates, applied to its two bodies as an equal and opposite pair, from a time profile
//! or from a servo tracking an angle (or displacement) profile.
//!
//! The coordinates are the hinge's own (docs/model.md §1): `x, y, z` are δ's A0 components
//! (m), `rx, ry, rz` its 3-2-1 angles roll, pitch and yaw (rad), whatever law the hinge has.
//! A motor's effort `u` (N along a displacement, N·m about an angle) is a generalized force:
//! its power is `u q̇` exactly, and positive `u` drives `q` up. In the hinge-wrench convention
//! of docs/model.md §4 (the law's wrench is restoring: the child receives `−F`, `−τ`) the
//! motor adds the wrench of the generalized force `−u`.

use super::Profile;
use crate::law::{HingeState, HingeWrench};
use crate::math::{Real, re, real};
use nalgebra::Vector3;

/// How a motor sets its effort.
#[derive(Clone, Debug, PartialEq)]
pub enum Drive {
    /// The effort's time history: N along a displacement, N·m about an angle.
    Effort(Profile<f64>),
    /// A PD servo tracking `target` (rad or m): `u = kp (q_ref − q) + kd (q̇_ref − q̇)`, q̇_ref
    /// the target's slope, clipped to `±limit` (Basilisk's `hingedRigidBodyPIDMotor` without
    /// the integral term).
    Servo {
        /// The coordinate's target history, rad or m.
        target: Profile<f64>,
        /// Proportional gain, N·m/rad or N/m.
        kp: f64,
        /// Derivative gain, N·m·s/rad or N·s/m.
        kd: f64,
        /// The largest effort the motor gives, N·m or N (infinite: no limit).
        limit: f64,
    },
}

/// One hinge motor.
#[derive(Clone, Debug, PartialEq)]
pub struct Motor {
    /// Name, for messages, the report and its output column.
    pub name: String,
    /// Index of the hinge it drives.
    pub hinge: usize,
    /// The coordinate it drives: 0–2 δ's A0 x, y, z; 3–5 roll, pitch, yaw.
    pub direction: usize,
    /// How it sets its effort.
    pub drive: Drive,
    /// Intervals `[on, off)` (s) in which it acts, sorted and disjoint (crate::loads::union);
    /// empty: at all times.
    pub windows: Vec<(f64, f64)>,
}

/// The coordinate `q` and its rate `q̇` of direction `d` (0–5) of a hinge in state `s`: δ's
/// A0 components (m, m/s), or the 3-2-1 angles roll, pitch, yaw (rad, rad/s).
pub fn coordinate<T: Real>(s: &HingeState<T>, d: usize) -> (T, T) {
    if d < 3 {
        (s.delta_in_a0[d], s.delta_rate_in_a0[d])
    } else {
        let phi = s.theta.phi();
        // rates_from_omega gives (yaw, pitch, roll) rates; phi is (roll, pitch, yaw).
        let rates = s.trig.rates_from_omega(&s.omega_rel_in_a);
        (phi[d - 3], rates[5 - d])
    }
}

/// The hinge wrench (the law's convention: restoring) of a generalized force `u` that drives
/// direction `d` of a hinge in state `s` up: the generalized force `−u` on that coordinate,
/// `τ = B(θ)⁻ᵀ` applied to the angles' part (docs/model.md §4).
pub fn wrench_of<T: Real>(s: &HingeState<T>, d: usize, u: T) -> HingeWrench<T> {
    let zero = T::zero();
    let mut f = [zero; 6];
    f[d] = -u;
    HingeWrench {
        force_in_a0: Vector3::new(f[0], f[1], f[2]),
        torque_in_a: if d < 3 {
            Vector3::zeros()
        } else {
            s.trig.torque_from_generalized(&Vector3::new(f[5], f[4], f[3]))
        },
    }
}

impl Motor {
    /// Whether the motor acts at time `t` (s).
    pub fn acts(&self, t: f64) -> bool {
        super::acts(&self.windows, t)
    }

    /// The effort at time `t` (s) on a hinge in state `s` (N or N·m, driving the coordinate
    /// up), zero when off; `command` (when set, from outside the run) replaces the drive.
    pub fn effort<T: Real>(&self, t: f64, s: &HingeState<T>, command: Option<f64>) -> T {
        if !self.acts(t) {
            return T::zero();
        }
        if let Some(u) = command {
            return real(u);
        }
        match &self.drive {
            Drive::Effort(p) => real(p.at(t)),
            Drive::Servo { target, kp, kd, limit } => {
                let (q, q_dot) = coordinate(s, self.direction);
                let u = (real::<T>(target.at(t)) - q) * real::<T>(*kp)
                    + (real::<T>(target.slope(t)) - q_dot) * real::<T>(*kd);
                if re(u) > *limit {
                    real(*limit)
                } else if re(u) < -*limit {
                    real(-*limit)
                } else {
                    u
                }
            }
        }
    }

    /// The motor's wrench (restoring convention) and its effort and power `u q̇` (W), at time
    /// `t` on a hinge in state `s`.
    pub fn apply<T: Real>(&self, t: f64, s: &HingeState<T>, command: Option<f64>) -> (HingeWrench<T>, T, T) {
        let u = self.effort(t, s, command);
        let (_, q_dot) = coordinate(s, self.direction);
        (wrench_of(s, self.direction, u), u, u * q_dot)
    }

    /// The times at which the motor switches or its profile bends (s), sorted.
    pub fn breaks(&self) -> Vec<f64> {
        let mut out: Vec<f64> = self.windows.iter().flat_map(|&(on, off)| [on, off]).collect();
        out.extend_from_slice(match &self.drive {
            Drive::Effort(p) => p.corners(),
            Drive::Servo { target, .. } => target.corners(),
        });
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// Whether the motor moves an angle (its effort is a torque, N·m).
    pub fn is_angular(&self) -> bool {
        self.direction >= 3
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Euler321, EulerTrig, Vec3};

    /// The motor's wrench does the power `u q̇` on the pair for every direction, at a general
    /// attitude: `−(F·δ̇ + τ·ω_rel)` (the child receives −F, −τ) equals `u q̇`.
    #[test]
    fn wrench_power_is_effort_times_rate() {
        let theta = Euler321::new(0.4, -0.3, 1.1);
        let dcm = theta.to_dcm();
        let s = HingeState {
            delta_in_a0: Vec3::new(0.01, -0.02, 0.03),
            delta_rate_in_a0: Vec3::new(0.5, -0.7, 0.2),
            theta,
            dcm_a_a0: dcm,
            omega_rel_in_a: Vec3::new(0.3, -1.2, 0.8),
            trig: EulerTrig::from_dcm(&dcm),
        };
        for d in 0..6 {
            let m = Motor {
                name: "m".into(),
                hinge: 0,
                direction: d,
                drive: Drive::Effort(Profile::Constant(2.5)),
                windows: vec![],
            };
            let (w, u, power) = m.apply(0.0, &s, None);
            let done = -(w.force_in_a0.dot(&s.delta_rate_in_a0) + w.torque_in_a.dot(&s.omega_rel_in_a));
            assert_eq!(u, 2.5);
            assert!((done - power).abs() < 1e-14, "direction {d}: {done} vs {power}");
            assert!(power.abs() > 0.1);
        }
    }

    /// The servo's effort is the PD law on the target and its slope, clipped at the limit.
    #[test]
    fn servo_tracks_and_clips() {
        let mut s = HingeState::at(Vec3::zeros(), Euler321::new(0.2, 0.0, 0.0));
        s.trig = EulerTrig::from_dcm(&s.dcm_a_a0);
        let target = Profile::Table { times: vec![0.0, 2.0], values: vec![0.0, 1.0] };
        let m = |limit| Motor {
            name: "m".into(),
            hinge: 0,
            direction: 5,
            drive: Drive::Servo { target: target.clone(), kp: 10.0, kd: 2.0, limit },
            windows: vec![(0.5, 3.0)],
        };
        // At t = 1: target 0.5, slope 0.5; yaw 0.2 at rest: 10·0.3 + 2·0.5 = 4.
        assert!((m(f64::INFINITY).effort(1.0, &s, None) - 4.0).abs() < 1e-12);
        assert_eq!(m(1.5).effort(1.0, &s, None), 1.5);
        assert_eq!(m(1.5).effort(0.2, &s, None), 0.0);
        assert_eq!(m(1.5).effort(1.0, &s, Some(-0.25)), -0.25);
        assert_eq!(m(1.5).breaks(), vec![0.0, 0.5, 2.0, 3.0]);
    }
}
