//! The built-in solid elements against physics.
//!
//! - **Patch test** (Irons & Razzaque 1972; Zienkiewicz, Taylor & Zhu 2013, §9.3): on a
//!   2 × 2 × 2 brick patch whose interior nodes are moved off the grid (distorted elements),
//!   the boundary nodes given the displacement of a constant strain, u = A x + c, the
//!   solved interior displacements are that field and the strain at every integration
//!   point is the constant one, for every element type.
//! - **Rigid-body motion** gives zero strain energy on the distorted patch: K u = 0 for the
//!   three translations and three rotations.
//! - **Bending frequency under refinement**: a free-free steel bar 0.2 × 0.01 × 0.01 m
//!   (L/h = 20); its first bending frequency under uniform refinement converges at the
//!   element's order — O(h²) for C3D8, O(h⁴) for C3D20 (Strang & Fix, *An Analysis of the
//!   Finite Element Method*, 1973, §6.3: the eigenvalue error of degree-k elements is
//!   O(h^{2k})) — and the Richardson-extrapolated limit is Timoshenko's 1317.298 Hz
//!   (crates/fe/tests/data/solid/timoshenko_free_free.py; Euler–Bernoulli's is 1329.150 Hz,
//!   0.9 % higher: shear and rotary inertia at L/h = 20). A free-free bar rather than a
//!   cantilever: a fully clamped root face is a stress singularity (the Poisson contraction
//!   held), which caps the C3D20 rate near 2 (measured: 1.97).

use flexmbd_fe::import::{FeMesh, ImportOptions};
use flexmbd_fe::solid::element::{point_data, stiffness_rule, strain_displacement};
use flexmbd_fe::solid::shape::{HEX20_EDGES, TET10_EDGES};
use flexmbd_fe::solid::{IsotropicElastic, MassMatrix, SolidKind, solid_model};
use flexmbd_fe::solid_box::SolidBox;
use flexmbd_fe::sparse_eigen::{SparseEigenOptions, lowest_modes};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use sprs::CsMat;

/// A 2 × 2 × 2 patch of a 0.2 m cube, its interior corner node moved by (13, −21, 17) mm and
/// the mid-edge nodes put back at the middle of their (straight) edges.
fn distorted_patch(kind: SolidKind) -> FeMesh {
    let b = SolidBox::steel([0.2, 0.2, 0.2], [2, 2, 2]);
    let mut mesh = b.mesh(kind).unwrap();
    mesh.nodes.positions[b.node_index(1, 1, 1)] += Vector3::new(0.013, -0.021, 0.017);
    let edges: &[[usize; 2]] = match kind {
        SolidKind::Tet10 => &TET10_EDGES,
        SolidKind::Hex20 => &HEX20_EDGES,
        _ => &[],
    };
    let corners = if kind.is_tetrahedron() { 4 } else { 8 };
    for e in &mesh.elements {
        for (k, [a, c]) in edges.iter().enumerate() {
            let p = (mesh.nodes.positions[e.nodes[*a]] + mesh.nodes.positions[e.nodes[*c]]) * 0.5;
            mesh.nodes.positions[e.nodes[corners + k]] = p;
        }
    }
    mesh
}

fn on_boundary(p: &Vector3<f64>) -> bool {
    p.iter()
        .any(|&x| x.abs() < 1e-12 || (x - 0.2).abs() < 1e-12)
}

fn dense(a: &CsMat<f64>) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(a.rows(), a.cols());
    for (v, (r, c)) in a.iter() {
        d[(r, c)] = *v;
    }
    d
}

#[test]
fn patch_test_reproduces_constant_strain_on_distorted_elements() {
    let a = Matrix3::new(1.0, 0.4, -0.3, 0.2, -0.7, 0.5, -0.6, 0.1, 0.9) * 1e-3;
    let c = Vector3::new(1e-4, -2e-4, 3e-4);
    let strain = (a + a.transpose()) * 0.5;
    let material = IsotropicElastic::STEEL;
    for kind in SolidKind::ALL {
        let mesh = distorted_patch(kind);
        let model = solid_model(
            &mesh,
            "patch",
            &material,
            MassMatrix::Consistent,
            &ImportOptions::default(),
        )
        .unwrap();
        let x = &model.mesh.nodes.positions;
        let exact: DVector<f64> =
            DVector::from_iterator(3 * x.len(), x.iter().flat_map(|p| (a * p + c).data.0[0]));
        let interior: Vec<usize> = (0..3 * x.len())
            .filter(|&r| !on_boundary(&x[r / 3]))
            .collect();
        let boundary: Vec<usize> = (0..3 * x.len())
            .filter(|&r| on_boundary(&x[r / 3]))
            .collect();
        assert!(!interior.is_empty());
        let k = dense(&model.k);
        let k_ii = k.select_rows(&interior).select_columns(&interior);
        let k_ib = k.select_rows(&interior).select_columns(&boundary);
        let u_b = exact.select_rows(&boundary);
        let u_i = k_ii.lu().solve(&(-(k_ib * u_b))).unwrap();
        let err = (&u_i - exact.select_rows(&interior)).amax() / exact.amax();
        assert!(err < 1e-10, "{kind}: interior displacement error {err:e}");
        // The strain at every stiffness integration point of every element.
        let want = [
            strain[(0, 0)],
            strain[(1, 1)],
            strain[(2, 2)],
            2.0 * strain[(0, 1)],
            2.0 * strain[(1, 2)],
            2.0 * strain[(2, 0)],
        ];
        let mut worst = 0.0_f64;
        for e in &model.mesh.elements {
            let xe: Vec<Vector3<f64>> = e.nodes.iter().map(|&n| x[n]).collect();
            let ue = DVector::from_iterator(
                3 * e.nodes.len(),
                e.nodes
                    .iter()
                    .flat_map(|&n| (0..3).map(move |d| 3 * n + d))
                    .map(|r| exact[r]),
            );
            for (p, _) in stiffness_rule(kind) {
                let pd = point_data(kind, &xe, p, &e.id).unwrap();
                let eps = strain_displacement(&pd.dn) * &ue;
                for (g, w) in eps.iter().zip(want) {
                    worst = worst.max((g - w).abs());
                }
            }
        }
        assert!(worst < 1e-12 * 1e-3, "{kind}: strain error {worst:e}");
        println!("{kind}: interior error {err:e}, strain error {worst:e}");
    }
}

#[test]
fn rigid_body_motion_has_zero_strain_energy_on_distorted_elements() {
    for kind in SolidKind::ALL {
        let mesh = distorted_patch(kind);
        let model = solid_model(
            &mesh,
            "patch",
            &IsotropicElastic::STEEL,
            MassMatrix::Consistent,
            &ImportOptions::default(),
        )
        .unwrap();
        let k = dense(&model.k);
        let x = &model.mesh.nodes.positions;
        for mode in 0..6 {
            let u = DVector::from_iterator(
                3 * x.len(),
                x.iter().flat_map(|p| {
                    let v = if mode < 3 {
                        Vector3::ith(mode, 1.0)
                    } else {
                        Vector3::ith(mode - 3, 1.0).cross(p)
                    };
                    v.data.0[0]
                }),
            );
            let energy = 0.5 * u.dot(&(&k * &u));
            // Against the energy of a unit strain of the same size: K's scale times |u|².
            let scale = k.amax() * u.norm_squared();
            assert!(
                energy.abs() < 1e-13 * scale,
                "{kind} mode {mode}: {energy:e}"
            );
        }
    }
}

/// Inverting an element (two nodes swapped) is refused naming it.
#[test]
fn an_inverted_element_is_refused_by_id() {
    for kind in SolidKind::ALL {
        let mut mesh = distorted_patch(kind);
        // Its mirror image: nodes 1 and 2 of a tetrahedron swapped (with their mid-edge
        // nodes), the bottom and top faces of a hexahedron.
        let n = &mut mesh.elements[3].nodes;
        let pairs: &[(usize, usize)] = match kind {
            SolidKind::Tet4 => &[(1, 2)],
            SolidKind::Tet10 => &[(1, 2), (4, 6), (8, 9)],
            SolidKind::Hex8 => &[(0, 4), (1, 5), (2, 6), (3, 7)],
            SolidKind::Hex20 => &[
                (0, 4),
                (1, 5),
                (2, 6),
                (3, 7),
                (8, 12),
                (9, 13),
                (10, 14),
                (11, 15),
            ],
        };
        for &(a, b) in pairs {
            n.swap(a, b);
        }
        let result = solid_model(
            &mesh,
            "patch.msh",
            &IsotropicElastic::STEEL,
            MassMatrix::Consistent,
            &ImportOptions::default(),
        );
        let Err(e) = result.map(|_| ()) else {
            panic!("{kind}: the inverted element was accepted");
        };
        let e = e.to_string();
        assert!(e.contains("element 4 of patch.msh"), "{e}");
        assert!(e.contains("Jacobian"), "{e}");
    }
}

/// The free-free bar's lowest elastic frequency (Hz) on an nx × n × n mesh of `kind`.
fn free_bar_frequency(kind: SolidKind, nx: usize, n: usize) -> f64 {
    free_bar_frequency_with(kind, nx, n, MassMatrix::Consistent)
}

/// [`free_bar_frequency`] with the mass matrix `mass`.
fn free_bar_frequency_with(kind: SolidKind, nx: usize, n: usize, mass: MassMatrix) -> f64 {
    let b = SolidBox::steel([0.2, 0.01, 0.01], [nx, n, n]);
    let mesh = b.mesh(kind).unwrap();
    let model = solid_model(&mesh, "bar", &b.material(), mass, &ImportOptions::default()).unwrap();
    let pairs = lowest_modes(&model.k, &model.m, 7, &SparseEigenOptions::default()).unwrap();
    pairs.omega_sq[6].sqrt() / (2.0 * std::f64::consts::PI)
}

#[test]
fn bending_frequency_converges_at_the_element_order_to_timoshenko() {
    let timoshenko = 1317.298;
    let (e, rho, l, h): (f64, f64, f64, f64) = (210e9, 7850.0, 0.2, 0.01);
    let euler_bernoulli = 4.730_040_744_862_704_f64.powi(2) / (2.0 * std::f64::consts::PI)
        * (e * h * h / (12.0 * rho)).sqrt()
        / (l * l);
    for (kind, meshes, order) in [
        (SolidKind::Hex8, [(20, 2), (40, 4), (80, 8)], 2.0),
        // Coarser C3D20 triples are not yet asymptotic: rates 3.06 on (4,1), (8,2),
        // (16,4) and 3.47 on (6,1), (12,2), (24,4).
        (SolidKind::Hex20, [(8, 2), (16, 4), (32, 8)], 4.0),
    ] {
        let f: Vec<f64> = meshes
            .iter()
            .map(|&(nx, n)| free_bar_frequency(kind, nx, n))
            .collect();
        let rate = ((f[0] - f[1]) / (f[1] - f[2])).log2();
        let limit = f[2] + (f[2] - f[1]) / (2.0_f64.powf(order) - 1.0);
        println!(
            "{kind}: f = {f:?} Hz, observed rate {rate:.3}, extrapolated {limit:.4} Hz, \
             Euler-Bernoulli {euler_bernoulli:.4} Hz ({:+.3} %)",
            100.0 * (limit / euler_bernoulli - 1.0)
        );
        assert!((rate - order).abs() < 0.3, "{kind}: rate {rate}");
        let off = limit / timoshenko - 1.0;
        println!("{kind}: extrapolated / Timoshenko - 1 = {off:+.2e}");
        assert!(off.abs() < 1e-3, "{kind}: {off}");
    }
}

/// HRZ-lumped C3D20 mass: the lumping error, O(h²), replaces the consistent mass's O(h⁴),
/// and it lowers the frequencies, so they converge from below at rate 2 to the same limit.
/// (C3D8 lumped by row sums, measured on 20×2×2 … 80×8×8: 1557.02, 1382.26, 1334.00 Hz,
/// rate 1.86, from above as its locked stiffness dominates; not asserted.)
#[test]
fn hrz_lumped_c3d20_frequencies_converge_from_below_to_the_same_limit() {
    let timoshenko = 1317.298;
    let f: Vec<f64> = [(8, 2), (16, 4), (32, 8)]
        .iter()
        .map(|&(nx, n)| free_bar_frequency_with(SolidKind::Hex20, nx, n, MassMatrix::Lumped))
        .collect();
    let rate = ((f[0] - f[1]) / (f[1] - f[2])).log2();
    let limit = f[2] + (f[2] - f[1]) / 3.0;
    println!(
        "C3D20 HRZ-lumped: f = {f:?} Hz, observed rate {rate:.3}, extrapolated {limit:.4} Hz \
         ({:+.2e} against Timoshenko)",
        limit / timoshenko - 1.0
    );
    assert!(f[0] < f[1] && f[1] < f[2] && f[2] < timoshenko, "{f:?}");
    assert!((rate - 2.0).abs() < 0.3, "rate {rate}");
    assert!((limit / timoshenko - 1.0).abs() < 1e-3, "{limit}");
}

/// The structured brick box of the eigen-solver tests (`SolidBox::assemble`, its own
/// hex8 code with the affine Jacobian) and the general C3D8 element on its mesh agree: two
/// routes to one K and M.
#[test]
fn solid_box_and_general_hex8_assemble_the_same_matrices() {
    let b = SolidBox::steel([0.3, 0.2, 0.1], [3, 2, 2]);
    let (k_box, m_box) = b.assemble().unwrap();
    let model = solid_model(
        &b.mesh(SolidKind::Hex8).unwrap(),
        "box",
        &b.material(),
        MassMatrix::Consistent,
        &ImportOptions::default(),
    )
    .unwrap();
    for (what, a, c) in [("K", &k_box, &model.k), ("M", &m_box, &model.m)] {
        let scale = a.data().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        let mut worst = 0.0_f64;
        for (v, (r, col)) in a.iter() {
            worst = worst.max((v - c.get(r, col).copied().unwrap_or(0.0)).abs());
        }
        for (v, (r, col)) in c.iter() {
            worst = worst.max((v - a.get(r, col).copied().unwrap_or(0.0)).abs());
        }
        assert!(worst < 1e-13 * scale, "{what}: {:e}", worst / scale);
    }
}
