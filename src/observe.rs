//! The outputs of MODEL.md §5, computed from a state, and their CSV column names.

use crate::kinematics::hinge_kinematics;
use crate::law::LawMemory;
use crate::math::{Euler321, Vec3};
use crate::model::Model;
use crate::state::BodyMotion;

/// Every quantity of MODEL.md §5 at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    /// Time, s.
    pub t: f64,
    /// Hub CoM `R_{B/N}`, m, N components.
    pub hub_r_in_n: Vec3,
    /// `ᴮR_{B/N} = [BN] R_{B/N}`, m, hub components.
    pub hub_r_in_hub: Vec3,
    /// `θ_{B/N}`, continuous in time (yaw and roll unwrapped), rad.
    pub hub_theta: Euler321,
    /// Per hinge: δ, m, A0 components.
    pub hinge_delta_in_a0: Vec<Vec3>,
    /// Per hinge: `θ_{A/A0}`, continuous in time, rad.
    pub hinge_theta: Vec<Euler321>,
    /// Per body: CoM `R_i`, m, N components.
    pub body_r_in_n: Vec<Vec3>,
    /// Per body: `θ_{i/N}`, principal values, rad.
    pub body_theta: Vec<Euler321>,
    /// Barycenter `Σ m_i R_i / Σ m_i`, m, N components.
    pub barycenter_in_n: Vec3,
    /// Linear momentum `Σ m_i Ṙ_i`, kg·m/s, N components.
    pub momentum_in_n: Vec3,
    /// Angular momentum about N's origin, kg·m²/s, N components.
    pub angular_momentum_in_n: Vec3,
    /// Kinetic energy T, J.
    pub kinetic_energy: f64,
    /// Hinge energy V (MODEL.md §4; not a potential for law 1), J.
    pub hinge_energy: f64,
    /// Per hinge: energy dissipated since the start, J (∫ dissipation power dt).
    pub hinge_dissipated: Vec<f64>,
    /// Scale of linear momentum `Σ m_i |Ṙ_i|`, kg·m/s, for relative drift figures.
    pub momentum_scale: f64,
    /// Scale of angular momentum `Σ (|R_i × m_i Ṙ_i| + |I_i ω_i|)`, kg·m²/s.
    pub angular_momentum_scale: f64,
}

impl Observation {
    /// Total energy `E = T + V`, J.
    pub fn energy(&self) -> f64 {
        self.kinetic_energy + self.hinge_energy
    }

    /// Energy dissipated by all hinges since the start, J; `E + D` is constant.
    pub fn dissipated(&self) -> f64 {
        self.hinge_dissipated.iter().sum()
    }
}

/// Computes observations, keeping the hub's continuous-angle reference between calls.
#[derive(Clone, Debug)]
pub struct Observer {
    hub_theta_ref: Euler321,
}

impl Observer {
    /// An observer whose hub angles start near `hub_theta` (the initial condition).
    pub fn new(hub_theta: Euler321) -> Self {
        Self { hub_theta_ref: hub_theta }
    }

    /// Every output of MODEL.md §5 at time `t` for state `y` (bodies, then per-hinge
    /// dissipated energy), with hinge angles continuous near `theta_refs` and the laws'
    /// `memories`. Calls must come in time order for the hub angles to stay continuous.
    pub fn observe(
        &mut self,
        model: &Model,
        t: f64,
        y: &[f64],
        theta_refs: &[Euler321],
        memories: &[LawMemory],
    ) -> Observation {
        let motions: Vec<BodyMotion> = (0..model.bodies.len()).map(|i| BodyMotion::from_state(y, i)).collect();
        let hub = &motions[0];
        let hub_theta = Euler321::from_dcm(&hub.dcm_n_b.transpose()).unwrapped_near(&self.hub_theta_ref);
        self.hub_theta_ref = hub_theta;

        let mut hinge_delta_in_a0 = Vec::with_capacity(model.hinges.len());
        let mut hinge_theta = Vec::with_capacity(model.hinges.len());
        let mut hinge_energy = 0.0;
        for ((h, r), m) in model.hinges.iter().zip(theta_refs).zip(memories) {
            let k = hinge_kinematics(h, &motions[h.parent], &motions[h.child], r);
            hinge_delta_in_a0.push(k.state.delta_in_a0);
            hinge_theta.push(k.state.theta);
            hinge_energy += h.law.stored_energy(&k.state, m);
        }
        let d0 = crate::state::BODY_STATE_LEN * model.bodies.len();
        let hinge_dissipated =
            y.get(d0..d0 + model.hinges.len()).map_or_else(|| vec![0.0; model.hinges.len()], <[f64]>::to_vec);

        let mut mass_moment = Vec3::zeros();
        let mut momentum = Vec3::zeros();
        let mut angular = Vec3::zeros();
        let (mut kinetic, mut p_scale, mut h_scale) = (0.0, 0.0, 0.0);
        for (b, m) in model.bodies.iter().zip(&motions) {
            let w_b = m.omega_in_body();
            let iw_b = b.inertia_in_body * w_b;
            let p = m.v_in_n * b.mass;
            let orbital = m.r_in_n.cross(&p);
            let spin = m.dcm_n_b * iw_b;
            mass_moment += m.r_in_n * b.mass;
            momentum += p;
            angular += orbital + spin;
            kinetic += 0.5 * b.mass * m.v_in_n.norm_squared() + 0.5 * w_b.dot(&iw_b);
            p_scale += p.norm();
            h_scale += orbital.norm() + spin.norm();
        }
        Observation {
            t,
            hub_r_in_n: hub.r_in_n,
            hub_r_in_hub: hub.dcm_n_b.transpose() * hub.r_in_n,
            hub_theta,
            hinge_delta_in_a0,
            hinge_theta,
            body_r_in_n: motions.iter().map(|m| m.r_in_n).collect(),
            body_theta: motions.iter().map(|m| Euler321::from_dcm(&m.dcm_n_b.transpose())).collect(),
            barycenter_in_n: mass_moment / model.total_mass(),
            momentum_in_n: momentum,
            angular_momentum_in_n: angular,
            kinetic_energy: kinetic,
            hinge_energy,
            hinge_dissipated,
            momentum_scale: p_scale,
            angular_momentum_scale: h_scale,
        }
    }
}

/// CSV column names for a model, in the order of [`row`] (names as in
/// `../shared/reference/README.md`).
pub fn columns(model: &Model) -> Vec<String> {
    let mut c: Vec<String> = vec!["t".into()];
    let xyz = |c: &mut Vec<String>, p: &str| c.extend(["x", "y", "z"].map(|a| format!("{p}_{a}")));
    let ypr = |c: &mut Vec<String>, p: &str| c.extend(["yaw", "pitch", "roll"].map(|a| format!("{p}_{a}")));
    xyz(&mut c, "R_B");
    xyz(&mut c, "BR_B");
    ypr(&mut c, "theta_B");
    for h in &model.hinges {
        xyz(&mut c, &format!("{}_delta", h.name));
        ypr(&mut c, &h.name);
    }
    for b in &model.bodies {
        xyz(&mut c, &format!("{}_R", b.name));
        ypr(&mut c, &b.name);
    }
    xyz(&mut c, "Rc");
    xyz(&mut c, "P");
    xyz(&mut c, "H");
    c.extend(["T", "V", "E", "D"].map(String::from));
    c
}

/// The values of an observation in the order of [`columns`].
pub fn row(o: &Observation) -> Vec<f64> {
    let mut r = vec![o.t];
    let v = |r: &mut Vec<f64>, x: &Vec3| r.extend_from_slice(x.as_slice());
    let a = |r: &mut Vec<f64>, e: &Euler321| r.extend_from_slice(&[e.yaw, e.pitch, e.roll]);
    v(&mut r, &o.hub_r_in_n);
    v(&mut r, &o.hub_r_in_hub);
    a(&mut r, &o.hub_theta);
    for (d, t) in o.hinge_delta_in_a0.iter().zip(&o.hinge_theta) {
        v(&mut r, d);
        a(&mut r, t);
    }
    for (p, t) in o.body_r_in_n.iter().zip(&o.body_theta) {
        v(&mut r, p);
        a(&mut r, t);
    }
    v(&mut r, &o.barycenter_in_n);
    v(&mut r, &o.momentum_in_n);
    v(&mut r, &o.angular_momentum_in_n);
    r.extend_from_slice(&[o.kinetic_energy, o.hinge_energy, o.energy(), o.dissipated()]);
    r
}
