//! The outputs of docs/model.md §5, computed from a state, and their CSV column names.

use crate::contact::ContactSummary;
use crate::kinematics::hinge_kinematics;
use crate::law::LawMemory;
use crate::math::{Euler321, Mat3, Vec3};
use crate::model::Model;
use crate::state::BodyMotion;

/// Every quantity of docs/model.md §5 at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    /// Time, s.
    pub t: f64,
    /// Hub CoM `R_{B/N}`, m, N components.
    pub hub_r_in_n: Vec3,
    /// `ᴮR_{B/N} = [BN] R_{B/N}`, m, hub components.
    pub hub_r_in_hub: Vec3,
    /// `θ_{B/N}`, continuous in time (yaw and roll unwrapped; at pitch ±90° roll keeps its
    /// last value, [`Euler321::attitude_from_dcm`]), rad.
    pub hub_theta: Euler321,
    /// The hub's attitude quaternion (Euler parameters) `β_{B/N}` = (w, x, y, z), scalar first,
    /// N to hub: its DCM is `[B N]` (Schaub & Junkins §3.5); unit, continuous in time.
    pub hub_quat: [f64; 4],
    /// `ω_{B/N}`, rad/s, hub components.
    pub hub_omega_in_hub: Vec3,
    /// Per hinge: δ, m, A0 components.
    pub hinge_delta_in_a0: Vec<Vec3>,
    /// Per hinge: `θ_{A/A0}`, continuous in time, rad.
    pub hinge_theta: Vec<Euler321>,
    /// Per hinge: δ̇, the rate of δ's A0 components, m/s.
    pub hinge_delta_rate_in_a0: Vec<Vec3>,
    /// Per hinge: `ω_{A/A0}`, rad/s, A components.
    pub hinge_omega_rel_in_a: Vec<Vec3>,
    /// Per hinge, the law's restoring force `F`, N, A0 components (the child receives −F at
    /// A's origin, the parent +F); a run asked for hinge-load columns adds the reactions of
    /// locked directions (`crate::dynamics::reactions`, `RunSettings::hinge_loads`).
    pub hinge_force_in_a0: Vec<Vec3>,
    /// Per hinge, the law's restoring torque `τ`, N·m, A components (the child receives −τ);
    /// a run asked for hinge-load columns adds the locked directions' reaction couples.
    pub hinge_torque_in_a: Vec<Vec3>,
    /// Per body: CoM `R_i`, m, N components.
    pub body_r_in_n: Vec<Vec3>,
    /// Per body: `θ_{i/N}`, principal values (roll 0 at pitch ±90°,
    /// [`Euler321::attitude_from_dcm`]), rad.
    pub body_theta: Vec<Euler321>,
    /// Per body: the attitude quaternion `β_{i/N}` = (w, x, y, z), scalar first, N to body (DCM
    /// `[i N]`), unit, continuous in time: right at every attitude, where 3-2-1 angles are not.
    pub body_quat: Vec<[f64; 4]>,
    /// Per body: CoM velocity `Ṙ_i`, m/s, N components.
    pub body_v_in_n: Vec<Vec3>,
    /// Per body: `ω_{i/N}`, rad/s, body components.
    pub body_omega_in_body: Vec<Vec3>,
    /// Barycenter `Σ m_i R_i / Σ m_i`, m, N components.
    pub barycenter_in_n: Vec3,
    /// Linear momentum `Σ m_i Ṙ_i`, kg·m/s, N components.
    pub momentum_in_n: Vec3,
    /// Angular momentum about N's origin, kg·m²/s, N components.
    pub angular_momentum_in_n: Vec3,
    /// Kinetic energy T, J.
    pub kinetic_energy: f64,
    /// Hinge energy V (docs/model.md §4; not a potential for law 1), J.
    pub hinge_energy: f64,
    /// Per hinge: energy dissipated since the start, J (∫ dissipation power dt).
    pub hinge_dissipated: Vec<f64>,
    /// Contact at this state, when the model has contact: pairs touching, the deepest
    /// penetration, the largest force, the elastic energy stored.
    pub contact: Option<ContactSummary>,
    /// Energy contact has dissipated since the start (damping and friction), J.
    pub contact_dissipated: f64,
    /// What the external loads, motors and control have given the system since the start,
    /// when the model has any (`E + D − W` is then the constant).
    pub loads: Option<LoadTotals>,
    /// What the motors and the hub's control do, when the model has any (set by the run:
    /// sampled commands are the run's memory).
    pub actuators: Option<crate::loads::control::Reading>,
    /// Per body, with contact: whether it touched another body since the previous row (at
    /// the integrator's accepted steps, or at this row). Empty without contact.
    pub touched: Vec<bool>,
    /// Scale of linear momentum `Σ m_i |Ṙ_i|`, kg·m/s, for relative drift figures.
    pub momentum_scale: f64,
    /// Scale of angular momentum `Σ (|R_i × m_i Ṙ_i| + |I_i ω_i|)`, kg·m²/s.
    pub angular_momentum_scale: f64,
    /// The hub's angular velocity about the spin axis (see [`Observer::new`]), rad/s.
    pub spin_rate: f64,
    /// The structure's moment of inertia about the spin axis through the barycenter, kg·m².
    pub inertia_about_spin_axis: f64,
    /// The largest distance of a panel (its shape's outline, or its CoM) from the spin axis
    /// through the barycenter, m.
    pub deployed_radius: f64,
    /// `deployed_radius` over the same radius in the deployed design (every tree coordinate
    /// zero); NaN for a structure without panels.
    pub deployed_fraction: f64,
}

impl Observation {
    /// Total energy `E = T + V`, J.
    pub fn energy(&self) -> f64 {
        self.kinetic_energy + self.potential_energy()
    }

    /// `V`: the hinges' energy and the energy stored in contacts, J.
    pub fn potential_energy(&self) -> f64 {
        self.hinge_energy + self.contact.map_or(0.0, |c| c.energy)
    }

    /// Energy dissipated by all hinges and contacts since the start, J; `E + D` is constant.
    pub fn dissipated(&self) -> f64 {
        self.hinge_dissipated.iter().sum::<f64>() + self.contact_dissipated
    }

    /// `W`: the work external loads have done since the start, J (0 without loads).
    pub fn work(&self) -> f64 {
        self.loads.map_or(0.0, |l| l.work)
    }
}

/// Computes observations, keeping the hub's continuous-angle reference between calls.
#[derive(Clone, Debug)]
pub struct Observer {
    hub_theta_ref: Euler321,
    /// The spin axis, a unit vector, N components.
    spin_axis_in_n: Vec3,
    /// Per body: the points whose distance from the spin axis measures the deployment (its
    /// shape's outline, or its CoM), body frame; empty for the hub.
    outline: Vec<Vec<Vec3>>,
    /// The deployed radius of the design (tree coordinates zero), m.
    design_radius: f64,
}

impl Observer {
    /// An observer of `model` whose hub angles start near `hub_theta` (the initial
    /// condition). The spin axis is fixed in N: along the initial angular momentum
    /// `h0_in_n` if it has one, else along the hub's z axis at the start. The design radius
    /// is measured in the zero configuration, about the spin axis as the hub sees it at the
    /// start, through that configuration's barycenter.
    pub fn new(model: &Model, hub_theta: Euler321, h0_in_n: &Vec3) -> Self {
        let dcm_n_hub = hub_theta.to_dcm().transpose();
        let spin_axis_in_n = if h0_in_n.norm() > 0.0 { h0_in_n.normalize() } else { dcm_n_hub * Vec3::z() };
        let outline: Vec<Vec<Vec3>> = model
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| match (i, &b.shape) {
                (0, _) => Vec::new(),
                (_, Some(s)) => s.outline(),
                (_, None) => vec![Vec3::zeros()],
            })
            .collect();
        let zero = model.zero_configuration();
        let axis_in_hub = dcm_n_hub.transpose() * spin_axis_in_n;
        let total = model.total_mass();
        let center = zero.iter().zip(&model.bodies).map(|((r, _), b)| r * b.mass).sum::<Vec3>() / total;
        let design_radius = radius(&zero, &outline, &center, &axis_in_hub);
        Self { hub_theta_ref: hub_theta, spin_axis_in_n, outline, design_radius }
    }

    /// Every output of docs/model.md §5 at time `t` for state `y` (bodies, then per-hinge
    /// dissipated energy), with hinge angles continuous near `theta_refs` and the laws'
    /// `memories`. Calls must come in time order for the hub angles to stay continuous.
    pub fn observe(
        &mut self,
        model: &Model,
        t: f64,
        y: &[f64],
        theta_refs: &[Euler321],
        memories: &[LawMemory],
        contact: Option<ContactSummary>,
    ) -> Observation {
        let motions: Vec<BodyMotion> = (0..model.bodies.len()).map(|i| BodyMotion::from_state(y, i)).collect();
        let hub = &motions[0];
        let hub_theta = Euler321::attitude_from_dcm(&hub.dcm_n_b.transpose(), self.hub_theta_ref.roll)
            .unwrapped_near(&self.hub_theta_ref);
        let body_quat: Vec<[f64; 4]> = (0..model.bodies.len()).map(|i| unit_quaternion(y, i)).collect();
        self.hub_theta_ref = hub_theta;

        let nh = model.hinges.len();
        let mut hinge_delta_in_a0 = Vec::with_capacity(nh);
        let mut hinge_theta = Vec::with_capacity(nh);
        let mut hinge_delta_rate_in_a0 = Vec::with_capacity(nh);
        let mut hinge_omega_rel_in_a = Vec::with_capacity(nh);
        let mut hinge_force_in_a0 = Vec::with_capacity(nh);
        let mut hinge_torque_in_a = Vec::with_capacity(nh);
        let mut hinge_energy = 0.0;
        for ((h, r), m) in model.hinges.iter().zip(theta_refs).zip(memories) {
            let k = hinge_kinematics(h, &motions[h.parent], &motions[h.child], r);
            hinge_delta_in_a0.push(k.state.delta_in_a0);
            hinge_theta.push(k.state.theta);
            hinge_delta_rate_in_a0.push(k.state.delta_rate_in_a0);
            hinge_omega_rel_in_a.push(k.state.omega_rel_in_a);
            let w = h.law.wrench(&k.state, m);
            hinge_force_in_a0.push(w.force_in_a0);
            hinge_torque_in_a.push(w.torque_in_a);
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
            let q = m.momenta(b.mass, &b.inertia_in_body);
            mass_moment += m.r_in_n * b.mass;
            momentum += q.linear;
            angular += q.orbital + q.spin;
            kinetic += 0.5 * b.mass * m.v_in_n.norm_squared() + 0.5 * w_b.dot(&(b.inertia_in_body * w_b));
            p_scale += q.linear.norm();
            h_scale += q.orbital.norm() + q.spin.norm();
        }
        if let Some(c) = &model.control {
            // Reaction wheels (crate::loads::control): their spin momenta join the hub's H,
            // and their energy h²/2J_s the kinetic energy (the hub's inertia lacks J_s g gᵀ).
            let w = crate::state::wheel_index(model);
            let h = &y[w..w + c.wheels().len()];
            let spin = hub.dcm_n_b * c.wheel_momentum_in_hub(h);
            angular += spin;
            h_scale += spin.norm();
            kinetic += c.wheels().iter().zip(h).map(|(wh, h)| 0.5 * h * h / wh.inertia).sum::<f64>();
        }
        let barycenter = mass_moment / model.total_mass();
        let poses: Vec<(Vec3, crate::math::Mat3)> = motions.iter().map(|m| (m.r_in_n, m.dcm_n_b)).collect();
        let deployed_radius = radius(&poses, &self.outline, &barycenter, &self.spin_axis_in_n);
        Observation {
            t,
            hub_r_in_n: hub.r_in_n,
            hub_r_in_hub: hub.dcm_n_b.transpose() * hub.r_in_n,
            hub_theta,
            hub_quat: body_quat[0],
            hub_omega_in_hub: hub.omega_in_body(),
            hinge_delta_in_a0,
            hinge_theta,
            hinge_delta_rate_in_a0,
            hinge_omega_rel_in_a,
            hinge_force_in_a0,
            hinge_torque_in_a,
            body_r_in_n: motions.iter().map(|m| m.r_in_n).collect(),
            body_theta: motions.iter().map(|m| Euler321::attitude_from_dcm(&m.dcm_n_b.transpose(), 0.0)).collect(),
            body_quat,
            body_v_in_n: motions.iter().map(|m| m.v_in_n).collect(),
            body_omega_in_body: motions.iter().map(|m| m.omega_in_body()).collect(),
            barycenter_in_n: barycenter,
            momentum_in_n: momentum,
            angular_momentum_in_n: angular,
            kinetic_energy: kinetic,
            hinge_energy,
            hinge_dissipated,
            contact,
            contact_dissipated: if model.contact.is_some() { y.get(d0 + nh).copied().unwrap_or(0.0) } else { 0.0 },
            loads: crate::state::work_index(model).map(|w| {
                let v = |k: usize| Vec3::new(y[w + k], y[w + k + 1], y[w + k + 2]);
                LoadTotals { work: y[w], impulse_in_n: v(1), angular_impulse_in_n: v(4), impulse_moment_in_n: v(7) }
            }),
            touched: Vec::new(),
            actuators: None,
            momentum_scale: p_scale,
            angular_momentum_scale: h_scale,
            spin_rate: hub.omega_in_n.dot(&self.spin_axis_in_n),
            inertia_about_spin_axis: inertia_about(model, &motions, &barycenter, &self.spin_axis_in_n),
            deployed_radius,
            deployed_fraction: if self.design_radius > 0.0 { deployed_radius / self.design_radius } else { f64::NAN },
        }
    }
}

/// Body `i`'s quaternion `q_{N←i}` from the state (w, x, y, z), normalized: the integrated
/// one, so continuous in time (no sign flips between rows).
fn unit_quaternion(y: &[f64], i: usize) -> [f64; 4] {
    let q = &y[crate::state::BODY_STATE_LEN * i + crate::state::QUAT..][..4];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// The largest distance from the axis through `center` along the unit vector `axis` of any
/// outline point of the bodies at `poses` (`(R in N, [N i])`), m.
fn radius(poses: &[(Vec3, crate::math::Mat3)], outline: &[Vec<Vec3>], center: &Vec3, axis: &Vec3) -> f64 {
    poses
        .iter()
        .zip(outline)
        .flat_map(|((r, dcm), points)| points.iter().map(move |p| r + dcm * p - center))
        .map(|d| (d - axis * d.dot(axis)).norm())
        .fold(0.0, f64::max)
}

/// The moment of inertia of the bodies at `motions` about the axis through `center` along
/// the unit vector `axis`, kg·m²: `Σ m_i |r_i⊥|² + aᵀ [N i] I_i [i N] a`.
fn inertia_about(model: &Model, motions: &[BodyMotion], center: &Vec3, axis: &Vec3) -> f64 {
    model
        .bodies
        .iter()
        .zip(motions)
        .map(|(b, m)| {
            crate::math::inertia_about_line(b.mass, &b.inertia_in_body, (&m.r_in_n, &m.dcm_n_b), center, axis)
        })
        .sum()
}

/// Whether a column name is a hinge load's (`<hinge>_F_x` … `<hinge>_M_z`; no other column
/// ends so, docs/outputs.md).
pub fn is_hinge_load(name: &str) -> bool {
    ["_F_x", "_F_y", "_F_z", "_M_x", "_M_y", "_M_z"].iter().any(|s| name.ends_with(s))
}

/// One output column.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Column {
    /// Its name in the CSV header.
    pub name: String,
    /// Whether it is written when no columns are chosen (see [`Selection`]).
    pub default: bool,
}

/// Every output column a model has, in the order of [`row`]: the default set (time, the hub's
/// pose and angular velocity, every hinge's δ, angles, δ̇ and ω_rel, every body's position
/// and angles, the barycenter, momenta and energies), and per body its velocity and angular
/// velocity, written only when chosen. Units and frames: `docs/outputs.md`.
pub fn catalogue(model: &Model) -> Vec<Column> {
    let mut c: Vec<Column> = Vec::new();
    let push = |c: &mut Vec<Column>, prefix: &str, parts: [&str; 3], default: bool| {
        c.extend(parts.map(|a| Column { name: format!("{prefix}_{a}"), default }))
    };
    const XYZ: [&str; 3] = ["x", "y", "z"];
    const YPR: [&str; 3] = ["yaw", "pitch", "roll"];
    const WXYZ: [&str; 4] = ["w", "x", "y", "z"];
    let quat = |c: &mut Vec<Column>, prefix: &str| {
        c.extend(WXYZ.map(|a| Column { name: format!("{prefix}_{a}"), default: true }))
    };
    c.push(Column { name: "t".into(), default: true });
    push(&mut c, "R_B", XYZ, true);
    push(&mut c, "BR_B", XYZ, true);
    push(&mut c, "theta_B", YPR, true);
    quat(&mut c, "q_B");
    push(&mut c, "w_B", XYZ, true);
    // The hub's MRPs for every scenario (the attitude a GNC engineer reads), not only with
    // [control].
    push(&mut c, "sigma_B", XYZ, true);
    for h in &model.hinges {
        push(&mut c, &format!("{}_delta", h.name), XYZ, true);
        push(&mut c, &h.name, YPR, true);
        push(&mut c, &format!("{}_delta_rate", h.name), XYZ, true);
        push(&mut c, &format!("{}_wrel", h.name), XYZ, true);
        push(&mut c, &format!("{}_F", h.name), XYZ, false);
        push(&mut c, &format!("{}_M", h.name), XYZ, false);
    }
    for b in &model.bodies {
        push(&mut c, &format!("{}_R", b.name), XYZ, true);
        push(&mut c, &b.name, YPR, true);
        quat(&mut c, &format!("{}_q", b.name));
        push(&mut c, &format!("{}_v", b.name), XYZ, false);
        push(&mut c, &format!("{}_w", b.name), XYZ, false);
    }
    push(&mut c, "Rc", XYZ, true);
    push(&mut c, "P", XYZ, true);
    push(&mut c, "H", XYZ, true);
    c.extend(["T", "V", "E", "D"].map(|n| Column { name: n.into(), default: true }));
    c.extend(["spin_rate", "I_spin", "radius", "deployed"].map(|n| Column { name: n.into(), default: true }));
    if model.contact.is_some() {
        c.extend(CONTACT_COLUMNS.map(|n| Column { name: n.into(), default: true }));
    }
    if model.has_work() {
        c.push(Column { name: "W".into(), default: true });
    }
    let one = |c: &mut Vec<Column>, name: String| c.push(Column { name, default: true });
    for m in &model.motors {
        one(&mut c, format!("{}_effort", m.name));
    }
    if let Some(control) = &model.control {
        one(&mut c, "pointing_error".into());
        push(&mut c, "L_req", XYZ, true);
        push(&mut c, "L", XYZ, true);
        for name in control.actuator_names() {
            one(&mut c, format!("{name}_torque"));
        }
        for w in control.wheels() {
            one(&mut c, format!("{}_speed", w.name));
            one(&mut c, format!("{}_h", w.name));
        }
    }
    c
}

/// What the external loads have given the system since the start (crate::loads).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadTotals {
    /// Work done, J.
    pub work: f64,
    /// Impulse ∫ΣF dt, N·s, N frame: what P gained.
    pub impulse_in_n: Vec3,
    /// Angular impulse about N's origin ∫Σ(r × F + τ) dt, N·m·s: what H gained.
    pub angular_impulse_in_n: Vec3,
    /// ∫ impulse dt, N·s²: the barycenter moved by this over the total mass beyond its
    /// uniform motion.
    pub impulse_moment_in_n: Vec3,
}

/// The contact columns, after the others, when the model has contact: body pairs touching,
/// deepest penetration (m), largest force between two bodies (N).
pub const CONTACT_COLUMNS: [&str; 3] = ["contacts", "penetration_max", "contact_force_max"];

/// The values of an observation in the order of [`catalogue`].
pub fn row(o: &Observation) -> Vec<f64> {
    let mut r = vec![o.t];
    let v = |r: &mut Vec<f64>, x: &Vec3| r.extend_from_slice(x.as_slice());
    let a = |r: &mut Vec<f64>, e: &Euler321| r.extend_from_slice(&[e.yaw, e.pitch, e.roll]);
    v(&mut r, &o.hub_r_in_n);
    v(&mut r, &o.hub_r_in_hub);
    a(&mut r, &o.hub_theta);
    r.extend_from_slice(&o.hub_quat);
    v(&mut r, &o.hub_omega_in_hub);
    v(&mut r, &crate::math::mrp_from_quat(&crate::math::quat_relative(&o.hub_quat, &[1.0, 0.0, 0.0, 0.0])));
    for i in 0..o.hinge_theta.len() {
        v(&mut r, &o.hinge_delta_in_a0[i]);
        a(&mut r, &o.hinge_theta[i]);
        v(&mut r, &o.hinge_delta_rate_in_a0[i]);
        v(&mut r, &o.hinge_omega_rel_in_a[i]);
        v(&mut r, &o.hinge_force_in_a0[i]);
        v(&mut r, &o.hinge_torque_in_a[i]);
    }
    for i in 0..o.body_r_in_n.len() {
        v(&mut r, &o.body_r_in_n[i]);
        a(&mut r, &o.body_theta[i]);
        r.extend_from_slice(&o.body_quat[i]);
        v(&mut r, &o.body_v_in_n[i]);
        v(&mut r, &o.body_omega_in_body[i]);
    }
    v(&mut r, &o.barycenter_in_n);
    v(&mut r, &o.momentum_in_n);
    v(&mut r, &o.angular_momentum_in_n);
    r.extend_from_slice(&[o.kinetic_energy, o.potential_energy(), o.energy(), o.dissipated()]);
    r.extend_from_slice(&[o.spin_rate, o.inertia_about_spin_axis, o.deployed_radius, o.deployed_fraction]);
    if let Some(c) = &o.contact {
        r.extend_from_slice(&[c.pairs as f64, c.deepest.0, c.force_max]);
    }
    if let Some(l) = o.loads {
        r.push(l.work);
    }
    if let Some(a) = &o.actuators {
        r.extend_from_slice(&a.motor_efforts);
        if !a.efforts.is_empty() {
            r.push(a.pointing_error);
            v(&mut r, &a.required_in_hub);
            v(&mut r, &a.applied_in_hub);
            r.extend_from_slice(&a.efforts);
            for (speed, h) in a.wheel_speeds.iter().zip(&a.wheel_momenta) {
                r.extend_from_slice(&[*speed, *h]);
            }
        }
    }
    r
}

/// Which columns of the [`catalogue`] are written: positions in it, in its order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    /// Positions in the catalogue, increasing.
    pub indices: Vec<usize>,
    /// Their names.
    pub names: Vec<String>,
}

impl Selection {
    /// Whether a hinge-load column (`<hinge>_F_*`, `<hinge>_M_*`) is among these: then a run
    /// must add the locked directions' reactions ([`crate::simulate::RunSettings::hinge_loads`]).
    pub fn has_hinge_loads(&self) -> bool {
        self.names.iter().any(|n| is_hinge_load(n))
    }

    /// The default columns.
    pub fn default_for(model: &Model) -> Self {
        Self::from_catalogue(catalogue(model), |c| c.default)
    }

    /// The columns matching any of `patterns`: names with `*` (any run of characters) and
    /// `?` (one character), or the word `default` for the default set. `t` is always
    /// written. Fails naming a pattern that matches no column.
    pub fn matching(model: &Model, patterns: &[String]) -> Result<Self, String> {
        let all = catalogue(model);
        for p in patterns {
            if p != "default" && !all.iter().any(|c| glob(p, &c.name)) {
                let near: Vec<&str> = all.iter().map(|c| c.name.as_str()).take(8).collect();
                return Err(format!(
                    "column pattern '{p}' matches no output column (columns are like {}, …; patterns take * and ?, and the word default for the default set)",
                    near.join(", ")
                ));
            }
        }
        Ok(Self::from_catalogue(all, |c| {
            c.name == "t" || patterns.iter().any(|p| if p == "default" { c.default } else { glob(p, &c.name) })
        }))
    }

    fn from_catalogue(all: Vec<Column>, keep: impl Fn(&Column) -> bool) -> Self {
        let (indices, names) = all.into_iter().enumerate().filter(|(_, c)| keep(c)).map(|(i, c)| (i, c.name)).unzip();
        Self { indices, names }
    }

    /// The selected values of a full [`row`].
    pub fn pick<'r>(&'r self, row: &'r [f64]) -> impl Iterator<Item = f64> + 'r {
        self.indices.iter().map(|&i| row[i])
    }
}

/// Whether `name` matches `pattern` (`*`: any run of characters, `?`: one character).
/// Compared byte by byte: `?` is one character for ASCII names (column names are ASCII;
/// body and hinge names matched this way should be too).
pub fn glob(pattern: &str, name: &str) -> bool {
    let (p, n) = (pattern.as_bytes(), name.as_bytes());
    // Iterative matching with backtracking to the last star.
    let (mut i, mut j, mut star, mut mark) = (0, 0, None, 0);
    while j < n.len() {
        if i < p.len() && (p[i] == b'?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == b'*' {
            star = Some(i);
            mark = j;
            i += 1;
        } else if let Some(s) = star {
            i = s + 1;
            mark += 1;
            j = mark;
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == b'*')
}

/// The whole structure's mass properties in the hub's frame at state `y`, as Basilisk's
/// `SCMassPropsMsg` gives a spacecraft's: total mass (kg), the barycenter from the hub's
/// centre of mass (m, hub components), and the inertia about the hub's centre of mass (kg·m²,
/// hub components), reaction wheels' spin inertias included (the hub's inertia as the
/// scenario gives it). Each body's inertia turned into the hub frame plus its mass at its
/// offset (the parallel-axis theorem, Schaub & Junkins, *Analytical Mechanics of Space
/// Systems*, eq. 4.25): during a deployment this is the inertia a controller should know.
pub fn mass_about_hub(model: &Model, y: &[f64]) -> (f64, Vec3, Mat3) {
    let hub = BodyMotion::from_state(y, 0);
    let dcm_b_n = hub.dcm_n_b.transpose();
    let (mut mass, mut first, mut inertia) = (0.0, Vec3::zeros(), Mat3::zeros());
    for (i, b) in model.bodies.iter().enumerate() {
        let m = BodyMotion::from_state(y, i);
        let r = dcm_b_n * (m.r_in_n - hub.r_in_n);
        let dcm_b_i = dcm_b_n * m.dcm_n_b;
        let mut own = b.inertia_in_body;
        if let (0, Some(c)) = (i, &model.control) {
            for w in c.wheels() {
                own += w.inertia * w.axis_in_hub * w.axis_in_hub.transpose();
            }
        }
        inertia +=
            dcm_b_i * own * dcm_b_i.transpose() + b.mass * (r.norm_squared() * Mat3::identity() - r * r.transpose());
        mass += b.mass;
        first += b.mass * r;
    }
    (mass, first / mass, inertia)
}
