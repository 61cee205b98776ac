//! The eigenpairs of `K φ = λ M φ` nearest a shift, for large structures: block Lanczos on
//! the shift-inverted operator `Op = (K − σM)⁻¹ M` with full reorthogonalisation in M's inner
//! product and Rayleigh–Ritz on the whole basis (Ericsson & Ruhe, *Math. Comp.* 35, 1980;
//! Grimes, Lewis & Simon, *SIAM J. Matrix Anal. Appl.* 15, 1994, the block shift-invert
//! Lanczos of structural codes; Golub & Van Loan §10.3), the solves by the block factors of
//! [`super::sparse`]. K and M symmetric, M positive definite.
//!
//! Why a block: the six rigid-body modes share one eigenvalue, and a flasher's rotational
//! symmetry pairs its flexible modes; a single Lanczos vector finds one vector of each
//! repeated eigenvalue in exact arithmetic (only round-off brings the others, late and
//! unreliably). A block of six starting vectors holds any multiplicity up to six.
//!
//! The operator's eigenvalues are `ν = 1/(λ − σ)`: those nearest σ are the largest, which
//! the Krylov space resolves first. The basis grows by a block at a time; every few blocks
//! the Ritz pairs are formed and the wanted ones checked by their residual in the
//! operator's terms, `‖Op φ − ν φ‖_M ≤ 1e-9 |ν|` (one more solve each); λ is then the Rayleigh
//! quotient `φᵀ K φ` (φ M-normalised), whose error is of the order of the residual squared.
//! Written here: no well-kept Rust crate offers a sparse generalized symmetric eigen-solver
//! (faer and nalgebra are dense; ARPACK's bindings need a Fortran library).

use super::sparse::BlockMatrix;
use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Vectors per block: the largest multiplicity found in one pass (the six rigid modes).
const BLOCK: usize = 6;
/// Relative residual a Ritz pair must reach.
const TOLERANCE: f64 = 1e-9;

/// M-orthogonalises `w` against `basis` (twice: "twice is enough", Giraud et al. 2005).
fn orthogonalise(w: &mut DVector<f64>, basis: &[DVector<f64>], m_basis: &[DVector<f64>]) {
    for _ in 0..2 {
        for (q, mq) in basis.iter().zip(m_basis) {
            let c = mq.dot(w);
            w.axpy(-c, q, 1.0);
        }
    }
}

/// The `count` eigenpairs of `K φ = λ M φ` nearest `shift`: λ ascending, shapes as columns,
/// M-normalised. Fails if `K − σM` is singular (σ an eigenvalue) or the pairs do not
/// converge within the matrix's size.
pub fn nearest(k: &BlockMatrix, m: &BlockMatrix, shift: f64, count: usize) -> Result<(Vec<f64>, DMatrix<f64>), String> {
    let n = 6 * k.rows.len();
    let count = count.min(n);
    let mut s = k.clone();
    for (i, row) in m.rows.iter().enumerate() {
        for (&j, b) in row {
            s.add(i, j, &(b * -shift));
        }
    }
    let factors = s.factor().ok_or("K − σM is singular at the shift: a mode sits exactly there")?;
    // The basis Q (M-orthonormal), M Q, and Op Q: the projected operator is Qᵀ M (Op Q).
    let mut q: Vec<DVector<f64>> = Vec::new();
    let mut mq: Vec<DVector<f64>> = Vec::new();
    let mut opq: Vec<DVector<f64>> = Vec::new();
    // The next block's candidates: deterministic, varied start vectors.
    let mut pending: Vec<DVector<f64>> = (0..BLOCK)
        .map(|b| DVector::from_fn(n, |i, _| 1.0 + 0.5 * ((i as f64) * (0.37 + 0.61 * b as f64) + b as f64).sin()))
        .collect();
    let mut next_check = (count + BLOCK).min(n);
    loop {
        let mut added = 0;
        for mut w in std::mem::take(&mut pending) {
            let before = w.dot(&m.mul(&w)).sqrt();
            orthogonalise(&mut w, &q, &mq);
            let mw = m.mul(&w);
            let norm = w.dot(&mw).sqrt();
            // A vector the basis already holds (to round-off) adds nothing.
            if norm.is_nan() || norm <= 1e-10 * before || q.len() == n {
                continue;
            }
            let qj = w / norm;
            let mqj = mw / norm;
            let op = factors.solve(&mqj);
            q.push(qj);
            mq.push(mqj);
            pending.push(op.clone());
            opq.push(op);
            added += 1;
        }
        let size = q.len();
        if size < next_check && added > 0 && size < n {
            continue;
        }
        // Rayleigh–Ritz: H = Qᵀ M Op Q (symmetric in exact arithmetic).
        let h = DMatrix::from_fn(size, size, |i, j| mq[i].dot(&opq[j]));
        let h = (&h + h.transpose()) * 0.5;
        let e = SymmetricEigen::new(h);
        let mut order: Vec<usize> = (0..size).collect();
        order.sort_by(|&x, &y| e.eigenvalues[y].abs().total_cmp(&e.eigenvalues[x].abs()));
        let wanted = &order[..count.min(size)];
        let mut pairs: Vec<(f64, DVector<f64>)> = Vec::with_capacity(wanted.len());
        let mut converged = true;
        for &c in wanted {
            let s = e.eigenvectors.column(c);
            let shape = q.iter().enumerate().fold(DVector::zeros(n), |acc, (i, qi)| acc + qi * s[i]);
            let ms = m.mul(&shape);
            let norm = shape.dot(&ms).sqrt();
            let (shape, ms) = (shape / norm, ms / norm);
            // The pair's residual in the operator's own terms, ‖Op φ − ν φ‖_M ≤ tol |ν|.
            let nu = e.eigenvalues[c];
            let r = factors.solve(&ms) - &shape * nu;
            if r.dot(&m.mul(&r)).sqrt() > TOLERANCE * nu.abs() {
                converged = false;
            }
            // The Rayleigh quotient: its error is the square of the residual's.
            let lambda = shape.dot(&k.mul(&shape));
            pairs.push((lambda, shape));
        }
        if converged && wanted.len() == count {
            pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
            let shapes = DMatrix::from_columns(&pairs.iter().map(|p| p.1.clone()).collect::<Vec<_>>());
            return Ok((pairs.iter().map(|p| p.0).collect(), shapes));
        }
        if size >= n || added == 0 {
            return Err(format!("the eigen-solver did not converge with a basis of {size} vectors"));
        }
        next_check = (size + size / 2).max(size + BLOCK).min(n);
    }
}
