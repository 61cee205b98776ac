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
use nalgebra::{DMatrix, DVector, SymmetricEigen};

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

    /// The `count` eigenpairs nearest `shift` (outside the deflated span): λ ascending,
    /// shapes as columns, M-normalised. Fails if `K − σM` is singular (σ an eigenvalue) or
    /// the pairs do not converge within the matrix's size.
    pub fn nearest(&self, shift: f64, count: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
        self.krylov(shift, count)
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
    fn krylov(&self, shift: f64, count: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
        let (k, m) = (self.k, self.m);
        let n = 6 * k.rows.len();
        let room = n - self.deflate.len();
        let count = count.min(room);
        let limit = room;
        let (shifted, factors) = self.factor(shift)?;
        // `(K − σM)⁻¹ b` with two steps of iterative refinement (Wilkinson; Higham, *Accuracy
        // and Stability of Numerical Algorithms*, ch. 12): near the lowest mode K − σM has a
        // condition number up to λ_max/|σ| (1e10 for a flasher's stiff hinges), and each step
        // takes the solve's error from κε to about (κε)².
        let solve = |b: &DVector<f64>| {
            let mut x = factors.solve(b);
            for _ in 0..2 {
                let r = b - shifted.mul(&x);
                x += factors.solve(&r);
            }
            x
        };
        let m_inverse = m.block_diagonal_inverse().ok_or("the mass matrix is singular")?;
        // The basis Q (M-orthonormal, M-orthogonal to the deflated vectors), M Q, and the
        // projected operator H = Qᵀ M Op Q, grown a column at a time.
        let mut q: Vec<DVector<f64>> = Vec::new();
        let mut mq: Vec<DVector<f64>> = Vec::new();
        let mut opq: Vec<DVector<f64>> = Vec::new();
        let mut h: Vec<Vec<f64>> = Vec::new();
        let mut pending: Vec<DVector<f64>> = (0..BLOCK)
            .map(|b| DVector::from_fn(n, |i, _| 1.0 + 0.5 * ((i as f64) * (0.37 + 0.61 * b as f64) + b as f64).sin()))
            .collect();
        let mut previous: Vec<f64> = Vec::new();
        let mut next_check = (count + BLOCK).min(limit);
        loop {
            let mut added = 0;
            for mut w in std::mem::take(&mut pending) {
                if q.len() == limit {
                    break;
                }
                let before = w.dot(&m.mul(&w)).sqrt();
                orthogonalise(&mut w, &self.deflate, &self.m_deflate);
                orthogonalise(&mut w, &q, &mq);
                let mw = m.mul(&w);
                let norm = w.dot(&mw).sqrt();
                // A vector the basis already holds (to round-off) adds nothing.
                if norm.is_nan() || norm <= 1e-10 * before {
                    continue;
                }
                let (qj, mqj) = (w / norm, mw / norm);
                let op = solve(&mqj);
                let column: Vec<f64> = mq.iter().map(|x| x.dot(&op)).collect();
                for (row, c) in h.iter_mut().zip(&column) {
                    row.push(*c);
                }
                let mut last = column;
                last.push(mqj.dot(&op));
                h.push(last);
                q.push(qj);
                mq.push(mqj);
                pending.push(op.clone());
                opq.push(op);
                added += 1;
            }
            let size = q.len();
            if size < next_check && added > 0 {
                continue;
            }
            // Rayleigh–Ritz on the basis (H symmetric in exact arithmetic).
            let e = SymmetricEigen::new(DMatrix::from_fn(size, size, |i, j| 0.5 * (h[i][j] + h[j][i])));
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
            let mut converged = wanted.len() == count;
            let mut pairs: Vec<(f64, DVector<f64>)> = Vec::with_capacity(wanted.len());
            for &c in wanted {
                let nu = e.eigenvalues[c];
                // The Ritz vector purified by one application of the operator, `Op Q s`
                // (known: no solve): it damps what the solves' round-off left along the stiff
                // modes by (λ − σ)/(λ_stiff − σ) (Ericsson & Ruhe 1980, §4; Nour-Omid et al.
                // 1987), which would otherwise spoil the Rayleigh quotient.
                let mut shape = DVector::zeros(n);
                for (i, op) in opq.iter().enumerate() {
                    shape.axpy(e.eigenvectors[(i, c)], op, 1.0);
                }
                orthogonalise(&mut shape, &self.deflate, &self.m_deflate);
                let ms = m.mul(&shape);
                let norm = shape.dot(&ms).sqrt();
                let (shape, ms) = (shape / norm, ms / norm);
                // The pair's residual `r = K φ − λ M φ` in M⁻¹'s norm, over λ − σ (the spread
                // the operator sees): it bounds the error of λ (to first order; the Rayleigh
                // quotient's is of the order of its square). K φ itself carries round-off of
                // ε λ_max, which bounds what the test can ask (100 ε: λ_max is estimated from
                // below).
                let ks = k.mul(&shape);
                let lambda = shape.dot(&ks);
                let r = ks - &ms * lambda;
                let attainable = 1e2 * f64::EPSILON * self.stiffest * nu.abs();
                let relative = m_inverse.mul(&r).dot(&r).sqrt() * nu.abs();
                if relative > TOLERANCE.max(attainable) && !settled {
                    converged = false;
                }
                pairs.push((lambda, shape));
            }
            if converged {
                pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
                let shapes = DMatrix::from_columns(&pairs.iter().map(|p| p.1.clone()).collect::<Vec<_>>());
                return Ok((pairs.iter().map(|p| p.0).collect(), shapes));
            }
            if size >= limit || added == 0 {
                return Err(format!("the eigen-solver did not converge with a basis of {size} vectors"));
            }
            next_check = (size + size / 2).max(size + BLOCK).min(limit);
        }
    }
}
