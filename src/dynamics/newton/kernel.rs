//! The elimination's inner loop, `T −= L U` for one multiplier L against a pivot row's
//! blocks (6 × 6, column-major), and the factors' triangular solves, with fused multiply-adds
//! on the 4-lane vectors of AVX2 where the processor has them (chosen at run time, so the
//! default build stays portable).
//!
//! Why our own: the update is 216 multiply-adds on blocks scattered over the factors' fill,
//! too small for a general matrix product (`matrixmultiply`, faer) to pay its packing, and
//! nalgebra's fixed-size product is compiled for the baseline x86-64 (SSE2, no FMA). On the
//! 996-panel starshade (238,435 such products a factorization in the minimum-degree order
//! these figures were measured in; 183,758 in today's minimum-fill order) a refactorization
//! took 6.8–9.1 ms with this kernel against 16.4–22.2 ms with nalgebra's products, and a
//! solve 0.51–0.53 against 0.61–0.72 ms (`cargo bench --bench flasher -- --scenario FILE`,
//! Intel Xeon 2-core, load ~1.5; docs/architecture.md, *Scale*). Rounding differs from the
//! plain products by the fused operations only (one rounding per multiply-add instead of
//! two).
//!
//! One body serves both builds: each loop is written once, `#[inline(always)]`, over a
//! multiply-add `fma(a, b, c) = a b + c` it is given, and instantiated twice: with
//! `f64::mul_add` inside a function compiled for AVX2+FMA (where it is one instruction), and
//! with a separate product and sum in the portable one.

use super::{Block, Vec6};

/// The factors the triangular solves read: the elimination `order`, each pivot's inverse
/// (`pivots`), and per eliminated node its blocks of U (`upper`: column, block) and of L
/// (`lower`: row, block).
pub(super) struct Factors<'a> {
    pub order: &'a [usize],
    pub pivots: &'a [Block],
    pub upper: &'a [Vec<(usize, Block)>],
    pub lower: &'a [Vec<(usize, Block)>],
}

/// Which build of the loops this processor runs, found once per factorization or solve.
#[derive(Clone, Copy)]
pub(super) struct Kernel {
    /// AVX2 and FMA are present (x86-64 only).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    fused: bool,
}

impl Kernel {
    /// The fused build where the processor has AVX2 and FMA, the portable one elsewhere.
    pub(super) fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        let fused = std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let fused = false;
        Self { fused }
    }

    /// The portable build, whatever the processor.
    #[cfg(test)]
    fn portable() -> Self {
        Self { fused: false }
    }

    /// `values[t] −= l · u` for each pivot-row block `u` (its column and block) and its
    /// target slot `t`, in order.
    pub(super) fn update_row(self, values: &mut [Block], l: &Block, upper: &[(usize, Block)], targets: &[usize]) {
        #[cfg(target_arch = "x86_64")]
        if self.fused {
            // SAFETY: `update_row_fused` only requires the AVX2 and FMA instructions, which
            // `detect` found this processor to have; it is otherwise ordinary safe code.
            unsafe { update_row_fused(values, l, upper, targets) };
            return;
        }
        update_row_with(values, l, upper, targets, plain_fma);
    }

    /// The factors' two triangular solves on `x` (per node, its 6 numbers; overwritten):
    /// forward, for p in the order, `x_i −= L[i][p] x_p`; backward, for p in reverse order,
    /// `x_p = S[p][p]⁻¹ (x_p − Σ U[p][j] x_j)` (the pivots held as their inverses).
    pub(super) fn substitute(self, factors: &Factors<'_>, x: &mut [Vec6]) {
        #[cfg(target_arch = "x86_64")]
        if self.fused {
            // SAFETY: as in `update_row`: the instructions `substitute_fused` requires were
            // found by `detect`.
            unsafe { substitute_fused(factors, x) };
            return;
        }
        substitute_with(factors, x, plain_fma);
    }
}

/// `a b + c` with two roundings: the portable build's multiply-add.
#[inline(always)]
fn plain_fma(a: f64, b: f64, c: f64) -> f64 {
    a * b + c
}

/// [`Kernel::update_row`] compiled for AVX2 with FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn update_row_fused(values: &mut [Block], l: &Block, upper: &[(usize, Block)], targets: &[usize]) {
    update_row_with(values, l, upper, targets, f64::mul_add);
}

/// [`Kernel::substitute`] compiled for AVX2 with FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn substitute_fused(factors: &Factors<'_>, x: &mut [Vec6]) {
    substitute_with(factors, x, f64::mul_add);
}

/// The row update's one body: each target column kept in registers while the six columns of
/// `l` are added in.
#[inline(always)]
fn update_row_with(
    values: &mut [Block],
    l: &Block,
    upper: &[(usize, Block)],
    targets: &[usize],
    fma: impl Fn(f64, f64, f64) -> f64 + Copy,
) {
    let l = l.as_slice();
    for ((_, u), &t) in upper.iter().zip(targets) {
        let (t, u) = (values[t].as_mut_slice(), u.as_slice());
        for (column, u_column) in t.chunks_exact_mut(6).zip(u.chunks_exact(6)) {
            let mut c = [0.0; 6];
            c.copy_from_slice(column);
            for (l_column, &b) in l.chunks_exact(6).zip(u_column) {
                for (c, &a) in c.iter_mut().zip(l_column) {
                    *c = fma(a, -b, *c);
                }
            }
            column.copy_from_slice(&c);
        }
    }
}

/// The solves' one body.
#[inline(always)]
fn substitute_with(factors: &Factors<'_>, x: &mut [Vec6], fma: impl Fn(f64, f64, f64) -> f64 + Copy) {
    let Factors { order, pivots, upper, lower } = *factors;
    for &p in order {
        let xp = x[p];
        for (i, l) in &lower[p] {
            let mut y: [f64; 6] = x[*i].into();
            add_product(&mut y, -1.0, l, &xp, fma);
            x[*i] = y.into();
        }
    }
    for &p in order.iter().rev() {
        let mut y: [f64; 6] = x[p].into();
        for (j, u) in &upper[p] {
            add_product(&mut y, -1.0, u, &x[*j], fma);
        }
        let mut z = [0.0; 6];
        add_product(&mut z, 1.0, &pivots[p], &y.into(), fma);
        x[p] = z.into();
    }
}

/// `y + s a b` for a 6 × 6 block `a` and a 6-vector `b`, column by column.
#[inline(always)]
fn add_product(y: &mut [f64; 6], s: f64, a: &Block, b: &Vec6, fma: impl Fn(f64, f64, f64) -> f64) {
    for (column, &b) in a.as_slice().chunks_exact(6).zip(b.iter()) {
        let b = s * b;
        for (y, &a) in y.iter_mut().zip(column) {
            *y = fma(a, b, *y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(seed: usize) -> Block {
        Block::from_fn(|r, c| (((seed * 31 + r * 7 + c * 13) % 17) as f64 - 8.0) / 8.0)
    }

    /// Both builds of the row update against nalgebra's block products (on a processor
    /// without AVX2 and FMA, `detect` is the portable build and the fused one goes untested
    /// here, as it is never run). Entries of mixed sign ≤ 1: 36 terms of size ≤ 6 each, so
    /// 1e-13 is some 100 roundings, while a wrong index or sign is off by order one.
    #[test]
    fn the_row_update_is_the_block_product() {
        let l = block(1);
        let upper: Vec<(usize, Block)> = (0..5).map(|k| (k, block(10 + k))).collect();
        let targets = [3, 0, 4, 1, 2];
        let start: Vec<Block> = (0..5).map(|k| block(20 + k)).collect();
        let mut expected = start.clone();
        for ((_, u), &t) in upper.iter().zip(&targets) {
            expected[t] -= l * u;
        }
        for kernel in [Kernel::portable(), Kernel::detect()] {
            let mut values = start.clone();
            kernel.update_row(&mut values, &l, &upper, &targets);
            for (v, e) in values.iter().zip(&expected) {
                assert!((v - e).amax() < 1e-13, "fused {}: {v} against {e}", kernel.fused);
            }
        }
    }

    /// Both builds of the triangular solves against the solves by nalgebra's products, on
    /// three nodes eliminated in the order 2, 0, 1 with every block present (tolerance: a few
    /// hundred roundings of numbers of order 10–100).
    #[test]
    fn the_solves_are_the_block_solves() {
        let order = [2, 0, 1];
        let pivots: Vec<Block> = (0..3).map(|k| block(40 + k)).collect();
        let upper = vec![vec![(1, block(50))], vec![], vec![(0, block(51)), (1, block(52))]];
        let lower = vec![vec![(1, block(60))], vec![], vec![(0, block(61)), (1, block(62))]];
        let start: Vec<Vec6> = (0..3).map(|k| Vec6::from_fn(|r, _| (k * 6 + r) as f64 - 8.0)).collect();
        let mut expected = start.clone();
        for &p in &order {
            let xp = expected[p];
            for (i, l) in &lower[p] {
                expected[*i] -= l * xp;
            }
        }
        for &p in order.iter().rev() {
            let mut xp = expected[p];
            for (j, u) in &upper[p] {
                xp -= u * expected[*j];
            }
            expected[p] = pivots[p] * xp;
        }
        for kernel in [Kernel::portable(), Kernel::detect()] {
            let mut x = start.clone();
            let factors = Factors { order: &order, pivots: &pivots, upper: &upper, lower: &lower };
            kernel.substitute(&factors, &mut x);
            for (v, e) in x.iter().zip(&expected) {
                assert!((v - e).amax() < 1e-9 * e.amax().max(1.0), "fused {}: {v} against {e}", kernel.fused);
            }
        }
    }
}
