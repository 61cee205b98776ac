//! A Newton matrix whose sparsity is the hinge graph, for the implicit integrator.
//!
//! `W = I − hγ J` in 13×13 blocks, one block row and column per body (pose and twist, see
//! [`crate::state`]); block (i, j) is nonzero only if bodies i and j are the same or share a
//! hinge. The Jacobian's blocks come from forward differences of the right-hand side with a
//! distance-2 colouring of the body graph: bodies of one colour have disjoint neighbourhoods,
//! so one evaluation per colour and state component fills all their columns (13 × colours
//! evaluations, not 13 × bodies). W is factored by block Gaussian elimination in a
//! minimum-degree order (exact, no fill for trees; fill along loops), dense LU inside the
//! diagonal blocks. Each hinge's dissipated-energy integral depends on the bodies but feeds
//! nothing back; its rows are taken as the identity, which simplified Newton tolerates (those
//! components converge in one iteration once the bodies have).

use crate::implicit::NewtonMatrix;
use crate::model::Model;
use crate::ode::OdeSystem;
use crate::state::BODY_STATE_LEN as B;
use nalgebra::SMatrix;
use std::collections::BTreeMap;

type Block = SMatrix<f64, B, B>;

/// The hinge-graph-sparse Newton matrix of a model's equations of motion.
pub struct GraphNewton<'a, S: OdeSystem + ?Sized> {
    system: &'a S,
    nb: usize,
    n: usize,
    /// Closed neighbourhoods: each body and the bodies it shares a hinge with.
    neighbours: Vec<Vec<usize>>,
    /// Colour classes of a distance-2 colouring.
    colours: Vec<Vec<usize>>,
    /// Jacobian blocks J[(i, j)] (row body i, column body j).
    jacobian: BTreeMap<(usize, usize), Block>,
    /// Elimination order and the factored blocks.
    order: Vec<usize>,
    /// Per eliminated body p: LU of the pivot block, and its row blocks U[p][j] and
    /// multipliers L[i][p] = W[i][p] W[p][p]⁻¹, for neighbours later in the order.
    pivots: Vec<Option<nalgebra::LU<f64, nalgebra::Const<B>, nalgebra::Const<B>>>>,
    upper: Vec<Vec<(usize, Block)>>,
    lower: Vec<Vec<(usize, Block)>>,
    evaluations: usize,
}

impl<'a, S: OdeSystem + ?Sized> GraphNewton<'a, S> {
    /// The Newton matrix of `system`, whose state is laid out for `model` (bodies, then one
    /// integral per hinge).
    pub fn new(system: &'a S, model: &Model) -> Self {
        let nb = model.bodies.len();
        let mut neighbours: Vec<Vec<usize>> = (0..nb).map(|i| vec![i]).collect();
        for h in &model.hinges {
            if !neighbours[h.parent].contains(&h.child) {
                neighbours[h.parent].push(h.child);
                neighbours[h.child].push(h.parent);
            }
        }
        for v in &mut neighbours {
            v.sort_unstable();
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
        // Minimum-degree elimination order on the body graph, with fill.
        let mut adj: Vec<std::collections::BTreeSet<usize>> =
            neighbours.iter().enumerate().map(|(i, v)| v.iter().copied().filter(|&j| j != i).collect()).collect();
        let mut done = vec![false; nb];
        let mut order = Vec::with_capacity(nb);
        for _ in 0..nb {
            let p = (0..nb).filter(|&i| !done[i]).min_by_key(|&i| adj[i].len()).expect("a body left");
            done[p] = true;
            order.push(p);
            let nbrs: Vec<usize> = adj[p].iter().copied().filter(|&j| !done[j]).collect();
            for &i in &nbrs {
                adj[i].remove(&p);
                for &j in &nbrs {
                    if i != j {
                        adj[i].insert(j);
                    }
                }
            }
        }
        let n = B * nb + model.hinges.len();
        Self {
            system,
            nb,
            n,
            neighbours,
            colours,
            jacobian: BTreeMap::new(),
            order,
            pivots: Vec::new(),
            upper: Vec::new(),
            lower: Vec::new(),
            evaluations: 0,
        }
    }

    /// Number of colours of the distance-2 colouring (Jacobian cost: 13 × colours evaluations).
    pub fn colour_count(&self) -> usize {
        self.colours.len()
    }
}

impl<S: OdeSystem + ?Sized> NewtonMatrix for GraphNewton<'_, S> {
    fn prepare(&mut self, t: f64, y: &[f64], f: &[f64], h_gamma: f64) -> bool {
        self.jacobian.clear();
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
                    for &i in &self.neighbours[b] {
                        let block = self.jacobian.entry((i, b)).or_insert_with(Block::zeros);
                        for r in 0..B {
                            block[(r, k)] = (fp[B * i + r] - f[B * i + r]) / d;
                        }
                    }
                }
            }
        }
        self.refactor(h_gamma)
    }

    fn refactor(&mut self, h_gamma: f64) -> bool {
        // W blocks, then elimination in order.
        let mut w: Vec<BTreeMap<usize, Block>> = vec![BTreeMap::new(); self.nb];
        for (&(i, j), jb) in &self.jacobian {
            let mut blk = -jb * h_gamma;
            if i == j {
                blk += Block::identity();
            }
            w[i].insert(j, blk);
        }
        let mut position = vec![0; self.nb];
        for (k, &p) in self.order.iter().enumerate() {
            position[p] = k;
        }
        self.pivots = vec![None; self.nb];
        self.upper = vec![Vec::new(); self.nb];
        self.lower = vec![Vec::new(); self.nb];
        for &p in &self.order {
            let Some(pivot) = w[p].get(&p).copied() else { return false };
            let lu = pivot.lu();
            if !lu.is_invertible() {
                return false;
            }
            let later: Vec<usize> = w[p].keys().copied().filter(|&j| position[j] > position[p]).collect();
            let upper: Vec<(usize, Block)> = later.iter().map(|&j| (j, w[p][&j])).collect();
            let mut lower = Vec::with_capacity(later.len());
            let pivot_t = pivot.transpose().lu();
            for &i in &later {
                let Some(w_ip) = w[i].get(&p).copied() else { continue };
                // L = W[i][p] W[p][p]⁻¹, from W[p][p]ᵀ Lᵀ = W[i][p]ᵀ.
                let lt = pivot_t.solve(&w_ip.transpose());
                let Some(lt) = lt else { return false };
                let l = lt.transpose();
                for (j, u) in &upper {
                    let entry = w[i].entry(*j).or_insert_with(Block::zeros);
                    *entry -= l * u;
                }
                lower.push((i, l));
            }
            self.pivots[p] = Some(lu);
            self.upper[p] = upper;
            self.lower[p] = lower;
        }
        true
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let get = |v: &[f64], b: usize| nalgebra::SVector::<f64, B>::from_column_slice(&v[B * b..B * (b + 1)]);
        // Forward: for p in order, x_i −= L[i][p] x_p.
        for &p in &self.order {
            let xp = get(rhs, p);
            for (i, l) in &self.lower[p] {
                let xi = get(rhs, *i) - l * xp;
                rhs[B * i..B * (i + 1)].copy_from_slice(xi.as_slice());
            }
        }
        // Backward: for p in reverse order, x_p = W[p][p]⁻¹ (x_p − Σ U[p][j] x_j).
        for &p in self.order.iter().rev() {
            let mut xp = get(rhs, p);
            for (j, u) in &self.upper[p] {
                xp -= u * get(rhs, *j);
            }
            let sol = self.pivots[p].as_ref().expect("factored").solve(&xp).expect("invertible pivot");
            rhs[B * p..B * (p + 1)].copy_from_slice(sol.as_slice());
        }
        // Dissipation rows: identity (see the module documentation).
    }

    fn evaluations(&self) -> usize {
        self.evaluations
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::Dynamics;
    use crate::implicit::DenseNewton;
    use crate::init::initial_state;
    use crate::scenario::Scenario;

    /// On the 3-panel case (a loop hinge, so elimination makes fill), the graph-sparse solve
    /// must match the dense one: both use forward-difference Jacobians (steps differ), so
    /// agreement to 1e-5 relative is what the differencing allows; a wrong block, colour or
    /// elimination step would be off by O(1).
    #[test]
    fn graph_solve_matches_dense_solve() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/paper-3panel.toml")).unwrap();
        let s = Scenario::from_toml(&text, "p3").unwrap();
        let (y, refs) = initial_state(&s.model, &s.initial);
        let dynamics = Dynamics::new(&s.model, refs);
        dynamics.initialize_memory(&y);
        let mut f = vec![0.0; y.len()];
        crate::ode::OdeSystem::rhs(&dynamics, 0.0, &y, &mut f);
        let h_gamma = 0.05;
        let mut graph = GraphNewton::new(&dynamics, &s.model);
        let mut dense = DenseNewton::new(&dynamics, y.len());
        assert!(graph.prepare(0.0, &y, &f, h_gamma));
        assert!(dense.prepare(0.0, &y, &f, h_gamma));
        let b: Vec<f64> = (0..y.len()).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        let (mut xg, mut xd) = (b.clone(), b.clone());
        graph.solve(&mut xg);
        dense.solve(&mut xd);
        let nb = 13 * s.model.bodies.len();
        let scale = xd[..nb].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = xg[..nb].iter().zip(&xd[..nb]).fold(0.0f64, |m, (a, c)| m.max((a - c).abs()));
        assert!(diff <= 1e-5 * scale, "graph vs dense: {diff:e} of {scale:e}");
        assert!(graph.colour_count() <= 4, "4 bodies need at most 4 colours");
    }
}
