//! A folded sheet as a scenario: rigid panels (polygons of nodes) known in two states, the
//! deployed design and the stowed configuration, joined by a hinge on every crease (an edge
//! two panels share). Whatever pattern the nodes come from (a flasher, a Miura sheet), the
//! scenario is built the same way:
//!
//! - every panel is a body whose frame has its origin at the panel's centroid, its z axis along
//!   the panel's normal and its x axis in its plane, away from every edge (so no crease is
//!   along it; the hub keeps the sheet's axes when it lies in the xy plane); its
//!   shape is the polygon (with the sheet's thickness) and its mass follows from the areal
//!   density; panel 0 is the hub, with the mass and inertia given;
//! - every crease is a hinge whose A0 and A frames coincide in the deployed state (so the
//!   deployed design is stress-free), with their origin at the crease's midpoint (or, for
//!   thick panels, moved across the crease onto the line about which the stowed fold is a
//!   pure turn: [`HingeAxes`]) and their
//!   z axis along the crease, so a fold is a yaw, far from the 3-2-1 singularity even near
//!   180°; hinges of a spanning tree from the hub take the stowed state as their initial
//!   values; the others close loops, with their A0 assembled in the deployed design;
//! - the stowed pose of a panel is the rigid motion that best carries its deployed nodes to
//!   its stowed ones (least squares; exact when the panel is rigid in the pattern), and how far
//!   a node is off it is reported: panels that must bend to stow carry strain.

use super::cuts::{cut_corners, tip_cuts};
use super::params::RunText;
use crate::math::{Euler321, Mat3, Vec3};
use crate::model::Shape;
use std::collections::{BTreeMap, VecDeque};
use std::f64::consts::PI;
use std::fmt::Write;

/// A sheet: node positions in both states and its panels.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    /// Node positions in the deployed design, m.
    pub deployed: Vec<Vec3>,
    /// The same nodes in the stowed configuration, m.
    pub stowed: Vec<Vec3>,
    /// Panels: the nodes round each, in order; panel 0 is the hub.
    pub panels: Vec<Vec<usize>>,
    /// Which way creases fold, keyed by (lower node, higher node). Needed where a crease is
    /// folded flat (±180°) when stowed, which the two states alone cannot tell apart; where
    /// given for other creases it is checked.
    pub senses: BTreeMap<(usize, usize), Sense>,
    /// Per panel, a translation added to its stowed pose, m (thick panels stacked in layers);
    /// empty for none.
    pub stowed_offsets: Vec<Vec3>,
    /// With thick panels, the hub's height, m: the hub is then a solid prism over its polygon
    /// on the top side of the sheet (its mass from the hub mass, its inertia from the shape);
    /// 0 for a hub with the given mass and inertia and no shape.
    pub hub_height: f64,
}

/// Which way a crease folds, seen from the sheet's top (the side its deployed panels' normals
/// point to).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    /// The top sides turn away from each other.
    Mountain,
    /// The top sides turn towards each other.
    Valley,
}

/// How close to a half turn a stowed fold is taken as folded flat, rad: its sign is then the
/// crease's sense, not round-off.
const FLAT_FOLD: f64 = 1e-6;

/// A hinge's stowed state: its fold and how far it is off its fold axis.
#[derive(Clone, Debug, PartialEq)]
pub struct HingeStrain {
    /// The hinge's name.
    pub hinge: String,
    /// Stowed fold angle, the yaw of `[A A0]`, rad.
    pub fold: f64,
    /// Stowed δ, A0 components, m.
    pub delta: Vec3,
    /// Stowed pitch and roll of `[A A0]` (rotations off the fold axis), rad.
    pub pitch: f64,
    /// See `pitch`.
    pub roll: f64,
    /// How far the fold axis was moved off the crease's midpoint, m, A0 components (x across
    /// the crease in the parent's plane, y the parent's normal; [`HingeAxes`]).
    pub axis_shift: Vec3,
}

impl HingeStrain {
    /// The largest of |δ| (m), |pitch| and |roll| (rad).
    pub fn off_axis(&self) -> f64 {
        self.delta.norm().max(self.pitch.abs()).max(self.roll.abs())
    }
}

pub use super::crease::CreaseLaw;
use super::crease::{FoldStop, LEAST_STOPPED_FOLD};

/// What a sheet is made of and how its scenario runs.
#[derive(Clone, Debug, PartialEq)]
pub struct SheetParams {
    /// Title of the scenario.
    pub title: String,
    /// Mass per unit area of the panels, kg/m².
    pub areal_density: f64,
    /// Panel thickness, m (≥ 0; mass properties only).
    pub thickness: f64,
    /// Where each hinge's fold axis lies (thickness accommodation; docs/flasher.md).
    pub hinge_axes: HingeAxes,
    /// Hub mass, kg.
    pub hub_mass: f64,
    /// Hub principal inertia about its centroid in its frame (x along its first edge, z its
    /// normal), kg·m².
    pub hub_inertia: [f64; 3],
    /// Initial hub spin about its z axis, rev/min.
    pub spin_rpm: f64,
    /// The `[run]` table.
    pub run: RunText,
}

/// Where a hinge's fold axis lies across its crease.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HingeAxes {
    /// Each axis moved off the crease, in the plane across it, to the one line about which a
    /// pure turn by the stowed fold carries the child from its deployed to its stowed place
    /// relative to the parent ("hinge shift", Lang et al., Appl. Mech. Rev. 70:010805, 2018,
    /// §4): both states free of hinge strain with thick panels. With zero thickness the
    /// line is the crease.
    #[default]
    Shifted,
    /// Every axis on its crease, in the panels' mid-plane: thick panels' stowed layer offsets
    /// are then taken up by stretching the hinges.
    MidPlane,
}

impl HingeAxes {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Shifted => "shifted",
            Self::MidPlane => "mid-plane",
        }
    }
}

/// Below this |det(I − R)| (a fold within ~1e-4 rad of flat) no axis is moved: a turn that
/// small cannot carry an offset, m-free.
const LEAST_TURN_FOR_SHIFT: f64 = 1e-8;

/// The point `c` (m, A0 components, in A0's x-y plane across the crease) about which the
/// stowed turn `r` = [A0 A] carries the stowed offset `d` (A's origin from A0's, A0
/// components, both taken at the crease's midpoint): moving both frames' origins to `c`
/// changes δ by `(R − I) c` (rigid panels), so `(I − R) c = d` in the plane across the fold
/// axis z. Zero where the fold is too small to carry an offset.
fn hinge_shift(d: &Vec3, r: &Mat3) -> Vec3 {
    let (a, b, c, e) = (1.0 - r[(0, 0)], -r[(0, 1)], -r[(1, 0)], 1.0 - r[(1, 1)]);
    let det = a * e - b * c;
    if d.norm() == 0.0 || det.abs() < LEAST_TURN_FOR_SHIFT {
        return Vec3::zeros();
    }
    Vec3::new((e * d.x - b * d.y) / det, (a * d.y - c * d.x) / det, 0.0)
}

/// What the builder found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SheetReport {
    /// Panels (the hub included) and hinges.
    pub panels: usize,
    /// Hinges, one per crease.
    pub hinges: usize,
    /// Independent loops: hinges − panels + 1.
    pub loops: usize,
    /// The largest relative difference of an edge's length between the two states.
    pub edge_mismatch: f64,
    /// The largest distance of a stowed node from its panel's rigid stowed pose, m: zero for
    /// panels that stow without bending.
    pub panel_strain: f64,
    /// Per hinge, its stowed fold and strain.
    pub strains: Vec<HingeStrain>,
    /// Per hinge given a stop at flat (thick panels, shifted axes): its name and the stop.
    pub stops: Vec<(String, FoldStop)>,
}

/// A panel's body frame in one state: `(centroid, [N body])`.
type Pose = (Vec3, Mat3);

/// The rigid motion `(R, t)` that best carries points `a` onto `b` (Kabsch, by SVD).
fn fit(a: &[Vec3], b: &[Vec3]) -> (Mat3, Vec3) {
    let ca = a.iter().sum::<Vec3>() / a.len() as f64;
    let cb = b.iter().sum::<Vec3>() / b.len() as f64;
    let h: Mat3 = a.iter().zip(b).map(|(p, q)| (q - cb) * (p - ca).transpose()).sum();
    let svd = h.svd(true, true);
    let (u, vt) = (svd.u.expect("u"), svd.v_t.expect("v"));
    let d = (u * vt).determinant().signum();
    let r = u * Mat3::from_diagonal(&Vec3::new(1.0, 1.0, d)) * vt;
    (r, cb - r * ca)
}

/// A panel's body x axis: of the directions in its plane at 5° steps from its first edge, the
/// one furthest from every edge. A crease along the child's x axis would put `θ_{c/A}` at
/// pitch ±90°, where 3-2-1 angles cannot be recovered from the frame (docs/model.md §7).
fn body_x(polygon: &[Vec3], normal: &Vec3) -> Vec3 {
    let e1 = (polygon[1] - polygon[0]).normalize();
    let e2 = normal.cross(&e1);
    let edges: Vec<Vec3> =
        (0..polygon.len()).map(|i| (polygon[(i + 1) % polygon.len()] - polygon[i]).normalize()).collect();
    let worst = |u: &Vec3| edges.iter().map(|e| e.dot(u).abs()).fold(0.0, f64::max);
    (0..36)
        .map(|k| {
            let phi = (5.0 * k as f64).to_radians();
            phi.cos() * e1 + phi.sin() * e2
        })
        .min_by(|a, b| worst(a).total_cmp(&worst(b)))
        .expect("36 candidates")
}

/// Builds the scenario text of `sheet`, with `law(a, b)` the law of the crease between nodes
/// a and b. Fails naming the panel or crease if the sheet is not a connected set of simple
/// planar panels, each edge shared by at most two of them.
pub fn sheet_scenario(
    sheet: &Sheet,
    law: impl Fn(usize, usize) -> CreaseLaw,
    p: &SheetParams,
) -> Result<(String, SheetReport), String> {
    let (dep, sto) = (&sheet.deployed, &sheet.stowed);
    if dep.len() != sto.len() {
        return Err(format!("{} deployed nodes but {} stowed ones", dep.len(), sto.len()));
    }
    if sheet.panels.len() < 2 {
        return Err("a sheet needs a hub and at least one panel".into());
    }
    // Panels: their deployed frames, shapes in their frames, and stowed poses.
    let mut deployed_pose: Vec<Pose> = Vec::new();
    let mut stowed_pose: Vec<Pose> = Vec::new();
    let mut local: Vec<Vec<Vec3>> = Vec::new();
    let mut masses = Vec::new();
    let mut report = SheetReport::default();
    let cuts = if p.thickness > 0.0 { tip_cuts(&sheet.panels, dep, 0.5 * p.thickness) } else { BTreeMap::new() };
    for (k, nodes) in sheet.panels.iter().enumerate() {
        if nodes.len() < 3 || nodes.iter().any(|&n| n >= dep.len()) {
            return Err(format!("panel {k}: needs 3 or more nodes of the sheet"));
        }
        let world: Vec<Vec3> = nodes.iter().map(|&n| dep[n]).collect();
        // A thick panel's corners are cut back at the pattern's vertices (`tip_cuts`); the
        // hub keeps its polygon.
        let outline = if k > 0 && !cuts.is_empty() { cut_corners(nodes, dep, &cuts) } else { world.clone() };
        let shape = Shape::Plate { vertices: outline.clone(), thickness: p.thickness };
        shape.check().map_err(|m| format!("panel {k}: {m}"))?;
        let centroid = shape.mass_properties(1.0).centroid;
        // A panel's mass properties (about its centroid, so in any frame there translated);
        // the hub's are not needed (it is taken as not turning at a stop).
        masses.push(shape.mass_properties(p.areal_density));
        let normal = (0..world.len())
            .map(|i| (world[i] - world[0]).cross(&(world[(i + 1) % world.len()] - world[0])))
            .sum::<Vec3>()
            .normalize();
        let frame = if k == 0 && (normal - Vec3::z()).norm() < 1e-12 {
            // The hub keeps the sheet's axes, so N is the sheet's frame.
            Mat3::identity()
        } else {
            let u = body_x(&world, &normal);
            Mat3::from_columns(&[u, normal.cross(&u), normal])
        };
        local.push(outline.iter().map(|x| frame.transpose() * (x - centroid)).collect());
        let stowed: Vec<Vec3> = nodes.iter().map(|&n| sto[n]).collect();
        let (r, t) = fit(&world, &stowed);
        for (x, s) in world.iter().zip(&stowed) {
            report.panel_strain = report.panel_strain.max((r * x + t - s).norm());
        }
        let offset = sheet.stowed_offsets.get(k).copied().unwrap_or_else(Vec3::zeros);
        // A hub prism's centre of mass is half its height above the sheet.
        let centroid = if k == 0 { centroid + frame.column(2) * (0.5 * sheet.hub_height) } else { centroid };
        deployed_pose.push((centroid, frame));
        stowed_pose.push((r * centroid + t + offset, r * frame));
    }
    // Creases: edges two panels share (key: the edge's nodes, lower first; value: the panels).
    let mut edges: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (k, nodes) in sheet.panels.iter().enumerate() {
        for i in 0..nodes.len() {
            let (a, b) = (nodes[i], nodes[(i + 1) % nodes.len()]);
            edges.entry((a.min(b), a.max(b))).or_default().push(k);
            let (ld, ls) = ((dep[a] - dep[b]).norm(), (sto[a] - sto[b]).norm());
            report.edge_mismatch = report.edge_mismatch.max((ld - ls).abs() / ld);
        }
    }
    let mut creases = Vec::new();
    for ((a, b), sides) in &edges {
        match sides.len() {
            1 => {}
            2 => creases.push((*a, *b, sides[0], sides[1])),
            _ => {
                return Err(format!(
                    "the edge from node {a} to node {b} is shared by {} panels; at most 2",
                    sides.len()
                ));
            }
        }
    }
    // Breadth-first over the creases from the hub: the tree, and each panel's place in it.
    let mut order = vec![usize::MAX; sheet.panels.len()];
    order[0] = 0;
    let mut queue = VecDeque::from([0]);
    let mut next = 1;
    let mut tree = vec![false; creases.len()];
    let mut by_panel = vec![Vec::new(); sheet.panels.len()];
    for (c, &(_, _, p1, p2)) in creases.iter().enumerate() {
        by_panel[p1].push(c);
        by_panel[p2].push(c);
    }
    while let Some(k) = queue.pop_front() {
        for &c in &by_panel[k] {
            let (_, _, p1, p2) = creases[c];
            let other = if p1 == k { p2 } else { p1 };
            if order[other] == usize::MAX {
                order[other] = next;
                next += 1;
                tree[c] = true;
                queue.push_back(other);
            }
        }
    }
    if let Some(k) = order.iter().position(|&o| o == usize::MAX) {
        return Err(format!("panel {k} shares no crease with the rest of the sheet"));
    }
    report.panels = sheet.panels.len();
    report.hinges = creases.len();
    report.loops = creases.len() + 1 - sheet.panels.len();

    let name = |k: usize| if k == 0 { "hub".to_string() } else { format!("p{k}") };
    let mut out = String::new();
    super::params::title_and_run(&mut out, &p.title, &p.run);
    for (k, vertices) in local.iter().enumerate() {
        let polygon: Vec<String> = vertices.iter().map(|v| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)).collect();
        let _ = writeln!(out, "[[body]]\nname = \"{}\"", name(k));
        if k == 0 && sheet.hub_height > 0.0 {
            // The prism over the hub's polygon (its local vertices are in the plane through
            // its centre of mass), mass per unit area so that its mass is the hub's.
            let area = 0.5
                * (0..vertices.len())
                    .map(|i| {
                        let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
                        a.x * b.y - b.x * a.y
                    })
                    .sum::<f64>()
                    .abs();
            let _ = writeln!(
                out,
                "shape = {{ polygon = [{}], thickness = {:?} }}\ndensity = {:?}\n",
                polygon.join(", "),
                sheet.hub_height,
                p.hub_mass / area
            );
        } else if k == 0 {
            let [a, b, c] = p.hub_inertia;
            let _ = writeln!(out, "mass = {:?}\ninertia = [{a:?}, {b:?}, {c:?}]\n", p.hub_mass);
        } else {
            let _ = writeln!(
                out,
                "shape = {{ polygon = [{}], thickness = {:?} }}\ndensity = {:?}\n",
                polygon.join(", "),
                p.thickness,
                p.areal_density
            );
        }
    }
    let mut initial = String::new();
    for (c, &(a, b, p1, p2)) in creases.iter().enumerate() {
        let (parent, child) = if order[p1] < order[p2] { (p1, p2) } else { (p2, p1) };
        // A0 = A in the deployed design: origin at the crease's midpoint (moved across it by
        // `axis_shift`), z along it, y the
        // parent's normal, x = y × z in its plane. Then [A0 p] is a yaw and a 90° roll, far
        // from the 3-2-1 singularity its angles would meet with z in the plane otherwise.
        let (cp, rp) = deployed_pose[parent];
        let (cc, rc) = deployed_pose[child];
        let mid = 0.5 * (dep[a] + dep[b]);
        let z = (dep[b] - dep[a]).normalize();
        let x = rp.column(2).cross(&z).normalize();
        let frame = Mat3::from_columns(&[x, z.cross(&x), z]);
        // The stowed state of the hinge: A0 and A in N, and δ (A0 components) with both
        // frames' origins at the deployed point `q`, from the two panels' stowed poses.
        let (sp, rps) = stowed_pose[parent];
        let (sc, rcs) = stowed_pose[child];
        let a0_n = rps * rp.transpose() * frame;
        let a_n = rcs * rc.transpose() * frame;
        let delta_at = |q: Vec3| {
            a0_n.transpose() * ((sc + rcs * (rc.transpose() * (q - cc))) - (sp + rps * (rp.transpose() * (q - cp))))
        };
        let axis_shift = match p.hinge_axes {
            HingeAxes::Shifted => hinge_shift(&delta_at(mid), &(a0_n.transpose() * a_n)),
            HingeAxes::MidPlane => Vec3::zeros(),
        };
        let origin = mid + frame * axis_shift;
        let r_a0_in_parent = rp.transpose() * (origin - cp);
        let theta_a0_p = Euler321::from_dcm(&(frame.transpose() * rp));
        let child_com = frame.transpose() * (cc - origin);
        let theta_c_a = Euler321::from_dcm(&(rc.transpose() * frame));
        let hname = format!("h{c}_{}_{}", name(parent), name(child));
        let l = law(a, b);
        let a0 = if tree[c] {
            format!(
                "{{ position = [{:?}, {:?}, {:?}], yaw = {:?}, pitch = {:?}, roll = {:?} }}",
                r_a0_in_parent.x, r_a0_in_parent.y, r_a0_in_parent.z, theta_a0_p.yaw, theta_a0_p.pitch, theta_a0_p.roll
            )
        } else {
            "\"assembled\"".to_string()
        };
        let mut theta = Euler321::from_dcm(&(a_n.transpose() * a0_n));
        let delta = delta_at(origin);
        if let Some(&sense) = sheet.senses.get(&(a, b)) {
            // Valley: the child turns towards the parent's top, A0's y axis (docs/flasher.md).
            let side = frame.column(0).dot(&(cc - mid)).signum();
            let want = if sense == Sense::Valley { side } else { -side };
            if theta.yaw.signum() != want && theta.yaw.abs() > PI - FLAT_FOLD {
                theta.yaw += 2.0 * PI * want;
            } else if theta.yaw.signum() != want && theta.yaw.abs() > FLAT_FOLD {
                return Err(format!(
                    "the crease from node {a} to node {b} is a {sense:?} but the stowed state folds it the other way, by {:.6}°",
                    theta.yaw.to_degrees()
                ));
            }
        }
        // A thick crease whose axis is shifted off its mid-plane folds one way only: its
        // panels' edges meet at flat (docs/flasher.md, Thick panels), a stop there.
        let stop = (p.thickness > 0.0
            && p.hinge_axes == HingeAxes::Shifted
            && l.k_stop > 0.0
            && theta.yaw.abs() > LEAST_STOPPED_FOLD)
            .then(|| {
                let about = |k: usize| {
                    let (centre, dcm) = &deployed_pose[k];
                    (k > 0).then(|| {
                        let m = &masses[k];
                        crate::math::inertia_about_line(m.mass, &m.inertia_about_centroid, (centre, dcm), &origin, &z)
                    })
                };
                FoldStop::new(l.k_stop, theta.yaw, [about(parent), about(child)])
            });
        if let Some(stop) = stop {
            report.stops.push((hname.clone(), stop));
        }
        // The two panels' reduced mass (kg; the hub's is its mass), for a membrane's damping.
        let mass = |k: usize| if k == 0 { p.hub_mass } else { masses[k].mass };
        let reduced_mass = mass(parent) * mass(child) / (mass(parent) + mass(child));
        let _ = writeln!(
            out,
            "[[hinge]]\nname = \"{hname}\"\nparent = \"{}\"\nchild = \"{}\"\na0 = {a0}\na = {{ child_com = [{:?}, {:?}, {:?}], yaw = {:?}, pitch = {:?}, roll = {:?} }}\n{}\n",
            name(parent),
            name(child),
            child_com.x,
            child_com.y,
            child_com.z,
            theta_c_a.yaw,
            theta_c_a.pitch,
            theta_c_a.roll,
            l.text(stop.as_ref(), (dep[b] - dep[a]).norm(), reduced_mass),
        );
        report.strains.push(HingeStrain {
            hinge: hname.clone(),
            fold: theta.yaw,
            delta,
            pitch: theta.pitch,
            roll: theta.roll,
            axis_shift,
        });
        if !tree[c] && theta.yaw.abs() > PI - FLAT_FOLD {
            let _ = writeln!(
                initial,
                "[initial.loop.{hname}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\n",
                theta.yaw, theta.pitch, theta.roll
            );
        }
        if tree[c] {
            let _ = writeln!(
                initial,
                "[initial.hinge.{hname}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\ndelta = [{:?}, {:?}, {:?}]\n",
                theta.yaw, theta.pitch, theta.roll, delta.x, delta.y, delta.z
            );
        }
    }
    // The hub's stowed pose in the scenario's N, which is the hub's deployed frame (the hub
    // sits at N's origin, unrotated, at zero coordinates): [B N] = R_sᵀ R_0.
    let (hub_c, hub_r) = stowed_pose[0];
    let (hub_c0, hub_r0) = deployed_pose[0];
    let hub_attitude = Euler321::from_dcm(&(hub_r.transpose() * hub_r0));
    let hub_position = hub_r0.transpose() * (hub_c - hub_c0);
    let _ = writeln!(
        out,
        "[initial.hub]\nposition = [{:?}, {:?}, {:?}]\nyaw = {:?}\npitch = {:?}\nroll = {:?}\nomega_rpm = [0.0, 0.0, {:?}]\n",
        hub_position.x,
        hub_position.y,
        hub_position.z,
        hub_attitude.yaw,
        hub_attitude.pitch,
        hub_attitude.roll,
        p.spin_rpm
    );
    out.push_str(&initial);
    Ok((out, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::initial_state;
    use crate::scenario::Scenario;
    use crate::state::BodyMotion;

    fn params() -> SheetParams {
        SheetParams {
            title: "test sheet".into(),
            areal_density: 2.0,
            thickness: 0.01,
            hinge_axes: HingeAxes::Shifted,
            hub_mass: 50.0,
            hub_inertia: [10.0, 10.0, 18.0],
            spin_rpm: 0.0,
            run: RunText { duration: 1.0, output_step: 0.1, tolerance: 1e-9, ..Default::default() },
        }
    }

    const LAW: CreaseLaw = CreaseLaw {
        k_translation: 1e5,
        k_rotation: 1e3,
        k_fold: 1.0,
        c_fold: 0.0,
        c_translation: 0.0,
        c_rotation: 0.0,
        k_stop: 0.0,
        membrane: None,
    };

    /// Every hinge of `s` is closed at the state `y`: δ, pitch and roll within round-off
    /// (1e-12 m, rad).
    fn assert_closed(s: &Scenario, y: &[f64]) {
        let refs = vec![Euler321::default(); s.model.hinges.len()];
        for (i, h) in s.model.hinges.iter().enumerate() {
            let k = crate::kinematics::hinge_kinematics(
                h,
                &BodyMotion::from_state(y, h.parent),
                &BodyMotion::from_state(y, h.child),
                &refs[i],
            );
            assert!(k.state.delta_in_a0.norm() < 1e-12, "{}: δ = {}", h.name, k.state.delta_in_a0);
            assert!(k.state.theta.pitch.abs() < 1e-12 && k.state.theta.roll.abs() < 1e-12, "{}", h.name);
        }
    }

    /// A square sheet of four panels round a vertex (one loop), folded by 120° about the
    /// y axis: the two creases on it fold, the two on the x axis stay flat, and the loop
    /// closes in both states.
    fn folded_square() -> Sheet {
        let grid = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        let deployed = vec![
            grid(0.0, 0.0),
            grid(1.0, 0.0),
            grid(1.0, 1.0),
            grid(0.0, 1.0),
            grid(-1.0, 1.0),
            grid(-1.0, 0.0),
            grid(-1.0, -1.0),
            grid(0.0, -1.0),
            grid(1.0, -1.0),
        ];
        // The x < 0 half turns by 120° about the y axis.
        let turn = Euler321::new(0.0, 120f64.to_radians(), 0.0).to_dcm().transpose();
        let stowed = deployed.iter().map(|p| if p.x < 0.0 { turn * p } else { *p }).collect();
        let panels = vec![vec![0, 1, 2, 3], vec![0, 3, 4, 5], vec![0, 5, 6, 7], vec![0, 7, 8, 1]];
        Sheet { deployed, stowed, panels, senses: BTreeMap::new(), stowed_offsets: Vec::new(), hub_height: 0.0 }
    }

    /// The scenario starts exactly in the stowed state: every panel's centroid where the
    /// stowed nodes put it, the loop hinge closed there (δ = 0, folded 0° or ±120° about its
    /// z axis), and the deployed design at zero coordinates is stress-free. Tolerances are
    /// round-off (1e-12 m, rad): both states are exact by construction.
    #[test]
    fn a_folded_square_starts_stowed_and_rests_deployed() {
        let sheet = folded_square();
        let (text, report) = sheet_scenario(&sheet, |_, _| LAW, &params()).expect("built");
        assert_eq!((report.panels, report.hinges, report.loops), (4, 4, 1));
        assert!(report.edge_mismatch < 1e-15 && report.panel_strain < 1e-14, "{report:?}");
        let mut folds: Vec<f64> = report.strains.iter().map(|f| f.fold.abs().to_degrees()).collect();
        folds.sort_by(f64::total_cmp);
        assert!(
            folds[0] < 1e-9 && folds[1] < 1e-9 && (folds[2] - 120.0).abs() < 1e-9 && (folds[3] - 120.0).abs() < 1e-9,
            "{folds:?}"
        );
        assert!(report.strains.iter().all(|f| f.off_axis() < 1e-12), "{report:?}");
        let s = Scenario::from_toml(&text, "sheet").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let (y, _) = initial_state(&s.model, &s.initial);
        // Centroids against the stowed nodes' panels (the hub stays at the origin).
        let hub_c0 = Vec3::new(0.5, 0.5, 0.0);
        for (k, nodes) in sheet.panels.iter().enumerate() {
            let stowed_centroid = nodes.iter().map(|&n| sheet.stowed[n]).sum::<Vec3>() / 4.0 - hub_c0;
            let r = BodyMotion::from_state(&y, k).r_in_n;
            assert!((r - stowed_centroid).norm() < 1e-12, "panel {k}: {r} vs {stowed_centroid}");
        }
        // Every hinge, the loop one included, is closed in the stowed state.
        assert_closed(&s, &y);
        // Released, the stored fold energy opens the sheet, conserving E (law 2 undamped):
        // to 1e-8 relative at rtol 1e-9 over 1 s, where frames off by round-off would leave
        // the loop preloaded and a wrong one would make it ring.
        let mut energy = Vec::new();
        let mut folds = Vec::new();
        let mut sink = |o: &crate::observe::Observation| -> Result<(), String> {
            energy.push(o.energy());
            folds.push(o.hinge_theta.iter().map(|t| t.yaw.abs()).fold(0.0, f64::max));
            Ok(())
        };
        crate::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).expect("runs");
        let e0 = energy[0];
        assert!(e0 > 0.1, "the folds store energy: {e0} J");
        let drift = energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
        assert!(drift < 1e-8 * e0, "E drifts by {drift:e} J of {e0} J");
        assert!(folds.last().unwrap() < &folds[0], "the sheet opens: {folds:?}");
    }

    /// Thick panels offset when stowed (the x < 0 half also moved by `o`, across the fold
    /// axis y, as a layer is): with the axes shifted every hinge is closed in the stowed state
    /// (δ, pitch and roll within round-off, 1e-12) though the panels sit offset, the two
    /// folded creases' axes moved, the flat ones not; in the mid-plane the folded hinges are
    /// stretched by the offset (|δ| of the order of |o|, well above 1e-3 m).
    #[test]
    fn shifted_axes_take_a_stowed_offset_without_strain() {
        let o = Vec3::new(0.013, 0.0, 0.021);
        let mut sheet = folded_square();
        sheet.stowed_offsets =
            sheet.panels.iter().map(|n| if sheet.deployed[n[2]].x < 0.0 { o } else { Vec3::zeros() }).collect();
        let (text, report) = sheet_scenario(&sheet, |_, _| LAW, &params()).expect("built");
        assert!(report.strains.iter().all(|f| f.off_axis() < 1e-12), "{report:?}");
        let moved: Vec<f64> = report.strains.iter().map(|f| f.axis_shift.norm()).collect();
        assert_eq!(moved.iter().filter(|&&m| m > 1e-3).count(), 2, "{moved:?}");
        assert_eq!(moved.iter().filter(|&&m| m == 0.0).count(), 2, "{moved:?}");
        let s = Scenario::from_toml(&text, "sheet").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let (y, _) = initial_state(&s.model, &s.initial);
        assert_closed(&s, &y);
        let mid = SheetParams { hinge_axes: HingeAxes::MidPlane, ..params() };
        let (_, report) = sheet_scenario(&sheet, |_, _| LAW, &mid).expect("built");
        let stretched = report.strains.iter().map(|f| f.delta.norm()).fold(0.0, f64::max);
        assert!(stretched > 1e-3, "{stretched}");
        assert!(report.strains.iter().all(|f| f.axis_shift == Vec3::zeros()));
    }

    /// `hinge_shift` solves `(I − R) c = d` across the axis: a turn by θ about the shifted
    /// line carries the crease's point by d (to 1e-15 relative), for folds from 1° to 180°
    /// either way; a flat fold moves nothing.
    #[test]
    fn the_shift_is_the_turns_fixed_line() {
        let d = Vec3::new(-0.0563, 0.0125, 0.0);
        for deg in [1.0, 60.0, -90.0, 179.0, 180.0, -180.0] {
            let r = Euler321::new(f64::to_radians(deg), 0.0, 0.0).to_dcm().transpose();
            let c = hinge_shift(&d, &r);
            let moved = c - r * c;
            assert!((moved - d).norm() < 1e-15 * c.norm().max(1.0), "{deg}°: {moved} vs {d}");
        }
        assert_eq!(hinge_shift(&d, &Mat3::identity()), Vec3::zeros());
    }

    #[test]
    fn bad_sheets_are_refused() {
        let mut s = folded_square();
        s.panels.push(vec![0, 1, 8]);
        s.panels.push(vec![0, 8, 1]);
        assert!(sheet_scenario(&s, |_, _| LAW, &params()).unwrap_err().contains("panels; at most 2"));
        let mut s = folded_square();
        s.deployed.push(Vec3::new(5.0, 5.0, 0.0));
        s.stowed.push(Vec3::new(5.0, 5.0, 0.0));
        s.deployed.push(Vec3::new(6.0, 5.0, 0.0));
        s.stowed.push(Vec3::new(6.0, 5.0, 0.0));
        s.deployed.push(Vec3::new(6.0, 6.0, 0.0));
        s.stowed.push(Vec3::new(6.0, 6.0, 0.0));
        s.panels.push(vec![9, 10, 11]);
        assert!(sheet_scenario(&s, |_, _| LAW, &params()).unwrap_err().contains("panel 4 shares no crease"));
    }
}
