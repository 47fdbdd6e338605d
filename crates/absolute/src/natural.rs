//! Seam to the body crate's natural-coordinate inertia terms (pending).
use flexmbd_body::{FlexibleBody, InertiaMethod};
use nalgebra::{DMatrix, DVector, Vector2};

#[allow(clippy::too_many_arguments)]
pub(crate) fn planar_terms(
    _body: &FlexibleBody,
    _method: InertiaMethod,
    _r0: Vector2<f64>,
    _u: Vector2<f64>,
    _r0d: Vector2<f64>,
    _ud: Vector2<f64>,
    _y: &[f64],
    _yd: &[f64],
    _m: &mut DMatrix<f64>,
    _q: &mut DVector<f64>,
) {
    unreachable!("flexible bodies are refused at compile time until the natural set lands")
}

pub(crate) fn planar_gravity(
    _body: &FlexibleBody,
    _u: Vector2<f64>,
    _y: &[f64],
    _g: Vector2<f64>,
    _q: &mut DVector<f64>,
) {
    unreachable!()
}
