//! A model's inputs by name (crate::model::inputs) with the values last set, turned into a
//! stepped run's commands: a body's three force or torque inputs make one vector in its
//! frame, the actuators one command for all. The C library, the FMU (through
//! [`super::Session`]) and the Python package's `Simulation.set_input` set inputs here.

use crate::loads::LoadFrame;
use crate::math::Vec3;
use crate::model::Model;
use crate::model::inputs::{Input, InputKind, inputs};
use crate::simulate::Stepper;

/// Every input of a model, with its value as last set (0 until set), in its unit.
#[derive(Clone, Debug)]
pub struct Inputs {
    list: Vec<Input>,
    values: Vec<f64>,
}

impl Inputs {
    /// Every input `model` takes: forces and torques on every body, motors, actuators.
    pub fn of(model: &Model) -> Self {
        let all: Vec<usize> = (0..model.bodies.len()).collect();
        let list = inputs(model, &all);
        let values = vec![0.0; list.len()];
        Self { list, values }
    }

    /// The inputs, in index order.
    pub fn list(&self) -> &[Input] {
        &self.list
    }

    /// Input `index`'s value as last set.
    pub fn value(&self, index: usize) -> Option<f64> {
        self.values.get(index).copied()
    }

    /// The input named `name`'s index; the error names some valid ones.
    pub fn index(&self, name: &str) -> Result<usize, String> {
        self.list.iter().position(|i| i.name == name).ok_or_else(|| {
            let some: Vec<&str> = self.list.iter().take(8).map(|i| i.name.as_str()).collect();
            format!(
                "no input {name:?}: inputs are <body>_F_x … <body>_T_z (body frame), <motor>_effort, <actuator>_torque, here {}{}",
                some.join(", "),
                if self.list.len() > 8 { ", …" } else { "" }
            )
        })
    }

    /// Sets input `index` to `value` and commands `stepper` from now on: the body's whole
    /// force or torque (its frame, at its centre of mass) from its three inputs' values, the
    /// motor's effort, or every actuator's torque. Refused: an index out of range, a value
    /// that is not finite.
    pub fn set(&mut self, stepper: &mut Stepper, index: usize, value: f64) -> Result<(), String> {
        let Some(input) = self.list.get(index) else {
            return Err(format!("input index {index} is out of range: there are {} inputs", self.list.len()));
        };
        if !value.is_finite() {
            return Err(format!(
                "input {}: the value must be a finite number ({}), got {value}",
                input.name,
                input.unit()
            ));
        }
        let kind = input.kind;
        self.values[index] = value;
        let pairs = || self.list.iter().zip(&self.values);
        match kind {
            InputKind::Force { body, .. } | InputKind::Torque { body, .. } => {
                let torque = matches!(kind, InputKind::Torque { .. });
                let mut v = Vec3::zeros();
                for (i, x) in pairs() {
                    match i.kind {
                        InputKind::Force { body: b, axis } if b == body && !torque => v[axis] = *x,
                        InputKind::Torque { body: b, axis } if b == body && torque => v[axis] = *x,
                        _ => {}
                    }
                }
                if torque {
                    stepper.set_torque(body, v, LoadFrame::Body)
                } else {
                    stepper.set_force(body, v, Vec3::zeros(), LoadFrame::Body)
                }
            }
            InputKind::Motor(m) => stepper.set_motor(m, Some(value)),
            InputKind::Actuator(_) => {
                let u = pairs().filter(|(i, _)| matches!(i.kind, InputKind::Actuator(_))).map(|(_, v)| *v);
                stepper.set_actuators(Some(u.collect()))
            }
        }
    }
}
