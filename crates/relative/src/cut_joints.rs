//! The constraints of the cut joints and of the drivers (docs/methods.md §4.6).

use nalgebra::Vector3;

/// Two unit vectors perpendicular to a and to each other.
pub(crate) fn perpendiculars(a: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let t = if a.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let n1 = a.cross(&t).normalize();
    let n2 = a.cross(&n1);
    (n1, n2)
}
