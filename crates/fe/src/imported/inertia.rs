//! The inertia data of an imported body: its mass cloud as an exact rewriting of the sparse
//! mass matrix, the shape integrals of that cloud, the node rows, and the reduced body.
//!
//! **The cloud** (docs/methods.md §2.1, §2.7). Both inertia routes act on a cloud of points
//! with scalar weights, r_k = r̄_k + X_k y. A consistent FE mass matrix couples nodes, so its
//! nodes alone are not such a cloud; but on translational DOFs with an isotropic mass,
//! M = M_s ⊗ 𝟙₃ (M_s the scalar N_n × N_n matrix), every pair term rewrites exactly:
//!
//! ```text
//! m_ij (e_i e_jᵀ + e_j e_iᵀ) = m_ij [(e_i + e_j)(e_i + e_j)ᵀ − e_i e_iᵀ − e_j e_jᵀ]
//! ```
//!
//! and, since the point kinematics (B_k, Ḃ_k Z, r_k) is affine in (1, r̄_k, X_k), the vector
//! e_i + e_j is the point at the midpoint of i and j with rows (X_i + X_j)/2 and weight
//! 4 m_ij. So the cloud is every node i with weight m_ii − Σ_{j≠i} m_ij and every coupled pair
//! i < j at its midpoint with weight 4 m_ij: Σ_k w_k f_k g_k = fᵀ M_s g for every pair of fields
//! interpolated from the nodes, and the B-matrix route on it is the projection on the sparse
//! M itself. Weights may be negative (a consistent tetrahedron's nodes get −ρV/20); their
//! sum is the mass. The shape integrals come from the same cloud, so the two routes agree to
//! round-off.
//!
//! A mass matrix that couples different directions, or puts inertia on rotational DOFs
//! (shells, beams, point inertias), is refused: such inertia is not in the cloud yet.

use nalgebra::{DMatrix, Vector3};

use super::interfaces::{ResolvedInterface, RetainedMap};
use super::reduction::RetainedModes;
use super::{ImportedBodySpec, invalid, point_dofs};
use crate::assembly::DofSets;
use crate::craig_bampton::{Reduction, damping_matrix};
use crate::error::FeError;
use crate::import::FeModel;
use crate::reduced::{
    Dof, MassCloud, ModeInventory, NodeModes, ReducedBody, ShapeIntegrals, StiffeningIntegrals,
};
use crate::sparse_reduction::{sparse_times_dense, symmetrise};

/// Relative size (to the largest |M| entry) above which a mass entry that the cloud cannot
/// hold is refused, and within which the three directions' scalar masses must agree.
pub const MASS_TOL: f64 = 1e-10;

/// The reduced body of an imported model (module docs; node rows: interface points first).
pub fn reduced_body(
    spec: &ImportedBodySpec,
    model: &FeModel,
    interfaces: &[ResolvedInterface],
    map: &RetainedMap,
    modes: RetainedModes,
    body: &str,
) -> Result<ReducedBody, FeError> {
    let x = sparse_times_dense(&map.t, &modes.x);
    let n = x.ncols();
    let m_ff = symmetrise(&(x.transpose() * sparse_times_dense(&model.m, &x)));
    let scalar = scalar_mass(model, body)?;
    let rows = translation_rows(model, &x);
    let cloud = cloud(model, &scalar, &rows, n);
    let shape_integrals = ShapeIntegrals::from_cloud(&cloud);
    let mut nodes = Vec::with_capacity(interfaces.len() + model.mesh.nodes.positions.len());
    for (p, itf) in interfaces.iter().enumerate() {
        let s = map.point_start(p);
        nodes.push(NodeModes {
            position: itf.point,
            translation: modes.x.rows(s, 3).into_owned(),
            rotation: modes.x.rows(s + 3, 3).into_owned(),
        });
    }
    nodes.extend(fe_node_modes(model, &x));
    let n_s = 6 * modes.boundary_points.len();
    let sets = DofSets::new(n, Vec::new(), (0..n_s).collect());
    let reduction = Reduction {
        sets,
        x: DMatrix::zeros(0, n),
        m_ff: m_ff.clone(),
        k_ff: modes.k_ff.clone(),
        omega_sq: modes.omega_sq.clone(),
    };
    let c_ff = damping_matrix(&spec.damping, &reduction);
    let inventory = ModeInventory {
        n_fe_dofs: model.n_dofs(),
        frame_dofs: modes
            .frame_point
            .map_or_else(Vec::new, |p| point_dofs(p).collect()),
        static_modes: modes
            .boundary_points
            .iter()
            .flat_map(|&p| point_dofs(p))
            .collect(),
        normal_frequencies_hz: modes
            .omega_sq
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect(),
        selection: spec.mode_selection,
        // Free-free elastic modes are M-orthogonal to the rigid-body modes: the Buckens
        // conditions hold exactly (crate::reference), as they do after the projection of a
        // clamped frame's modes (`reference: Buckens`, super::reduction).
        reference: if modes.frame_point.is_none()
            || spec.reference == crate::ReferenceCondition::Buckens
        {
            crate::ReferenceCondition::Buckens
        } else {
            crate::ReferenceCondition::InterfaceFixed
        },
        point_names: interfaces.iter().map(|i| i.name.clone()).collect(),
    };
    Ok(ReducedBody {
        dim: flexmbd_core::Dim::Spatial,
        inventory,
        modes: x,
        m_ff,
        k_ff: modes.k_ff,
        c_ff,
        cloud,
        shape_integrals,
        nodes,
        stiffening: StiffeningIntegrals::default(),
        foreshortening: None,
    })
}

/// The scalar mass matrix M_s as (i, j, m_ij) over node pairs with i ≤ j, from the Ux–Ux
/// entries of M, after checking that Uy–Uy and Uz–Uz repeat them and that nothing else of
/// M is non-zero (module docs).
fn scalar_mass(model: &FeModel, body: &str) -> Result<Vec<(usize, usize, f64)>, FeError> {
    let largest = model.m.data().iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let tol = MASS_TOL * largest;
    let mut per_direction: [Vec<(usize, usize, f64)>; 3] = Default::default();
    for (&value, (r, c)) in model.m.iter() {
        let (a, b) = (model.dofs[r], model.dofs[c]);
        let (sa, sb) = (translation(a.dof), translation(b.dof));
        match (sa, sb) {
            (Some(da), Some(db)) if da == db => {
                if a.node <= b.node {
                    per_direction[da].push((a.node, b.node, value));
                }
            }
            _ if value.abs() <= tol => {}
            _ => {
                return Err(invalid(
                    format!("{body}.source: M"),
                    format!(
                        "{value:e} between {}@{} and {}@{}",
                        a.dof.name(),
                        model.mesh.nodes.ids[a.node],
                        b.dof.name(),
                        model.mesh.nodes.ids[b.node]
                    ),
                    "an imported mass matrix must be translational and isotropic (no inertia on \
                     rotational DOFs, no coupling of directions): such inertia is not supported yet",
                ));
            }
        }
    }
    for list in &mut per_direction {
        list.sort_by_key(|&(i, j, _)| (i, j));
        merge_duplicates(list);
        list.retain(|&(_, _, v)| v != 0.0);
    }
    let [x, y, z] = per_direction;
    for (name, other) in [("uy", &y), ("uz", &z)] {
        let same = x.len() == other.len()
            && x.iter()
                .zip(other.iter())
                .all(|(p, q)| p.0 == q.0 && p.1 == q.1 && (p.2 - q.2).abs() <= tol);
        if !same {
            return Err(invalid(
                format!("{body}.source: M"),
                format!("its ux and {name} blocks"),
                "differ: an imported mass matrix must be isotropic (the same mass in every \
                 direction), and every node needs its three translational DOFs",
            ));
        }
    }
    Ok(x)
}

fn merge_duplicates(list: &mut Vec<(usize, usize, f64)>) {
    let mut out: Vec<(usize, usize, f64)> = Vec::with_capacity(list.len());
    for &(i, j, v) in list.iter() {
        match out.last_mut() {
            Some(last) if last.0 == i && last.1 == j => last.2 += v,
            _ => out.push((i, j, v)),
        }
    }
    *list = out;
}

fn translation(d: Dof) -> Option<usize> {
    match d {
        Dof::Ux => Some(0),
        Dof::Uy => Some(1),
        Dof::Uz => Some(2),
        _ => None,
    }
}

/// The translation rows X_i (3 × n, row-major) of every FE node; zero where a DOF is absent.
fn translation_rows(model: &FeModel, x: &DMatrix<f64>) -> Vec<f64> {
    let n = x.ncols();
    let mut rows = vec![0.0; model.mesh.nodes.positions.len() * 3 * n];
    for (r, d) in model.dofs.iter().enumerate() {
        if let Some(a) = translation(d.dof) {
            let start = d.node * 3 * n + a * n;
            for j in 0..n {
                rows[start + j] = x[(r, j)];
            }
        }
    }
    rows
}

/// The cloud of the module docs: every node with m_ii − Σ_{j≠i} m_ij, every coupled pair at its
/// midpoint with 4 m_ij; points of zero weight are left out.
fn cloud(model: &FeModel, scalar: &[(usize, usize, f64)], rows: &[f64], n: usize) -> MassCloud {
    let positions = &model.mesh.nodes.positions;
    let mut node_weight = vec![0.0; positions.len()];
    for &(i, j, m) in scalar {
        if i == j {
            node_weight[i] += m;
        } else {
            node_weight[i] -= m;
            node_weight[j] -= m;
        }
    }
    let row = |k: usize| &rows[k * 3 * n..(k + 1) * 3 * n];
    let mut cloud = MassCloud {
        n_modes: n,
        positions: Vec::new(),
        weights: Vec::new(),
        mode_rows: Vec::new(),
        description: String::new(),
    };
    for (i, &w) in node_weight.iter().enumerate() {
        if w != 0.0 {
            cloud.positions.push(positions[i]);
            cloud.weights.push(w);
            cloud.mode_rows.extend_from_slice(row(i));
        }
    }
    let n_nodes = cloud.len();
    for &(i, j, m) in scalar.iter().filter(|(i, j, _)| i != j) {
        cloud.positions.push((positions[i] + positions[j]) * 0.5);
        cloud.weights.push(4.0 * m);
        cloud
            .mode_rows
            .extend(row(i).iter().zip(row(j)).map(|(a, b)| 0.5 * (a + b)));
    }
    cloud.description = format!(
        "the sparse mass matrix rewritten exactly: {n_nodes} nodes and {} coupled node pairs",
        cloud.len() - n_nodes
    );
    cloud
}

/// Node rows of every FE node: translation from its Ux, Uy, Uz rows of X, rotation from its
/// Rx, Ry, Rz rows (zero where a DOF is absent).
fn fe_node_modes(model: &FeModel, x: &DMatrix<f64>) -> Vec<NodeModes> {
    let n = x.ncols();
    let mut nodes: Vec<NodeModes> = model
        .mesh
        .nodes
        .positions
        .iter()
        .map(|p: &Vector3<f64>| NodeModes {
            position: *p,
            translation: DMatrix::zeros(3, n),
            rotation: DMatrix::zeros(3, n),
        })
        .collect();
    for (r, d) in model.dofs.iter().enumerate() {
        let node = &mut nodes[d.node];
        let (target, a) = match d.dof {
            Dof::Ux => (&mut node.translation, 0),
            Dof::Uy => (&mut node.translation, 1),
            Dof::Uz => (&mut node.translation, 2),
            Dof::Rx => (&mut node.rotation, 0),
            Dof::Ry => (&mut node.rotation, 1),
            Dof::Rz => (&mut node.rotation, 2),
        };
        for j in 0..n {
            target[(a, j)] = x[(r, j)];
        }
    }
    nodes
}
