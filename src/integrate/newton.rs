//! The Newton matrix of an implicit method: `W = I − hγ J` formed, factored and solved
//! with, behind one trait, so how the Jacobian is found is separate from the method.
//! [`DenseNewton`] (here) is for small systems and tests; runs use
//! `crate::dynamics::newton::GraphNewton`, which follows the hinge graph.

use super::step::OdeSystem;

/// Forms and factors `W = I − hγ J(t, y)` and solves with it.
pub trait NewtonMatrix {
    /// Forms and factors W at `(t, y)`. Returns false if W is singular. A Jacobian formed by
    /// differences evaluates `f(t, y)` itself, as its base point (counted in
    /// [`Self::evaluations`]): the integrators' own `f` at `y` is not always f (SDIRK4's is a
    /// stage's implied derivative, generalized-α's its own ẏ), and an exact Jacobian needs
    /// none, so no caller evaluates one for it.
    fn prepare(&mut self, t: f64, y: &[f64], h_gamma: f64) -> bool;
    /// Forms and factors W at `(t, y)` with only the Jacobian's contact part brought up to
    /// date there, the rest kept from the last [`Self::prepare`] (a Newton iteration that
    /// failed as points came into contact within the step needs the contact's stiffness, not
    /// the hinges' again). By default, and wherever the Jacobian has no such split, as
    /// [`Self::prepare`]. Returns false if W is singular.
    fn refresh_contact(&mut self, t: f64, y: &[f64], h_gamma: f64) -> bool {
        self.prepare(t, y, h_gamma)
    }
    /// Refactors W for a new `hγ` with the Jacobian kept. Returns false if singular.
    fn refactor(&mut self, h_gamma: f64) -> bool;
    /// Overwrites `b` with `W⁻¹ b`.
    fn solve(&mut self, b: &mut [f64]);
    /// Right-hand-side evaluations spent forming Jacobians so far.
    fn evaluations(&self) -> usize;
    /// After a factorization that failed: the unknown block whose pivot was singular, as
    /// the implementation numbers its blocks (`GraphNewton`: the bodies in model order, then
    /// one per locked hinge it carries), if it knows.
    fn singular_block(&self) -> Option<usize> {
        None
    }
}

/// A dense Newton matrix: the Jacobian by forward differences, an LU factorization. Its cost
/// grows as n³; for small systems and for testing.
pub struct DenseNewton<'a, S: OdeSystem + ?Sized> {
    system: &'a S,
    jacobian: nalgebra::DMatrix<f64>,
    lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    evaluations: usize,
}

impl<'a, S: OdeSystem + ?Sized> DenseNewton<'a, S> {
    /// A dense Newton matrix for `system` of dimension `n`.
    pub fn new(system: &'a S, n: usize) -> Self {
        Self { system, jacobian: nalgebra::DMatrix::zeros(n, n), lu: None, evaluations: 0 }
    }
}

impl<S: OdeSystem + ?Sized> NewtonMatrix for DenseNewton<'_, S> {
    fn prepare(&mut self, t: f64, y: &[f64], h_gamma: f64) -> bool {
        let n = y.len();
        let mut f = vec![0.0; n];
        self.system.rhs(t, y, &mut f);
        self.evaluations += 1;
        let mut yp = y.to_vec();
        let mut fp = vec![0.0; n];
        for j in 0..n {
            let d = (f64::EPSILON * y[j].abs().max(1e-5)).sqrt().max(1e-8);
            yp[j] = y[j] + d;
            self.system.rhs(t, &yp, &mut fp);
            self.evaluations += 1;
            for i in 0..n {
                self.jacobian[(i, j)] = (fp[i] - f[i]) / d;
            }
            yp[j] = y[j];
        }
        self.refactor(h_gamma)
    }

    fn refactor(&mut self, h_gamma: f64) -> bool {
        let n = self.jacobian.nrows();
        let w = nalgebra::DMatrix::identity(n, n) - &self.jacobian * h_gamma;
        let lu = w.lu();
        let ok = lu.is_invertible();
        self.lu = Some(lu);
        ok
    }

    fn solve(&mut self, b: &mut [f64]) {
        let lu = self.lu.as_ref().expect("prepared before solving");
        let mut v = nalgebra::DVector::from_column_slice(b);
        lu.solve_mut(&mut v);
        b.copy_from_slice(v.as_slice());
    }

    fn evaluations(&self) -> usize {
        self.evaluations
    }
}
