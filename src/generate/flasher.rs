//! The flasher: a flat disc that wraps round a polygonal hub (Guest & Pellegrino, "Inextensional
//! wrapping of flat membranes", 1992; Zirbel et al., J. Mech. Des. 135:111005, 2013), built
//! stowed first and unfolded into the plane (docs/flasher.md has the derivation).
//!
//! With `N` gores (the hub a regular N-gon of circumradius `A`, side `s = 2A sin(β/2)`,
//! `β = 2π/N`) and `n` nodes per major fold (`n − 1` rings), every hub corner `H_k` starts two
//! major folds: a valley line `V_k,i` and a mountain line `M_k,i` (`i = 1…n`, both starting at
//! `H_k`). Stowed with zero thickness, the sheet lies on the side walls of the prism over the
//! hub: `V_k,i` at the foot of prism edge `k + i − 1`, `M_k,i` on the same edge at height
//! `(i − 1) Δz`. The flatness of the sheet fixes `Δz`: the sector angles round every node must
//! sum to 2π. Round a hub corner that gives `Δz = s tan(β/2)`; round `M_k,i` it asks
//! `z_{i+1} − z_i = z_i − z_{i−1}` (constant steps); round `V_k,i` it holds for any heights.
//! Unfolding the triangles into the plane, keeping their stowed edge lengths, gives the
//! deployed disc; that it closes up N-fold symmetric, flat and without overlap is checked and
//! reported, not assumed.
//!
//! Per gore the triangles are the strip between `V_k` and `M_k` (`H_k V_k,2 M_k,2`, then
//! `V_k,i V_k,i+1 M_k,i+1` and `V_k,i M_k,i+1 M_k,i`) and the region between `M_k` and `V_k+1`
//! (`H_k H_k+1 M_k,2`, then `V_k+1,i−1 V_k+1,i M_k,i` and `M_k,i V_k+1,i M_k,i+1`):
//! `N (4n − 5)` triangles.

use super::crease::Membrane;
use super::sheet::{CreaseLaw, HingeAxes, Sense, Sheet, SheetParams, SheetReport, sheet_scenario};
use crate::math::Vec3;
use std::collections::{BTreeMap, VecDeque};
use std::f64::consts::PI;

/// How the flasher's sheet is divided into rigid bodies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PanelModel {
    /// Rigid quadrilaterals, each two triangles that lie in one plane in both the stowed and
    /// the deployed state (joined across the crease that is flat in both): no stowed strain.
    Quads,
    /// Rigid quadrilaterals of one ring each (`M_k,i M_k,i+1 V_k+1,i+1 V_k+1,i`): these are
    /// bent across a prism edge when stowed, so the stowed state carries hinge strain, which
    /// the report gives.
    RingQuads,
    /// Triangles, with a bending hinge on each diagonal of the [`PanelModel::Quads`] panels
    /// (the bar-and-hinge idealisation): exact in both states.
    Triangles,
}

impl PanelModel {
    /// The model's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Quads => "quads",
            Self::RingQuads => "ring-quads",
            Self::Triangles => "triangles",
        }
    }
}

/// What kind of hinge a crease gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CreaseKind {
    /// A fold of the pattern (major folds, ring creases, the hub's edges).
    Fold,
    /// A panel's diagonal (triangle model): the hinge stands for the panel's bending.
    Diagonal,
}

/// The flasher's shape parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlasherShape {
    /// Number of gores N (hub sides), ≥ 3.
    pub gores: usize,
    /// Rings of panels, n − 1 ≥ 1 (n nodes per major fold).
    pub rings: usize,
    /// Hub circumradius A, m.
    pub hub_radius: f64,
    /// How the sheet is divided into bodies.
    pub model: PanelModel,
}

/// The geometric checks of a built flasher (lengths in m, relative where said).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlasherGeometry {
    /// Largest distance of a node from the hub's axis in the deployed disc, times 2, m.
    pub deployed_diameter: f64,
    /// Diameter of the stowed package (the prism's circumscribed circle), m.
    pub stowed_diameter: f64,
    /// Height of the stowed package, m.
    pub stowed_height: f64,
    /// Largest mismatch where the unfolding reaches a node twice (closing a loop), m.
    pub closure: f64,
    /// Largest relative difference of a triangle edge's length between the two states.
    pub edge_mismatch: f64,
    /// Largest distance of a deployed node from the hub's plane, m.
    pub flatness: f64,
    /// Largest distance between a deployed node rotated by 2π/N and its counterpart in the
    /// next gore, m.
    pub symmetry: f64,
    /// Sum of the triangles' areas over the area between the rim and the hub, minus 1: zero
    /// when the unfolded triangles tile the disc without overlap.
    pub overlap: f64,
    /// Largest distance of a stowed node from the prism's side (zero thickness), m.
    pub off_prism: f64,
}

/// A flasher: its sheet, the kind of every crease and its geometry checks.
#[derive(Clone, Debug)]
pub struct Flasher {
    /// Nodes in both states and the panels (panel 0 the hub).
    pub sheet: Sheet,
    /// Kind of every edge two panels share, keyed by (lower node, higher node).
    pub kinds: BTreeMap<(usize, usize), CreaseKind>,
    /// The checks.
    pub geometry: FlasherGeometry,
    /// Per panel (the hub first): the outward normal of the prism wall it lies in when
    /// stowed and its layer there, counted outwards from 0 (the wrap in each wall is a z-fold
    /// from the hub out: ring i's region at 2(i − 1), its strip at 2i − 1); `None` for the
    /// hub and for panels that span two walls (`ring-quads`).
    pub layers: Vec<Option<Layer>>,
}

/// A stowed panel's prism wall (its outward unit normal) and its layer there (0 innermost).
pub type Layer = (Vec3, usize);

/// Node numbering: hub corners first, then per gore `V_k,i`, `M_k,i` for i = 2…n.
struct Nodes {
    gores: usize,
    n: usize,
}

impl Nodes {
    fn hub(&self, k: usize) -> usize {
        k % self.gores
    }
    fn v(&self, k: usize, i: usize) -> usize {
        if i == 1 { self.hub(k) } else { self.gores + (k % self.gores) * 2 * (self.n - 1) + 2 * (i - 2) }
    }
    fn m(&self, k: usize, i: usize) -> usize {
        if i == 1 { self.hub(k) } else { self.v(k, i) + 1 }
    }
    fn count(&self) -> usize {
        self.gores * (1 + 2 * (self.n - 1))
    }
}

/// A triangle of the sheet and the panel it belongs to (its index among the panels).
type Triangle = [usize; 3];

/// The largest number of gores accepted: beyond it the hub's sides and the panels' aspect
/// make the geometry meaningless in double precision.
pub const MAX_GORES: usize = 1000;

/// Builds a flasher's nodes, panels and crease kinds, and checks its geometry.
pub fn flasher(shape: &FlasherShape) -> Result<Flasher, String> {
    let FlasherShape { gores, rings, hub_radius, model } = *shape;
    if !(3..=MAX_GORES).contains(&gores) {
        return Err(format!("a flasher needs 3 ≤ gores ≤ {MAX_GORES}; got {gores}"));
    }
    if rings < 1 || gores.saturating_mul(rings.saturating_mul(4)) > 4 * super::MAX_PANELS {
        return Err(format!(
            "a flasher needs rings ≥ 1 and gores × rings ≤ {} (about 2 panels per gore and ring); got {rings}",
            2 * super::MAX_PANELS
        ));
    }
    if !(hub_radius.is_finite() && hub_radius > 0.0) {
        return Err(format!("the hub radius must be a positive length in m; got {hub_radius}"));
    }
    let n = rings + 1;
    let nodes = Nodes { gores, n };
    let beta = 2.0 * PI / gores as f64;
    let side = 2.0 * hub_radius * (beta / 2.0).sin();
    let dz = side * (beta / 2.0).tan();
    let corner = |m: usize, z: f64| {
        let a = (m % gores) as f64 * beta;
        Vec3::new(hub_radius * a.cos(), hub_radius * a.sin(), z)
    };
    // Stowed nodes on the prism (zero thickness).
    let mut stowed = vec![Vec3::zeros(); nodes.count()];
    for k in 0..gores {
        stowed[nodes.hub(k)] = corner(k, 0.0);
        for i in 2..=n {
            stowed[nodes.v(k, i)] = corner(k + i - 1, 0.0);
            stowed[nodes.m(k, i)] = corner(k + i - 1, (i - 1) as f64 * dz);
        }
    }
    // Triangles, gore by gore, and how they pair into the Quads model's panels.
    let mut triangles: Vec<Triangle> = Vec::new();
    let mut quads: Vec<Vec<usize>> = Vec::new();
    let mut ring_quads: Vec<Vec<usize>> = Vec::new();
    // The edge each Quads panel's two triangles share (its diagonal), as (a, b).
    let mut diagonals: Vec<(usize, usize)> = Vec::new();
    // Per triangle and per quad: its wall's outward normal and its layer there.
    let wall = |w: usize| {
        let a = ((w % gores) as f64 + 0.5) * beta;
        Vec3::new(a.cos(), a.sin(), 0.0)
    };
    let (mut tri_layers, mut quad_layers) = (Vec::new(), Vec::new());
    for k in 0..gores {
        let (v, m, vn) = (|i| nodes.v(k, i), |i| nodes.m(k, i), |i| nodes.v(k + 1, i));
        // The strip between V_k and M_k: a triangle at the hub corner, then planar quads;
        // ring i lies in wall k + i − 1, layer 2i − 1.
        triangles.push([v(1), v(2), m(2)]);
        tri_layers.push((wall(k), 1));
        quads.push(vec![v(1), v(2), m(2)]);
        quad_layers.push((wall(k), 1));
        ring_quads.push(vec![v(1), v(2), m(2)]);
        for i in 2..n {
            triangles.push([v(i), v(i + 1), m(i + 1)]);
            triangles.push([v(i), m(i + 1), m(i)]);
            tri_layers.extend([(wall(k + i - 1), 2 * i - 1); 2]);
            quads.push(vec![v(i), v(i + 1), m(i + 1), m(i)]);
            quad_layers.push((wall(k + i - 1), 2 * i - 1));
            ring_quads.push(vec![v(i), v(i + 1), m(i + 1), m(i)]);
            diagonals.push((v(i), m(i + 1)));
        }
        // The region between M_k and V_k+1: ring i in wall k + i − 1, layer 2(i − 1).
        triangles.push([m(1), vn(1), m(2)]);
        tri_layers.push((wall(k), 0));
        quads.push(vec![m(1), vn(1), m(2)]);
        quad_layers.push((wall(k), 0));
        ring_quads.push(vec![m(1), vn(1), vn(2), m(2)]);
        for i in 2..=n {
            triangles.push([vn(i - 1), vn(i), m(i)]);
            tri_layers.push((wall(k + i - 1), 2 * (i - 1)));
            if i < n {
                triangles.push([m(i), vn(i), m(i + 1)]);
                tri_layers.push((wall(k + i - 1), 2 * (i - 1)));
                quads.push(vec![vn(i - 1), vn(i), m(i + 1), m(i)]);
                quad_layers.push((wall(k + i - 1), 2 * (i - 1)));
                diagonals.push((m(i), vn(i)));
                ring_quads.push(vec![m(i), vn(i), vn(i + 1), m(i + 1)]);
            } else {
                quads.push(vec![vn(i - 1), vn(i), m(i)]);
                quad_layers.push((wall(k + i - 1), 2 * (i - 1)));
            }
        }
    }
    let deployed_xy = unfold(&nodes, &stowed, &triangles)?;
    let deployed: Vec<Vec3> = deployed_xy.0;
    let mut geometry = FlasherGeometry { closure: deployed_xy.1, ..Default::default() };
    check(&nodes, &stowed, &deployed, &triangles, hub_radius, dz, &mut geometry);

    let hub: Vec<usize> = (0..gores).collect();
    let (body_panels, layers): (Vec<Vec<usize>>, Vec<Option<Layer>>) = match model {
        PanelModel::Quads => (quads, quad_layers.into_iter().map(Some).collect()),
        PanelModel::RingQuads => {
            let count = ring_quads.len();
            (ring_quads, vec![None; count])
        }
        PanelModel::Triangles => {
            (triangles.iter().map(|t| t.to_vec()).collect(), tri_layers.into_iter().map(Some).collect())
        }
    };
    let layers: Vec<Option<Layer>> = std::iter::once(None).chain(layers).collect();
    // Every panel counter-clockwise seen from the deployed sheet's top (+z).
    let mut panels = vec![hub];
    for p in body_panels {
        let area = signed_area(&p.iter().map(|&i| deployed[i]).collect::<Vec<_>>());
        panels.push(if area < 0.0 { p.into_iter().rev().collect() } else { p });
    }
    // Crease kinds: an edge two triangles share is a diagonal when both lie in one Quads panel.
    let edge = |a: usize, b: usize| (a.min(b), a.max(b));
    let mut kinds = BTreeMap::new();
    for p in &panels {
        for i in 0..p.len() {
            kinds.insert(edge(p[i], p[(i + 1) % p.len()]), CreaseKind::Fold);
        }
    }
    if model == PanelModel::Triangles {
        for &(a, b) in &diagonals {
            kinds.insert(edge(a, b), CreaseKind::Diagonal);
        }
    }
    // Senses of the major folds, folded flat (180°) when stowed: mountain along M, valley
    // along V, seen from the deployed top.
    let mut senses = BTreeMap::new();
    for k in 0..gores {
        for i in 1..n {
            senses.insert(edge(nodes.m(k, i), nodes.m(k, i + 1)), Sense::Mountain);
            senses.insert(edge(nodes.v(k, i), nodes.v(k, i + 1)), Sense::Valley);
        }
    }
    Ok(Flasher {
        sheet: Sheet { deployed, stowed, panels, senses, stowed_offsets: Vec::new(), hub_height: 0.0 },
        kinds,
        geometry,
        layers,
    })
}

/// Twice the signed area of a polygon's projection on the xy plane, m².
fn signed_area(p: &[Vec3]) -> f64 {
    (0..p.len()).map(|i| p[i].x * p[(i + 1) % p.len()].y - p[(i + 1) % p.len()].x * p[i].y).sum()
}

/// Unfolds the stowed triangles into the plane z = 0 from the hub (which keeps its place),
/// breadth first, each triangle placed on its two placed nodes with its stowed edge lengths,
/// on the far side of the edge from the triangle it was reached from. Returns the nodes and
/// the largest mismatch where a node is reached again.
fn unfold(nodes: &Nodes, stowed: &[Vec3], triangles: &[Triangle]) -> Result<(Vec<Vec3>, f64), String> {
    let mut at: Vec<Option<Vec3>> = vec![None; stowed.len()];
    for k in 0..nodes.gores {
        at[nodes.hub(k)] = Some(stowed[nodes.hub(k)]);
    }
    let mut by_edge: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    let mut done = vec![false; triangles.len()];
    let mut queue = VecDeque::new();
    let mut closure = 0.0_f64;
    let mut put = |at: &mut Vec<Option<Vec3>>, node: usize, p: Vec3| match at[node] {
        Some(q) => closure = closure.max((p - q).norm()),
        None => at[node] = Some(p),
    };
    // Seeds: the triangles on the hub's sides, placed outside the hub.
    for (t, tri) in triangles.iter().enumerate() {
        let hub_side = (0..3).find(|&i| tri[i] < nodes.gores && tri[(i + 1) % 3] < nodes.gores);
        if let Some(i) = hub_side {
            let (a, b, c) = (tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]);
            let p = place(&at, stowed, a, b, c, Vec3::zeros())?;
            put(&mut at, c, p);
            done[t] = true;
            queue.push_back(t);
        }
    }
    while let Some(t) = queue.pop_front() {
        let tri = triangles[t];
        for i in 0..3 {
            let (a, b, far) = (tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]);
            for &u in &by_edge[&(a.min(b), a.max(b))] {
                if done[u] {
                    continue;
                }
                let c = *triangles[u].iter().find(|&&x| x != a && x != b).expect("a triangle has 3 nodes");
                let away_from = at[far].expect("placed");
                let p = place(&at, stowed, a, b, c, away_from)?;
                put(&mut at, c, p);
                done[u] = true;
                queue.push_back(u);
            }
        }
    }
    let placed: Option<Vec<Vec3>> = at.into_iter().collect();
    let placed = placed.ok_or("the flasher's triangles do not all connect to the hub")?;
    Ok((placed, closure))
}

/// Node `c` in the plane z = 0 at its stowed distances from the placed nodes `a` and `b`, on
/// the side of line ab away from `away`.
fn place(at: &[Option<Vec3>], stowed: &[Vec3], a: usize, b: usize, c: usize, away: Vec3) -> Result<Vec3, String> {
    let (pa, pb) = (at[a].expect("placed"), at[b].expect("placed"));
    let (ra, rb) = ((stowed[c] - stowed[a]).norm(), (stowed[c] - stowed[b]).norm());
    let l = (pb - pa).norm();
    let u = (pb - pa) / l;
    let normal = Vec3::new(-u.y, u.x, 0.0);
    let x = (ra * ra - rb * rb + l * l) / (2.0 * l);
    let h2 = ra * ra - x * x;
    if h2 < -1e-9 * ra * ra {
        return Err(format!("the stowed triangle of nodes {a}, {b}, {c} is not a triangle"));
    }
    let h = h2.max(0.0).sqrt();
    let h = if normal.dot(&(away - pa)) > 0.0 { -h } else { h };
    Ok(pa + x * u + h * normal)
}

/// Fills in the checks of the deployed and stowed nodes.
fn check(
    nodes: &Nodes,
    stowed: &[Vec3],
    deployed: &[Vec3],
    triangles: &[Triangle],
    hub_radius: f64,
    dz: f64,
    g: &mut FlasherGeometry,
) {
    let (gores, n) = (nodes.gores, nodes.n);
    g.deployed_diameter = 2.0 * deployed.iter().map(|p| p.xy().norm()).fold(0.0, f64::max);
    g.stowed_diameter = 2.0 * hub_radius;
    g.stowed_height = (n - 1) as f64 * dz;
    g.flatness = deployed.iter().map(|p| p.z.abs()).fold(0.0, f64::max);
    g.off_prism = stowed
        .iter()
        .map(|p| {
            // Distance from the prism's side: the corners are on the circumscribed circle.
            (p.xy().norm() - hub_radius).abs().max(if p.z < -1e-12 || p.z > g.stowed_height + 1e-12 {
                p.z.abs()
            } else {
                0.0
            })
        })
        .fold(0.0, f64::max);
    for t in triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            let (ls, ld) = ((stowed[a] - stowed[b]).norm(), (deployed[a] - deployed[b]).norm());
            g.edge_mismatch = g.edge_mismatch.max((ls - ld).abs() / ls);
        }
    }
    let beta = 2.0 * PI / gores as f64;
    let turn = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), beta);
    for k in 0..gores {
        for i in 1..=n {
            for (here, next) in [(nodes.v(k, i), nodes.v(k + 1, i)), (nodes.m(k, i), nodes.m(k + 1, i))] {
                g.symmetry = g.symmetry.max((turn * deployed[here] - deployed[next]).norm());
            }
        }
    }
    // Overlap: the triangles' areas against the area inside the rim (the loop of edges that
    // only one triangle has, the hub's sides aside) less the hub's.
    let triangles_area: f64 = triangles.iter().map(|t| 0.5 * signed_area(&t.map(|i| deployed[i])).abs()).sum();
    let mut count: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for t in triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut next: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (&(a, b), &c) in &count {
        if c == 1 && !(a < gores && b < gores) {
            next.entry(a).or_default().push(b);
            next.entry(b).or_default().push(a);
        }
    }
    let mut rim = Vec::new();
    if let Some((&start, _)) = next.iter().next() {
        let (mut prev, mut here) = (usize::MAX, start);
        loop {
            rim.push(deployed[here]);
            let Some(&to) = next[&here].iter().find(|&&x| x != prev) else { break };
            (prev, here) = (here, to);
            if here == start || rim.len() > next.len() {
                break;
            }
        }
    }
    let hub_area = 0.5 * gores as f64 * hub_radius * hub_radius * beta.sin();
    let rim_area = 0.5 * signed_area(&rim).abs();
    g.overlap = triangles_area / (rim_area - hub_area) - 1.0;
}

/// Stiffness and damping per crease kind, SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlasherLaws {
    /// Fold creases: fold stiffness (N·m/rad) and damping (N·m·s/rad).
    pub k_fold: f64,
    /// Fold damping, N·m·s/rad; `None`: [`THIN_C_FOLD`] for thin panels, [`THICK_C_FOLD`] for
    /// thick ones ([`FlasherLaws::fold_damping`]).
    pub c_fold: Option<f64>,
    /// Diagonals (triangle model): bending stiffness, N·m/rad.
    pub k_bending: f64,
    /// Diagonal bending damping, N·m·s/rad.
    pub c_bending: f64,
    /// Every hinge's three translations: stiffness, N/m.
    pub k_translation: f64,
    /// Translational damping, N·s/m.
    pub c_translation: f64,
    /// Every hinge's two rotations other than its fold: stiffness, N·m/rad.
    pub k_rotation: f64,
    /// Their damping, N·m·s/rad.
    pub c_rotation: f64,
    /// Thick panels (axes shifted): stiffness of each folding crease's stop at flat, where its
    /// panels' edges meet, N·m/rad (0: none); damped for the contact's restitution.
    pub k_stop: f64,
    /// Thick panels (axes shifted): bending stiffness per unit length of the membrane that
    /// bonds each folding crease's panels, N·m (0: no membrane, the crease a pin on its
    /// axis; docs/flasher.md, *Membrane hinges*).
    pub membrane_bending: f64,
    /// Thick panels: the membrane's width across the fold line, m (`None`:
    /// [`MEMBRANE_WIDTH_THICKNESSES`] panel thicknesses).
    pub membrane_width: Option<f64>,
    /// Thick panels: damping ratio of the panels' motion across a fold line while its
    /// membrane is slack (on the two panels' reduced mass).
    pub membrane_damping_ratio: f64,
}

/// Fold damping of a thin flasher's creases unless given, N·m·s/rad: light, so that the sheet
/// opens by its stored fold energy in a few seconds.
pub const THIN_C_FOLD: f64 = 0.05;

/// Fold damping of a thick flasher's creases unless given, N·m·s/rad (the starshade's value).
/// Thick panels stand for hardware, deployed through damped hinges: at [`THIN_C_FOLD`] the
/// 6 × 3, 1-cm flasher slams into flat with 154 J and rings for seconds against its stops and
/// neighbours (ζ ≈ 0.13 on an outer crease; 77 % of its run's time went there), at 1 it opens
/// on the same time scale (90 % at 1.93 s against 1.42 s; its thin twin at 1, 2.00 s) and
/// settles (docs/flasher.md, *Damped folds*).
pub const THICK_C_FOLD: f64 = 1.0;

impl FlasherLaws {
    /// The creases' fold damping for panels `thickness` m thick, N·m·s/rad: as given, or the
    /// thin or thick default.
    pub fn fold_damping(&self, thickness: f64) -> f64 {
        self.c_fold.unwrap_or(if thickness > 0.0 { THICK_C_FOLD } else { THIN_C_FOLD })
    }
}

/// A thick flasher's membrane hinges are this many panel thicknesses wide unless told
/// otherwise (docs/flasher.md, *Membrane hinges*).
pub const MEMBRANE_WIDTH_THICKNESSES: f64 = 5.0;

/// The bending stiffness per unit length of a 125-µm (5-mil) polyimide (Kapton) film, N·m:
/// `D = E t³ / (12 (1 − ν²))` with E = 2.5 GPa, ν = 0.34 (DuPont's Kapton HN data sheet).
pub const KAPTON_125UM_BENDING: f64 = 2.5e9 * 125e-6 * 125e-6 * 125e-6 / (12.0 * (1.0 - 0.34 * 0.34));

impl Default for FlasherLaws {
    /// The command line's defaults, chosen so that a flasher deploys by its stored fold energy
    /// in a few seconds: folds at 1 N·m/rad, lightly damped (0.05 N·m·s/rad; 1 with thick
    /// panels, [`THICK_C_FOLD`]); bending
    /// diagonals soft (0.1 N·m/rad, 0.05 N·m·s/rad), since stiff diagonals hold the wrap
    /// folded (at 1e3 N·m/rad a 12-gore, 5-ring flasher stayed at 33 % of its radius); off-axis
    /// rotations at 1e3 N·m/rad (0.1 N·m·s/rad) and translations at 1e6 N/m (10 N·s/m), damped
    /// so that their vibrations do not set the step size for the whole run. Thick panels'
    /// creases stop at flat at 1e4 N·m/rad: a panel slapping flat at the deployment's fold
    /// rates (≲ 1 rad/s, ≲ 0.1 kg·m² about its crease) passes it by ≲ 5e-3 rad; off-axis
    /// stiffness as low as 1e3 N·m/rad is what lets the (not rigidly foldable) wrap open,
    /// and without the stop it let a fold swing 17° past flat through its neighbour.
    fn default() -> Self {
        Self {
            k_fold: 1.0,
            c_fold: None,
            k_bending: 0.1,
            c_bending: 0.05,
            k_translation: 1e6,
            c_translation: 10.0,
            k_rotation: 1e3,
            c_rotation: 0.1,
            k_stop: 1e4,
            membrane_bending: KAPTON_125UM_BENDING,
            membrane_width: None,
            membrane_damping_ratio: 1.0,
        }
    }
}

/// A flasher and how it is written as a scenario: the report the generator prints.
#[derive(Clone, Debug)]
pub struct FlasherReport {
    /// The shape asked for.
    pub shape: FlasherShape,
    /// The geometry checks.
    pub geometry: FlasherGeometry,
    /// The sheet builder's report (counts, loops, strain, stowed folds).
    pub sheet: SheetReport,
    /// Stored strain energy of the stowed state in the hinges' stiff directions, J
    /// (½ k δ² and ½ k θ² off the fold; zero when every panel is rigid in both states).
    pub strain_energy: f64,
    /// With thick panels: the panel thickness (m) and the outermost layer of the stowed wrap.
    pub layers: Option<(f64, usize)>,
    /// Where the hinges' fold axes lie.
    pub hinge_axes: HingeAxes,
    /// The folding creases' membrane hinges, if any, and their count.
    pub membrane: Option<(Membrane, usize)>,
    /// The thick panels' defaults this flasher took because they were not given, as the
    /// report names them (e.g. `fold damping 1 N·m·s/rad`); empty for thin panels.
    pub thick_defaults: Vec<String>,
}

/// The `[contact]` table written with thick panels.
pub fn contact_defaults() -> String {
    format!(
        "\n# Thick panels: contact between every pair of bodies (docs/contact.md).\n[contact]\nstiffness = 1e8       # N/m^1.5 per contact point\nrestitution = {:?}\nfriction = 0.2\n",
        super::crease::RESTITUTION
    )
}

/// Builds the scenario text of a flasher and its report.
pub fn flasher_scenario(
    shape: &FlasherShape,
    laws: &FlasherLaws,
    p: &SheetParams,
) -> Result<(String, FlasherReport), String> {
    let mut f = flasher(shape)?;
    let outermost = f.layers.iter().flatten().map(|l| l.1).max();
    let layers = (p.thickness > 0.0).then_some(()).and(outermost).map(|l| (p.thickness, l));
    // Thick panels: each stowed in its layer, its mid-plane (layer + ½) thicknesses out from
    // its wall; the hinges take up what the layers do not match.
    if p.thickness > 0.0 {
        f.sheet.hub_height = f.geometry.stowed_height;
        f.sheet.stowed_offsets = f
            .layers
            .iter()
            .map(|l| l.map_or(Vec3::zeros(), |(n, layer)| n * ((layer as f64 + 0.5) * p.thickness)))
            .collect();
    }
    // Membrane hinges on the folding creases of thick panels with shifted axes (not on the
    // triangle model's diagonals, which stand for the bending of a quadrilateral panel).
    let membrane =
        (p.thickness > 0.0 && p.hinge_axes == HingeAxes::Shifted && laws.membrane_bending > 0.0).then(|| Membrane {
            bending: laws.membrane_bending,
            width: laws.membrane_width.unwrap_or(MEMBRANE_WIDTH_THICKNESSES * p.thickness),
            damping_ratio: laws.membrane_damping_ratio,
        });
    let membranes = std::cell::Cell::new(0);
    let law = |a: usize, b: usize| {
        let (k_fold, c_fold, membrane) = match f.kinds.get(&(a.min(b), a.max(b))) {
            Some(CreaseKind::Diagonal) => (laws.k_bending, laws.c_bending, None),
            _ => (laws.k_fold, laws.fold_damping(p.thickness), membrane),
        };
        membranes.set(membranes.get() + usize::from(membrane.is_some()));
        CreaseLaw {
            k_translation: laws.k_translation,
            k_rotation: laws.k_rotation,
            k_fold,
            c_translation: laws.c_translation,
            c_rotation: laws.c_rotation,
            c_fold,
            k_stop: laws.k_stop,
            membrane,
        }
    };
    let (mut text, sheet) = sheet_scenario(&f.sheet, law, p)?;
    if p.thickness > 0.0 {
        // Thick panels stowed in layers: contact keeps them from passing through each other
        // (docs/contact.md); the values are a starting point, the report of a run says
        // whether the penetration stays a small part of the thickness.
        text.push_str(&contact_defaults());
    }
    let strain_energy = sheet
        .strains
        .iter()
        .map(|s| {
            0.5 * laws.k_translation * s.delta.norm_squared()
                + 0.5 * laws.k_rotation * (s.pitch.powi(2) + s.roll.powi(2))
        })
        .sum();
    Ok((
        text,
        FlasherReport {
            shape: *shape,
            geometry: f.geometry,
            sheet,
            strain_energy,
            layers,
            hinge_axes: p.hinge_axes,
            membrane: membrane.map(|m| (m, membranes.get())),
            thick_defaults: Vec::new(),
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::RunText;
    use crate::kinematics::{hinge_kinematics, initial_state};
    use crate::scenario::Scenario;
    use crate::state::BodyMotion;

    pub(crate) fn params() -> SheetParams {
        SheetParams {
            title: "flasher".into(),
            areal_density: 1.0,
            thickness: 0.0,
            hinge_axes: HingeAxes::Shifted,
            hub_mass: 100.0,
            hub_inertia: [25.0, 25.0, 50.0],
            spin_rpm: 0.0,
            run: RunText { duration: 1.0, output_step: 0.01, tolerance: 1e-9, ..Default::default() },
        }
    }

    /// Every hinge, the loop ones included, starts at its stowed state: δ, pitch and roll at
    /// round-off (1e-12 m, rad) for the models exact in both states; and in the deployed
    /// design (every tree coordinate zero) every hinge is at rest, its fold zero too.
    #[test]
    fn every_hinge_is_closed_stowed_and_at_rest_deployed() {
        for (model, deployed) in [
            (PanelModel::Quads, false),
            (PanelModel::Triangles, false),
            (PanelModel::Quads, true),
            (PanelModel::Triangles, true),
        ] {
            let shape = FlasherShape { gores: 6, rings: 3, hub_radius: 1.0, model };
            let (text, _) = flasher_scenario(&shape, &FlasherLaws::default(), &params()).unwrap();
            let s = Scenario::from_toml(&text, "flasher").unwrap_or_else(|e| panic!("{e}"));
            let design = crate::kinematics::InitialConditions {
                hinges: vec![None; s.model.hinges.len()],
                body_attitudes: vec![None; s.model.bodies.len()],
                ..Default::default()
            };
            let (y, refs) = initial_state(&s.model, if deployed { &design } else { &s.initial });
            for (i, h) in s.model.hinges.iter().enumerate() {
                let k = hinge_kinematics(
                    h,
                    &BodyMotion::from_state(&y, h.parent),
                    &BodyMotion::from_state(&y, h.child),
                    &refs[i],
                );
                let mut off = k.state.delta_in_a0.norm().max(k.state.theta.pitch.abs()).max(k.state.theta.roll.abs());
                if deployed {
                    off = off.max(k.state.theta.yaw.abs());
                }
                assert!(
                    off < 1e-12,
                    "{model:?} {} (tree {}): δ {} θ {:?}",
                    h.name,
                    s.model.is_tree_hinge[i],
                    k.state.delta_in_a0,
                    k.state.theta
                );
            }
        }
    }
}
