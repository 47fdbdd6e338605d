//! Starting ALI3-P from a given state (a static equilibrium, a checkpoint of another run).

use flexmbd_core::{Formulation, Request, SystemTerms};
use nalgebra::DVector;

use crate::StaticSolution;

/// A formulation that starts from given positions and velocities: `initial_guess` returns
/// them, everything else is forwarded to the wrapped formulation. Build ALI3-P with it
/// ([`crate::Ali3p::new`]) and step with the wrapped formulation afterwards.
pub struct StartFrom<'a, F: Formulation + ?Sized> {
    inner: &'a mut F,
    q: DVector<f64>,
    qd: DVector<f64>,
}

impl<'a, F: Formulation + ?Sized> StartFrom<'a, F> {
    /// Start `inner` at (q, q̇).
    pub fn new(inner: &'a mut F, q: DVector<f64>, qd: DVector<f64>) -> Self {
        StartFrom { inner, q, qd }
    }
    /// Start `inner` at rest at the static equilibrium `sol`.
    pub fn at_rest(inner: &'a mut F, sol: &StaticSolution) -> Self {
        let n = sol.q.len();
        StartFrom {
            inner,
            q: sol.q.clone(),
            qd: DVector::zeros(n),
        }
    }
}

impl<F: Formulation + ?Sized> Formulation for StartFrom<'_, F> {
    fn n_coordinates(&self) -> usize {
        self.inner.n_coordinates()
    }
    fn n_constraints(&self) -> usize {
        self.inner.n_constraints()
    }
    fn initial_guess(&self, q: &mut DVector<f64>, qd: &mut DVector<f64>) {
        q.copy_from(&self.q);
        qd.copy_from(&self.qd);
    }
    fn specified_coordinates(&self) -> &[usize] {
        self.inner.specified_coordinates()
    }
    fn evaluate(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        req: Request,
        out: &mut SystemTerms,
    ) {
        self.inner.evaluate(t, q, qd, req, out)
    }
    fn constant_tangents(&self) -> bool {
        self.inner.constant_tangents()
    }
    fn constant_mass(&self) -> bool {
        self.inner.constant_mass()
    }
    fn symmetric_tangent(&self) -> bool {
        self.inner.symmetric_tangent()
    }
}
