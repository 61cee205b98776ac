//! The block elimination's pattern, found once per structure and elimination order, so that
//! each refactorization only computes numbers: every block of the factors (fill included)
//! has a slot in one array, and each update of the elimination knows its target slot.
//!
//! The classical split of a sparse factorization into a symbolic and a numeric phase (Duff,
//! Erisman & Reid, *Direct Methods for Sparse Matrices*, ch. 10; George & Liu 1981): the
//! pattern depends only on the graph and the order, which change only when a contact pair
//! first touches or the carried locks change, while the numbers change at every
//! refactorization. The numeric phase does the same operations in the same order as the
//! elimination on maps it replaces, so the factors are bit-for-bit the same.

use super::Block;

/// One row eliminated with a pivot: its block in the pivot's column, and the slots its
/// updates go to (one per block of the pivot's row after it, in that row's order).
#[derive(Clone, Debug)]
struct Lower {
    row: usize,
    slot: usize,
    targets: Vec<usize>,
}

/// The pattern of the factors of a block matrix in one elimination order.
#[derive(Clone, Debug)]
pub(crate) struct Symbolic {
    /// The order it was found for, and the locked hinges' nodes it had.
    order: Vec<usize>,
    groups: Vec<(usize, usize, usize)>,
    /// Per block row: (column, slot), columns ascending.
    row_slots: Vec<Vec<(usize, usize)>>,
    /// Number of slots.
    slots: usize,
    /// Per node: its diagonal block's slot.
    pivot: Vec<usize>,
    /// Per pivot: the blocks of its row after it (column, slot), columns ascending.
    upper: Vec<Vec<(usize, usize)>>,
    /// Per pivot: the rows eliminated with it.
    lower: Vec<Vec<Lower>>,
}

impl Symbolic {
    /// The pattern of eliminating a matrix whose blocks are at `pattern` (per row, the
    /// columns, any order) in `order` (`position[p]` = p's place in it); `groups` is kept to
    /// recognise the structure again. `None` if a node has no diagonal block.
    pub(crate) fn new(
        pattern: &[Vec<usize>],
        order: &[usize],
        position: &[usize],
        groups: &[(usize, usize, usize)],
    ) -> Option<Self> {
        let n = pattern.len();
        let mut rows: Vec<std::collections::BTreeSet<usize>> =
            pattern.iter().map(|r| r.iter().copied().collect()).collect();
        // The elimination on the pattern: row i gains the pivot row's later columns.
        let mut later: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut eliminated: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &p in order {
            later[p] = rows[p].iter().copied().filter(|&j| position[j] > position[p]).collect();
            for &i in &later[p] {
                if rows[i].contains(&p) {
                    rows[i].extend(later[p].iter().copied());
                    eliminated[p].push(i);
                }
            }
        }
        let mut slots = 0;
        let row_slots: Vec<Vec<(usize, usize)>> = rows
            .iter()
            .map(|r| {
                r.iter()
                    .map(|&j| {
                        slots += 1;
                        (j, slots - 1)
                    })
                    .collect()
            })
            .collect();
        let find = |i: usize, j: usize| row_slots[i].binary_search_by_key(&j, |e| e.0).ok().map(|k| row_slots[i][k].1);
        let mut pivot = vec![0; n];
        let mut upper = vec![Vec::new(); n];
        let mut lower = vec![Vec::new(); n];
        for &p in order {
            pivot[p] = find(p, p)?;
            upper[p] = later[p].iter().map(|&j| (j, find(p, j).expect("in the pattern"))).collect();
            lower[p] = eliminated[p]
                .iter()
                .map(|&i| Lower {
                    row: i,
                    slot: find(i, p).expect("in the pattern"),
                    targets: later[p].iter().map(|&j| find(i, j).expect("the fill is in the pattern")).collect(),
                })
                .collect();
        }
        Some(Self { order: order.to_vec(), groups: groups.to_vec(), row_slots, slots, pivot, upper, lower })
    }

    /// Whether this is the pattern of `order` with `groups`' nodes.
    pub(crate) fn fits(&self, order: &[usize], groups: &[(usize, usize, usize)]) -> bool {
        self.order == order && self.groups == groups
    }

    /// Number of slots (blocks of the factors, fill included).
    pub(crate) fn slots(&self) -> usize {
        self.slots
    }

    /// The slot of block (i, j), if the pattern has it.
    pub(crate) fn slot(&self, i: usize, j: usize) -> Option<usize> {
        self.row_slots[i].binary_search_by_key(&j, |e| e.0).ok().map(|k| self.row_slots[i][k].1)
    }

    /// Eliminates the matrix whose blocks are in `values` (by slot; overwritten): per node,
    /// its pivot block's inverse in `pivots`, the multipliers `L[i][p]` in `lower[p]` and
    /// its row's later blocks `U[p][j]` in `upper[p]` (each resized to the node count).
    /// Fails with the node whose pivot block is singular.
    pub(crate) fn eliminate(
        &self,
        values: &mut [Block],
        pivots: &mut Vec<Block>,
        upper: &mut Vec<Vec<(usize, Block)>>,
        lower: &mut Vec<Vec<(usize, Block)>>,
    ) -> Result<(), usize> {
        let n = self.pivot.len();
        pivots.resize(n, Block::zeros());
        upper.resize(n, Vec::new());
        lower.resize(n, Vec::new());
        let kernel = super::kernel::Kernel::detect();
        for &p in &self.order {
            let pivot = values[self.pivot[p]];
            // The pivot's inverse (by LU): the multipliers are products with it, and so is
            // each solve's step.
            let Some(inverse) = pivot.lu().try_inverse() else { return Err(p) };
            upper[p].clear();
            upper[p].extend(self.upper[p].iter().map(|&(j, s)| (j, values[s])));
            lower[p].clear();
            for row in &self.lower[p] {
                // L = S[i][p] S[p][p]⁻¹.
                let l = values[row.slot] * inverse;
                kernel.update_row(values, &l, &upper[p], &row.targets);
                lower[p].push((row.row, l));
            }
            pivots[p] = inverse;
        }
        Ok(())
    }
}
