//! A hinge between two bodies: where its frames A0 and A sit in them, and its law
//! (docs/model.md §2).

use crate::law::HingeLaw;
use crate::math::{Mat3, Vec3};

/// Where a hinge's zero-force frame A0 sits in its parent (docs/model.md §2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParentFrame {
    /// Given explicitly: origin `ᵖr_{A0/p}` (m, parent components) and `[A0 p]`.
    Given {
        /// `ᵖr_{A0/p}`, m, parent components.
        r_a0_in_parent: Vec3,
        /// `[A0 p]`.
        dcm_a0_parent: Mat3,
    },
    /// Placed once where A lies when every tree coordinate is zero (loop hinges only).
    Assembled,
}

/// A hinge as described in a scenario, before A0 frames are assembled.
#[derive(Debug)]
pub struct HingeSpec {
    /// Unique name, used for output columns.
    pub name: String,
    /// Index of the parent body.
    pub parent: usize,
    /// Index of the child body.
    pub child: usize,
    /// A0 in the parent.
    pub parent_frame: ParentFrame,
    /// `ᴬr_{c/A}`: the child's CoM from A's origin, m, A components.
    pub r_child_in_a: Vec3,
    /// `[c A]`: the child's body frame relative to A.
    pub dcm_child_a: Mat3,
    /// Force and torque response.
    pub law: Box<dyn HingeLaw>,
}

/// A hinge with both frames resolved (docs/model.md §2).
#[derive(Debug)]
pub struct Hinge {
    /// Unique name, used for output columns.
    pub name: String,
    /// Index of the parent body.
    pub parent: usize,
    /// Index of the child body.
    pub child: usize,
    /// `ᵖr_{A0/p}`: A0's origin from the parent CoM, m, parent components.
    pub r_a0_in_parent: Vec3,
    /// `[A0 p]`.
    pub dcm_a0_parent: Mat3,
    /// `ᴬr_{c/A}`: the child's CoM from A's origin, m, A components.
    pub r_child_in_a: Vec3,
    /// `[c A]`.
    pub dcm_child_a: Mat3,
    /// `ᶜr_{A/c} = −[c A] ᴬr_{c/A}`: A's origin from the child CoM, m, child components.
    pub(crate) r_a_in_child: Vec3,
    /// `[p A0] = [A0 p]ᵀ`.
    pub(crate) dcm_parent_a0: Mat3,
    /// Force and torque response.
    pub law: Box<dyn HingeLaw>,
    /// Whether A0 was assembled (docs/model.md §2) rather than given.
    pub assembled: bool,
}

/// The frames of a hinge placed from one of its bodies, all in N: the placed body's pose and
/// the hinge frames between the two (docs/model.md §2–3). From [`Hinge::place`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The placed body's CoM, m, N components.
    pub r_in_n: Vec3,
    /// The placed body's attitude `[N b]`.
    pub dcm_n_b: Mat3,
    /// `[N A0]`.
    pub dcm_n_a0: Mat3,
    /// `[N A]`.
    pub dcm_n_a: Mat3,
    /// A0's origin from the parent CoM, m, N components.
    pub arm_a0_in_n: Vec3,
    /// δ, A's origin from A0's, m, N components.
    pub delta_in_n: Vec3,
    /// A's origin from the child CoM, m, N components.
    pub arm_a_in_n: Vec3,
}

impl Hinge {
    /// The two bodies this hinge joins, the lower index first (a pair of bodies as contact
    /// and its episodes name it).
    pub fn bodies_sorted(&self) -> (usize, usize) {
        (self.parent.min(self.child), self.parent.max(self.child))
    }

    /// Places the body on the far side of this hinge from the pose `(R in N, [N b])` of the
    /// body on the near side, at relative attitude `[A A0]` and displacement δ (A0
    /// components, m). `reversed` is false when the near body is the hinge's parent.
    ///
    /// Frame chain (docs/model.md §2): `[N A0] = [N p][p A0]`, `[N A] = [N A0][A A0]ᵀ`,
    /// `[N c] = [N A][c A]ᵀ`, and `R_c = R_p + [N p] ᵖr_{A0/p} + [N A0] δ − [N c] ᶜr_{A/c}`.
    pub fn place(&self, reversed: bool, from: (Vec3, Mat3), dcm_a_a0: &Mat3, delta_in_a0: &Vec3) -> Placement {
        if !reversed {
            let (r_p, dcm_n_p) = from;
            let dcm_n_a0 = dcm_n_p * self.dcm_parent_a0;
            let dcm_n_a = dcm_n_a0 * dcm_a_a0.transpose();
            let dcm_n_c = dcm_n_a * self.dcm_child_a.transpose();
            let arm_a0 = dcm_n_p * self.r_a0_in_parent;
            let delta_n = dcm_n_a0 * delta_in_a0;
            let arm_a = dcm_n_c * self.r_a_in_child;
            let r_c = r_p + arm_a0 + delta_n - arm_a;
            Placement {
                r_in_n: r_c,
                dcm_n_b: dcm_n_c,
                dcm_n_a0,
                dcm_n_a,
                arm_a0_in_n: arm_a0,
                delta_in_n: delta_n,
                arm_a_in_n: arm_a,
            }
        } else {
            let (r_c, dcm_n_c) = from;
            let dcm_n_a = dcm_n_c * self.dcm_child_a;
            let dcm_n_a0 = dcm_n_a * dcm_a_a0;
            let dcm_n_p = dcm_n_a0 * self.dcm_a0_parent;
            let arm_a = dcm_n_c * self.r_a_in_child;
            let delta_n = dcm_n_a0 * delta_in_a0;
            let arm_a0 = dcm_n_p * self.r_a0_in_parent;
            let r_p = r_c + arm_a - delta_n - arm_a0;
            Placement {
                r_in_n: r_p,
                dcm_n_b: dcm_n_p,
                dcm_n_a0,
                dcm_n_a,
                arm_a0_in_n: arm_a0,
                delta_in_n: delta_n,
                arm_a_in_n: arm_a,
            }
        }
    }
}
