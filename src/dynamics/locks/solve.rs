//! The multiplier solves: the smallest mass-weighted correction `Δ = M⁻¹ Jᵀ λ` that meets
//! every engaged lock's row, along the forest of locked hinges, dense for a few rows, or in
//! the envelope of `J M⁻¹ Jᵀ`; and the acceleration correction the right-hand side applies.

use super::rows::{Lock, Row, rows};
use crate::math::{Euler321, Vec3};
use crate::model::Model;
use crate::state::{BODY_STATE_LEN, BodyMotion, OMEGA, VEL};

/// A row's part on one body in that body's twist components (linear: N, angular: body, as
/// the state's `(v, ω)` and their derivatives are stored): its coefficients, and `M⁻¹ Jᵀ`,
/// from the linear and angular coefficients `lin`, `ang` (N components).
/// Written into `out` in place (returning the 96 bytes costs a copy per row).
#[inline]
fn on_body(model: &Model, motions: &[BodyMotion], body: usize, lin: &Vec3, ang: &Vec3, out: &mut [[f64; 6]]) {
    let b = &model.bodies[body];
    let ang_b = motions[body].dcm_n_b.tr_mul(ang);
    let m_ang = b.inertia_inv_in_body * ang_b;
    let inv_mass = 1.0 / b.mass;
    out[0] = [lin.x, lin.y, lin.z, ang_b.x, ang_b.y, ang_b.z];
    out[1] = [lin.x * inv_mass, lin.y * inv_mass, lin.z * inv_mass, m_ang.x, m_ang.y, m_ang.z];
}

/// Body `b`'s twist part `(v̇ or Δv in N components, ω̇ or Δω in body components)` of a
/// state-like vector `y` (the layout of [`crate::state`]: VEL and OMEGA are adjacent).
#[inline]
fn twist6(y: &[f64], b: usize) -> &[f64; 6] {
    const { assert!(OMEGA == VEL + 3) };
    let o = BODY_STATE_LEN * b + VEL;
    y[o..o + 6].try_into().expect("six components")
}

/// Work space for the multiplier solves, reused across evaluations.
///
/// Each solve finds the smallest mass-weighted correction `Δ = M⁻¹ Jᵀ λ` with `J Δ = −r` for
/// residuals r (accelerations: `J a + γ`; projections: the locked coordinates' errors or
/// rates), in one of two ways:
/// - When the locked hinges form a forest over the bodies (no loop of locked hinges, the usual
///   case), by eliminating the augmented system `[M −Jᵀ; J 0]` along each tree from the leaves
///   (Baraff's linear-time ordering: a body, then the hinge joining it to its parent, so a
///   body's block grows into its articulated inertia `A = M + Σ J_pᵀ (J_c A_c⁻¹ J_cᵀ)⁻¹ J_p`
///   and nothing fills in). Linear in the locks for every tree shape: a hub with many locked
///   panels too.
/// - Otherwise `K = J M⁻¹ Jᵀ`, which couples only rows whose hinges share a body, is
///   assembled hinge pair by hinge pair into envelope storage — row i holds columns
///   `first[i]..=i`, `first[i]` the first row of the earliest hinge sharing a body with row
///   i's — and factored there (Cholesky makes no fill outside the envelope).
#[derive(Debug, Default)]
pub struct Workspace {
    /// Per row, in the bodies' twist components (linear: N, angular: body): its coefficients
    /// on the parent, `M⁻¹ Jᵀ` on the parent, its coefficients on the child, `M⁻¹ Jᵀ` on the
    /// child.
    parts: Vec<[[f64; 6]; 4]>,
    /// Rows `start..end` of each hinge (rows of one hinge are contiguous).
    groups: Vec<(usize, usize)>,
    /// Hinges (indices into `groups`) met so far per body (emptied after use).
    by_body: Vec<Vec<usize>>,
    /// The products that make up K's entries within the envelope: (index into `matrix`, row
    /// r, row s, side of r's coefficients, side of s's `M⁻¹ Jᵀ`), one per body that rows r
    /// and s share (indices into `parts`: 0 or 2, and 1 or 3).
    terms: Vec<(usize, usize, usize, u8, u8)>,
    /// Per hinge (start row, end row, parent, child): what `terms`, `first` and `offset`
    /// were computed for.
    structure: Vec<(usize, usize, usize, usize)>,
    /// Per row: the first column of its envelope.
    first: Vec<usize>,
    /// Per row: where its envelope starts in `matrix`.
    offset: Vec<usize>,
    /// K's lower triangle within the envelope, row by row, then its Cholesky factor.
    matrix: Vec<f64>,
    /// Reciprocals of the factor's diagonal (the factorization and solves multiply rather
    /// than divide: divisions would lengthen the latency chain several times).
    inv_diag: Vec<f64>,
    /// Right-hand side, then the multipliers λ.
    lambda: Vec<f64>,
    /// Residuals of the rows (kept for its allocation).
    residual: Vec<f64>,
    /// The elimination order and its scratch when the locked hinges form a forest and
    /// eliminating along it is the cheaper solve.
    forest: Option<Forest>,
    /// Per body: the correction `Δ = M⁻¹ Jᵀ λ` of the last solve, components as for `z`.
    pub(super) delta: Vec<[f64; 6]>,
    /// Bodies that locked hinges join.
    pub(super) touched: Vec<usize>,
}

/// A 6×6 block, row-major.
type Mat6 = [[f64; 6]; 6];

/// Most rows solved dense on the stack rather than in the envelope (see
/// [`Workspace::solve_small`]).
const SMALL: usize = 12;

/// The forest of locked hinges: hinges (indices into `groups`) in breadth-first order from
/// each tree's root, as (hinge, near body, far body, far body's side in the rows: 0 parent,
/// 1 child), and the roots.
#[derive(Debug, Default)]
struct Forest {
    order: Vec<(usize, usize, usize, usize)>,
    /// Per entry of `order`: whether its far body is a leaf (no other locked hinge).
    leaf: Vec<bool>,
    roots: Vec<usize>,
    /// Per body: the articulated block A (then its Cholesky factor) and the right-hand side z
    /// (then `A⁻¹ z`), components (linear: N, angular: body).
    art: Vec<Mat6>,
    z: Vec<[f64; 6]>,
    /// Per row: `A_c⁻¹ J_cᵀ` on its hinge's far body, `L_K⁻¹ J_p` on its near body, and
    /// `L_K⁻¹ b`. Per hinge: the Cholesky factor of `K = J_c A_c⁻¹ J_cᵀ`.
    w: Vec<[f64; 6]>,
    p: Vec<[f64; 6]>,
    beta: Vec<f64>,
    k_factor: Vec<Mat6>,
}

impl Forest {
    /// The elimination of [`Workspace::correct_forest`] along this forest: the corrections
    /// into `delta` and the multipliers into `lambda`, from the rows' body components `parts`
    /// and their grouping by hinge `groups`, for the bodies `touched`.
    #[allow(clippy::needless_range_loop, clippy::too_many_arguments)] // index loops over small dense blocks, as the formulas
    fn eliminate(
        &mut self,
        model: &Model,
        rows: &[Row],
        residual: &[f64],
        parts: &[[[f64; 6]; 4]],
        groups: &[(usize, usize)],
        touched: &[usize],
        lambda: &mut Vec<f64>,
        delta: &mut [[f64; 6]],
    ) -> bool {
        let nb = model.bodies.len();
        if self.art.len() < nb {
            self.art.resize(nb, [[0.0; 6]; 6]);
            self.z.resize(nb, [0.0; 6]);
        }
        let n = rows.len();
        self.w.resize(n, [0.0; 6]);
        self.p.resize(n, [0.0; 6]);
        self.beta.resize(n, 0.0);
        self.k_factor.resize(groups.len(), [[0.0; 6]; 6]);
        lambda.clear();
        lambda.resize(n, 0.0);
        // The row's coefficients on one side, body components (linear: N, angular: body).
        let row_on = |r: usize, side: usize| -> [f64; 6] { parts[r][2 * side] };
        for &b in touched {
            let body = &model.bodies[b];
            let mut a = [[0.0; 6]; 6];
            for k in 0..3 {
                a[k][k] = body.mass;
                for l in 0..3 {
                    a[3 + k][3 + l] = body.inertia_in_body[(k, l)];
                }
            }
            self.art[b] = a;
            self.z[b] = [0.0; 6];
        }
        // From the leaves: factor the far body's block (complete: its own hinges further out
        // come later in breadth-first order, so were eliminated before), then the hinge.
        for (&(g, near, far, far_side), &leaf) in self.order.iter().zip(&self.leaf).rev() {
            let (start, end) = groups[g];
            let k = end - start;
            // A leaf's block is its mass matrix, whose inverse the rows already carry
            // (`M⁻¹ Jᵀ`), and its right-hand side is zero.
            if !leaf {
                if !cholesky_small(&mut self.art[far], 6) {
                    return false;
                }
                let (l_far, z_far) = (&self.art[far], &mut self.z[far]);
                forward_small(l_far, 6, z_far);
                backward_small(l_far, 6, z_far);
            }
            let (y_far, l_far) = (&self.z[far], &self.art[far]);
            let mut j_far = [[0.0; 6]; 6];
            let mut j_near = [[0.0; 6]; 6];
            for r in start..end {
                j_far[r - start] = row_on(r, far_side);
                j_near[r - start] = row_on(r, 1 - far_side);
            }
            let mut kk = [[0.0; 6]; 6];
            for r in start..end {
                let j = &j_far[r - start];
                let w = if leaf {
                    parts[r][2 * far_side + 1]
                } else {
                    let mut w = *j;
                    forward_small(l_far, 6, &mut w);
                    backward_small(l_far, 6, &mut w);
                    w
                };
                self.w[r] = w;
                for s in start..=r {
                    kk[r - start][s - start] = dot6(&j_far[s - start], &w);
                }
                self.beta[r] = -residual[r] - dot6(j, y_far);
            }
            if !cholesky_small(&mut kk, k) {
                return false;
            }
            // P = L_K⁻¹ J_near, β = L_K⁻¹ b, column by column of the near side.
            for c in 0..6 {
                let mut x: [f64; 6] = std::array::from_fn(|i| if i < k { j_near[i][c] } else { 0.0 });
                forward_small(&kk, k, &mut x);
                for i in 0..k {
                    self.p[start + i][c] = x[i];
                }
            }
            forward_small(&kk, k, &mut self.beta[start..end]);
            self.k_factor[g] = kk;
            // Lower triangles only: the factorization reads no more.
            let (art, z) = (&mut self.art[near], &mut self.z[near]);
            for r in start..end {
                let (p, beta) = (&self.p[r], self.beta[r]);
                for i in 0..6 {
                    z[i] += p[i] * beta;
                    for j in 0..=i {
                        art[i][j] += p[i] * p[j];
                    }
                }
            }
        }
        for &root in &self.roots {
            if !cholesky_small(&mut self.art[root], 6) {
                return false;
            }
            let l = &self.art[root];
            let mut d = self.z[root];
            forward_small(l, 6, &mut d);
            backward_small(l, 6, &mut d);
            delta[root] = d;
        }
        // From the roots: each hinge's multipliers, then its far body.
        for &(g, near, far, _) in &self.order {
            let (start, end) = groups[g];
            let k = end - start;
            let d_near = delta[near];
            let mut mult = [0.0; 6];
            for r in start..end {
                mult[r - start] = self.beta[r] - dot6(&self.p[r], &d_near);
            }
            backward_small(&self.k_factor[g], k, &mut mult[..k]);
            lambda[start..end].copy_from_slice(&mult[..k]);
            let mut d = self.z[far];
            for r in start..end {
                for i in 0..6 {
                    d[i] += self.w[r][i] * mult[r - start];
                }
            }
            delta[far] = d;
        }
        true
    }
}

/// In-place Cholesky factorization of the leading n×n block of `a` (lower triangle, with
/// the reciprocal of the diagonal stored on the diagonal). False if not positive definite.
// Index loops over small dense blocks read as the formulas they implement.
#[allow(clippy::needless_range_loop)]
fn cholesky_small(a: &mut Mat6, n: usize) -> bool {
    for i in 0..n {
        for j in 0..=i {
            let mut v = a[i][j];
            for k in 0..j {
                v -= a[i][k] * a[j][k];
            }
            if i == j {
                if v.is_nan() || v <= 0.0 {
                    return false;
                }
                a[i][i] = 1.0 / v.sqrt();
            } else {
                a[i][j] = v * a[j][j];
            }
        }
    }
    true
}

/// `x ← L⁻¹ x` for a factor from [`cholesky_small`].
fn forward_small(l: &Mat6, n: usize, x: &mut [f64]) {
    for i in 0..n {
        let mut v = x[i];
        for k in 0..i {
            v -= l[i][k] * x[k];
        }
        x[i] = v * l[i][i];
    }
}

/// `x ← L⁻ᵀ x` for a factor from [`cholesky_small`].
fn backward_small(l: &Mat6, n: usize, x: &mut [f64]) {
    for i in (0..n).rev() {
        let v = x[i] * l[i][i];
        x[i] = v;
        for k in 0..i {
            x[k] -= l[i][k] * v;
        }
    }
}

/// `a · b` for 6-vectors.
#[inline]
fn dot6(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Workspace {
    /// The multipliers λ of the last solve, one per row (`Δ = M⁻¹ Jᵀ λ`).
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }

    /// Entry (i, j), j in `first[i]..=i`, of the envelope storage.
    #[inline]
    fn at(&self, i: usize, j: usize) -> usize {
        self.offset[i] + j - self.first[i]
    }

    /// Forms the rows' body components and `M⁻¹ Jᵀ` for `rows` at `motions`, and the
    /// structure of the solve when the set of locked hinges changed.
    pub(super) fn prepare(&mut self, model: &Model, rows: &[Row], motions: &[BodyMotion]) {
        let bodies = &model.bodies;
        // Per row and side: the coefficients in body components and M⁻¹ Jᵀ.
        // Filled in place: pushing the 192-byte parts costs a copy each.
        self.parts.resize(rows.len(), [[0.0; 6]; 4]);
        self.groups.clear();
        for (i, (r, part)) in rows.iter().zip(self.parts.iter_mut()).enumerate() {
            on_body(model, motions, r.parent, &r.lin_p, &r.ang_p, &mut part[..2]);
            on_body(model, motions, r.child, &r.lin_c, &r.ang_c, &mut part[2..]);
            match self.groups.last_mut() {
                Some((start, end)) if rows[*start].parent == r.parent && rows[*start].child == r.child => *end = i + 1,
                _ => self.groups.push((i, i + 1)),
            }
        }
        // Which hinges each hinge meets (through the bodies' hinge lists: linear in the
        // locks), and so the envelope.
        // The structure depends only on which hinges are locked: computed when it changes.
        let key = self.groups.iter().map(|g| (g.0, g.1, rows[g.0].parent, rows[g.0].child));
        if !key.clone().eq(self.structure.iter().copied()) {
            self.structure.clear();
            self.structure.extend(key);
            self.forest = forest(&self.structure, bodies.len());
            self.touched = self.structure.iter().flat_map(|s| [s.2, s.3]).collect();
            self.touched.sort_unstable();
            self.touched.dedup();
            // The envelope: each hinge's rows start at the first row of the earliest hinge
            // sharing a body with it (hinges are met in order, so the first one met at a body
            // is its earliest).
            if self.by_body.len() < bodies.len() {
                self.by_body.resize(bodies.len(), Vec::new());
            }
            self.first.clear();
            self.offset.clear();
            let mut size = 0;
            for (gi, g) in self.groups.iter().enumerate() {
                let (p, c) = (rows[g.0].parent, rows[g.0].child);
                let earliest =
                    [&self.by_body[p], &self.by_body[c]].iter().filter_map(|v| v.first()).fold(gi, |a, &b| a.min(b));
                let first = self.groups[earliest].0;
                for i in g.0..g.1 {
                    self.first.push(first);
                    self.offset.push(size);
                    size += i - first + 1;
                }
                self.by_body[p].push(gi);
                self.by_body[c].push(gi);
            }
            // Eliminate along the forest only where it is cheaper: its 6×6 body blocks cost
            // more than a narrow envelope (a chain with one or two locks per hinge), far less
            // than a wide one (a hub holding many locked hinges makes K dense). Estimated
            // multiply-adds per solve; the constants follow the loops below. Up to SMALL rows,
            // K dense on the stack is cheapest (the 1-DOF example all locked, 10 rows: 1.2
            // against 1.5–1.9 µs per evaluation by the forest).
            if let Some(f) = &self.forest {
                let tree: usize = f
                    .order
                    .iter()
                    .zip(&f.leaf)
                    .map(|(o, leaf)| {
                        let k = self.groups[o.0].1 - self.groups[o.0].0;
                        k * (30 + 6 * k) + if *leaf { 30 } else { 100 + 80 * k }
                    })
                    .sum::<usize>()
                    + 100 * f.roots.len();
                let envelope: usize =
                    (0..self.first.len()).map(|i| (i - self.first[i] + 1) * (i - self.first[i] + 25) / 2).sum();
                if tree >= envelope || rows.len() <= SMALL {
                    self.forest = None;
                }
            }
            for g in &self.groups {
                self.by_body[rows[g.0].parent].clear();
                self.by_body[rows[g.0].child].clear();
            }
            self.terms.clear();
            if self.forest.is_none() {
                self.envelope_terms(rows);
            }
        }
    }

    /// The products that make up K's entries, from the hinge pairs that share a body (the
    /// envelope's nonzero blocks: for a hub holding n locked hinges there are n²/2, so they
    /// are listed only when the envelope is used).
    fn envelope_terms(&mut self, rows: &[Row]) {
        self.terms.clear();
        for (gi, g) in self.groups.iter().enumerate() {
            let (p, c) = (rows[g.0].parent, rows[g.0].child);
            let mut partners: Vec<usize> = self.by_body[p].iter().chain(&self.by_body[c]).copied().collect();
            partners.push(gi);
            partners.sort_unstable();
            partners.dedup();
            for hi in partners {
                let h = self.groups[hi];
                let (ph, ch) = (rows[h.0].parent, rows[h.0].child);
                for r in g.0..g.1 {
                    for s in h.0..h.1.min(r + 1) {
                        let k = self.offset[r] + s - self.first[r];
                        for (a, body_r) in [(0, p), (2, c)] {
                            for (b, body_s) in [(1, ph), (3, ch)] {
                                if body_r == body_s {
                                    self.terms.push((k, r, s, a, b));
                                }
                            }
                        }
                    }
                }
            }
            self.by_body[p].push(gi);
            self.by_body[c].push(gi);
        }
        for g in &self.groups {
            self.by_body[rows[g.0].parent].clear();
            self.by_body[rows[g.0].child].clear();
        }
    }

    /// Assembles `K = J M⁻¹ Jᵀ` (after [`Self::prepare`]) in its envelope and factors it.
    /// Returns false if K is singular (redundant locks).
    fn factor_envelope(&mut self) -> bool {
        let size = self.offset.last().map_or(0, |o| o + self.first.len() - self.first.last().unwrap_or(&0));
        self.matrix.clear();
        self.matrix.resize(size, 0.0);
        for &(k, r, s, a, b) in &self.terms {
            self.matrix[k] += dot6(&self.parts[r][a as usize], &self.parts[s][b as usize]);
        }
        self.cholesky()
    }

    /// Cholesky factorization of `matrix` in place, within the envelope.
    fn cholesky(&mut self) -> bool {
        let n = self.first.len();
        self.inv_diag.clear();
        for i in 0..n {
            let fi = self.first[i];
            for j in fi..i {
                let f = fi.max(self.first[j]);
                let (ri, rj) = (self.at(i, f), self.at(j, f));
                let mut v = self.matrix[self.at(i, j)];
                for k in 0..j - f {
                    v -= self.matrix[ri + k] * self.matrix[rj + k];
                }
                let ij = self.at(i, j);
                self.matrix[ij] = v * self.inv_diag[j];
            }
            let ri = self.offset[i];
            let d = self.matrix[self.at(i, i)] - self.matrix[ri..ri + i - fi].iter().map(|x| x * x).sum::<f64>();
            if d.is_nan() || d <= 0.0 {
                return false;
            }
            let d = d.sqrt();
            let ii = self.at(i, i);
            self.matrix[ii] = d;
            self.inv_diag.push(1.0 / d);
        }
        true
    }

    /// Overwrites `self.lambda` (the right-hand side) with `K⁻¹` of it for at most [`SMALL`]
    /// rows, K assembled and factored dense on the stack (after [`Self::prepare`]): for a
    /// few locks the envelope's bookkeeping costs more than the arithmetic. Returns false if
    /// K is singular.
    #[allow(clippy::needless_range_loop)] // index loops over a small dense matrix, as the formulas
    fn solve_small(&mut self, rows: &[Row]) -> bool {
        let n = rows.len();
        let mut k = [[0.0; SMALL]; SMALL];
        // K_ij = Σ over the bodies rows i and j share of (J_i)_b · (M⁻¹ J_jᵀ)_b.
        for i in 0..n {
            let (pi, ci) = (rows[i].parent, rows[i].child);
            for j in 0..=i {
                let (pj, cj) = (rows[j].parent, rows[j].child);
                let (a, b) = (&self.parts[i], &self.parts[j]);
                let mut v = 0.0;
                for (side_i, body_i) in [(0, pi), (2, ci)] {
                    for (side_j, body_j) in [(1, pj), (3, cj)] {
                        if body_i == body_j {
                            v += dot6(&a[side_i], &b[side_j]);
                        }
                    }
                }
                k[i][j] = v;
            }
        }
        // Cholesky, lower triangle in place, with the diagonal's reciprocals.
        let mut inv_diag = [0.0; SMALL];
        for i in 0..n {
            for j in 0..i {
                let mut v = k[i][j];
                for m in 0..j {
                    v -= k[i][m] * k[j][m];
                }
                k[i][j] = v * inv_diag[j];
            }
            let d = k[i][i] - (0..i).map(|m| k[i][m] * k[i][m]).sum::<f64>();
            if d.is_nan() || d <= 0.0 {
                return false;
            }
            inv_diag[i] = 1.0 / d.sqrt();
        }
        let x = &mut self.lambda;
        for i in 0..n {
            let v = x[i] - (0..i).map(|m| k[i][m] * x[m]).sum::<f64>();
            x[i] = v * inv_diag[i];
        }
        for i in (0..n).rev() {
            let v = x[i] - (i + 1..n).map(|m| k[m][i] * x[m]).sum::<f64>();
            x[i] = v * inv_diag[i];
        }
        true
    }

    /// Overwrites `self.lambda` (the right-hand side) with `K⁻¹` of it.
    fn solve(&mut self) {
        let n = self.lambda.len();
        for i in 0..n {
            let (fi, ri) = (self.first[i], self.offset[i]);
            let mut v = self.lambda[i];
            for (k, l) in (fi..i).zip(&self.matrix[ri..]) {
                v -= l * self.lambda[k];
            }
            self.lambda[i] = v * self.inv_diag[i];
        }
        for i in (0..n).rev() {
            let (fi, ri) = (self.first[i], self.offset[i]);
            let v = self.lambda[i] * self.inv_diag[i];
            self.lambda[i] = v;
            for (k, l) in (fi..i).zip(&self.matrix[ri..]) {
                self.lambda[k] -= l * v;
            }
        }
    }

    /// The smallest mass-weighted correction `Δ = M⁻¹ Jᵀ λ` with `J Δ = −residual` (one
    /// residual per row of `rows`, after [`Self::prepare`]), into `self.delta` for the
    /// bodies in `self.touched`. Returns false if the locks are redundant here.
    pub(super) fn correct(&mut self, model: &Model, rows: &[Row], residual: &[f64]) -> bool {
        if self.delta.len() < model.bodies.len() {
            self.delta.resize(model.bodies.len(), [0.0; 6]);
        }
        for &b in &self.touched {
            self.delta[b] = [0.0; 6];
        }
        if self.forest.is_some() {
            return self.correct_forest(model, rows, residual);
        }
        self.lambda.clear();
        self.lambda.extend(residual.iter().map(|r| -r));
        if rows.len() <= SMALL {
            if !self.solve_small(rows) {
                return false;
            }
        } else {
            if !self.factor_envelope() {
                return false;
            }
            self.solve();
        }
        for ((row, part), &l) in rows.iter().zip(&self.parts).zip(&self.lambda) {
            for (body, m) in [(row.parent, &part[1]), (row.child, &part[3])] {
                for (d, m) in self.delta[body].iter_mut().zip(m) {
                    *d += m * l;
                }
            }
        }
        true
    }

    /// [`Self::correct`] by elimination along the forest of locked hinges.
    fn correct_forest(&mut self, model: &Model, rows: &[Row], residual: &[f64]) -> bool {
        let Workspace { forest, parts, groups, touched, lambda, delta, .. } = self;
        let Some(forest) = forest.as_mut() else { return false };
        forest.eliminate(model, rows, residual, parts, groups, touched, lambda, delta)
    }
}

/// The forest of locked hinges over the bodies, or None if they close a loop (or two hinges
/// join the same bodies). `structure` lists per hinge (start row, end row, parent, child).
fn forest(structure: &[(usize, usize, usize, usize)], n_bodies: usize) -> Option<Forest> {
    let mut adjacent: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n_bodies];
    for (g, &(_, _, p, c)) in structure.iter().enumerate() {
        adjacent[p].push((g, c));
        adjacent[c].push((g, p));
    }
    let mut seen = vec![false; n_bodies];
    let mut used = vec![false; structure.len()];
    let mut out = Forest::default();
    let mut edges = 0;
    for root in 0..n_bodies {
        if seen[root] || adjacent[root].is_empty() {
            continue;
        }
        seen[root] = true;
        out.roots.push(root);
        let mut queue = std::collections::VecDeque::from([root]);
        while let Some(b) = queue.pop_front() {
            for &(g, other) in &adjacent[b] {
                if used[g] {
                    continue;
                }
                used[g] = true;
                if seen[other] {
                    return None;
                }
                seen[other] = true;
                let far_side = if structure[g].2 == other { 0 } else { 1 };
                out.order.push((g, b, other, far_side));
                edges += 1;
                queue.push_back(other);
            }
        }
    }
    out.leaf = out.order.iter().map(|o| adjacent[o.2].len() == 1).collect();
    (edges == structure.len()).then_some(out)
}

/// Relative size, against the sum of the magnitudes of its terms, below which a row's
/// acceleration residual `J a + γ` is round-off (a few ulps of the largest term).
pub const IDLE_RESIDUAL: f64 = 16.0 * f64::EPSILON;

/// Corrects the free accelerations in the state derivative `dydt` (layout of
/// [`crate::state`]: `R̈` in N components, `ω̇` in body components) so that every locked
/// coordinate has zero acceleration, given the locks' `rows` at this state (rows of one
/// hinge contiguous). Works in each body's own components, so the free body loop's results
/// are used as they are. Returns false if `J M⁻¹ Jᵀ` is singular (redundant locks).
///
/// When the free accelerations already satisfy every lock to round-off (each residual
/// `J a + γ` within [`IDLE_RESIDUAL`] of the magnitudes of its terms), the multipliers are
/// zero to round-off and nothing is solved: a lock that carries no load, such as an
/// out-of-plane direction of a planar deployment, costs its rows and residual only.
pub fn constrain_accelerations(
    model: &Model,
    rows: &[Row],
    motions: &[BodyMotion],
    dydt: &mut [f64],
    work: &mut Workspace,
) -> bool {
    let mut residual = std::mem::take(&mut work.residual);
    residual.clear();
    // The residuals in N components: the bodies' accelerations turned into N once per hinge.
    let mut idle = true;
    let accelerations = |b: usize| {
        let t = twist6(dydt, b);
        (Vec3::new(t[0], t[1], t[2]), motions[b].dcm_n_b * Vec3::new(t[3], t[4], t[5]))
    };
    for group in rows.chunk_by(|a, b| a.parent == b.parent && a.child == b.child) {
        let ((a_p, alpha_p), (a_c, alpha_c)) = (accelerations(group[0].parent), accelerations(group[0].child));
        for r in group {
            let terms = [r.gamma, r.lin_p.dot(&a_p), r.ang_p.dot(&alpha_p), r.lin_c.dot(&a_c), r.ang_c.dot(&alpha_c)];
            let value: f64 = terms.iter().sum();
            idle &= value.abs() <= IDLE_RESIDUAL * terms.iter().map(|t| t.abs()).sum::<f64>();
            residual.push(value);
        }
    }
    if idle {
        work.lambda.clear();
        work.lambda.resize(rows.len(), 0.0);
        work.residual = residual;
        return true;
    }
    work.prepare(model, rows, motions);
    let ok = work.correct(model, rows, &residual);
    work.residual = residual;
    if !ok {
        return false;
    }
    for &body in &work.touched {
        let o = BODY_STATE_LEN * body + VEL;
        for (a, d) in dydt[o..o + 6].iter_mut().zip(&work.delta[body]) {
            *a += d;
        }
    }
    true
}

/// Whether the locks are independent here (`J M⁻¹ Jᵀ` positive definite); redundant locks,
/// such as a closed loop of fully locked hinges, are not.
pub fn independent(model: &Model, locks: &[Lock], motions: &[BodyMotion], refs: &[Euler321]) -> bool {
    let rows = rows(model, locks, motions, refs);
    let mut work = Workspace::default();
    work.prepare(model, &rows, motions);
    work.correct(model, &rows, &vec![0.0; rows.len()])
}

#[cfg(test)]
mod tests;
