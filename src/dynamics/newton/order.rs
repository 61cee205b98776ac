//! The elimination order of the hinge-graph Newton matrix: minimum degree with fill, over the
//! bodies and the locked hinges' nodes, each locked hinge matched to a body of its own.
//!
//! A locked hinge's node has no diagonal block of its own (its constraint rows, a zero block
//! of the saddle-point matrix): it may be eliminated only once an eliminated body gives it one
//! (`J S⁻¹ M⁻¹ Jᵀ`). One eliminated body per lock is not always enough: two hinges locked in
//! all six directions on one body, that body eliminated first, leave the second hinge's pivot
//! exactly zero (the first took the body's six freedoms) although the matrix is regular. So
//! a lock becomes eligible when it can be *matched* to an eliminated body of its own, each
//! body matched to at most one lock (an augmenting path may move earlier locks to their other
//! body). Then every leading block is regular when the locked hinges form a forest: orient
//! each lock toward its matched body; every body has at most one lock pointing at it, so in
//! each tree the locks point away from one root, and taking the locks from the root outward
//! the constraint rows are block triangular, each diagonal block a lock's rows on its own
//! matched body (a hinge's relative motion as a function of one body's twist is invertible,
//! so any of its rows are independent). A star of locked panels matches each lock to its
//! panel and fills nothing; requiring both bodies instead would join all the star's locks
//! in one dense block when the hub goes.

use std::collections::{BTreeSet, VecDeque};

/// Matching of lock nodes to eliminated bodies.
struct Matching<'a> {
    /// Each lock's two bodies.
    locks: &'a [(usize, usize)],
    /// Per body: the lock matched to it.
    owner: Vec<Option<usize>>,
}

impl Matching<'_> {
    /// Tries to match lock `g` to one of its eliminated bodies, moving other locks along an
    /// augmenting path if needed (breadth-first, so long chains need no deep recursion).
    fn augment(&mut self, g: usize, body_done: &[bool]) -> bool {
        // Per body reached: the lock that reached it; per lock: the body it holds now.
        let mut reached_by: Vec<Option<usize>> = vec![None; self.owner.len()];
        let mut holds: std::collections::HashMap<usize, usize> = Default::default();
        let mut queue = VecDeque::from([g]);
        while let Some(l) = queue.pop_front() {
            let (a, b) = self.locks[l];
            for body in [a, b] {
                if !body_done[body] || reached_by[body].is_some() {
                    continue;
                }
                reached_by[body] = Some(l);
                match self.owner[body] {
                    None => {
                        // Augment: each lock on the path takes the body it reached.
                        let (mut body, mut lock) = (body, l);
                        loop {
                            self.owner[body] = Some(lock);
                            match holds.get(&lock) {
                                Some(&previous) => {
                                    body = previous;
                                    lock = reached_by[previous].expect("reached on the way");
                                }
                                None => return true,
                            }
                        }
                    }
                    Some(other) if other != g && !holds.contains_key(&other) => {
                        holds.insert(other, body);
                        queue.push_back(other);
                    }
                    Some(_) => {}
                }
            }
        }
        false
    }
}

/// The elimination order of `nb` bodies coupled as `neighbours` says and of one node per
/// lock group (`locks[g]`: its parent and child body; node `nb + g`). Minimum degree among
/// the eligible nodes, fill included. Locks that can never be matched come last. (Locked
/// hinges that close a loop of locked hinges have redundant rows: some pivot is singular
/// whatever the order, and the factorization says so.)
pub fn elimination_order(neighbours: &[Vec<usize>], locks: &[(usize, usize)]) -> Vec<usize> {
    let nb = neighbours.len();
    let n_nodes = nb + locks.len();
    let mut adj: Vec<BTreeSet<usize>> =
        neighbours.iter().enumerate().map(|(i, v)| v.iter().copied().filter(|&j| j != i).collect()).collect();
    adj.resize(n_nodes, BTreeSet::new());
    for (g, &(p, c)) in locks.iter().enumerate() {
        for b in [p, c] {
            adj[nb + g].insert(b);
            adj[b].insert(nb + g);
        }
    }
    let mut done = vec![false; n_nodes];
    let mut order = Vec::with_capacity(n_nodes);
    let mut by_degree: BTreeSet<(usize, usize)> = (0..nb).map(|i| (adj[i].len(), i)).collect();
    let mut eligible: Vec<bool> = (0..n_nodes).map(|i| i < nb).collect();
    let mut matching = Matching { locks, owner: vec![None; nb] };
    // Locks whose bodies are both eliminated but that found no match yet (rare: only when
    // the greedy matches blocked them); retried whenever a body is eliminated.
    let mut stuck: BTreeSet<usize> = BTreeSet::new();
    while let Some((_, p)) = by_degree.pop_first() {
        done[p] = true;
        order.push(p);
        let nbrs: Vec<usize> = adj[p].iter().copied().filter(|&j| !done[j]).collect();
        for &i in &nbrs {
            if eligible[i] {
                by_degree.remove(&(adj[i].len(), i));
            }
            adj[i].remove(&p);
            for &j in &nbrs {
                if i != j {
                    adj[i].insert(j);
                }
            }
            if eligible[i] {
                by_degree.insert((adj[i].len(), i));
            }
        }
        if p >= nb {
            continue;
        }
        // A body went: its waiting locks (and the stuck ones) try to find a match.
        let mut candidates: Vec<usize> = nbrs
            .iter()
            .filter(|&&i| i >= nb && !eligible[i] && (locks[i - nb].0 == p || locks[i - nb].1 == p))
            .map(|&i| i - nb)
            .collect();
        candidates.extend(stuck.iter().copied());
        for g in candidates {
            let i = nb + g;
            if eligible[i] {
                continue;
            }
            if matching.augment(g, &done[..nb]) {
                eligible[i] = true;
                stuck.remove(&g);
                by_degree.insert((adj[i].len(), i));
            } else if done[locks[g].0] && done[locks[g].1] {
                stuck.insert(g);
            }
        }
    }
    order.extend((nb..n_nodes).filter(|&i| !done[i]));
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether the order eliminates every lock after a distinct body of its own.
    fn matched_in_order(nb: usize, locks: &[(usize, usize)], order: &[usize]) -> bool {
        let mut done = vec![false; nb];
        let mut m = Matching { locks, owner: vec![None; nb] };
        for &p in order {
            if p < nb {
                done[p] = true;
            } else if !m.augment(p - nb, &done) {
                return false;
            }
        }
        true
    }

    #[test]
    fn two_full_locks_on_one_body_wait_for_their_other_bodies() {
        // Bodies 0 (hub) – 1 – 2 and 1 – 3: locks (0,1), (1,2), (1,3) all on body 1.
        let neighbours = vec![vec![0, 1], vec![0, 1, 2, 3], vec![1, 2], vec![1, 3]];
        let locks = [(0, 1), (1, 2), (1, 3)];
        let order = elimination_order(&neighbours, &locks);
        assert_eq!(order.len(), 7);
        assert!(matched_in_order(4, &locks, &order), "{order:?}");
    }

    #[test]
    fn a_star_of_locked_panels_takes_each_lock_after_its_panel() {
        let n = 50;
        let mut neighbours = vec![(0..=n).collect::<Vec<_>>()];
        neighbours.extend((1..=n).map(|i| vec![0, i]));
        let locks: Vec<(usize, usize)> = (1..=n).map(|i| (0, i)).collect();
        let order = elimination_order(&neighbours, &locks);
        assert!(matched_in_order(n + 1, &locks, &order));
        // Each lock goes with its panel, before the hub (once the hub's degree is down to
        // that of a panel the two are interchangeable): no clique of locks round the hub.
        let hub_at = order.iter().position(|&p| p == 0).unwrap();
        let locks_before_hub = order[..hub_at].iter().filter(|&&p| p > n).count();
        assert!(locks_before_hub >= n - 2, "{order:?}");
    }

    #[test]
    fn every_node_is_ordered_once_even_with_a_loop_of_locks() {
        // A triangle of bodies, every hinge locked: redundant rows (the factorization
        // reports them singular); the order still holds every node once.
        let neighbours = vec![vec![0, 1, 2], vec![0, 1, 2], vec![0, 1, 2]];
        let locks = [(0, 1), (1, 2), (2, 0)];
        let mut order = elimination_order(&neighbours, &locks);
        order.sort();
        assert_eq!(order, (0..6).collect::<Vec<_>>());
    }
}
