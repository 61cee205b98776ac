//! One body pair's contact in the exact Jacobian (see [`super::jacobian`]): the force on the
//! sample body A summed over the pair's contact points, and its moments about both centres of
//! mass, with their derivatives in the pair's 26 state lanes (A's 13 at 0..13, B's at 13..26).
//!
//! The law is differentiated in each point's six local inputs (its place and velocity in B)
//! by dual numbers of six lanes, and the chain rule to the 26 lanes is linear in the point's
//! body-fixed offset `s`: its place is `p = a + [B A] s` and its velocity
//! `v = v_a + S s − ω_B × p` (`S = [B N][ω_A×][N A]`). So with `G_p`, `G_v` the force's 3 × 3
//! derivatives in `p` and `v`, `C = G_p − G_v [ω_B×]` and `Ω` the lanes of `ω_B`:
//!
//! ```text
//! ∂f   = C ∂a + Σ_j s_j C ∂[B A]_j + G_v ∂v_a + Σ_j s_j G_v ∂S_j + G_v [p×] ∂Ω
//! ∂(p × f) = [p×] ∂f − [f×] ∂p
//! ```
//!
//! Each point adds its 3 × 3 coefficients of the nine 3 × 26 lane matrices
//! (`∂a, ∂[B A]_j, ∂v_a, ∂S_j, ∂Ω`) to the pair's sums, and the lanes are formed once per pair
//! at the end: a few 3 × 3 products per point instead of a dozen 3 × 26 ones (the pair's
//! points number 10–60 on a stowed thick flasher).

use super::lanes::{D13, D26 as D, widen};
use crate::math::skew;
use crate::state::{BODY_STATE_LEN as B, BodyMotion};
use nalgebra::{Const, Matrix3, SMatrix, U1, Vector3};

/// A 3-vector's value and its derivatives in the 26 lanes of a pair (3 × 26).
#[derive(Clone, Copy)]
struct Lanes3 {
    value: Vector3<f64>,
    lanes: SMatrix<f64, 3, 26>,
}

impl Lanes3 {
    /// Back to dual numbers.
    fn dual(value: &Vector3<f64>, lanes: &SMatrix<f64, 3, 26>) -> Vector3<D> {
        Vector3::from_fn(|i, _| D::new(value[i], num_dual::Derivative::some(lanes.row(i).transpose())))
    }
}

/// The lane matrices a point's derivatives are combined from, in this order: `∂a`,
/// `∂[B A]_j` (j = 0, 1, 2), `∂v_a`, `∂S_j`, `∂Ω`.
const TERMS: usize = 9;

/// Dual numbers of the six local contact inputs.
type D6 = num_dual::DualSVec64<6>;

/// A body pair in contact (sample body A, probed body B), its points' contact summed.
pub(super) struct PairSum {
    /// (A, B).
    pub(super) bodies: (usize, usize),
    /// `[N B]`.
    pub(super) dcm_n_b: Matrix3<D>,
    /// `[B N](R_A − R_B)`, m.
    a_in_b: Lanes3,
    /// `[B A]`, by columns.
    dcm_b_a: [Lanes3; 3],
    /// `[B N](Ṙ_A − Ṙ_B)`, m/s.
    velocity_a_in_b: Lanes3,
    /// `[B N][ω_A×][N A]`, 1/s, by columns: a body-fixed offset's velocity from A's rotation,
    /// in B.
    spin_a_in_b: [Lanes3; 3],
    /// `[B N]ω_B`, rad/s.
    omega_b_in_b: Lanes3,
    /// The force on A, N, B frame, and its moment about B's centre of mass, N·m, B frame.
    force: Vector3<f64>,
    moment_about_b: Vector3<f64>,
    /// The coefficients of the [`TERMS`] lane matrices in the force's and the moment's
    /// derivatives, summed over the points.
    force_coefficients: [Matrix3<f64>; TERMS],
    moment_coefficients: [Matrix3<f64>; TERMS],
}

impl PairSum {
    /// The pair `bodies` from each body's motion in its own 13 lanes (`motion_a`, `motion_b`:
    /// A's become the pair's lanes 0..13, B's 13..26). Each quantity is `[B N]` times
    /// something of A's plus something of B's, so its lanes are formed in 13 lanes a side
    /// (A's with `[B N]` and B's part held at their values, B's with A's part held) rather
    /// than in 26 throughout.
    pub(super) fn new(bodies: (usize, usize), motion_a: &BodyMotion<D13>, motion_b: &BodyMotion<D13>) -> Self {
        let dcm_b_n = motion_b.dcm_n_b.transpose();
        let dcm_b_n_value = dcm_b_n.map(|x| x.re);
        // [B N] (u + w), u of A's, w of B's.
        let in_b = |u: &Vector3<D13>, w: &Vector3<D13>| {
            let from_a = dcm_b_n_value.map(D13::from_re) * u;
            let from_b = dcm_b_n * (u.map(|x| D13::from_re(x.re)) + w);
            let mut lanes = SMatrix::<f64, 3, 26>::zeros();
            for i in 0..3 {
                if let Some(g) = from_a[i].eps.0 {
                    lanes.fixed_view_mut::<1, 13>(i, 0).copy_from(&g.transpose());
                }
                if let Some(g) = from_b[i].eps.0 {
                    lanes.fixed_view_mut::<1, 13>(i, B).copy_from(&g.transpose());
                }
            }
            Lanes3 { value: from_b.map(|x| x.re), lanes }
        };
        let zero = Vector3::<D13>::zeros();
        let dcm_n_a = &motion_a.dcm_n_b;
        Self {
            bodies,
            a_in_b: in_b(&motion_a.r_in_n, &(-motion_b.r_in_n)),
            dcm_b_a: [0, 1, 2].map(|j| in_b(&dcm_n_a.column(j).into_owned(), &zero)),
            velocity_a_in_b: in_b(&motion_a.v_in_n, &(-motion_b.v_in_n)),
            spin_a_in_b: [0, 1, 2].map(|j| in_b(&motion_a.omega_in_n.cross(&dcm_n_a.column(j).into_owned()), &zero)),
            omega_b_in_b: in_b(&zero, &motion_b.omega_in_n),
            dcm_n_b: motion_b.dcm_n_b.map(|x| widen(x, B)),
            force: Vector3::zeros(),
            moment_about_b: Vector3::zeros(),
            force_coefficients: [Matrix3::zeros(); TERMS],
            moment_coefficients: [Matrix3::zeros(); TERMS],
        }
    }

    /// Adds the contact of `sample` in `solid` (crate::contact::ContactSet::local_force), for
    /// a point that came into contact at `impact_speed` (m/s; held).
    pub(super) fn add(
        &mut self,
        set: &crate::contact::ContactSet,
        sample: &crate::contact::solid::Sample,
        solid: &crate::contact::solid::Solid,
        impact_speed: Option<f64>,
    ) {
        let s = sample.point_in_body;
        let mut p = self.a_in_b.value;
        let mut v = self.velocity_a_in_b.value;
        for j in 0..3 {
            p += self.dcm_b_a[j].value * s[j];
            v += self.spin_a_in_b[j].value * s[j];
        }
        let w = self.omega_b_in_b.value;
        v -= w.cross(&p);
        let local = [p.x, p.y, p.z, v.x, v.y, v.z];
        let seed: [D6; 6] = std::array::from_fn(|k| D6::from_re(local[k]).derivative(k));
        let (p6, v6) = (Vector3::new(seed[0], seed[1], seed[2]), Vector3::new(seed[3], seed[4], seed[5]));
        let Some(f) = set.local_force(sample, solid, &p6, &v6, impact_speed) else { return };
        // ∂f/∂(p, v): 3 × 6.
        let mut g = SMatrix::<f64, 3, 6>::zeros();
        for i in 0..3 {
            g.set_row(i, &f.force_in_b[i].eps.unwrap_generic(Const::<6>, U1).transpose());
        }
        let (g_p, g_v): (Matrix3<f64>, Matrix3<f64>) = (g.fixed_columns::<3>(0).into(), g.fixed_columns::<3>(3).into());
        let force = f.force_in_b.map(|c| c.re);
        let (p_cross, f_cross) = (skew(&p), skew(&force));
        let c = g_p - g_v * skew(&w);
        let g_v_p = g_v * p_cross;
        // The moment's: [p×] ∂f − [f×] ∂p, with ∂p = ∂a + Σ s_j ∂[B A]_j.
        let m_c = p_cross * c - f_cross;
        let m_v = p_cross * g_v;
        let (fc, mc) = (&mut self.force_coefficients, &mut self.moment_coefficients);
        fc[0] += c;
        mc[0] += m_c;
        fc[4] += g_v;
        mc[4] += m_v;
        fc[8] += g_v_p;
        mc[8] += p_cross * g_v_p;
        for j in 0..3 {
            fc[1 + j] += c * s[j];
            mc[1 + j] += m_c * s[j];
            fc[5 + j] += g_v * s[j];
            mc[5 + j] += m_v * s[j];
        }
        self.force += force;
        self.moment_about_b += p.cross(&force);
    }

    /// The force on A (N) and its moments about A's and B's centres of mass (N·m), all in B
    /// components, as dual numbers in the pair's 26 lanes. The moment about A is
    /// `Σ (p − a) × f = M_B − a × F`.
    pub(super) fn force_and_moments(&self) -> (Vector3<D>, Vector3<D>, Vector3<D>) {
        let terms: [&SMatrix<f64, 3, 26>; TERMS] = [
            &self.a_in_b.lanes,
            &self.dcm_b_a[0].lanes,
            &self.dcm_b_a[1].lanes,
            &self.dcm_b_a[2].lanes,
            &self.velocity_a_in_b.lanes,
            &self.spin_a_in_b[0].lanes,
            &self.spin_a_in_b[1].lanes,
            &self.spin_a_in_b[2].lanes,
            &self.omega_b_in_b.lanes,
        ];
        let mut force_lanes = SMatrix::<f64, 3, 26>::zeros();
        let mut moment_lanes = SMatrix::<f64, 3, 26>::zeros();
        for (k, term) in terms.iter().enumerate() {
            force_lanes += self.force_coefficients[k] * *term;
            moment_lanes += self.moment_coefficients[k] * *term;
        }
        let a = &self.a_in_b;
        let moment_about_a = self.moment_about_b - a.value.cross(&self.force);
        let moment_about_a_lanes = moment_lanes - skew(&a.value) * force_lanes + skew(&self.force) * a.lanes;
        (
            Lanes3::dual(&self.force, &force_lanes),
            Lanes3::dual(&moment_about_a, &moment_about_a_lanes),
            Lanes3::dual(&self.moment_about_b, &moment_lanes),
        )
    }
}
