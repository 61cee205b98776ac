//! Thick panels' vertex cut-outs (docs/flasher.md, *Thick panels*): how far each panel corner
//! at a pattern vertex is cut back, and a panel's outline with its corners cut.

use crate::math::Vec3;
use std::collections::BTreeMap;

/// How far thick panels are cut back from each pattern vertex along each edge there (m, by
/// (vertex, other end of the edge)), with `h` half the thickness. Thick panels meeting at a
/// vertex tip to tip overlap as soon as the folds leave flat (the vertex interference that
/// thickness-accommodated patterns clear with cut-outs at the vertices: Zirbel et al. 2013),
/// and a thin plate's rounded rim (docs/contact.md §1) ends (h)/tan(α/2) short of an acute
/// corner of angle α. So every panel corner at a vertex is cut back by 1.5 h / tan(α/2) for
/// the sharpest panel corner there (the factor keeps the cut edge when the outline is moved
/// in by h), at most a third of the edge; one length per edge and vertex, so that the two
/// panels of a crease keep a common crease line and end it at the same point (their crease
/// samples match, docs/contact.md §1). The hub (panel 0) is not cut.
pub(super) fn tip_cuts(panels: &[Vec<usize>], dep: &[Vec3], h: f64) -> BTreeMap<(usize, usize), f64> {
    let mut radius: BTreeMap<usize, f64> = BTreeMap::new();
    let corners = |nodes: &[usize]| {
        let n = nodes.len();
        (0..n).map(move |i| (nodes[(i + n - 1) % n], nodes[i], nodes[(i + 1) % n])).collect::<Vec<_>>()
    };
    for nodes in panels.iter().skip(1) {
        for (prev, v, next) in corners(nodes) {
            let (u1, u2) = (dep[prev] - dep[v], dep[next] - dep[v]);
            let cos = (u1.dot(&u2) / (u1.norm() * u2.norm())).clamp(-1.0, 1.0);
            if cos > 0.0 {
                let r = 1.5 * h / (0.5 * cos.acos()).tan();
                let e = radius.entry(v).or_insert(0.0);
                *e = e.max(r);
            }
        }
    }
    let mut cuts = BTreeMap::new();
    for nodes in panels.iter().skip(1) {
        for (prev, v, next) in corners(nodes) {
            let r = radius.get(&v).copied().unwrap_or(0.0);
            for other in [prev, next] {
                cuts.insert((v, other), r.min((dep[other] - dep[v]).norm() / 3.0));
            }
        }
    }
    cuts
}

/// A panel's outline (nodes of `dep`, in order) with its corners cut back by `cuts`.
pub(super) fn cut_corners(nodes: &[usize], dep: &[Vec3], cuts: &BTreeMap<(usize, usize), f64>) -> Vec<Vec3> {
    let n = nodes.len();
    let mut out = Vec::with_capacity(2 * n);
    for i in 0..n {
        let (prev, v, next) = (nodes[(i + n - 1) % n], nodes[i], nodes[(i + 1) % n]);
        let c1 = cuts.get(&(v, prev)).copied().unwrap_or(0.0);
        let c2 = cuts.get(&(v, next)).copied().unwrap_or(0.0);
        if c1 > 0.0 {
            out.push(dep[v] + (dep[prev] - dep[v]).normalize() * c1);
        }
        if c1 <= 0.0 || c2 <= 0.0 {
            out.push(dep[v]);
        }
        if c2 > 0.0 {
            out.push(dep[v] + (dep[next] - dep[v]).normalize() * c2);
        }
    }
    out
}
