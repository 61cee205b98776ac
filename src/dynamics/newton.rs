//! A Newton matrix whose sparsity is the hinge graph, for the implicit integrator.
//!
//! `W = I − hγ J`, with per body the pose x = (R, q) (7 numbers) and the twist v = (Ṙ, ω)
//! (6, see [`crate::state`]). The pose rates `ẋ = (Ṙ, ½ q ⊗ ω)` depend on the body's own
//! state only, and their Jacobian is known in closed form; the accelerations' Jacobian
//! `(A_x, A_v)` has a block (i, j) only where bodies i and j are the same or share a hinge.
//! Eliminating the pose corrections body by body (exactly: `(I − hγ ∂ẋ/∂x)⁻¹` is
//! `diag(I₃, (I₄ + cΩ)/(1 + c²|ω|²))`, c = hγ/2) leaves a system in the twists alone,
//!
//! `S Δv = r_v + hγ A_x P r_x`,  `S = I − hγ A_v − (hγ)² A_x P ∂ẋ/∂v`,
//!
//! with 6×6 blocks on the same graph; then `Δx = P (r_x + hγ ∂ẋ/∂v Δv)`. This is W⁻¹
//! exactly, at a sixth of the block cost of eliminating 13×13 blocks.
//!
//! `(A_x, A_v)` are exact, from dual numbers ([`super::jacobian`]), when the system offers
//! them; with locked directions the locks then become rows of the twist system (one node
//! per locked hinge, see [`GraphNewton::new_exact`]). Otherwise (a law without a dual
//! form) they come from forward differences of the right-hand side with a distance-2
//! colouring of the body graph: bodies of one colour have disjoint neighbourhoods, so one
//! evaluation per colour and state component fills all their columns (13 × colours
//! evaluations, not 13 × bodies); locked directions then couple whole clusters of bodies. S is factored by block Gaussian elimination in a
//! minimum-fill order (no fill for trees; fill along loops), dense LU inside the diagonal
//! blocks. Each hinge's dissipated-energy integral depends on the bodies but feeds nothing
//! back; its rows are taken as the identity, which simplified Newton tolerates (those
//! components converge in one iteration once the bodies have).

use super::jacobian::{BlockSink, ConstraintRow, ExactJacobian, PoseBlock, TwistBlock};
use crate::integrate::NewtonMatrix;
use crate::integrate::OdeSystem;
use crate::model::Model;
use crate::state::{BODY_STATE_LEN as B, OMEGA, QUAT, VEL};
use nalgebra::{SMatrix, SVector};
use std::collections::BTreeMap;
use symbolic::Symbolic;

/// Pose numbers per body (R, q).
const X: usize = 7;
/// Twist numbers per body (Ṙ, ω).
const V: usize = 6;
type Block = TwistBlock;
type Vec6 = SVector<f64, V>;
type Vec7 = SVector<f64, X>;

/// Per body at the Jacobian's state: `P = (I − hγ ∂ẋ/∂x)⁻¹` applied to a pose vector, and
/// `∂ẋ/∂v` applied to a twist, both in closed form.
#[derive(Clone, Copy, Debug, Default)]
struct PoseRates {
    /// The quaternion q = (w, x, y, z).
    q: [f64; 4],
    /// ω, body components, rad/s.
    omega: [f64; 3],
}

impl PoseRates {
    /// `Ω(ω)` with `q̇ = ½ Ω(ω) q`, applied to `u`.
    fn omega_times(&self, u: &[f64]) -> [f64; 4] {
        let [p, r, s] = self.omega;
        [
            -p * u[1] - r * u[2] - s * u[3],
            p * u[0] + s * u[2] - r * u[3],
            r * u[0] - s * u[1] + p * u[3],
            s * u[0] + r * u[1] - p * u[2],
        ]
    }

    /// `P x` for a pose vector x: identity on R; on q, `(I + cΩ) x_q / (1 + c²|ω|²)`.
    fn p_times(&self, x: &Vec7, h_gamma: f64) -> Vec7 {
        let c = 0.5 * h_gamma;
        let w2: f64 = self.omega.iter().map(|w| w * w).sum();
        let o = self.omega_times(&x.as_slice()[3..7]);
        let den = 1.0 / (1.0 + c * c * w2);
        Vec7::from_column_slice(&[
            x[0],
            x[1],
            x[2],
            (x[3] + c * o[0]) * den,
            (x[4] + c * o[1]) * den,
            (x[5] + c * o[2]) * den,
            (x[6] + c * o[3]) * den,
        ])
    }

    /// `∂ẋ/∂v · v`: Ṙ's part is the velocity itself; q̇'s is `½ q ⊗ (0, δω)`.
    fn rates_times(&self, v: &Vec6) -> Vec7 {
        let q = crate::math::quat_rate(&self.q, &crate::math::Vec3::new(v[3], v[4], v[5]));
        Vec7::from_column_slice(&[v[0], v[1], v[2], q[0], q[1], q[2], q[3]])
    }

    /// `P ∂ẋ/∂v` as a 7×6 matrix.
    fn p_rates(&self, h_gamma: f64) -> SMatrix<f64, X, V> {
        let mut m = SMatrix::<f64, X, V>::zeros();
        for k in 0..V {
            let mut e = Vec6::zeros();
            e[k] = 1.0;
            m.set_column(k, &self.p_times(&self.rates_times(&e), h_gamma));
        }
        m
    }
}

/// The hinge-graph-sparse Newton matrix of a model's equations of motion.
pub struct GraphNewton<'a, S: OdeSystem + ?Sized> {
    system: &'a S,
    /// The exact Jacobian's source, if the system has one.
    exact: Option<&'a dyn ExactJacobian>,
    /// Jacobians formed exactly and by differences.
    exact_count: usize,
    differenced_count: usize,
    nb: usize,
    n: usize,
    /// Closed neighbourhoods: each body and the bodies it shares a hinge with, sorted.
    neighbours: Vec<Vec<usize>>,
    /// Colour classes of a distance-2 colouring.
    colours: Vec<Vec<usize>>,
    /// Per body i, per neighbour j (as in `neighbours[i]`): `∂a_i/∂x_j` and `∂a_i/∂v_j`.
    jac_x: Vec<Vec<PoseBlock>>,
    jac_v: Vec<Vec<Block>>,
    /// Per body, the state the Jacobian was formed at (for the pose rates).
    pose: Vec<PoseRates>,
    h_gamma: f64,
    /// Elimination order and each body's position in it.
    order: Vec<usize>,
    position: Vec<usize>,
    /// Per eliminated body p: the inverse of the pivot block, its row blocks U[p][j] and
    /// multipliers L[i][p] = S[i][p] S[p][p]⁻¹, for neighbours later in the order.
    pivots: Vec<Block>,
    /// The elimination's patterns for the last orders factored, and the blocks of the last
    /// factorization by slot (`symbolic.rs`).
    symbolic: Vec<Symbolic>,
    values: Vec<Block>,
    upper: Vec<Vec<(usize, Block)>>,
    lower: Vec<Vec<(usize, Block)>>,
    evaluations: usize,
    /// Scratch for [`NewtonMatrix::solve`]: `P r_x` and the twist unknowns per body (then
    /// the scaled multipliers per locked hinge).
    p_rx: Vec<Vec7>,
    twist: Vec<Vec6>,
    /// Locked hinges (parent, child, locked directions) carried as constraint rows: node
    /// `nb + g` of the elimination (see [`GraphNewton::new_exact`]). Empty otherwise, and
    /// empty while every lock is idle (see [`ExactJacobian::constraint_jacobian`]).
    groups: Vec<(usize, usize, usize)>,
    /// Whether any direction is locked; the elimination order and positions with the nodes
    /// of the locks last carried (`carried`, as `groups`) and without any (idle or
    /// disengaged locks leave the Newton matrix: their multipliers are zero, and a motion
    /// that keeps them idle never leaves their constraints).
    has_locks: bool,
    carried: Vec<(usize, usize, usize)>,
    with_locks: (Vec<usize>, Vec<usize>),
    without_locks: (Vec<usize>, Vec<usize>),
    /// The hinges' body pairs.
    edges: Vec<(usize, usize)>,
    /// The locks' rows at the last Jacobian, in the order of `groups`.
    group_rows: Vec<ConstraintRow>,
    /// The last exact Jacobian's blocks but the contact's (`jac_x`, `jac_v`), kept for
    /// [`NewtonMatrix::refresh_contact`]; `None` without contact or with locks.
    rest: Option<RestBlocks>,
    /// The node whose pivot block was singular in the last factorization that failed (a
    /// body, or `nb + g` for the locks of `groups[g]`).
    singular: Option<usize>,
}

/// A Jacobian's blocks as `GraphNewton` keeps them: per body, per neighbour, `∂a_i/∂x_j`
/// and `∂a_i/∂v_j`.
type RestBlocks = (Vec<Vec<PoseBlock>>, Vec<Vec<Block>>);

/// Adds the blocks `send` sends to `jac_x` and `jac_v` at their neighbour slots, and returns
/// what `send` does.
fn gather<R>(
    neighbours: &[Vec<usize>],
    jac_x: &mut [Vec<PoseBlock>],
    jac_v: &mut [Vec<Block>],
    send: impl FnOnce(&mut BlockSink<'_>) -> R,
) -> R {
    let mut add = |i: usize, j: usize, dx: &PoseBlock, dv: &Block| {
        let slot = neighbours[i].binary_search(&j).expect("blocks only between neighbours");
        jac_x[i][slot] += dx;
        jac_v[i][slot] += dv;
    };
    send(&mut add)
}

impl<'a, S: OdeSystem + ?Sized> GraphNewton<'a, S> {
    /// The Newton matrix of `system`, whose state is laid out for `model` (bodies, then one
    /// integral per hinge).
    pub fn new(system: &'a S, model: &Model) -> Self {
        Self::build(system, model, None)
    }

    /// The Newton matrix of `system`, laid out as for [`Self::new`], whose Jacobian is formed
    /// exactly from `source` where it can (see [`ExactJacobian`]).
    ///
    /// With locked directions the Newton matrix carries the constraints as rows instead of
    /// differencing the constraint solve (which couples whole clusters of bodies). With
    /// `M a = F + Jᵀλ` and `J a + γ = 0` linearised exactly (C = ∂(Ja + γ)/∂(x, v) with a
    /// held, the constraint wrenches' derivatives with λ held added to A), the twist system
    /// becomes
    ///
    /// `[S  −M⁻¹Jᵀ; J + hγ C_v + (hγ)² C_x P ∂ẋ/∂v  0] [Δv; hγ Δλ] = [r̃_v; J r_v − hγ C_x P r_x]`.
    ///
    /// Its graph is the hinge graph plus one node per locked hinge, so its elimination stays
    /// sparse.
    pub fn new_exact(system: &'a S, model: &Model, source: &'a dyn ExactJacobian) -> Self {
        Self::build(system, model, Some(source))
    }

    fn build(system: &'a S, model: &Model, exact: Option<&'a dyn ExactJacobian>) -> Self {
        let nb = model.bodies.len();
        let edges: Vec<(usize, usize)> = model.hinges.iter().map(|h| (h.parent, h.child)).collect();
        let has_locks = exact.is_some_and(|e| !e.locked_hinges().is_empty());
        let mut newton = Self {
            system,
            exact,
            exact_count: 0,
            differenced_count: 0,
            nb,
            n: B * nb + model.energy_states(),
            jac_x: Vec::new(),
            jac_v: Vec::new(),
            neighbours: Vec::new(),
            colours: Vec::new(),
            pose: vec![PoseRates::default(); nb],
            h_gamma: 0.0,
            order: Vec::new(),
            position: Vec::new(),
            pivots: Vec::new(),
            symbolic: Vec::new(),
            values: Vec::new(),
            upper: Vec::new(),
            lower: Vec::new(),
            evaluations: 0,
            p_rx: Vec::new(),
            twist: Vec::new(),
            groups: Vec::new(),
            has_locks,
            carried: Vec::new(),
            with_locks: (Vec::new(), Vec::new()),
            without_locks: (Vec::new(), Vec::new()),
            group_rows: Vec::new(),
            edges: edges.clone(),
            rest: None,
            singular: None,
        };
        // With an exact Jacobian the locks are rows of the system (`groups`), and bodies couple
        // along hinges only.
        if !newton.has_locks {
            newton.set_structure(&Self::differenced_coupling(model, edges));
        } else {
            newton.set_structure(&edges);
            newton.without_locks = (newton.order.clone(), newton.position.clone());
        }
        newton
    }

    /// Carries the locks `carried` (per hinge, in hinge order: parent, child, number of rows)
    /// as rows of the Newton matrix. The elimination order with them is kept for the next
    /// Jacobian: the carried set changes only when locks engage, or all fall idle or wake
    /// at once.
    fn carry_locks(&mut self, carried: Vec<(usize, usize, usize)>) {
        if carried.is_empty() {
            self.groups.clear();
            (self.order, self.position) = self.without_locks.clone();
            return;
        }
        if carried != self.carried {
            // Same pairs, so the same neighbourhoods: the blocks already formed are kept.
            let (jac_x, jac_v) = (std::mem::take(&mut self.jac_x), std::mem::take(&mut self.jac_v));
            self.groups = carried.clone();
            let edges = std::mem::take(&mut self.edges);
            self.set_structure(&edges);
            self.edges = edges;
            (self.jac_x, self.jac_v) = (jac_x, jac_v);
            self.with_locks = (self.order.clone(), self.position.clone());
            self.carried = carried;
        }
        self.groups.clone_from(&self.carried);
        (self.order, self.position) = self.with_locks.clone();
    }

    /// Each body's attitude and rate at `y`, for the pose rates.
    fn set_pose(&mut self, y: &[f64]) {
        for (b, pose) in self.pose.iter_mut().enumerate() {
            let s = &y[B * b..B * (b + 1)];
            pose.q.copy_from_slice(&s[QUAT..QUAT + 4]);
            pose.omega.copy_from_slice(&s[OMEGA..OMEGA + 3]);
        }
    }

    /// Every Jacobian block zero.
    fn zero_blocks(&mut self) {
        self.jac_x.iter_mut().flatten().for_each(|b| *b = PoseBlock::zeros());
        self.jac_v.iter_mut().flatten().for_each(|b| *b = Block::zeros());
    }

    /// Makes room in the structure for blocks between the bodies of `pairs` (contact): the
    /// pairs not yet neighbours join the graph for the rest of the run, and the elimination
    /// orders (with and without the locks' rows) are found again.
    fn add_pairs(&mut self, pairs: &[(usize, usize)]) -> bool {
        let new: Vec<(usize, usize)> =
            pairs.iter().copied().filter(|&(a, b)| self.neighbours[a].binary_search(&b).is_err()).collect();
        if new.is_empty() {
            return false;
        }
        self.edges.extend(new);
        let groups = std::mem::take(&mut self.groups);
        let edges = std::mem::take(&mut self.edges);
        self.set_structure(&edges);
        self.edges = edges;
        self.without_locks = (self.order.clone(), self.position.clone());
        // The next Jacobian with locks carried finds their order again.
        self.carried.clear();
        self.groups = groups;
        if !self.groups.is_empty() {
            let carried = std::mem::take(&mut self.groups);
            self.carry_locks(carried);
        }
        self.zero_blocks();
        self.rest = None;
        true
    }

    /// The body pairs a differenced Jacobian couples: the hinges, and every pair in a cluster
    /// of bodies joined by locked hinges.
    fn differenced_coupling(model: &Model, edges: Vec<(usize, usize)>) -> Vec<(usize, usize)> {
        let nb = model.bodies.len();
        // Differenced Jacobians see the constraint solve, which couples every body of a
        // cluster joined by locked hinges (the multipliers are solved over the whole
        // cluster): each such body depends on all the others.
        let mut cluster: Vec<usize> = (0..nb).collect();
        fn root(c: &mut [usize], mut i: usize) -> usize {
            while c[i] != i {
                c[i] = c[c[i]];
                i = c[i];
            }
            i
        }
        for h in model.hinges.iter().filter(|h| h.law.locked_directions().contains(&true)) {
            let (a, b) = (root(&mut cluster, h.parent), root(&mut cluster, h.child));
            cluster[a.max(b)] = a.min(b);
        }
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); nb];
        for i in 0..nb {
            let r = root(&mut cluster, i);
            members[r].push(i);
        }
        let mut coupled = edges;
        for m in members.iter().filter(|m| m.len() > 1) {
            for (k, &i) in m.iter().enumerate() {
                coupled.extend(m[k + 1..].iter().map(|&j| (i, j)));
            }
        }
        coupled
    }

    /// Neighbourhoods, colouring and elimination order for bodies coupled along `pairs`,
    /// plus one node per entry of `self.groups` joined to its two bodies.
    fn set_structure(&mut self, pairs: &[(usize, usize)]) {
        let nb = self.nb;
        let mut neighbours: Vec<Vec<usize>> = (0..nb).map(|i| vec![i]).collect();
        for &(a, b) in pairs {
            neighbours[a].push(b);
            neighbours[b].push(a);
        }
        for v in &mut neighbours {
            v.sort_unstable();
            v.dedup();
        }
        // Greedy distance-2 colouring.
        let mut colour = vec![usize::MAX; nb];
        let mut colours: Vec<Vec<usize>> = Vec::new();
        for b in 0..nb {
            let mut used = std::collections::BTreeSet::new();
            for &u in &neighbours[b] {
                for &w in &neighbours[u] {
                    if colour[w] != usize::MAX {
                        used.insert(colour[w]);
                    }
                }
            }
            let c = (0..).find(|c| !used.contains(c)).expect("a free colour");
            colour[b] = c;
            if c == colours.len() {
                colours.push(Vec::new());
            }
            colours[c].push(b);
        }
        // Minimum-fill elimination order, each locked hinge's node after a body
        // it is matched to (`order.rs` says why).
        let pairs: Vec<(usize, usize)> = self.groups.iter().map(|&(p, c, _)| (p, c)).collect();
        let order = order::elimination_order(&neighbours, &pairs);
        let n_nodes = nb + self.groups.len();
        let mut position = vec![0; n_nodes];
        for (k, &p) in order.iter().enumerate() {
            position[p] = k;
        }
        self.symbolic.clear();
        self.jac_x = neighbours.iter().map(|v| vec![PoseBlock::zeros(); v.len()]).collect();
        self.jac_v = neighbours.iter().map(|v| vec![Block::zeros(); v.len()]).collect();
        self.neighbours = neighbours;
        self.colours = colours;
        self.order = order;
        self.position = position;
    }

    /// Jacobians formed so far: (exactly, by finite differences).
    pub fn jacobian_counts(&self) -> (usize, usize) {
        (self.exact_count, self.differenced_count)
    }

    /// Number of off-diagonal blocks in the factors (fill included).
    pub fn fill_blocks(&self) -> usize {
        self.upper.iter().map(Vec::len).sum::<usize>() + self.lower.iter().map(Vec::len).sum::<usize>()
    }

    /// Number of colours of the distance-2 colouring (Jacobian cost: 13 × colours evaluations).
    pub fn colour_count(&self) -> usize {
        self.colours.len()
    }
}

impl<S: OdeSystem + ?Sized> GraphNewton<'_, S> {
    /// The Newton matrix in the bodies' twists (and the locked hinges' multipliers) at `hγ`,
    /// the pose corrections eliminated: `S = I − hγ ∂a/∂v − (hγ)² ∂a/∂x P ∂ẋ/∂v` by 6 × 6
    /// blocks, one block row per body then per locked hinge, with the Jacobian of the last
    /// [`NewtonMatrix::prepare`]. What [`NewtonMatrix::refactor`] factors; public for the
    /// benchmark that factors it with a general sparse LU (`benches/sparse_lu.rs`).
    pub fn twist_blocks(&self, h_gamma: f64) -> Vec<BTreeMap<usize, Block>> {
        let mut s: Vec<BTreeMap<usize, Block>> = vec![BTreeMap::new(); self.nb + self.groups.len()];
        self.twist_entries(h_gamma, &mut |i, j, b| *s[i].entry(j).or_insert_with(Block::zeros) += b);
        s
    }

    /// [`Self::twist_blocks`]'s blocks one at a time, as (row, column, block) to be added:
    /// what both the maps and the numeric refactorization are filled from.
    fn twist_entries(&self, h_gamma: f64, add: &mut dyn FnMut(usize, usize, &Block)) {
        let p_rates: Vec<SMatrix<f64, X, V>> = self.pose.iter().map(|p| p.p_rates(h_gamma)).collect();
        // S blocks; the elimination adds its fill.
        for i in 0..self.nb {
            for (slot, &j) in self.neighbours[i].iter().enumerate() {
                let mut blk = -self.jac_v[i][slot] * h_gamma - self.jac_x[i][slot] * p_rates[j] * (h_gamma * h_gamma);
                if i == j {
                    blk += Block::identity();
                }
                add(i, j, &blk);
            }
        }
        // Locked hinges: J in their rows, −M⁻¹Jᵀ in their bodies' rows; the rows and columns
        // beyond the hinge's locked directions are the identity (a multiplier of zero).
        // A lock's row: J + hγ ∂(Ja+γ)/∂v + (hγ)² ∂(Ja+γ)/∂x P ∂ẋ/∂v (the pose corrections
        // eliminated as for S).
        let mut first = 0;
        for (g, &(p, c, k)) in self.groups.iter().enumerate() {
            let node = self.nb + g;
            let mut diagonal = Block::zeros();
            for d in k..V {
                diagonal[(d, d)] = 1.0;
            }
            add(node, node, &diagonal);
            for (side, b) in [p, c].into_iter().enumerate() {
                let (mut row_block, mut column_block) = (Block::zeros(), Block::zeros());
                for (r, row) in self.group_rows[first..first + k].iter().enumerate() {
                    let d_pose = SMatrix::<f64, 1, X>::from_row_slice(&row.d_pose[side]);
                    let through_pose = d_pose * p_rates[b] * (h_gamma * h_gamma);
                    for col in 0..V {
                        row_block[(r, col)] = row.j[side][col] + h_gamma * row.d_twist[side][col] + through_pose[col];
                        column_block[(col, r)] = -row.m_inv_j[side][col];
                    }
                }
                add(node, b, &row_block);
                add(b, node, &column_block);
            }
            first += k;
        }
    }
}

impl<S: OdeSystem + ?Sized> NewtonMatrix for GraphNewton<'_, S> {
    fn refresh_contact(&mut self, t: f64, y: &[f64], h_gamma: f64) -> bool {
        let (Some(source), Some((rest_x, rest_v))) = (self.exact, self.rest.take()) else {
            return self.prepare(t, y, h_gamma);
        };
        // A pair new in contact changes the structure (and the slots the rest was kept in).
        if self.add_pairs(&source.coupled_pairs(y)) {
            return self.prepare(t, y, h_gamma);
        }
        self.set_pose(y);
        for (dst, src) in self.jac_x.iter_mut().zip(&rest_x) {
            dst.copy_from_slice(src);
        }
        for (dst, src) in self.jac_v.iter_mut().zip(&rest_v) {
            dst.copy_from_slice(src);
        }
        self.rest = Some((rest_x, rest_v));
        if !gather(&self.neighbours, &mut self.jac_x, &mut self.jac_v, |add| source.contact_jacobian(y, add)) {
            return self.prepare(t, y, h_gamma);
        }
        self.exact_count += 1;
        self.refactor(h_gamma)
    }

    fn prepare(&mut self, t: f64, y: &[f64], h_gamma: f64) -> bool {
        self.set_pose(y);
        if let Some(source) = self.exact {
            self.zero_blocks();
            // Bodies in contact couple like bodies sharing a hinge: room for their blocks.
            // The structure only grows, so the elimination order changes only when a new
            // pair first touches.
            self.add_pairs(&source.coupled_pairs(y));
            let (neighbours, jac_x, jac_v) = (&self.neighbours, &mut self.jac_x, &mut self.jac_v);
            // With contact and no locks, the rest's blocks first, kept for
            // `refresh_contact` (in the last ones' buffers), then the contact's.
            let kept = self.rest.take();
            let mut whole = !self.has_locks && gather(neighbours, jac_x, jac_v, |add| source.rest_jacobian(y, add));
            if whole {
                let (mut rest_x, mut rest_v) = kept.unwrap_or_default();
                rest_x.clone_from(jac_x);
                rest_v.clone_from(jac_v);
                self.rest = Some((rest_x, rest_v));
                whole = gather(neighbours, jac_x, jac_v, |add| source.contact_jacobian(y, add));
            } else {
                jac_x.iter_mut().flatten().for_each(|b| *b = PoseBlock::zeros());
                jac_v.iter_mut().flatten().for_each(|b| *b = Block::zeros());
                whole = gather(neighbours, jac_x, jac_v, |add| source.acceleration_jacobian(y, add));
            }
            if whole {
                self.group_rows.clear();
                if self.has_locks {
                    // No rows: every lock idle or disengaged (see
                    // `ExactJacobian::constraint_jacobian`).
                    let locks = gather(neighbours, jac_x, jac_v, |add| source.constraint_jacobian(y, add));
                    self.group_rows = locks.rows;
                    self.carry_locks(locks.groups);
                }
                self.exact_count += 1;
                return self.refactor(h_gamma);
            }
        }
        if self.has_locks {
            // The structure carries the constraints as rows, which differences of the
            // constrained right-hand side do not fit (every law has a dual form).
            return false;
        }
        self.differenced_count += 1;
        // The base point of the differences.
        let mut f = vec![0.0; self.n];
        self.system.rhs(t, y, &mut f);
        self.evaluations += 1;
        let mut yp = y.to_vec();
        let mut fp = vec![0.0; self.n];
        for class in &self.colours {
            for k in 0..B {
                let mut steps = Vec::with_capacity(class.len());
                for &b in class {
                    let idx = B * b + k;
                    let d = (f64::EPSILON * y[idx].abs().max(1e-3)).sqrt();
                    yp[idx] = y[idx] + d;
                    steps.push(d);
                }
                self.system.rhs(t, &yp, &mut fp);
                self.evaluations += 1;
                for (&b, &d) in class.iter().zip(&steps) {
                    yp[B * b + k] = y[B * b + k];
                    // Column k of body b, in the accelerations of b's neighbours i (b is in
                    // i's neighbourhood: the relation is symmetric).
                    for &i in &self.neighbours[b] {
                        let slot = self.neighbours[i].binary_search(&b).expect("symmetric neighbourhoods");
                        for r in 0..V {
                            let v = (fp[B * i + VEL + r] - f[B * i + VEL + r]) / d;
                            if k < X {
                                self.jac_x[i][slot][(r, k)] = v;
                            } else {
                                self.jac_v[i][slot][(r, k - X)] = v;
                            }
                        }
                    }
                }
            }
        }
        self.refactor(h_gamma)
    }

    fn refactor(&mut self, h_gamma: f64) -> bool {
        self.h_gamma = h_gamma;
        // The elimination's pattern for this order and these locks, found once
        // (`symbolic.rs`); the two last are kept (the orders with and without the locks).
        let k = match self.symbolic.iter().position(|s| s.fits(&self.order, &self.groups)) {
            Some(k) => k,
            None => {
                let mut pattern = vec![Vec::new(); self.nb + self.groups.len()];
                self.twist_entries(h_gamma, &mut |i, j, _| pattern[i].push(j));
                let Some(s) = Symbolic::new(&pattern, &self.order, &self.position, &self.groups) else {
                    self.singular = None;
                    return false;
                };
                if self.symbolic.len() == 2 {
                    self.symbolic.remove(0);
                }
                self.symbolic.push(s);
                self.symbolic.len() - 1
            }
        };
        let mut values = std::mem::take(&mut self.values);
        values.clear();
        values.resize(self.symbolic[k].slots(), Block::zeros());
        let symbolic = &self.symbolic[k];
        self.twist_entries(h_gamma, &mut |i, j, b| {
            values[symbolic.slot(i, j).expect("the pattern holds every block")] += b;
        });
        let eliminated = self.symbolic[k].eliminate(&mut values, &mut self.pivots, &mut self.upper, &mut self.lower);
        self.values = values;
        self.singular = eliminated.err();
        eliminated.is_ok()
    }

    fn singular_block(&self) -> Option<usize> {
        self.singular
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let h_gamma = self.h_gamma;
        let pose_of = |v: &[f64], b: usize| Vec7::from_column_slice(&v[B * b..B * b + X]);
        let twist_of = |v: &[f64], b: usize| Vec6::from_column_slice(&v[B * b + X..B * (b + 1)]);
        // P r_x per body, then r_v += hγ Σ_j A_x[i][j] P_j r_x,j. (Scratch vectors kept
        // across solves: for thousands of bodies a fresh allocation costs page faults.)
        let (mut p_rx, mut twist) = (std::mem::take(&mut self.p_rx), std::mem::take(&mut self.twist));
        p_rx.clear();
        p_rx.extend((0..self.nb).map(|b| self.pose[b].p_times(&pose_of(rhs, b), h_gamma)));
        twist.clear();
        twist.extend((0..self.nb).map(|i| {
            let mut r = twist_of(rhs, i);
            for (slot, &j) in self.neighbours[i].iter().enumerate() {
                r += self.jac_x[i][slot] * p_rx[j] * h_gamma;
            }
            r
        }));
        // Locked hinges: J r_v − hγ ∂(Ja+γ)/∂x P r_x (zero beyond the locked directions).
        let mut first = 0;
        for &(p, c, k) in &self.groups {
            let mut r = Vec6::zeros();
            for (i, row) in self.group_rows[first..first + k].iter().enumerate() {
                for (side, b) in [p, c].into_iter().enumerate() {
                    let r_v = twist_of(rhs, b);
                    r[i] += (0..V).map(|col| row.j[side][col] * r_v[col]).sum::<f64>()
                        - h_gamma * (0..X).map(|col| row.d_pose[side][col] * p_rx[b][col]).sum::<f64>();
                }
            }
            twist.push(r);
            first += k;
        }
        // The two triangular solves (`kernel.rs`).
        let factors =
            kernel::Factors { order: &self.order, pivots: &self.pivots, upper: &self.upper, lower: &self.lower };
        kernel::Kernel::detect().substitute(&factors, &mut twist);
        // Poses: Δx = P (r_x + hγ ∂ẋ/∂v Δv) = P r_x + hγ P ∂ẋ/∂v Δv.
        for b in 0..self.nb {
            let dx = p_rx[b] + self.pose[b].p_times(&self.pose[b].rates_times(&twist[b]), h_gamma) * h_gamma;
            rhs[B * b..B * b + X].copy_from_slice(dx.as_slice());
            rhs[B * b + X..B * (b + 1)].copy_from_slice(twist[b].as_slice());
        }
        // Dissipation rows: identity (see the module documentation).
        (self.p_rx, self.twist) = (p_rx, twist);
    }

    fn evaluations(&self) -> usize {
        self.evaluations
    }
}

mod kernel;
pub mod order;
pub(crate) mod symbolic;
#[cfg(test)]
mod tests;
