//! A matrix of 6 × 6 blocks on the bodies' coupling graph (a hinge or a contact between two
//! bodies gives a block), factored by block Gaussian elimination in a minimum-fill order
//! (crate::dynamics::newton::order: no fill for trees, fill along loops), each pivot block
//! inverted by LU, by the Newton matrix's own elimination (crate::dynamics::newton::symbolic):
//! the solves of the shift-invert eigen-solver ([`super::lanczos`]).
//!
//! Written here rather than taken from a sparse library: the structure is the one the Newton
//! matrix already factors this way (crate::dynamics::newton), and a general sparse LU would
//! rediscover the 6 × 6 blocks (docs/linear.md compares the costs).

use crate::dynamics::newton::order::elimination_order;
use crate::dynamics::newton::symbolic::Symbolic;
use nalgebra::{DMatrix, DVector, SMatrix};
use std::collections::BTreeMap;

/// A 6 × 6 block.
pub type Block = SMatrix<f64, 6, 6>;

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
        let x = DMatrix::from_column_slice(x.len(), 1, x.as_slice());
        DVector::from_column_slice(self.mul_many(&x).as_slice())
    }

    /// `self · x` for every column of x (6n rows), six columns at a time as 6 × 6 blocks.
    pub fn mul_many(&self, x: &DMatrix<f64>) -> DMatrix<f64> {
        let mut y = DMatrix::zeros(x.nrows(), x.ncols());
        for first in (0..x.ncols()).step_by(6) {
            let xs = node_blocks(x, first);
            let ys: Vec<Block> = self.rows.iter().map(|row| row.iter().map(|(&j, b)| b * xs[j]).sum()).collect();
            write_node_blocks(&ys, &mut y, first);
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

    /// Its LU factors in a minimum-fill order; `None` if a pivot block is singular. The
    /// elimination is the Newton matrix's (crate::dynamics::newton::symbolic): its pattern,
    /// then its numbers.
    pub fn factor(&self) -> Option<Factors> {
        let pattern: Vec<Vec<usize>> = self.rows.iter().map(|r| r.keys().copied().collect()).collect();
        let order = elimination_order(&pattern, &[]);
        let mut position = vec![0; pattern.len()];
        for (k, &p) in order.iter().enumerate() {
            position[p] = k;
        }
        let symbolic = Symbolic::new(&pattern, &order, &position, &[])?;
        let mut values = vec![Block::zeros(); symbolic.slots()];
        for (i, row) in self.rows.iter().enumerate() {
            for (&j, b) in row {
                values[symbolic.slot(i, j)?] = *b;
            }
        }
        let (mut pivots, mut upper, mut lower) = (Vec::new(), Vec::new(), Vec::new());
        symbolic.eliminate(&mut values, &mut pivots, &mut upper, &mut lower).is_ok().then_some(Factors {
            order,
            pivots,
            lower,
            upper,
        })
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
        let b = DMatrix::from_column_slice(b.len(), 1, b.as_slice());
        DVector::from_column_slice(self.solve_many(&b).as_slice())
    }

    /// Solves `A X = B` for every column of B, six at a time as 6 × 6 blocks (the factors
    /// read once for six solves, each update a fixed 6 × 6 product).
    pub fn solve_many(&self, b: &DMatrix<f64>) -> DMatrix<f64> {
        let mut x = DMatrix::zeros(b.nrows(), b.ncols());
        for first in (0..b.ncols()).step_by(6) {
            let mut xs = node_blocks(b, first);
            for &p in &self.order {
                let xp = xs[p];
                for (i, l) in &self.lower[p] {
                    xs[*i] -= l * xp;
                }
            }
            for &p in self.order.iter().rev() {
                let mut v = xs[p];
                for (j, u) in &self.upper[p] {
                    v -= u * xs[*j];
                }
                xs[p] = self.pivots[p] * v;
            }
            write_node_blocks(&xs, &mut x, first);
        }
        x
    }
}

/// Columns `first..first + 6` of `x` (6n rows) as one 6 × 6 block per node (zero where x
/// has fewer columns).
fn node_blocks(x: &DMatrix<f64>, first: usize) -> Vec<Block> {
    let width = (x.ncols() - first).min(6);
    (0..x.nrows() / 6).map(|i| Block::from_fn(|r, c| if c < width { x[(6 * i + r, first + c)] } else { 0.0 })).collect()
}

/// Writes [`node_blocks`]'s blocks back into columns `first..` of `x`.
fn write_node_blocks(blocks: &[Block], x: &mut DMatrix<f64>, first: usize) {
    let width = (x.ncols() - first).min(6);
    for (i, b) in blocks.iter().enumerate() {
        x.view_mut((6 * i, first), (6, width)).copy_from(&b.columns(0, width));
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
        let factors = a.factor().unwrap();
        let x = factors.solve(&b);
        let mut dense = nalgebra::DMatrix::zeros(6 * n, 6 * n);
        for (i, row) in a.rows.iter().enumerate() {
            for (&j, blk) in row {
                dense.view_mut((6 * i, 6 * j), (6, 6)).copy_from(blk);
            }
        }
        let reference = dense.lu().solve(&b).unwrap();
        assert!((&x - reference).amax() < 1e-13);
        // Many right-hand sides at once (more than one block of six, the last partial): each
        // column as its own solve, and the product back to the right-hand sides.
        let many = DMatrix::from_fn(6 * n, 8, |k, c| ((k * (c + 1)) as f64).cos());
        let xs = factors.solve_many(&many);
        for c in 0..8 {
            let own = factors.solve(&many.column(c).into_owned());
            assert!((xs.column(c) - own).amax() < 1e-14, "column {c}");
        }
        assert!((a.mul_many(&xs) - &many).amax() < 1e-12);
        assert!((a.mul(&x) - &b).amax() < 1e-12);
    }
}
