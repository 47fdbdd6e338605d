//! Starting ALI3-P from a given state (a static equilibrium, a checkpoint of another run).

use flexmbd_core::{Coordinates, Formulation, Request, State, SystemTerms};
use nalgebra::DVector;

use crate::StaticSolution;

/// A formulation that starts from given positions and velocities: its [`Coordinates`] are
/// the wrapped formulation's with the initial guess replaced, everything else is forwarded.
/// Build ALI3-P with it ([`crate::Ali3p::new`]) and step with the wrapped formulation
/// afterwards.
pub struct StartFrom<'a, F: Formulation + ?Sized> {
    inner: &'a mut F,
    coordinates: Coordinates,
}

impl<'a, F: Formulation + ?Sized> StartFrom<'a, F> {
    /// Start `inner` at (q, q̇).
    pub fn new(inner: &'a mut F, q: DVector<f64>, qd: DVector<f64>) -> Self {
        let coordinates = Coordinates {
            specified: inner.specified_coordinates().to_vec(),
            ..Coordinates::new(q, qd, inner.n_constraints())
        };
        StartFrom { inner, coordinates }
    }
    /// Start `inner` at rest at the static equilibrium `sol`.
    pub fn at_rest(inner: &'a mut F, sol: &StaticSolution) -> Self {
        let n = sol.q.len();
        StartFrom::new(inner, sol.q.clone(), DVector::zeros(n))
    }
}

impl<F: Formulation + ?Sized> Formulation for StartFrom<'_, F> {
    fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }
    fn evaluate(&mut self, state: State<'_>, req: Request, out: &mut SystemTerms) {
        self.inner.evaluate(state, req, out)
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
    fn declared_pattern(&self) -> Option<flexmbd_core::DeclaredPattern> {
        self.inner.declared_pattern()
    }
    fn predictor_repeats_miss(&self) -> bool {
        self.inner.predictor_repeats_miss()
    }
}
