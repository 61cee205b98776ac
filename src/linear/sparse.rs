//! A matrix of 6 × 6 blocks on the bodies' coupling graph (a hinge or a contact between two
//! bodies gives a block), factored by block Gaussian elimination in a minimum-degree order
//! (crate::dynamics::newton::order: no fill for trees, fill along loops), dense LU inside the
//! pivot blocks: the solves of the shift-invert eigen-solver ([`super::lanczos`]).
//!
//! Written here rather than taken from a sparse library: the structure is the one the Newton
//! matrix already factors this way (crate::dynamics::newton), and a general sparse LU would
//! rediscover the 6 × 6 blocks (docs/linear.md compares the costs).

use crate::dynamics::newton::order::elimination_order;
use nalgebra::{DVector, SMatrix, SVector};
use std::collections::BTreeMap;

/// A 6 × 6 block.
pub type Block = SMatrix<f64, 6, 6>;
type Vec6 = SVector<f64, 6>;

/// A square matrix of 6 × 6 blocks, stored by block row.
#[derive(Clone, Debug, Default)]
pub struct BlockMatrix {
    /// Per block row i: the blocks (column j → block).
    pub rows: Vec<BTreeMap<usize, Block>>,
}

impl BlockMatrix {
    /// An empty matrix of `n` block rows.
    pub fn new(n: usize) -> Self {
        Self { rows: vec![BTreeMap::new(); n] }
    }

    /// Adds `b` to block (i, j).
    pub fn add(&mut self, i: usize, j: usize, b: &Block) {
        *self.rows[i].entry(j).or_insert_with(Block::zeros) += b;
    }

    /// `self · x` (x of 6n).
    pub fn mul(&self, x: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(x.len());
        for (i, row) in self.rows.iter().enumerate() {
            let mut acc = Vec6::zeros();
            for (&j, b) in row {
                acc += b * x.fixed_rows::<6>(6 * j);
            }
            y.fixed_rows_mut::<6>(6 * i).copy_from(&acc);
        }
        y
    }

    /// The matrix without block row and column `drop` (renumbered).
    pub fn without(&self, drop: usize) -> Self {
        let map = |k: usize| if k > drop { k - 1 } else { k };
        let rows = self
            .rows
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != drop)
            .map(|(_, row)| row.iter().filter(|(j, _)| **j != drop).map(|(j, b)| (map(*j), *b)).collect())
            .collect();
        Self { rows }
    }

    /// The inverse of a block-diagonal matrix (its off-diagonal blocks ignored); `None` if a
    /// diagonal block is singular.
    pub fn block_diagonal_inverse(&self) -> Option<Self> {
        let mut out = Self::new(self.rows.len());
        for (i, row) in self.rows.iter().enumerate() {
            out.rows[i].insert(i, row.get(&i)?.try_inverse()?);
        }
        Some(out)
    }

    /// Its LU factors in a minimum-degree order; `None` if a pivot block is singular.
    pub fn factor(&self) -> Option<Factors> {
        let n = self.rows.len();
        let neighbours: Vec<Vec<usize>> = self.rows.iter().map(|r| r.keys().copied().collect()).collect();
        let order = elimination_order(&neighbours, &[]);
        let mut rows = self.rows.clone();
        let mut done = vec![false; n];
        let mut pivots = vec![Block::zeros(); n];
        let mut lower: Vec<Vec<(usize, Block)>> = vec![Vec::new(); n];
        let mut upper: Vec<Vec<(usize, Block)>> = vec![Vec::new(); n];
        for &p in &order {
            done[p] = true;
            let inverse = rows[p].get(&p).copied().unwrap_or_else(Block::zeros).try_inverse()?;
            let up: Vec<(usize, Block)> = rows[p].iter().filter(|(j, _)| !done[**j]).map(|(j, b)| (*j, *b)).collect();
            let column: Vec<(usize, Block)> =
                (0..n).filter(|&i| !done[i]).filter_map(|i| rows[i].get(&p).map(|b| (i, b * inverse))).collect();
            for (i, l) in &column {
                for (j, u) in &up {
                    *rows[*i].entry(*j).or_insert_with(Block::zeros) -= l * u;
                }
                rows[*i].remove(&p);
            }
            pivots[p] = inverse;
            upper[p] = up;
            lower[p] = column;
        }
        Some(Factors { order, pivots, lower, upper })
    }
}

/// LU factors of a [`BlockMatrix`].
#[derive(Clone, Debug)]
pub struct Factors {
    order: Vec<usize>,
    /// Per node, its pivot block's inverse.
    pivots: Vec<Block>,
    /// Per node p: the multipliers `L[i][p]` of the rows eliminated with it.
    lower: Vec<Vec<(usize, Block)>>,
    /// Per node p: its row's blocks `U[p][j]` to the nodes eliminated after it.
    upper: Vec<Vec<(usize, Block)>>,
}

impl Factors {
    /// Solves `A x = b`.
    pub fn solve(&self, b: &DVector<f64>) -> DVector<f64> {
        let mut x = b.clone();
        for &p in &self.order {
            let xp: Vec6 = x.fixed_rows::<6>(6 * p).into_owned();
            for (i, l) in &self.lower[p] {
                let mut xi = x.fixed_rows_mut::<6>(6 * i);
                xi -= l * xp;
            }
        }
        for &p in self.order.iter().rev() {
            let mut xp: Vec6 = x.fixed_rows::<6>(6 * p).into_owned();
            for (j, u) in &self.upper[p] {
                xp -= u * x.fixed_rows::<6>(6 * j);
            }
            x.fixed_rows_mut::<6>(6 * p).copy_from(&(self.pivots[p] * xp));
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A loop of four nodes with a chord: the factors solve to round-off against nalgebra's
    /// dense LU of the same matrix.
    #[test]
    fn solves_a_loop() {
        let n = 4;
        let mut a = BlockMatrix::new(n);
        let block = |s: f64| Block::from_fn(|r, c| if r == c { 10.0 + s } else { ((r * 7 + c * 3) as f64 * s).sin() });
        for i in 0..n {
            a.add(i, i, &block(i as f64 + 1.0));
            let j = (i + 1) % n;
            a.add(i, j, &(block(0.3 * i as f64) * 0.1));
            a.add(j, i, &(block(0.7 * i as f64) * 0.1));
        }
        a.add(0, 2, &(block(2.0) * 0.05));
        a.add(2, 0, &(block(3.0) * 0.05));
        let b = DVector::from_fn(6 * n, |k, _| (k as f64).cos());
        let x = a.factor().unwrap().solve(&b);
        let mut dense = nalgebra::DMatrix::zeros(6 * n, 6 * n);
        for (i, row) in a.rows.iter().enumerate() {
            for (&j, blk) in row {
                dense.view_mut((6 * i, 6 * j), (6, 6)).copy_from(blk);
            }
        }
        let reference = dense.lu().solve(&b).unwrap();
        assert!((x - reference).amax() < 1e-13);
    }
}
