//! The motors and the hub's control seen from the dynamics (crate::loads::motor,
//! crate::loads::control): their efforts at a state, the commands held between the control's
//! samples, commands set from outside the run, and when the actuators saturated.

use super::Dynamics;
use crate::law::{HingeState, HingeWrench};
use crate::loads::control::Reading;
use crate::loads::{Load, LoadFrame, Profile, Vector};
use crate::math::{Real, Vec3, quat_angle, quat_relative};
use crate::state::{BODY_STATE_LEN, OMEGA, QUAT};
use nalgebra::Vector3;

/// What one actuator of the hub's control did over the run (at accepted steps): its largest
/// effort and momentum, and when its limits cut it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ActuatorRecord {
    /// The largest |effort| after the limits, N·m.
    pub effort_max: f64,
    /// A wheel's largest momentum relative to the hub, `|J_s Ω|`, N·m·s (0 for a torque
    /// source).
    pub momentum_max: f64,
    /// The first time its torque limit cut the command, s.
    pub torque_first: Option<f64>,
    /// How long its torque limit cut the command, s (steps that ended cut).
    pub torque_time: f64,
    /// The first time a wheel's momentum limit cut its torque, s.
    pub momentum_first: Option<f64>,
    /// How long the momentum limit cut it, s.
    pub momentum_time: f64,
}

/// The actuators' per-run memory.
#[derive(Clone, Debug, Default)]
pub struct ActuatorMemory {
    /// Sampled control: the law's torque and the efforts held since the last sample.
    held: Option<(Vec3, Vec<f64>, Vec<bool>)>,
    /// The next sample time, s.
    next_sample: f64,
    /// Commands from outside the run: per motor an effort replacing its drive.
    pub(crate) motor_commands: Vec<Option<f64>>,
    /// Commands from outside the run: the actuators' efforts, replacing the law's.
    pub(crate) actuator_commands: Option<Vec<f64>>,
    /// Per actuator, its saturation over the run.
    pub(crate) record: Vec<ActuatorRecord>,
    /// The time of the last accepted state, s.
    last_accept: f64,
}

/// The hub's actuation at a state.
#[derive(Clone, Debug, Default)]
pub(super) struct Actuated {
    /// The law's torque L, N·m, hub components.
    pub(super) required: Vec3,
    /// Per actuator, its effort after every limit, N·m.
    pub(super) efforts: Vec<f64>,
    /// Per actuator, whether its torque limit cut it.
    torque_cut: Vec<bool>,
    /// Per actuator, whether a wheel's momentum limit cut it.
    momentum_cut: Vec<bool>,
}

impl Dynamics<'_> {
    /// The motors' wrench on hinge `i` in state `s` at time `t` (restoring convention,
    /// crate::loads::motor) and their power, W; `None` without motors on it.
    pub(super) fn motor_wrench<T: Real>(&self, i: usize, s: &HingeState<T>, t: f64) -> Option<(HingeWrench<T>, T)> {
        let list = &self.motors_of_hinge[i];
        if list.is_empty() {
            return None;
        }
        let memory = self.actuators.borrow();
        let zero = Vector3::zeros();
        let mut sum = (HingeWrench { force_in_a0: zero, torque_in_a: zero }, T::zero());
        for &m in list {
            let command = memory.motor_commands.get(m).copied().flatten();
            let (w, _, power) = self.model.motors[m].apply(t, s, command);
            sum.0.force_in_a0 += w.force_in_a0;
            sum.0.torque_in_a += w.torque_in_a;
            sum.1 += power;
        }
        Some(sum)
    }

    /// The hub's actuation at state `y` (time as last set): the law's torque, the efforts
    /// after every limit, and per actuator whether a torque or a momentum limit cut it.
    /// `None` without control.
    pub(super) fn actuation(&self, y: &[f64]) -> Option<Actuated> {
        let c = self.model.control.as_ref()?;
        let s = &y[..BODY_STATE_LEN];
        let omega = Vec3::new(s[OMEGA], s[OMEGA + 1], s[OMEGA + 2]);
        let memory = self.actuators.borrow();
        let (required, mut efforts, torque_cut) = match (&memory.actuator_commands, &memory.held) {
            (Some(u), _) => {
                let (u, cut) = c.clip(u);
                (Vec3::zeros(), u, cut)
            }
            (None, Some((l, u, cut))) => (*l, u.clone(), cut.clone()),
            (None, None) => {
                let l = c.required(&s[QUAT..QUAT + 4], &omega);
                let (u, cut) = c.allocate(&l);
                (l, u, cut)
            }
        };
        let w = crate::state::wheel_index(self.model);
        let momentum_cut = c.limit_momentum(&mut efforts, &y[w..w + c.wheels().len()], &omega);
        Some(Actuated { required, efforts, torque_cut, momentum_cut })
    }

    /// The hub's control torque as a function of its own state `hub` (13 numbers, dual for
    /// the Jacobian), N·m, hub components: the actuators' torque less the wheels' gyroscopic
    /// reaction `ω × Σ g h`, the wheel momenta `wheel_h` held. Held and outside commands are
    /// constants; the continuous law is differentiated through.
    pub(super) fn control_torque<T: Real>(&self, hub: &[T], wheel_h: &[f64]) -> Option<Vector3<T>> {
        let c = self.model.control.as_ref()?;
        let omega = Vector3::new(hub[OMEGA], hub[OMEGA + 1], hub[OMEGA + 2]);
        let memory = self.actuators.borrow();
        let mut efforts: Vec<T> = match (&memory.actuator_commands, &memory.held) {
            (Some(u), _) => c.clip(u).0.iter().map(|x| crate::math::real(*x)).collect(),
            (None, Some((_, u, _))) => u.iter().map(|x| crate::math::real(*x)).collect(),
            (None, None) => c.allocate(&c.required(&hub[QUAT..QUAT + 4], &omega)).0,
        };
        c.limit_momentum(&mut efforts, wheel_h, &omega);
        let gh = c.wheel_momentum_in_hub(wheel_h).map(crate::math::real::<T>);
        Some(c.hub_torque(&efforts) - omega.cross(&gh))
    }

    /// Starts the actuators' memory at the initial state: no commands from outside, the
    /// control's first sample taken (when it samples), no saturation.
    pub(super) fn start_actuators(&self, y: &[f64]) {
        let n = self.model.control.as_ref().map_or(0, |c| c.actuator_count());
        *self.actuators.borrow_mut() = ActuatorMemory {
            motor_commands: vec![None; self.model.motors.len()],
            record: vec![ActuatorRecord::default(); n],
            ..Default::default()
        };
        self.sample_control(0.0, y);
    }

    /// Takes the control's sample at `t` if one is due (sampled control only).
    fn sample_control(&self, t: f64, y: &[f64]) {
        let Some(c) = &self.model.control else { return };
        let Some(period) = c.period else { return };
        let mut memory = self.actuators.borrow_mut();
        if memory.held.is_some() && t < memory.next_sample - 1e-9 * period {
            return;
        }
        let s = &y[..BODY_STATE_LEN];
        let omega = Vec3::new(s[OMEGA], s[OMEGA + 1], s[OMEGA + 2]);
        let l = c.required(&s[QUAT..QUAT + 4], &omega);
        let (u, cut) = c.allocate(&l);
        memory.held = Some((l, u, cut));
        memory.next_sample = ((t / period + 1e-9).floor() + 1.0) * period;
    }

    /// At an accepted state: the saturation record over the step, then the control's sample
    /// if one is due.
    pub(super) fn accept_actuators(&self, t: f64, y: &[f64]) {
        if let (Some(c), Some(Actuated { efforts, torque_cut, momentum_cut, .. })) =
            (&self.model.control, self.actuation(y))
        {
            let omega = Vec3::new(y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]);
            let w = crate::state::wheel_index(self.model);
            let mut memory = self.actuators.borrow_mut();
            let dt = t - memory.last_accept;
            for (k, s) in memory.record.iter_mut().enumerate() {
                s.effort_max = s.effort_max.max(efforts[k].abs());
                if let Some(wheel) = c.wheels().get(k) {
                    let speed = crate::loads::control::Control::wheel_speed(wheel, y[w + k], &omega);
                    s.momentum_max = s.momentum_max.max((wheel.inertia * speed).abs());
                }
            }
            for ((s, tc), mc) in memory.record.iter_mut().zip(torque_cut).zip(momentum_cut) {
                if tc {
                    s.torque_first.get_or_insert(t);
                    s.torque_time += dt;
                }
                if mc {
                    s.momentum_first.get_or_insert(t);
                    s.momentum_time += dt;
                }
            }
            memory.last_accept = t;
        }
        self.sample_control(t, y);
    }

    /// What the motors and the control do at time `t` (s) and state `y`: an output row's
    /// columns. `None` without motors or control.
    pub fn actuator_reading(&self, t: f64, y: &[f64]) -> Option<Reading> {
        let model = self.model;
        if model.motors.is_empty() && model.control.is_none() {
            return None;
        }
        // A row at a sample instant shows what acts from that instant: the new sample (taken
        // here from the row's state if the step's acceptance has not taken it yet; the same
        // sample, at the same time and state).
        self.sample_control(t, y);
        let refs = self.theta_refs();
        let memory = self.actuators.borrow();
        let motor_efforts = model
            .motors
            .iter()
            .enumerate()
            .map(|(m, motor)| {
                let k = self.kinematics_at(motor.hinge, y, &refs);
                motor.effort(t, &k.state, memory.motor_commands.get(m).copied().flatten())
            })
            .collect();
        drop(memory);
        let mut reading = Reading { motor_efforts, pointing_error: f64::NAN, ..Default::default() };
        if let (Some(c), Some(Actuated { required, efforts, .. })) = (&model.control, self.actuation(y)) {
            let s = &y[..BODY_STATE_LEN];
            let q = &s[QUAT..QUAT + 4];
            let omega = Vec3::new(s[OMEGA], s[OMEGA + 1], s[OMEGA + 2]);
            reading.sigma_hub = crate::math::mrp_from_quat(&quat_relative(q, &[1.0, 0.0, 0.0, 0.0]));
            if matches!(
                c.law,
                crate::loads::control::Law::MrpPd { .. } | crate::loads::control::Law::QuaternionPd { .. }
            ) {
                reading.pointing_error = quat_angle(&quat_relative(q, &c.target));
            }
            reading.required_in_hub = required;
            reading.applied_in_hub = c.hub_torque(&efforts);
            reading.efforts = efforts;
            let w = crate::state::wheel_index(model);
            reading.wheel_momenta = y[w..w + c.wheels().len()].to_vec();
            reading.wheel_speeds = c
                .wheels()
                .iter()
                .zip(&reading.wheel_momenta)
                .map(|(wh, h)| crate::loads::control::Control::wheel_speed(wh, *h, &omega))
                .collect();
        }
        Some(reading)
    }

    /// Sets the wheels' spin momenta in the initial state `y` from their initial speeds
    /// relative to the hub: `h = J_s (g·ω + Ω₀)`.
    pub fn set_initial_wheels(&self, y: &mut [f64]) {
        let Some(c) = &self.model.control else { return };
        let omega = Vec3::new(y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]);
        let w = crate::state::wheel_index(self.model);
        for (k, wheel) in c.wheels().iter().enumerate() {
            y[w + k] = wheel.inertia * (wheel.axis_in_hub.dot(&omega) + wheel.speed);
        }
    }

    /// Per actuator of the hub's control, what it did over the run.
    pub fn actuator_records(&self) -> Vec<ActuatorRecord> {
        self.actuators.borrow().record.clone()
    }

    /// Sets the torque a body receives from outside the run (N·m, in `frame`), replacing
    /// the torque set before; it acts like a `[[load]]` until changed. Fails unless the
    /// model is [`crate::model::Model::commandable`] (its state must carry the work).
    pub fn command_torque(&self, body: usize, torque: Vec3, frame: LoadFrame) -> Result<(), String> {
        self.commanded_load(body, |l| {
            l.torque = Some(Vector { profile: Profile::Constant(torque), frame });
        })
    }

    /// Sets the force a body receives from outside the run (N, in `frame`) at a point of it
    /// (m from its centre of mass, body frame), replacing the force set before.
    pub fn command_force(&self, body: usize, force: Vec3, point_in_body: Vec3, frame: LoadFrame) -> Result<(), String> {
        self.commanded_load(body, |l| {
            l.force = Some(Vector { profile: Profile::Constant(force), frame });
            l.point_in_body = point_in_body;
        })
    }

    fn commanded_load(&self, body: usize, change: impl FnOnce(&mut Load)) -> Result<(), String> {
        if !self.model.commandable {
            return Err("this run was not started for commands (Model::commandable)".into());
        }
        if body >= self.model.bodies.len() {
            return Err(format!("no body {body}: the model has {}", self.model.bodies.len()));
        }
        let mut loads = self.commanded.borrow_mut();
        let k = match loads.iter().position(|l| l.body == body) {
            Some(k) => k,
            None => {
                loads.push(Load {
                    name: format!("command on '{}'", self.model.bodies[body].name),
                    body,
                    point_in_body: Vec3::zeros(),
                    force: None,
                    torque: None,
                    windows: Vec::new(),
                });
                loads.len() - 1
            }
        };
        change(&mut loads[k]);
        Ok(())
    }

    /// Sets motor `motor`'s effort from outside the run (N or N·m), replacing its drive;
    /// `None` gives it back to its drive.
    pub fn command_motor(&self, motor: usize, effort: Option<f64>) -> Result<(), String> {
        let mut memory = self.actuators.borrow_mut();
        let slot = memory.motor_commands.get_mut(motor).ok_or_else(|| format!("no motor {motor}"))?;
        *slot = effort;
        Ok(())
    }

    /// Sets the control's actuator efforts from outside the run (wheel motor torques or
    /// torque sources', N·m, one per actuator), replacing the law's; `None` gives them back
    /// to the law. The actuators' torque limits still apply (and are recorded).
    pub fn command_actuators(&self, efforts: Option<Vec<f64>>) -> Result<(), String> {
        let Some(c) = &self.model.control else { return Err("the scenario has no [control]".into()) };
        let efforts = match efforts {
            Some(u) if u.len() != c.actuator_count() => {
                return Err(format!(
                    "{} values for {} actuators ({})",
                    u.len(),
                    c.actuator_count(),
                    c.actuator_names().join(", ")
                ));
            }
            Some(u) => Some(u),
            None => None,
        };
        self.actuators.borrow_mut().actuator_commands = efforts;
        Ok(())
    }
}
