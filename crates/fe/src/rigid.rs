//! A rigid body as a [`ReducedBody`] with zero modes (docs/methods.md §2.4, "Rigid body").
//!
//! The body gets a small mass cloud whose mass, first moment and second moment
//! reproduce the given mass, centre of mass and inertia tensor to round-off, so
//! that both inertia routes of `flexmbd-body` (B-matrix projection on the cloud
//! and shape integrals) work unchanged on rigid bodies.
//!
//! * 3D: six points `c ± d_i e_i` on the principal axes `e_i` of the second
//!   moment about the centre of mass, `P_c = ½ tr(I_c) 𝟙 − I_c = Σ λ_i e_i e_iᵀ`,
//!   each of weight m/6, with `d_i = √(3 λ_i / m)`. `λ_i ≥ 0` is the triangle
//!   inequality of the principal moments (`I_1 + I_2 ≥ I_3`).
//! * 2D: the body lives in z = 0 and only `I_zz` matters: four points
//!   `c ± d e_x`, `c ± d e_y` of weight m/4 with `d = √(I_zz / m)`.

use crate::reduced::{MassCloud, ModeInventory, ReducedBody, ShapeIntegrals, StiffeningIntegrals};
use flexmbd_core::{Dim, InvalidValue};
use nalgebra::{DMatrix, Matrix3, SymmetricEigen, Vector3};

fn fmt_vec(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

fn fmt_mat(m: &Matrix3<f64>) -> String {
    format!(
        "[[{}, {}, {}], [{}, {}, {}], [{}, {}, {}]]",
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)]
    )
}

impl ReducedBody {
    /// A rigid body (zero modes) with the given mass (kg), centre of mass (m, body
    /// components) and inertia tensor about the centre of mass (kg·m², body axes).
    ///
    /// Refused, naming the field (`mass`, `center_of_mass`, `inertia_about_com`) and value:
    /// a mass that is not finite and > 0; a non-finite centre of mass (in 2D also
    /// a non-zero z, since a planar body lives in z = 0); in 3D an inertia tensor
    /// that is not finite, not symmetric, not positive definite or whose principal
    /// moments violate the triangle inequality; in 2D an `I_zz` that is not finite
    /// and > 0 (the other entries are not used in 2D).
    pub fn rigid(
        dim: Dim,
        mass: f64,
        center_of_mass: Vector3<f64>,
        inertia_about_com: Matrix3<f64>,
    ) -> Result<ReducedBody, InvalidValue> {
        flexmbd_core::require_positive("mass", mass)?;
        if !center_of_mass.iter().all(|v| v.is_finite()) {
            return Err(InvalidValue::new(
                "center_of_mass",
                fmt_vec(&center_of_mass),
                "must be finite",
            ));
        }
        let cloud = match dim {
            Dim::Planar => planar_cloud(mass, center_of_mass, &inertia_about_com)?,
            Dim::Spatial => spatial_cloud(mass, center_of_mass, &inertia_about_com)?,
        };
        Ok(Self::with_rigid_cloud(dim, cloud))
    }

    /// The body with no FE model and no modes whose inertia is that of `cloud`:
    /// the shape integrals are taken from the cloud, every modal matrix is 0 × 0.
    fn with_rigid_cloud(dim: Dim, cloud: MassCloud) -> ReducedBody {
        let shape_integrals = ShapeIntegrals::from_cloud(&cloud);
        ReducedBody {
            dim,
            inventory: ModeInventory {
                n_fe_dofs: 0,
                frame_dofs: Vec::new(),
                static_modes: Vec::new(),
                normal_frequencies_hz: Vec::new(),
                selection: Default::default(),
                reference: Default::default(),
                point_names: Vec::new(),
            },
            modes: DMatrix::zeros(0, 0),
            m_ff: DMatrix::zeros(0, 0),
            k_ff: DMatrix::zeros(0, 0),
            c_ff: DMatrix::zeros(0, 0),
            cloud,
            shape_integrals,
            nodes: Vec::new(),
            stiffening: StiffeningIntegrals::default(),
            foreshortening: None,
        }
    }
}

/// A cloud of point masses with no mode rows (a rigid body's).
fn rigid_cloud(positions: Vec<Vector3<f64>>, weights: Vec<f64>, description: &str) -> MassCloud {
    MassCloud {
        n_modes: 0,
        positions,
        weights,
        mode_rows: Vec::new(),
        description: description.to_string(),
    }
}

/// 2D: four points `c ± d e_x`, `c ± d e_y` of weight m/4 with `d = √(I_zz / m)`,
/// after checking that the body lies in z = 0 and that `I_zz` is positive (the
/// other entries of the tensor do not enter a planar motion).
fn planar_cloud(
    mass: f64,
    c: Vector3<f64>,
    inertia_about_com: &Matrix3<f64>,
) -> Result<MassCloud, InvalidValue> {
    if c.z != 0.0 {
        return Err(InvalidValue::new(
            "center_of_mass.z",
            c.z,
            "a planar body lives in z = 0",
        ));
    }
    let izz = inertia_about_com[(2, 2)];
    if !(izz.is_finite() && izz > 0.0) {
        return Err(InvalidValue::new(
            "inertia_about_com.zz",
            izz,
            "must be finite and > 0",
        ));
    }
    let d = (izz / mass).sqrt();
    let positions = vec![
        c + Vector3::new(d, 0.0, 0.0),
        c - Vector3::new(d, 0.0, 0.0),
        c + Vector3::new(0.0, d, 0.0),
        c - Vector3::new(0.0, d, 0.0),
    ];
    Ok(rigid_cloud(
        positions,
        vec![0.25 * mass; 4],
        "rigid body: 4 points at ±√(I_zz/m) along x and y about the centre of mass",
    ))
}

/// 3D: six points `c ± d_k e_k` of weight m/6 on the principal axes `e_k`, with
/// `d_k = √(3 λ_k / m)` for the principal second moments `λ_k`.
fn spatial_cloud(
    mass: f64,
    c: Vector3<f64>,
    inertia_about_com: &Matrix3<f64>,
) -> Result<MassCloud, InvalidValue> {
    let (lambda, axes) = principal_second_moments(inertia_about_com)?;
    let mut positions = Vec::with_capacity(6);
    for k in 0..3 {
        let e: Vector3<f64> = axes.column(k).into_owned();
        let d = (3.0 * lambda[k] / mass).sqrt();
        positions.push(c + d * e);
        positions.push(c - d * e);
    }
    Ok(rigid_cloud(
        positions,
        vec![mass / 6.0; 6],
        "rigid body: 6 points on the principal axes about the centre of mass",
    ))
}

/// The principal second moments `λ_k = ½ tr(I) − I_k` about the centre of mass
/// and the principal axes (columns) of an inertia tensor `I`, refused unless
/// `I` is finite, symmetric and positive definite with `λ_k ≥ 0` (the triangle
/// inequality `I_1 + I_2 ≥ I_3`; a round-off negative `λ_k` is taken as 0).
fn principal_second_moments(i: &Matrix3<f64>) -> Result<([f64; 3], Matrix3<f64>), InvalidValue> {
    let bad = |reason: &str| {
        Err(InvalidValue::new(
            "inertia_about_com",
            fmt_mat(i),
            reason.to_string(),
        ))
    };
    if !i.iter().all(|v| v.is_finite()) {
        return bad("must be finite");
    }
    let scale = i.abs().max();
    if (i - i.transpose()).abs().max() > 1e-12 * scale {
        return bad("must be symmetric");
    }
    let sym = 0.5 * (i + i.transpose());
    let eig = SymmetricEigen::new(sym);
    let min = eig.eigenvalues.min();
    if min.is_nan() || min <= 0.0 {
        return bad("must be positive definite (principal moments > 0)");
    }
    let tr = eig.eigenvalues.sum();
    let tol = 1e-12 * tr;
    let mut lambda = [0.0; 3];
    for k in 0..3 {
        let l = 0.5 * tr - eig.eigenvalues[k];
        if l < -tol {
            return bad("principal moments violate the triangle inequality I1 + I2 >= I3");
        }
        lambda[k] = l.max(0.0);
    }
    Ok((lambda, eig.eigenvectors))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_reproduces_mass_properties() {
        let c = Vector3::new(0.3, -0.2, 0.1);
        let i = Matrix3::new(2.0, 0.1, -0.2, 0.1, 3.0, 0.05, -0.2, 0.05, 4.0);
        let b = ReducedBody::rigid(Dim::Spatial, 5.0, c, i).unwrap();
        let si = &b.shape_integrals;
        assert!((si.mass - 5.0).abs() < 1e-14);
        assert!((si.first_moment - 5.0 * c).norm() < 1e-14);
        let p_c = si.second_moment - 5.0 * c * c.transpose();
        let i_c = Matrix3::identity() * p_c.trace() - p_c;
        assert!((i_c - i).abs().max() < 1e-13);
    }

    #[test]
    fn rigid_refuses_bad_input() {
        let z = Vector3::zeros();
        let e = ReducedBody::rigid(Dim::Spatial, -1.0, z, Matrix3::identity()).unwrap_err();
        assert_eq!(e.field, "mass");
        let bad = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 3.0));
        let e = ReducedBody::rigid(Dim::Spatial, 1.0, z, bad).unwrap_err();
        assert_eq!(e.field, "inertia_about_com");
        assert!(e.reason.contains("triangle"));
    }
}
