//! The static description of a structure: bodies, hinges, and the spanning tree used to turn
//! relative initial conditions into body poses (docs/model.md §2).

pub mod body;
pub mod contact;
pub mod hinge;
pub mod inputs;
pub mod mesh;
pub mod rates;
pub mod shape;

pub use body::Body;
pub use hinge::{Hinge, HingeSpec, ParentFrame, Placement};
pub use shape::{MassProperties, Shape};

use crate::law::HingeLaw;
use crate::math::{Euler321, Mat3, Vec3};
use std::collections::VecDeque;
use thiserror::Error;

/// One edge of the spanning tree, in the order bodies are placed from the hub.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TreeEdge {
    /// The hinge.
    pub hinge: usize,
    /// The body already placed.
    pub from: usize,
    /// The body this edge places.
    pub to: usize,
    /// True when `to` is the hinge's parent (the edge is walked from child to parent).
    pub reversed: bool,
}

/// The structure: bodies, hinges, and a spanning tree rooted at the hub.
#[derive(Debug)]
pub struct Model {
    /// Bodies; index 0 is the hub.
    pub bodies: Vec<Body>,
    /// Hinges, tree and loop, in input order.
    pub hinges: Vec<Hinge>,
    /// Tree edges in placement order (breadth first from the hub).
    pub tree: Vec<TreeEdge>,
    /// For each hinge, whether it is a tree hinge.
    pub is_tree_hinge: Vec<bool>,
    /// Contact among the bodies with shapes, if the scenario asks for it
    /// ([`Model::enable_contact`]).
    pub contact: Option<crate::contact::ContactSet>,
    /// External loads on the bodies (crate::loads), in input order.
    pub loads: Vec<crate::loads::Load>,
    /// Hinge motors (crate::loads::motor), in input order.
    pub motors: Vec<crate::loads::motor::Motor>,
    /// Attitude or spin control of the hub (crate::loads::control). With wheels, the hub's
    /// inertia here is the spacecraft's with its wheels held less the wheels' spin
    /// inertias, `Σ J_s g gᵀ` (their spin momenta are states of their own).
    pub control: Option<crate::loads::control::Control>,
    /// Whether forces, torques and motor efforts may be set from outside the run (stepping
    /// from Python): the state then carries the work and impulse integrals even without
    /// loads.
    pub commandable: bool,
}

/// The state's integrals of the external loads, in this order: work W (J), impulse ∫ΣF dt
/// (N·s, N frame, 3), angular impulse about N's origin ∫Σ(r × F + τ) dt (N·m·s, 3), and the
/// impulse's own time integral (N·s², 3: it moves the barycenter by that over the mass).
pub const LOAD_STATES: usize = 10;

/// What is wrong with a model, and which body or hinge it concerns.
#[derive(Debug, Error, Clone, PartialEq)]
#[error("{message}")]
pub struct ModelError {
    /// Human-readable description naming the body or hinge and what would be valid.
    pub message: String,
    /// Index of the body concerned, if any.
    pub body: Option<usize>,
    /// Index of the hinge concerned, if any.
    pub hinge: Option<usize>,
}

impl ModelError {
    pub(crate) fn body(body: usize, message: String) -> Self {
        Self { message, body: Some(body), hinge: None }
    }
    fn hinge(hinge: usize, message: String) -> Self {
        Self { message, body: None, hinge: Some(hinge) }
    }
}
impl Model {
    /// Builds a model: checks the hinge graph, finds the spanning tree and assembles every
    /// `Assembled` A0 frame.
    ///
    /// The tree takes, in order: first the hinges listed in `preferred` (those a scenario
    /// gives initial values for; they must not close a loop among themselves), then the
    /// other hinges with a given A0 in input order. Assembled hinges are never tree hinges.
    pub fn new(bodies: Vec<Body>, specs: Vec<HingeSpec>, preferred: &[usize]) -> Result<Self, ModelError> {
        let nb = bodies.len();
        if nb == 0 {
            return Err(ModelError {
                message: "a model needs at least one body (the hub)".into(),
                body: None,
                hinge: None,
            });
        }
        for (h, s) in specs.iter().enumerate() {
            if s.parent >= nb || s.child >= nb {
                return Err(ModelError::hinge(h, format!("hinge '{}': body index out of range", s.name)));
            }
            if s.parent == s.child {
                return Err(ModelError::hinge(
                    h,
                    format!(
                        "hinge '{}' joins body '{}' to itself; parent and child must differ",
                        s.name, bodies[s.parent].name
                    ),
                ));
            }
            if s.child == 0 {
                return Err(ModelError::hinge(
                    h,
                    format!(
                        "hinge '{}' has the hub '{}' as its child; the hub must be a parent (swap parent and child and their frames)",
                        s.name, bodies[0].name
                    ),
                ));
            }
        }

        // Spanning tree by union-find over preferred, then given-A0 hinges (Kruskal order).
        let mut root: Vec<usize> = (0..nb).collect();
        fn find(root: &mut [usize], mut i: usize) -> usize {
            while root[i] != i {
                root[i] = root[root[i]];
                i = root[i];
            }
            i
        }
        let mut is_tree = vec![false; specs.len()];
        for &h in preferred {
            let s = &specs[h];
            if s.parent_frame == ParentFrame::Assembled {
                return Err(ModelError::hinge(
                    h,
                    format!(
                        "hinge '{}' has an assembled A0 and so is a loop hinge; it takes no initial values",
                        s.name
                    ),
                ));
            }
            let (a, b) = (find(&mut root, s.parent), find(&mut root, s.child));
            if a == b {
                return Err(ModelError::hinge(
                    h,
                    format!(
                        "hinge '{}' closes a loop with other hinges that have initial values; give initial values only for hinges that form a tree (the loop hinge's state follows from the bodies)",
                        s.name
                    ),
                ));
            }
            root[a] = b;
            is_tree[h] = true;
        }
        for (h, s) in specs.iter().enumerate() {
            if is_tree[h] || s.parent_frame == ParentFrame::Assembled {
                continue;
            }
            let (a, b) = (find(&mut root, s.parent), find(&mut root, s.child));
            if a != b {
                root[a] = b;
                is_tree[h] = true;
            }
        }
        let hub_root = find(&mut root, 0);
        for i in 1..nb {
            if find(&mut root, i) != hub_root {
                let through_assembled =
                    specs.iter().any(|s| s.parent_frame == ParentFrame::Assembled && (s.parent == i || s.child == i));
                let hint = if through_assembled {
                    " except through assembled hinges, which cannot be tree hinges; give one of them an explicit A0"
                } else {
                    "; add a hinge that connects it"
                };
                return Err(ModelError::body(
                    i,
                    format!("body '{}' is not connected to the hub '{}'{hint}", bodies[i].name, bodies[0].name),
                ));
            }
        }

        // Breadth-first placement order over tree hinges.
        let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for (h, s) in specs.iter().enumerate() {
            if is_tree[h] {
                adjacency[s.parent].push(h);
                adjacency[s.child].push(h);
            }
        }
        let mut placed = vec![false; nb];
        placed[0] = true;
        let mut queue = VecDeque::from([0usize]);
        let mut tree = Vec::with_capacity(nb.saturating_sub(1));
        while let Some(b) = queue.pop_front() {
            for &h in &adjacency[b] {
                let s = &specs[h];
                let (to, reversed) = if s.parent == b { (s.child, false) } else { (s.parent, true) };
                if !placed[to] {
                    placed[to] = true;
                    tree.push(TreeEdge { hinge: h, from: b, to, reversed });
                    queue.push_back(to);
                }
            }
        }

        let mut hinges: Vec<Hinge> = specs
            .into_iter()
            .map(|s| {
                let (r_a0_in_parent, dcm_a0_parent, assembled) = match s.parent_frame {
                    ParentFrame::Given { r_a0_in_parent, dcm_a0_parent } => (r_a0_in_parent, dcm_a0_parent, false),
                    ParentFrame::Assembled => (Vec3::zeros(), Mat3::identity(), true),
                };
                Hinge {
                    r_a_in_child: -(s.dcm_child_a * s.r_child_in_a),
                    dcm_parent_a0: dcm_a0_parent.transpose(),
                    name: s.name,
                    parent: s.parent,
                    child: s.child,
                    r_a0_in_parent,
                    dcm_a0_parent,
                    r_child_in_a: s.r_child_in_a,
                    dcm_child_a: s.dcm_child_a,
                    law: s.law,
                    assembled,
                }
            })
            .collect();

        // The laws were allocated among the scenario parser's data; copies made now, in hinge
        // order, lie together in memory, which the right-hand side's one pass over the
        // hinges reads as a stream (on a 4096-panel grid this is the difference between
        // the laws' data coming from cache or not).
        let laws: Vec<Box<dyn HingeLaw>> = hinges.iter().map(|h| h.law.clone_box()).collect();
        for (h, law) in hinges.iter_mut().zip(laws) {
            h.law = law;
        }
        let mut model = Model {
            bodies,
            hinges: Vec::new(),
            tree,
            is_tree_hinge: is_tree,
            contact: None,
            loads: Vec::new(),
            motors: Vec::new(),
            control: None,
            commandable: false,
        };
        // Assemble A0 frames at zero tree coordinates (docs/model.md §2).
        if hinges.iter().any(|h| h.assembled) {
            std::mem::swap(&mut model.hinges, &mut hinges);
            let poses = model.zero_configuration();
            for h in model.hinges.iter_mut().filter(|h| h.assembled) {
                let (r_p, dcm_n_p) = poses[h.parent];
                let (r_c, dcm_n_c) = poses[h.child];
                let r_a = r_c + dcm_n_c * h.r_a_in_child;
                let dcm_n_a = dcm_n_c * h.dcm_child_a;
                h.r_a0_in_parent = dcm_n_p.transpose() * (r_a - r_p);
                h.dcm_a0_parent = dcm_n_a.transpose() * dcm_n_p;
                h.dcm_parent_a0 = h.dcm_a0_parent.transpose();
            }
        } else {
            model.hinges = hinges;
        }
        Ok(model)
    }

    /// Body poses `(R_i in N, [N i])` with the hub at the origin, unrotated, and every tree
    /// coordinate zero.
    pub fn zero_configuration(&self) -> Vec<(Vec3, Mat3)> {
        let mut poses = vec![(Vec3::zeros(), Mat3::identity()); self.bodies.len()];
        for e in &self.tree {
            let h = &self.hinges[e.hinge];
            let placed = h.place(e.reversed, poses[e.from], &Euler321::default().to_dcm(), &Vec3::zeros());
            poses[e.to] = (placed.r_in_n, placed.dcm_n_b);
        }
        poses
    }

    /// The states after the bodies' (crate::state): one dissipated energy per hinge, then
    /// one for contact when it is on, then, when anything does work on the structure from
    /// outside it ([`Model::has_work`]), the integrals of its effect ([`LOAD_STATES`]: work,
    /// impulse, angular impulse, the impulse's time integral), then one spin momentum per
    /// reaction wheel.
    pub fn energy_states(&self) -> usize {
        self.hinges.len()
            + usize::from(self.contact.is_some())
            + if self.has_work() { LOAD_STATES } else { 0 }
            + self.wheel_count()
    }

    /// Whether anything does work on the structure from outside its hinges and contacts:
    /// external loads, motors, the hub's control, or commands from outside the run.
    pub fn has_work(&self) -> bool {
        !self.loads.is_empty() || !self.motors.is_empty() || self.control.is_some() || self.commandable
    }

    /// Whether anything external changes the momenta: loads, torque sources, commands.
    pub fn has_external(&self) -> bool {
        !self.loads.is_empty()
            || self.commandable
            || self
                .control
                .as_ref()
                .is_some_and(|c| matches!(c.actuators, crate::loads::control::Actuators::Thrusters(_)))
    }

    /// Number of reaction wheels.
    pub fn wheel_count(&self) -> usize {
        self.control.as_ref().map_or(0, |c| c.wheels().len())
    }

    /// Where the work W is (then the other [`LOAD_STATES`]) among the states after the
    /// bodies', if the model has it.
    pub fn work_offset(&self) -> Option<usize> {
        self.has_work().then(|| self.hinges.len() + usize::from(self.contact.is_some()))
    }

    /// Where the first wheel's spin momentum is (the others follow) among the states after
    /// the bodies'.
    pub fn wheel_offset(&self) -> usize {
        self.energy_states() - self.wheel_count()
    }

    /// Total mass, kg.
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    /// Index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// Index of the hinge with this name.
    pub fn hinge_index(&self, name: &str) -> Option<usize> {
        self.hinges.iter().position(|h| h.name == name)
    }
}
