//! Attitude and spin control of the hub (docs/gnc.md): a feedback law giving the torque the
//! hub should receive, and the actuators that give it: a reaction-wheel cluster (internal:
//! the wheels' momentum is part of H) or torque sources (thruster pairs, or an ideal torque
//! about the hub's axes; external).
//!
//! Frames: `B` is the hub's frame, `N` the inertial one, `R` the target's. Quaternions are
//! `(w, x, y, z)`, scalar first, N to the frame (`β_{B/N}`: its DCM is `[B N]`, Schaub &
//! Junkins §3.5), as in the state and the `q_B_*` columns. Torques, rates and wheel axes are
//! in B components.
//!
//! Wheels follow Schaub & Junkins §4.5 (balanced wheels, spin axis `g` fixed in B): wheel
//! k's spin momentum `h_k = J_s (g_k · ω + Ω_k)` (N·m·s) is a state with `ḣ_k = u_k`, the
//! motor torque on the wheel; the hub, whose inertia is that of the spacecraft with its
//! wheels less `Σ J_s g gᵀ`, receives `−ω × Σ g_k h_k − Σ g_k u_k`. To give the hub the
//! torque `L`, the wheels take `u = −G⁺ L` (`G` the axes as columns, `G⁺` its Moore–Penrose
//! inverse: the least-squares torque for fewer than three axes, the smallest wheel torques
//! for more).

use crate::math::{Mat3, Real, Vec3, mrp_from_quat, quat_relative, re, real};
use nalgebra::{DMatrix, Vector3};

/// The feedback law: the torque the hub should receive, `L` (N·m, B components).
#[derive(Clone, Debug, PartialEq)]
pub enum Law {
    /// `L = −K σ_{B/R} − P ω_{B/N}`: MRP proportional–derivative feedback to a fixed target
    /// attitude (Schaub & Junkins §8.4; Basilisk's `mrpFeedback` with no integral term and
    /// an inertial reference).
    MrpPd {
        /// Attitude gain K, N·m (per unit MRP).
        k: f64,
        /// Rate gain P, N·m·s.
        p: f64,
    },
    /// `L = −K sgn(q_w) q_v − P ω`, `q = β_{B/R}`: quaternion feedback the short way round
    /// (Wie, Weiss & Arapostathis 1989).
    QuaternionPd {
        /// Attitude gain K, N·m (per unit quaternion vector part).
        k: f64,
        /// Rate gain P, N·m·s.
        p: f64,
    },
    /// `L = −P (ω − Ω a)`: holds a spin rate Ω (rad/s) about a hub axis a and damps the
    /// other rates (rate damping when Ω = 0).
    SpinHold {
        /// The spin axis a, unit, B components.
        axis_in_hub: Vec3,
        /// The spin rate Ω, rad/s.
        rate: f64,
        /// Rate gain P, N·m·s.
        p: f64,
    },
    /// No law: `L = 0`; the actuators act only on commands from outside the run (a stepped
    /// run's `set_wheel_torque`).
    None,
}

/// One reaction wheel on the hub.
#[derive(Clone, Debug, PartialEq)]
pub struct Wheel {
    /// Name, for the report and the output columns.
    pub name: String,
    /// Spin axis g, unit, hub components.
    pub axis_in_hub: Vec3,
    /// Spin inertia J_s about g, kg·m².
    pub inertia: f64,
    /// Largest motor torque, N·m (infinite: no limit).
    pub max_torque: f64,
    /// Largest momentum relative to the hub, `|J_s Ω|`, N·m·s (infinite: no limit): at it
    /// the motor torque that would spin the wheel further is cut to zero.
    pub max_momentum: f64,
    /// Initial speed Ω relative to the hub, rad/s.
    pub speed: f64,
}

/// A torque source on the hub (a pair of opposed thrusters): a torque about its axis of
/// either sign up to a limit. External: it changes H.
#[derive(Clone, Debug, PartialEq)]
pub struct Thruster {
    /// Name, for the report and the output columns.
    pub name: String,
    /// Torque axis, unit, hub components.
    pub axis_in_hub: Vec3,
    /// Largest torque, N·m (infinite: no limit).
    pub max_torque: f64,
}

/// What turns the law's torque into torque on the hub.
#[derive(Clone, Debug, PartialEq)]
pub enum Actuators {
    /// A reaction-wheel cluster.
    Wheels(Vec<Wheel>),
    /// Torque sources (with none given: the hub's x, y and z axes, each up to the control's
    /// `max_torque`).
    Thrusters(Vec<Thruster>),
}

/// Attitude or spin control of the hub.
#[derive(Clone, Debug, PartialEq)]
pub struct Control {
    /// The feedback law.
    pub law: Law,
    /// The target attitude `β_{R/N}`, unit, scalar first (the MRP and quaternion laws).
    pub target: [f64; 4],
    /// The actuators.
    pub actuators: Actuators,
    /// Sample period of the law, s: the actuators hold each command for a period (zero-order
    /// hold, as a flight computer's task); `None`: the law acts continuously.
    pub period: Option<f64>,
    /// Per actuator: the row k of the allocation, `effort_k = allocation[k] · L`.
    allocation: Vec<Vec3>,
}

/// One evaluation of the control at a state: what the law asked and what the actuators do.
#[derive(Clone, Debug, PartialEq)]
pub struct Actuation<T: nalgebra::Scalar = f64> {
    /// The law's torque L, N·m, hub components.
    pub required_in_hub: Vector3<T>,
    /// Per actuator, its effort (wheel motor torque u_k on the wheel, or a source's torque),
    /// N·m, after its limits.
    pub efforts: Vec<T>,
}

impl Control {
    /// A control with its allocation: `−G⁺` for wheels (the hub receives `−g u`), `G⁺` for
    /// torque sources. Fails if the actuators' axes are all zero.
    pub fn new(law: Law, target: [f64; 4], actuators: Actuators, period: Option<f64>) -> Result<Self, String> {
        let (axes, sign): (Vec<Vec3>, f64) = match &actuators {
            Actuators::Wheels(w) => (w.iter().map(|w| w.axis_in_hub).collect(), -1.0),
            Actuators::Thrusters(t) => (t.iter().map(|t| t.axis_in_hub).collect(), 1.0),
        };
        if axes.is_empty() {
            return Err("the control has no actuators".into());
        }
        let g = DMatrix::from_fn(3, axes.len(), |r, c| axes[c][r]);
        let pinv = g.pseudo_inverse(1e-12).map_err(|e| format!("the actuators' axes: {e}"))?;
        let allocation = (0..axes.len()).map(|k| Vec3::new(pinv[(k, 0)], pinv[(k, 1)], pinv[(k, 2)]) * sign).collect();
        Ok(Self { law, target, actuators, period, allocation })
    }

    /// Number of actuators.
    pub fn actuator_count(&self) -> usize {
        self.allocation.len()
    }

    /// The wheels, if the actuators are wheels.
    pub fn wheels(&self) -> &[Wheel] {
        match &self.actuators {
            Actuators::Wheels(w) => w,
            Actuators::Thrusters(_) => &[],
        }
    }

    /// Per actuator: its axis (hub components) and torque limit (N·m).
    fn axis_and_limit(&self, k: usize) -> (Vec3, f64) {
        match &self.actuators {
            Actuators::Wheels(w) => (w[k].axis_in_hub, w[k].max_torque),
            Actuators::Thrusters(t) => (t[k].axis_in_hub, t[k].max_torque),
        }
    }

    /// Actuator names, in order.
    pub fn actuator_names(&self) -> Vec<&str> {
        match &self.actuators {
            Actuators::Wheels(w) => w.iter().map(|w| w.name.as_str()).collect(),
            Actuators::Thrusters(t) => t.iter().map(|t| t.name.as_str()).collect(),
        }
    }

    /// The law's torque `L` (N·m, hub components) for the hub at `β_{B/N}` = `q_hub` (need
    /// not be unit) turning at `omega_in_hub` (rad/s).
    pub fn required<T: Real>(&self, q_hub: &[T], omega_in_hub: &Vector3<T>) -> Vector3<T> {
        match &self.law {
            Law::MrpPd { k, p } => {
                let sigma = mrp_from_quat(&quat_relative(q_hub, &self.target));
                -(sigma * real::<T>(*k) + omega_in_hub * real::<T>(*p))
            }
            Law::QuaternionPd { k, p } => {
                let q = quat_relative(q_hub, &self.target);
                let s = if q[0] < T::zero() { -T::one() } else { T::one() };
                -(Vector3::new(q[1], q[2], q[3]) * (s * real::<T>(*k)) + omega_in_hub * real::<T>(*p))
            }
            Law::SpinHold { axis_in_hub, rate, p } => {
                -(omega_in_hub - axis_in_hub.map(real::<T>) * real::<T>(*rate)) * real::<T>(*p)
            }
            Law::None => Vector3::zeros(),
        }
    }

    /// The actuators' commands for the law's torque `l`, each within its torque limit, and
    /// per actuator whether the limit cut it.
    pub fn allocate<T: Real>(&self, l: &Vector3<T>) -> (Vec<T>, Vec<bool>) {
        let mut cut = vec![false; self.allocation.len()];
        let efforts = self
            .allocation
            .iter()
            .enumerate()
            .map(|(k, row)| {
                let u = l.dot(&row.map(real::<T>));
                let (_, limit) = self.axis_and_limit(k);
                if re(u).abs() > limit {
                    cut[k] = true;
                    if re(u) > 0.0 { real(limit) } else { real(-limit) }
                } else {
                    u
                }
            })
            .collect();
        (efforts, cut)
    }

    /// Efforts set from outside, each clipped to its actuator's torque limit (N·m), and per
    /// actuator whether the limit cut it.
    pub fn clip(&self, efforts: &[f64]) -> (Vec<f64>, Vec<bool>) {
        efforts
            .iter()
            .enumerate()
            .map(|(k, u)| {
                let limit = self.axis_and_limit(k).1;
                (u.clamp(-limit, limit), u.abs() > limit)
            })
            .unzip()
    }

    /// Wheel k's speed relative to the hub, Ω = h/J_s − g·ω (rad/s), for its spin momentum
    /// `h` (N·m·s) and the hub's rate `omega_in_hub` (rad/s).
    pub fn wheel_speed<T: Real>(wheel: &Wheel, h: f64, omega_in_hub: &Vector3<T>) -> T {
        real::<T>(h / wheel.inertia) - omega_in_hub.dot(&wheel.axis_in_hub.map(real::<T>))
    }

    /// Cuts to zero the wheel torques that would spin a wheel at its momentum limit further
    /// (`|J_s Ω| ≥ max_momentum` and `u Ω > 0`); returns per actuator whether it did.
    pub fn limit_momentum<T: Real>(&self, efforts: &mut [T], wheel_h: &[f64], omega_in_hub: &Vector3<T>) -> Vec<bool> {
        let wheels = self.wheels();
        let mut cut = vec![false; efforts.len()];
        for (k, w) in wheels.iter().enumerate() {
            let speed = re(Self::wheel_speed(w, wheel_h[k], omega_in_hub));
            if (w.inertia * speed).abs() >= w.max_momentum && re(efforts[k]) * speed > 0.0 {
                efforts[k] = T::zero();
                cut[k] = true;
            }
        }
        cut
    }

    /// The torque the actuators' `efforts` give the hub, N·m, hub components, less the
    /// wheels' gyroscopic reaction: wheels `−Σ g u`, torque sources `Σ a τ`.
    pub fn hub_torque<T: Real>(&self, efforts: &[T]) -> Vector3<T> {
        let sign = if matches!(self.actuators, Actuators::Wheels(_)) { -1.0 } else { 1.0 };
        efforts.iter().enumerate().fold(Vector3::zeros(), |acc, (k, u)| {
            let (axis, _) = self.axis_and_limit(k);
            acc + axis.map(real::<T>) * (*u * real::<T>(sign))
        })
    }

    /// The wheels' spin momenta along their axes, `Σ g h`, N·m·s, hub components.
    pub fn wheel_momentum_in_hub(&self, wheel_h: &[f64]) -> Vec3 {
        self.wheels().iter().zip(wheel_h).map(|(w, h)| w.axis_in_hub * *h).sum()
    }

    /// `Σ J_s g gᵀ`, kg·m², hub components: what the wheels' spin takes from the hub's
    /// inertia (the spacecraft's with the wheels held).
    pub fn wheel_spin_inertia(&self) -> Mat3 {
        self.wheels().iter().map(|w| w.axis_in_hub * w.axis_in_hub.transpose() * w.inertia).sum()
    }
}

/// What the motors and the hub's control did at one instant: an output row's columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Reading {
    /// Per motor: its effort, N or N·m (driving its coordinate up).
    pub motor_efforts: Vec<f64>,
    /// With control: the hub's MRPs `σ_{B/N}`, the short way round.
    pub sigma_hub: Vec3,
    /// With control to a target attitude: the angle from the hub to the target, rad in
    /// [0, π]; NaN for spin hold and for no law.
    pub pointing_error: f64,
    /// The law's torque L (held between samples), N·m, hub components.
    pub required_in_hub: Vec3,
    /// What the actuators give the hub (`−Σ g u` or `Σ a τ`; without the wheels' gyroscopic
    /// reaction), N·m, hub components.
    pub applied_in_hub: Vec3,
    /// Per actuator, its effort after its limits, N·m.
    pub efforts: Vec<f64>,
    /// Per wheel: speed relative to the hub Ω, rad/s.
    pub wheel_speeds: Vec<f64>,
    /// Per wheel: spin momentum `h = J_s (g·ω + Ω)`, N·m·s.
    pub wheel_momenta: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wheels(axes: &[Vec3]) -> Actuators {
        Actuators::Wheels(
            axes.iter()
                .enumerate()
                .map(|(k, a)| Wheel {
                    name: format!("w{k}"),
                    axis_in_hub: a.normalize(),
                    inertia: 0.1,
                    max_torque: 0.2,
                    max_momentum: f64::INFINITY,
                    speed: 0.0,
                })
                .collect(),
        )
    }

    /// Four wheels in a pyramid give the hub exactly the torque asked (`−G (−G⁺ L) = L`)
    /// within their limits, and clip beyond them.
    #[test]
    fn pyramid_gives_the_torque_asked() {
        let s = 1.0 / 3f64.sqrt();
        let axes = [Vec3::new(s, s, s), Vec3::new(-s, s, s), Vec3::new(-s, -s, s), Vec3::new(s, -s, s)];
        let c = Control::new(Law::MrpPd { k: 1.0, p: 1.0 }, [1.0, 0.0, 0.0, 0.0], wheels(&axes), None).unwrap();
        let l = Vec3::new(0.01, -0.02, 0.03);
        let (u, cut) = c.allocate(&l);
        assert!(cut.iter().all(|c| !c));
        assert!((c.hub_torque(&u) - l).norm() < 1e-16);
        let (_, cut) = c.allocate(&(l * 100.0));
        assert!(cut.iter().any(|c| *c));
    }

    /// The MRP law at a small rotation φ about z: `L_z = −K tan(φ/4) − P ω_z`.
    #[test]
    fn mrp_law_small_rotation() {
        let c = Control::new(
            Law::MrpPd { k: 2.0, p: 3.0 },
            [1.0, 0.0, 0.0, 0.0],
            Actuators::Thrusters(vec![Thruster { name: "z".into(), axis_in_hub: Vec3::z(), max_torque: 1.0 }]),
            None,
        )
        .unwrap();
        let phi: f64 = 0.1;
        let q = [(phi / 2.0).cos(), 0.0, 0.0, (phi / 2.0).sin()];
        let l = c.required(&q, &Vec3::new(0.0, 0.0, 0.5));
        assert!((l.z + 2.0 * (phi / 4.0).tan() + 1.5).abs() < 1e-15);
    }
}
