//! Force elements, written once for every formulation over its [`MarkerKinematics`].
//!
//! **Spring–damper** between markers P1 and P2 (docs/methods.md §2.6): with d = r_P2 − r_P1,
//! l = |d|, n = d/l and the tension f = k (l − l₀) + c n·(ṙ_P2 − ṙ_P1), the markers feel −f n
//! (at P2) and +f n (at P1), so Q += −f Jᵀn with J = ∂d/∂q. Tangents:
//! K += Jᵀ(k nnᵀ + f/l (I − nnᵀ)) J and C += c Jᵀ nnᵀ J; the terms from ∂J/∂q and the damper's
//! ∂l̇/∂q are left out (exact for rigid bodies in natural coordinates without a damper; a
//! tangent only steers Newton). Its potential energy is ½ k (l − l₀)².
//!
//! The free length l₀ is the scene's `free_length`, or the markers' distance at the start.

use flexmbd_core::{MarkerKinematics, SystemTerms};
use nalgebra::{DVector, Matrix3, Vector3};

use crate::error::ModelError;
use crate::prepared::{MarkerId, PreparedScene};
use crate::scene::Force;

/// A linear spring–damper between two markers, `M` being the formulation's marker handle.
#[derive(Clone, Debug)]
pub struct SpringDamper<M> {
    /// Marker P1 (the force's `marker1`).
    pub first: M,
    /// Marker P2 (the force's `marker2`).
    pub second: M,
    /// Stiffness k (N/m).
    pub stiffness: f64,
    /// Damping c (N·s/m).
    pub damping: f64,
    /// Free length l₀ (m).
    pub free_length: f64,
}

/// The force elements of a scene, compiled for one formulation, with the scratch their
/// Jacobians need (sized once: evaluating them allocates nothing).
#[derive(Clone, Debug)]
pub struct ForceElements<M> {
    springs: Vec<SpringDamper<M>>,
    /// (coordinate, ∂d/∂q_i) of the element being evaluated.
    columns: Vec<(usize, Vector3<f64>)>,
}

impl<M> Default for ForceElements<M> {
    fn default() -> Self {
        ForceElements {
            springs: Vec::new(),
            columns: Vec::new(),
        }
    }
}

impl<M> ForceElements<M> {
    /// Compile the scene's force elements for a formulation: `marker` maps a marker to the
    /// formulation's handle, `kinematics` at (`q0`, `qd0`) gives the markers' start positions
    /// (for free lengths left to the start); `n_coordinates` bounds the Jacobian columns.
    pub fn new<K>(
        prepared: &PreparedScene,
        mut marker: impl FnMut(MarkerId) -> M,
        kinematics: &K,
        q0: &DVector<f64>,
        qd0: &DVector<f64>,
        n_coordinates: usize,
    ) -> Result<Self, ModelError>
    where
        K: MarkerKinematics<Marker = M>,
    {
        let scene = prepared.scene();
        let mut springs = Vec::with_capacity(scene.forces.len());
        for (force, pair) in scene.forces.iter().zip(prepared.force_markers()) {
            let Force::SpringDamper {
                stiffness, damping, ..
            } = force;
            let (first, second) = (marker(pair.first), marker(pair.second));
            let (r1, _) = kinematics.marker_state(&first, q0, qd0);
            let (r2, _) = kinematics.marker_state(&second, q0, qd0);
            springs.push(SpringDamper {
                first,
                second,
                stiffness: *stiffness,
                damping: *damping,
                free_length: force.spring_free_length(&scene.origin, &r1, &r2)?,
            });
        }
        Ok(ForceElements {
            springs,
            columns: Vec::with_capacity(2 * n_coordinates),
        })
    }

    /// True when the scene has no force elements.
    pub fn is_empty(&self) -> bool {
        self.springs.is_empty()
    }

    /// The spring–dampers.
    pub fn springs(&self) -> &[SpringDamper<M>] {
        &self.springs
    }

    /// Add the elements' generalized forces Q at (q, q̇) to `out.forces`, and with `tangents`
    /// their K and C to `out.stiffness` and `out.damping`.
    pub fn add_forces<K>(
        &mut self,
        kinematics: &mut K,
        q: &DVector<f64>,
        qd: &DVector<f64>,
        tangents: bool,
        out: &mut SystemTerms,
    ) where
        K: MarkerKinematics<Marker = M>,
    {
        let columns = &mut self.columns;
        for spring in &self.springs {
            let (r1, v1) = kinematics.marker_state(&spring.first, q, qd);
            let (r2, v2) = kinematics.marker_state(&spring.second, q, qd);
            let d = r2 - r1;
            let l = d.norm();
            let n = d / l;
            let f =
                spring.stiffness * (l - spring.free_length) + spring.damping * n.dot(&(v2 - v1));
            columns.clear();
            kinematics.marker_jacobian(&spring.second, q, &mut |i, c| columns.push((i, c)));
            kinematics.marker_jacobian(&spring.first, q, &mut |i, c| columns.push((i, -c)));
            for &(i, c) in columns.iter() {
                out.forces[i] -= f * n.dot(&c);
            }
            if tangents {
                add_tangents(spring, &n, f, l, columns, out);
            }
        }
    }

    /// Potential energy of the elements at q (J): Σ ½ k (l − l₀)².
    pub fn potential_energy<K>(&self, kinematics: &K, q: &DVector<f64>, qd: &DVector<f64>) -> f64
    where
        K: MarkerKinematics<Marker = M>,
    {
        self.springs
            .iter()
            .map(|spring| {
                let (r1, _) = kinematics.marker_state(&spring.first, q, qd);
                let (r2, _) = kinematics.marker_state(&spring.second, q, qd);
                let stretch = (r2 - r1).norm() - spring.free_length;
                0.5 * spring.stiffness * stretch * stretch
            })
            .sum()
    }
}

/// K += Jᵀ(k nnᵀ + f/l (I − nnᵀ)) J, C += c Jᵀ nnᵀ J over the element's Jacobian columns.
fn add_tangents<M>(
    spring: &SpringDamper<M>,
    n: &Vector3<f64>,
    f: f64,
    l: f64,
    columns: &[(usize, Vector3<f64>)],
    out: &mut SystemTerms,
) {
    let nn = n * n.transpose();
    let stiffness = nn * spring.stiffness + (Matrix3::identity() - nn) * (f / l);
    for &(i, ci) in columns {
        let kc = stiffness * ci;
        let cc = spring.damping * n.dot(&ci);
        for &(j, cj) in columns {
            out.stiffness[(j, i)] += cj.dot(&kc);
            out.damping[(j, i)] += cc * n.dot(&cj);
        }
    }
}
