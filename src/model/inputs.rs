//! The inputs a model takes from outside a run (a user's controller, an FMU's host, a C
//! program, a Basilisk simulation): their names, as `foldsim linearize`, the C library, the
//! FMU and the Python package all name them (docs/interop.md), and what each one commands.

use super::Model;

/// What an input commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// One component (`axis` 0, 1, 2 for x, y, z) of the force on body `body`, N, in the
    /// body's own frame, at its centre of mass.
    Force {
        /// The body's index.
        body: usize,
        /// The component, 0..3.
        axis: usize,
    },
    /// One component of the torque on body `body`, N·m, in the body's own frame.
    Torque {
        /// The body's index.
        body: usize,
        /// The component, 0..3.
        axis: usize,
    },
    /// Motor `0`'s effort, N or N·m (it replaces the motor's drive once set).
    Motor(usize),
    /// The control's actuator `0` (a reaction wheel's motor torque or a torque source's),
    /// N·m (once set, every actuator is commanded from outside and the control law rests).
    Actuator(usize),
}

/// One input: its name and what it commands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// `<body>_F_x` … `<body>_T_z`, `<motor>_effort`, `<actuator>_torque`.
    pub name: String,
    /// What it sets.
    pub kind: InputKind,
}

impl Input {
    /// The input's unit: N, N·m, or "N or N·m" for a motor (by its hinge coordinate).
    pub fn unit(&self) -> &'static str {
        match self.kind {
            InputKind::Force { .. } => "N",
            InputKind::Torque { .. } | InputKind::Actuator(_) => "N.m",
            InputKind::Motor(_) => "N or N.m",
        }
    }
}

/// The inputs of `model` with forces and torques on `bodies` (indices, in that order; the hub
/// is 0): six per body (`F_x`, `F_y`, `F_z`, `T_x`, `T_y`, `T_z`), then every motor's effort,
/// then every actuator of the control.
pub fn inputs(model: &Model, bodies: &[usize]) -> Vec<Input> {
    let mut out = Vec::new();
    for &body in bodies {
        let b = &model.bodies[body].name;
        for (axis, a) in XYZ.iter().enumerate() {
            out.push(Input { name: format!("{b}_F_{a}"), kind: InputKind::Force { body, axis } });
        }
        for (axis, a) in XYZ.iter().enumerate() {
            out.push(Input { name: format!("{b}_T_{a}"), kind: InputKind::Torque { body, axis } });
        }
    }
    for (m, motor) in model.motors.iter().enumerate() {
        out.push(Input { name: format!("{}_effort", motor.name), kind: InputKind::Motor(m) });
    }
    if let Some(c) = &model.control {
        for (k, a) in c.actuator_names().iter().enumerate() {
            out.push(Input { name: format!("{a}_torque"), kind: InputKind::Actuator(k) });
        }
    }
    out
}

const XYZ: [&str; 3] = ["x", "y", "z"];
