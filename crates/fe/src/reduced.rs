//! The plain data that FE preprocessing hands to the run-time body (`flexmbd-body`).
//!
//! A [`ReducedBody`] is everything a formulation needs of one flexible body and
//! nothing of the FE model it came from: the mode inventory, the reduced
//! matrices, the mass cloud (docs/methods.md §2.1) on which **both** inertia routes
//! act, the 13 shape integrals (§2.3) computed from that same cloud, the nodal
//! mode rows (for joints and sensors) and the per-mode stiffening integrals (§6).
//! A rigid body is the same type with zero modes.

use flexmbd_core::Dim;
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// A nodal degree of freedom in body (node-frame) axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Dof {
    /// Translation along body x.
    Ux,
    /// Translation along body y.
    Uy,
    /// Translation along body z (3D only).
    Uz,
    /// Rotation about body x (3D only; torsion of a beam along x).
    Rx,
    /// Rotation about body y (3D only).
    Ry,
    /// Rotation about body z.
    Rz,
}

impl Dof {
    /// The lower-case name used in outputs: `ux`, `uy`, `uz`, `rx`, `ry`, `rz`.
    pub fn name(self) -> &'static str {
        match self {
            Dof::Ux => "ux",
            Dof::Uy => "uy",
            Dof::Uz => "uz",
            Dof::Rx => "rx",
            Dof::Ry => "ry",
            Dof::Rz => "rz",
        }
    }
}

/// One nodal DOF of the FE model: node index (0 = first point of the polyline) and DOF.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct NodeDof {
    /// Node index along the mesh, 0-based.
    pub node: usize,
    /// Which DOF of the node.
    pub dof: Dof,
}

/// What the modes of a body are: the mode inventory printed by `flexmbd modes`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeInventory {
    /// DOFs of the free-floating FE model.
    pub n_fe_dofs: usize,
    /// The reference DOFs taken by the floating frame (methods.md §1.4): every mode vanishes
    /// there when `reference` is interface-fixed.
    pub frame_dofs: Vec<NodeDof>,
    /// The frame's reference condition ([`crate::reference`]).
    #[serde(default)]
    pub reference: crate::ReferenceCondition,
    /// One static (constraint) mode per boundary DOF, in mode order (they come first in **X**).
    pub static_modes: Vec<NodeDof>,
    /// Fixed-interface normal-mode frequencies in Hz, ascending (they follow the static modes in **X**);
    /// Ritz frequencies for load-dependent Ritz vectors (`selection`).
    pub normal_frequencies_hz: Vec<f64>,
    /// Which vectors follow the static modes (docs/methods.md §1.6).
    #[serde(default)]
    pub selection: crate::ModeSelection,
    /// The names of the body's first nodes when they are interface points (an imported
    /// body: node k < `point_names.len()` is the point of interface `point_names[k]`);
    /// empty for a beam, whose nodes are FE nodes.
    #[serde(default)]
    pub point_names: Vec<String>,
}

impl ModeInventory {
    /// Total number of modal coordinates n = n_s + n_d.
    pub fn n_modes(&self) -> usize {
        self.static_modes.len() + self.normal_frequencies_hz.len()
    }
}

/// The discrete mass model both inertia routes use (docs/methods.md §2.1, §2.7):
/// points with scalar (diagonal) weights, undeformed positions and translational mode rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MassCloud {
    /// Number of modal coordinates n (columns of every mode row).
    pub n_modes: usize,
    /// Undeformed positions r̄_u,k in body components (m). In 2D the z component is 0.
    pub positions: Vec<Vector3<f64>>,
    /// Scalar weights w_k (kg), one per point.
    pub weights: Vec<f64>,
    /// Translational mode rows X_k (3 × n per point), point-major, row-major within a point:
    /// entry (k, a, j) at `k * 3 * n + a * n + j`.
    pub mode_rows: Vec<f64>,
    /// Which cloud this is (e.g. "4 Gauss stations per element, 4 section points each"),
    /// reported beside cost comparisons (docs/methods.md §2.7, "Cost").
    pub description: String,
}

impl MassCloud {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.weights.len()
    }
    /// True when the cloud has no points.
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }
    /// The 3 × n mode rows of point `k`, row-major.
    pub fn rows(&self, k: usize) -> &[f64] {
        let w = 3 * self.n_modes;
        &self.mode_rows[k * w..(k + 1) * w]
    }
}

/// The 13 inertia shape integrals of docs/methods.md §2.3, computed on the mass cloud.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeIntegrals {
    /// m = ∫ dm (kg).
    pub mass: f64,
    /// m̄_u = ∫ r̄_u dm (kg·m).
    pub first_moment: Vector3<f64>,
    /// P̄_u = ∫ r̄_u r̄_uᵀ dm (kg·m²).
    pub second_moment: Matrix3<f64>,
    /// S = ∫ X dm (3 × n).
    pub s: DMatrix<f64>,
    /// Sᵃ = ∫ r̄_u,a X dm (3 × n), a = 0..3.
    pub s_a: [DMatrix<f64>; 3],
    /// Sᵃᵇ = ∫ X_aᵀ X_b dm (n × n), a, b = 0..3; Sᵇᵃ = (Sᵃᵇ)ᵀ.
    pub s_ab: [[DMatrix<f64>; 3]; 3],
}

/// Mode rows at one FE node: translation and small rotation of the node (body components).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NodeModes {
    /// Undeformed node position r̄_u (m).
    pub position: Vector3<f64>,
    /// Translation rows X^t (3 × n).
    pub translation: DMatrix<f64>,
    /// Rotation rows X^r (3 × n): θ̄ = X^r y.
    pub rotation: DMatrix<f64>,
}

/// Per-mode integrals for geometric stiffening (docs/methods.md §6.1). Later methods
/// (K_H, foreshortening integrals) add fields here without changing the body's interface.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StiffeningIntegrals {
    /// K_Gk = ∫ EA g_u,k G dx (n × n each, one per mode k); empty for a rigid body.
    pub k_g: Vec<DMatrix<f64>>,
    /// Element means Ḡ_e of G = g_v g_vᵀ + g_w g_wᵀ (n × n each, one per element;
    /// docs/methods.md §6.2 correction); empty for a rigid body.
    #[serde(default)]
    pub g_mean: Vec<DMatrix<f64>>,
    /// EA_e L_e per element: H_ijkl = Σ_e `h_weight[e]` Ḡ_e,ij Ḡ_e,kl (§6.2).
    #[serde(default)]
    pub h_weight: Vec<f64>,
}

/// One reduced body: the output of FE preprocessing and the input of `flexmbd-body`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReducedBody {
    /// Planar or spatial.
    pub dim: Dim,
    /// What the modes are.
    pub inventory: ModeInventory,
    /// Full mode matrix **X** (N_fe × n), zero rows on the frame DOFs. Empty (0 × 0) for a rigid body.
    pub modes: DMatrix<f64>,
    /// Reduced mass M_ff = Xᵀ M X (n × n).
    pub m_ff: DMatrix<f64>,
    /// Reduced stiffness K_ff = Xᵀ K X (n × n).
    pub k_ff: DMatrix<f64>,
    /// Reduced damping C_ff (n × n).
    pub c_ff: DMatrix<f64>,
    /// The mass cloud both inertia routes act on.
    pub cloud: MassCloud,
    /// The shape integrals of `cloud`.
    pub shape_integrals: ShapeIntegrals,
    /// Nodal mode rows, one entry per FE node (empty for a rigid body).
    pub nodes: Vec<NodeModes>,
    /// Geometric-stiffening integrals.
    pub stiffening: StiffeningIntegrals,
    /// Foreshortening data (FS0, docs/methods.md §6.3): F at every cloud point and node.
    /// Computed only when asked ([`crate::foreshortening::foreshortening`]); `None` otherwise.
    #[serde(default)]
    pub foreshortening: Option<crate::foreshortening::ForeshorteningData>,
}

impl ReducedBody {
    /// Number of modal coordinates n.
    pub fn n_modes(&self) -> usize {
        self.inventory.n_modes()
    }
    /// Total mass (kg).
    pub fn mass(&self) -> f64 {
        self.shape_integrals.mass
    }
}

impl ShapeIntegrals {
    /// The undeformed centre of mass c = m̄_u / m (m, body components).
    pub fn center_of_mass(&self) -> Vector3<f64> {
        self.first_moment / self.mass
    }

    /// The undeformed inertia tensor about the centre of mass, body axes (kg·m²):
    /// I_c = tr(P_c) 𝟙 − P_c with P_c = P̄_u − m c cᵀ.
    pub fn inertia_about_center_of_mass(&self) -> Matrix3<f64> {
        let c = self.center_of_mass();
        let p_c = self.second_moment - c * c.transpose() * self.mass;
        Matrix3::identity() * p_c.trace() - p_c
    }

    /// The 13 constants of docs/methods.md §2.3 on a diagonal cloud: every integral
    /// ∫ f g dm is Σ_k w_k f_k g_k, so they agree with B-matrix projection on the
    /// same cloud to round-off (§2.7).
    pub fn from_cloud(cloud: &MassCloud) -> Self {
        let n = cloud.n_modes;
        let mut si = ShapeIntegrals {
            mass: 0.0,
            first_moment: Vector3::zeros(),
            second_moment: Matrix3::zeros(),
            s: DMatrix::zeros(3, n),
            s_a: std::array::from_fn(|_| DMatrix::zeros(3, n)),
            s_ab: std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(n, n))),
        };
        for k in 0..cloud.len() {
            let w = cloud.weights[k];
            let r = cloud.positions[k];
            let x = cloud.rows(k);
            si.mass += w;
            si.first_moment += w * r;
            si.second_moment += w * r * r.transpose();
            for a in 0..3 {
                let xa = &x[a * n..(a + 1) * n];
                for j in 0..n {
                    si.s[(a, j)] += w * xa[j];
                    for c in 0..3 {
                        si.s_a[c][(a, j)] += w * r[c] * xa[j];
                    }
                }
                for b in 0..3 {
                    let xb = &x[b * n..(b + 1) * n];
                    let sab = &mut si.s_ab[a][b];
                    for i in 0..n {
                        let wi = w * xa[i];
                        if wi == 0.0 {
                            continue;
                        }
                        for j in 0..n {
                            sab[(i, j)] += wi * xb[j];
                        }
                    }
                }
            }
        }
        si
    }
}
