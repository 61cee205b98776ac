//! Contact among a model's bodies (docs/contact.md): each shape as a contact solid, and the
//! creases that hinged neighbours share, found in each hinge's undeformed state.

use super::shape::Shape;
use super::{Model, ModelError};
use crate::contact::law::ContactLaw;
use crate::contact::solid::Solid;
use crate::contact::{ContactSet, Frame};
use crate::math::{Mat3, Vec3};

/// The default distance between the sample points of solid bodies and thick plates, m: the
/// thinnest feature among the shapes that take part (a plate's thickness, a quarter of a
/// box's shortest edge or of a cylinder's diameter or height), so that an edge passing
/// through the thinnest solid meets a point inside it.
pub fn default_spacing(shapes: &[&Shape]) -> f64 {
    shapes
        .iter()
        .map(|s| match s {
            Shape::Plate { thickness, .. } => *thickness,
            Shape::Cuboid { size, .. } => size.min() / 4.0,
            Shape::Cylinder { radius, height } => (2.0 * radius).min(*height) / 4.0,
        })
        .fold(f64::INFINITY, f64::min)
}

impl Model {
    /// The pairs of bodies a hinge joins, each the lower index first (as contact and its
    /// episodes name a pair).
    pub fn hinged_pairs(&self) -> std::collections::HashSet<(usize, usize)> {
        self.hinges.iter().map(|h| h.bodies_sorted()).collect()
    }

    /// Turns contact on under `law`: every body with a shape takes part, sample points
    /// `spacing` m apart on solid bodies and thick plates (default [`default_spacing`]),
    /// no contact between the `excluded` pairs (body indices), and none along the crease of
    /// two bodies joined by a hinge (the samples of each that touch the other when the hinge
    /// is undeformed). Returns how many crease samples that left out.
    pub fn enable_contact(
        &mut self,
        law: ContactLaw,
        spacing: Option<f64>,
        excluded: &[(usize, usize)],
    ) -> Result<usize, ModelError> {
        for (i, b) in self.bodies.iter().enumerate() {
            if let Some(Shape::Plate { thickness, .. }) = &b.shape
                && *thickness <= 0.0
            {
                return Err(ModelError::body(
                    i,
                    format!(
                        "body '{}': a plate needs a thickness > 0 m to take part in contact (a solid that others cannot enter); its shape has none",
                        b.name
                    ),
                ));
            }
        }
        let shapes: Vec<&Shape> = self.bodies.iter().filter_map(|b| b.shape.as_ref()).collect();
        let spacing = spacing.unwrap_or_else(|| default_spacing(&shapes));
        let mut solids = Vec::with_capacity(self.bodies.len());
        for (i, b) in self.bodies.iter().enumerate() {
            let solid = match &b.shape {
                None => None,
                Some(Shape::Plate { vertices, thickness }) => Some(Solid::plate(vertices, *thickness, spacing)),
                Some(Shape::Cuboid { size, center }) => Some(Solid::cuboid(*size, *center, spacing)),
                Some(Shape::Cylinder { radius, height }) => Some(Solid::cylinder(*radius, *height, spacing)),
            };
            solids.push(solid.transpose().map_err(|m| ModelError::body(i, format!("body '{}': {m}", b.name)))?);
        }
        let mut set = ContactSet::new(law, solids);
        for &(a, b) in excluded {
            set.exclude(a, b);
        }
        let mut crease = 0;
        for h in &self.hinges {
            let placed = h.place(false, (Vec3::zeros(), Mat3::identity()), &Mat3::identity(), &Vec3::zeros());
            crease += set.mark_crease(h.parent, h.child, (placed.r_in_n, placed.dcm_n_b));
        }
        self.contact = Some(set);
        Ok(crease)
    }

    /// Per body, whether it touches another body at the poses `poses` (centre of mass, m, N;
    /// `[N b]`): some point of it in another body, or of another in it, deeper than
    /// `min_depth` m. All false without contact.
    pub fn touching(&self, poses: &[(Vec3, Mat3)], min_depth: f64) -> Vec<bool> {
        let frames: Vec<Frame> =
            poses.iter().map(|&(r, dcm)| Frame { position_in_n: r, dcm_n_b: dcm, ..Default::default() }).collect();
        let mut out = vec![false; self.bodies.len()];
        for (a, b, depth) in self.overlaps(&frames) {
            if depth > min_depth {
                out[a] = true;
                out[b] = true;
            }
        }
        out
    }

    /// The contact points whose bodies overlap at the poses `frames`, beyond the creases and
    /// excluded pairs: `(sample's body, other body, depth m)` of the deepest point of each
    /// overlapping pair, deepest first. Empty without contact.
    pub fn overlaps(&self, frames: &[Frame]) -> Vec<(usize, usize, f64)> {
        let Some(set) = &self.contact else { return Vec::new() };
        let mut points = Vec::new();
        set.evaluate(frames, &Default::default(), &mut Default::default(), &mut points);
        let mut deepest: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
        for p in &points {
            let key = (p.key.body as usize, p.key.other as usize);
            let d = deepest.entry((key.0.min(key.1), key.0.max(key.1))).or_insert(0.0);
            *d = d.max(p.depth);
        }
        let mut out: Vec<(usize, usize, f64)> = deepest.into_iter().map(|((a, b), d)| (a, b, d)).collect();
        out.sort_by(|x, y| y.2.total_cmp(&x.2));
        out
    }
}
