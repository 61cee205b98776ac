//! The eigenpairs of `K φ = λ M φ` nearest a shift, for large structures: block Lanczos on
//! the shift-inverted operator `Op = (K − σM)⁻¹ M` with full reorthogonalisation in M's inner
//! product and Rayleigh–Ritz on the whole basis (Ericsson & Ruhe, *Math. Comp.* 35, 1980;
//! Grimes, Lewis & Simon, *SIAM J. Matrix Anal. Appl.* 15, 1994, the block shift-invert
//! Lanczos of structural codes; Golub & Van Loan §10.3), the solves by the block factors of
//! [`super::sparse`]. K and M symmetric, M positive definite.
//!
//! Why a block: a flasher's rotational symmetry pairs its flexible modes, and a single
//! Lanczos vector finds one vector of each repeated eigenvalue in exact arithmetic (only
//! round-off brings the others, late and unreliably). A block of six starting vectors holds
//! any multiplicity up to six.
//!
//! Known eigenvectors (the rigid-body motions of a free structure) are deflated: every basis
//! vector is kept M-orthogonal to them, so the shift can sit near the lowest flexible mode
//! without the rigid ones (λ = 0, the operator's largest eigenvalues there) swamping the
//! solves' round-off.
//!
//! The operator's eigenvalues are `ν = 1/(λ − σ)`: those nearest σ are the largest, which
//! the Krylov space resolves first. The basis grows by a block at a time; every so often
//! the Ritz pairs are formed, their vectors purified by one more application of the
//! operator, and the wanted ones checked by their residual `‖K φ − λ M φ‖_{M⁻¹} ≤ tol (λ − σ)`
//! with λ the Rayleigh quotient `φᵀ K φ` (φ M-normalised), tol 1e-8 or the round-off of K φ
//! where that is larger (a stiff structure: ε λ_max/(λ − σ)), or by their Ritz values
//! settling. The residual bounds λ's error to first order; it is of the order of its square.
//! Written here: no well-kept Rust crate offers a sparse generalized symmetric eigen-solver
//! (faer and nalgebra are dense; ARPACK's bindings need a Fortran library).

use super::sparse::{BlockMatrix, Factors};
use nalgebra::{DMatrix, DMatrixView, DVector, SymmetricEigen};

/// Vectors per block: the largest multiplicity found in one pass.
const BLOCK: usize = 6;
/// Relative residual a Ritz pair must reach where the solves allow.
const TOLERANCE: f64 = 1e-8;

/// A generalized symmetric eigenproblem `K φ = λ M φ` with eigenvectors to leave out.
pub struct Problem<'a> {
    /// Stiffness, symmetric.
    pub k: &'a BlockMatrix,
    /// Mass, symmetric positive definite.
    pub m: &'a BlockMatrix,
    /// An estimate of the largest λ (1/s²; K's diagonal over M's bounds it from below): it
    /// sets the accuracy the solves can reach.
    pub stiffest: f64,
    /// Eigenvectors to deflate, M-orthonormal (see [`Problem::deflating`]).
    deflate: Vec<DVector<f64>>,
    /// M times each of them.
    m_deflate: Vec<DVector<f64>>,
}

/// M-orthogonalises `w` against `basis` (twice: "twice is enough", Giraud et al. 2005).
fn orthogonalise(w: &mut DVector<f64>, basis: &[DVector<f64>], m_basis: &[DVector<f64>]) {
    for _ in 0..2 {
        for (q, mq) in basis.iter().zip(m_basis) {
            let c = mq.dot(w);
            w.axpy(-c, q, 1.0);
        }
    }
}

impl<'a> Problem<'a> {
    /// The problem with nothing deflated.
    pub fn new(k: &'a BlockMatrix, m: &'a BlockMatrix, stiffest: f64) -> Self {
        Self { k, m, stiffest, deflate: Vec::new(), m_deflate: Vec::new() }
    }

    /// The same with the span of `vectors` (eigenvectors of the problem, or the solves will
    /// not keep out of it) left out: M-orthonormalised here.
    pub fn deflating(mut self, vectors: &[DVector<f64>]) -> Self {
        for v in vectors {
            let mut w = v.clone();
            orthogonalise(&mut w, &self.deflate, &self.m_deflate);
            let mw = self.m.mul(&w);
            let norm = w.dot(&mw).sqrt();
            if norm > 1e-12 * v.dot(&self.m.mul(v)).sqrt() {
                self.deflate.push(w / norm);
                self.m_deflate.push(mw / norm);
            }
        }
        self
    }

    /// The deflated vectors, M-orthonormal.
    pub fn deflated(&self) -> &[DVector<f64>] {
        &self.deflate
    }

    /// The `count` lowest eigenpairs (outside the deflated span): λ ascending, shapes as
    /// columns, M-normalised. Shift-invert at `σ = −f λ_max` (λ_max = [`Problem::stiffest`])
    /// for f = 1e-9, then 1e-8, 1e-7, 1e-6 until every pair passes its residual test.
    ///
    /// Why these shifts: the nearer σ to the lowest modes, the better the operator separates
    /// them (relative gaps `(λ_j − λ_i)/(λ_i − σ)`) and the smaller the basis, but `K − σM`
    /// has a condition number of about `λ_max/|σ|` and its solves lose that many digits. On
    /// the starshade's flashers (`cargo bench --bench modes`; λ_max 2e8 s⁻² from the hinges'
    /// 1e7 N/m stretch, lowest flexible ω² 1.7e-3 at 228 panels and 2.2e-6 held at 996), f =
    /// 1e-9 agrees with f = 1e-6 (the shift used before) and with the dense solver within its
    /// own error at 228, 420 and 612 panels, in a basis 2–3 times smaller; f = 1e-10 put the
    /// 996-panel flasher's lowest hub-held mode 8 % off and f = 1e-11 the 228-panel one's
    /// 4e-3 off, their pairs' residuals far above the test and accepted only because their Ritz
    /// values had settled. An answer that only settles is therefore tried again further out.
    /// If no shift passes, the last (f = 1e-6) answer is returned.
    pub fn lowest(&self, count: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
        let mut last = Err("no shift tried".to_string());
        for f in [1e-9, 1e-8, 1e-7, 1e-6] {
            last = self.krylov(-f * self.stiffest, count);
            if let Ok(pairs) = &last
                && pairs.trusted
            {
                break;
            }
        }
        last.map(|p| (p.values, p.shapes))
    }

    /// The `count` eigenpairs nearest `shift` (outside the deflated span): λ ascending,
    /// shapes as columns, M-normalised. Fails if `K − σM` is singular (σ an eigenvalue) or
    /// the pairs do not converge within the matrix's size.
    pub fn nearest(&self, shift: f64, count: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
        self.krylov(shift, count).map(|p| (p.values, p.shapes))
    }

    /// `K − σM` and its factors.
    fn factor(&self, shift: f64) -> Result<(BlockMatrix, Factors), String> {
        let mut s = self.k.clone();
        for (i, row) in self.m.rows.iter().enumerate() {
            for (&j, b) in row {
                s.add(i, j, &(b * -shift));
            }
        }
        let factors = s.factor().ok_or("K − σM is singular at the shift: a mode sits exactly there")?;
        Ok((s, factors))
    }

    /// Block shift-invert Lanczos.
    fn krylov(&self, shift: f64, count: usize) -> Result<Pairs, String> {
        let (k, m) = (self.k, self.m);
        let n = 6 * k.rows.len();
        let room = n - self.deflate.len();
        let count = count.min(room);
        let limit = room;
        let (shifted, factors) = self.factor(shift)?;
        // `(K − σM)⁻¹ B` with two steps of iterative refinement (Wilkinson; Higham, *Accuracy
        // and Stability of Numerical Algorithms*, ch. 12): K − σM has a condition number of
        // about λ_max/|σ| (see `first_mode_shift`), and each step takes the solve's error
        // from κε to about (κε)². A block of vectors at a time: the factors read once.
        let solve = |b: &DMatrix<f64>| {
            let mut x = factors.solve_many(b);
            for _ in 0..2 {
                let r = b - shifted.mul_many(&x);
                x += factors.solve_many(&r);
            }
            x
        };
        let m_inverse = m.block_diagonal_inverse().ok_or("the mass matrix is singular")?;
        let deflate = Columns::new(n).with(&self.deflate);
        let m_deflate = Columns::images(n).with(&self.m_deflate);
        // The basis Q (M-orthonormal, M-orthogonal to the deflated vectors), M Q, Op Q, and
        // the projected operator H = Qᵀ M Op Q, grown a block at a time.
        let (mut q, mut mq, mut opq) = (Columns::new(n), Columns::images(n), Columns::new(n));
        let mut h = DMatrix::<f64>::zeros(0, 0);
        let mut pending =
            DMatrix::from_fn(n, BLOCK, |i, b| 1.0 + 0.5 * ((i as f64) * (0.37 + 0.61 * b as f64) + b as f64).sin());
        let mut previous: Vec<f64> = Vec::new();
        let mut next_check = (count + BLOCK).min(limit);
        loop {
            let old = q.len;
            let before: Vec<f64> =
                m.mul_many(&pending).column_iter().zip(pending.column_iter()).map(|(a, b)| a.dot(&b).sqrt()).collect();
            // Block classical Gram–Schmidt, twice ("twice is enough", Giraud et al. 2005),
            // as matrix products; then the block's own vectors one by one.
            for _ in 0..2 {
                deflate.project_out(&m_deflate, &mut pending);
                q.project_out(&mq, &mut pending);
            }
            for (c, before) in before.iter().enumerate() {
                if q.len == limit {
                    break;
                }
                let mut w = pending.column(c).into_owned();
                for _ in 0..2 {
                    for j in old..q.len {
                        let coefficient = mq.data.column(j).dot(&w);
                        w.axpy(-coefficient, &q.data.column(j), 1.0);
                    }
                }
                let mw = m.mul(&w);
                let norm = w.dot(&mw).sqrt();
                // A vector the basis already holds (to round-off) adds nothing.
                if norm.is_nan() || norm <= 1e-10 * before {
                    continue;
                }
                q.push(&(w / norm));
                mq.push(&(mw / norm));
            }
            let added = q.len - old;
            if added > 0 {
                let new_mq = mq.data.columns(old, added).into_owned();
                let op = solve(&new_mq);
                // H's new columns (and rows, by symmetry): (M Q)ᵀ Op Q_new.
                let column = mq.transposed() * &op;
                let size = q.len;
                h = h.resize(size, size, 0.0);
                for (jj, j) in (old..size).enumerate() {
                    for i in 0..size {
                        h[(i, j)] = column[(i, jj)];
                        if i < old {
                            h[(j, i)] = column[(i, jj)];
                        }
                    }
                }
                for c in op.column_iter() {
                    opq.push(&c.into_owned());
                }
                pending = op;
            }
            let size = q.len;
            if size < next_check && added > 0 {
                continue;
            }
            // Rayleigh–Ritz on the basis (H symmetric in exact arithmetic).
            let e = SymmetricEigen::new((&h + h.transpose()) * 0.5);
            let mut order: Vec<usize> = (0..size).collect();
            order.sort_by(|&x, &y| e.eigenvalues[y].total_cmp(&e.eigenvalues[x]));
            let wanted = &order[..count.min(size)];
            let values: Vec<f64> = wanted.iter().map(|&c| e.eigenvalues[c]).collect();
            // Ritz values that a larger basis left unchanged (to 1e-12) have converged as far
            // as the solves allow, whatever their residual (Ritz values of the operator's
            // largest eigenvalues only grow with the basis, towards them).
            let settled = values.len() == previous.len()
                && values.iter().zip(&previous).all(|(a, b)| (a - b).abs() <= 1e-12 * a.abs());
            previous = values;
            // Every pair's residual below the test: the answer is trusted; settled Ritz values
            // with larger residuals are accepted but not trusted (see [`Problem::lowest`]).
            let mut trusted = wanted.len() == count;
            // The Ritz vectors purified by one application of the operator, `Op Q s` (known:
            // no solve): it damps what the solves' round-off left along the stiff modes by
            // (λ − σ)/(λ_stiff − σ) (Ericsson & Ruhe 1980, §4; Nour-Omid et al. 1987), which
            // would otherwise spoil the Rayleigh quotient.
            let s = DMatrix::from_fn(size, wanted.len(), |i, j| e.eigenvectors[(i, wanted[j])]);
            let mut shapes = opq.view() * s;
            deflate.project_out(&m_deflate, &mut shapes);
            let ms = m.mul_many(&shapes);
            let ks = k.mul_many(&shapes);
            let mut pairs: Vec<(f64, DVector<f64>)> = Vec::with_capacity(wanted.len());
            for (j, &c) in wanted.iter().enumerate() {
                let nu = e.eigenvalues[c];
                let norm = shapes.column(j).dot(&ms.column(j)).sqrt();
                let (shape, ms, ks) = (shapes.column(j) / norm, ms.column(j) / norm, ks.column(j) / norm);
                // The pair's residual `r = K φ − λ M φ` in M⁻¹'s norm, over λ − σ (the spread
                // the operator sees): it bounds the error of λ (to first order; the Rayleigh
                // quotient's is of the order of its square). K φ itself carries round-off of
                // ε λ_max, which bounds what the test can ask (100 ε: λ_max is estimated from
                // below).
                let lambda = shape.dot(&ks);
                let r = ks - &ms * lambda;
                let attainable = 1e2 * f64::EPSILON * self.stiffest * nu.abs();
                let relative = m_inverse.mul(&r).dot(&r).sqrt() * nu.abs();
                if relative > TOLERANCE.max(attainable) {
                    trusted = false;
                }
                pairs.push((lambda, shape));
            }
            if trusted || (settled && wanted.len() == count) {
                pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
                let shapes = DMatrix::from_columns(&pairs.iter().map(|p| p.1.clone()).collect::<Vec<_>>());
                return Ok(Pairs { values: pairs.iter().map(|p| p.0).collect(), shapes, trusted });
            }
            if size >= limit || added == 0 {
                return Err(format!("the eigen-solver did not converge with a basis of {size} vectors"));
            }
            next_check = (size + size / 2).max(size + BLOCK).min(limit);
        }
    }
}

/// Eigenpairs found by [`Problem::krylov`].
struct Pairs {
    /// λ ascending.
    values: Vec<f64>,
    /// The shapes as columns, M-normalised.
    shapes: DMatrix<f64>,
    /// Whether every pair passed its residual test (not merely settled).
    trusted: bool,
}

/// Columns of length n, grown one at a time (capacity doubled as needed), for the basis and
/// its images: products with them as matrix products (matrixmultiply, through nalgebra).
struct Columns {
    /// n × capacity; the first `len` columns hold the vectors.
    data: DMatrix<f64>,
    len: usize,
    /// For the images of a projection (see [`Columns::transposed`]): capacity × n, the
    /// vectors as its first `len` rows, so that their transpose is a view whose columns are
    /// contiguous; empty otherwise.
    rows: Option<DMatrix<f64>>,
}

impl Columns {
    fn new(n: usize) -> Self {
        Self { data: DMatrix::zeros(n, 0), len: 0, rows: None }
    }

    /// Columns that also keep their transpose, for [`Columns::transposed`].
    fn images(n: usize) -> Self {
        Self { rows: Some(DMatrix::zeros(0, n)), ..Self::new(n) }
    }

    /// These columns with `vectors` pushed.
    fn with(mut self, vectors: &[DVector<f64>]) -> Self {
        for v in vectors {
            self.push(v);
        }
        self
    }

    fn push(&mut self, v: &DVector<f64>) {
        if self.len == self.data.ncols() {
            let capacity = (2 * self.len).max(8 * BLOCK);
            let n = self.data.nrows();
            self.data.resize_mut(n, capacity, 0.0);
            if let Some(rows) = self.rows.as_mut() {
                rows.resize_mut(capacity, n, 0.0);
            }
        }
        self.data.column_mut(self.len).copy_from(v);
        if let Some(rows) = self.rows.as_mut() {
            for (j, x) in v.iter().enumerate() {
                rows[(self.len, j)] = *x;
            }
        }
        self.len += 1;
    }

    /// The vectors, n × len.
    fn view(&self) -> DMatrixView<'_, f64> {
        self.data.columns(0, self.len)
    }

    /// Their transpose, len × n, without a copy: the first `len` rows of `rows`, whose columns
    /// are contiguous. (A view of `data` with row stride n, which this replaced, went through
    /// nalgebra 0.35's gemv on a strided vector when a product had a side of 5 or less, which
    /// loops over the view's whole span and wrote out of bounds: dimforge/nalgebra#1616;
    /// `foldsim modes --count 1` crashed on the 67-body flasher, found by
    /// `tests/fuzz_linear.rs`.) Only for columns made by [`Columns::images`].
    fn transposed(&self) -> DMatrixView<'_, f64> {
        self.rows.as_ref().expect("columns made to be images").rows(0, self.len)
    }

    /// `w ← w − Q (images)ᵀ w` for every column of w: with `images` = M Q and Q M-orthonormal,
    /// the projection out of Q's span in M's inner product.
    fn project_out(&self, images: &Columns, w: &mut DMatrix<f64>) {
        if self.len > 0 {
            let coefficients = images.transposed() * &*w;
            w.gemm(-1.0, &self.view(), &coefficients, 1.0);
        }
    }
}
