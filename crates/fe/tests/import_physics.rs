//! Imported matrices against physics and against independent solvers:
//! frequencies against SciPy on the same matrices (1e-6 relative, issue 25's
//! criterion) and against CalculiX's own eigen-solution; rigid-body motion in the
//! null space of K; total mass; the import options checked analytically.

use std::path::PathBuf;

use flexmbd_fe::assembly::to_dense;
use flexmbd_fe::import::{self, FeModel, ImportOptions, PointMass, Source};
use flexmbd_fe::modal::{constrained_eigen, generalized_eigen};
use flexmbd_fe::{Dof, FeError};
use nalgebra::{DMatrix, DVector, Vector3};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/import")
        .join(name)
}

fn numbers(name: &str, tag: Option<&str>) -> Vec<f64> {
    std::fs::read_to_string(data(name))
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| match tag {
            Some(t) => l.strip_prefix(t).map(str::trim),
            None => Some(l.trim()),
        })
        .map(|v| v.parse().unwrap())
        .collect()
}

fn bar(options: &ImportOptions) -> FeModel {
    import::read_calculix(
        &data("bar_mesh.inp"),
        &data("bar_free.dof"),
        &data("bar_free.sti"),
        &data("bar_free.mas"),
        options,
    )
    .unwrap()
}

fn rotor() -> FeModel {
    import::read_ansys(
        &data("exudyn/rotorAnsysNodalCoordinates.txt"),
        &data("exudyn/rotorAnsysMatrixDofMappingVector.txt"),
        &data("exudyn/rotorAnsysStiffnessMatrixSparse.txt"),
        &data("exudyn/rotorAnsysMassMatrixSparse.txt"),
        &ImportOptions::default(),
    )
    .unwrap()
}

/// Clamped frequencies (Hz) of the bar: every DOF of the nodes at x = 0 held.
fn clamped_hz(model: &FeModel, n: usize) -> Vec<f64> {
    let fixed: Vec<usize> = (0..model.n_dofs())
        .filter(|&r| model.mesh.nodes.positions[model.dofs[r].node].x == 0.0)
        .collect();
    assert_eq!(fixed.len(), 12);
    let e = constrained_eigen(&to_dense(&model.k), &to_dense(&model.m), &fixed, "bar").unwrap();
    e.frequencies_hz()[..n].to_vec()
}

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn clamped_bar_frequencies_agree_with_scipy_on_the_same_matrices() {
    let scipy = numbers("bar_scipy_frequencies.txt", Some("clamped "));
    let ours = clamped_hz(&bar(&ImportOptions::default()), scipy.len());
    let rel = max_rel(&ours, &scipy);
    println!("clamped bar, ours vs SciPy: max relative difference {rel:e}");
    assert!(rel <= 1e-6, "{rel:e}: {ours:?} vs {scipy:?}");
}

/// CalculiX prints 7 significant digits: its frequencies agree with ours to half a
/// unit of the 7th digit (it solves the same clamped problem, its DOFs removed).
#[test]
fn clamped_bar_frequencies_agree_with_calculix_to_its_printed_digits() {
    let ccx = numbers("bar_ccx_frequencies.txt", None);
    let ours = clamped_hz(&bar(&ImportOptions::default()), ccx.len());
    for (f, c) in ours.iter().zip(&ccx) {
        let half_digit = 0.5 * 10f64.powf(c.log10().floor() - 6.0);
        println!(
            "ours {f:.6} Hz, CalculiX {c} Hz, |Δ| = {:.2e} (half digit {half_digit:.0e})",
            (f - c).abs()
        );
        assert!((f - c).abs() <= half_digit, "{f} vs CalculiX {c}");
    }
}

/// Six rigid-body modes, and the elastic ones against SciPy.
#[test]
fn free_free_frequencies_agree_with_scipy_for_the_bar_and_the_ansys_rotor() {
    for (model, reference) in [
        (
            bar(&ImportOptions::default()),
            numbers("bar_scipy_frequencies.txt", Some("free ")),
        ),
        (rotor(), numbers("exudyn/rotor_scipy_frequencies.txt", None)),
    ] {
        let e = generalized_eigen(&to_dense(&model.k), &to_dense(&model.m), &model.source).unwrap();
        // Six rigid-body modes: their frequencies (round-off) at least 1000 times
        // below the first elastic one, i.e. |ω²| ≤ 1e-6 ω²_7.
        let rigid = e.omega_sq[..6].iter().fold(0.0_f64, |m, w| m.max(w.abs()));
        println!(
            "rigid-body |ω²| up to {rigid:e}, first elastic ω² {:e}",
            e.omega_sq[6]
        );
        assert!(rigid <= 1e-6 * e.omega_sq[6], "{rigid:e}");
        let ours = &e.frequencies_hz()[6..reference.len()];
        let rel = max_rel(ours, &reference[6..]);
        println!(
            "{}: elastic modes, ours vs SciPy: max relative difference {rel:e}",
            model.source
        );
        assert!(rel <= 1e-6, "{rel:e}");
    }
}

/// A rigid motion u = t + ω × x, laid out through the DOF map.
fn rigid(model: &FeModel, t: Vector3<f64>, w: Vector3<f64>) -> DVector<f64> {
    DVector::from_fn(model.n_dofs(), |r, _| {
        let d = model.dofs[r];
        let u = t + w.cross(&model.mesh.nodes.positions[d.node]);
        match d.dof {
            Dof::Ux => u.x,
            Dof::Uy => u.y,
            Dof::Uz => u.z,
            _ => unreachable!("solid models"),
        }
    })
}

/// The node table and node vector put each row at its node: rigid translations and
/// rotations built from the positions are in the null space of K, to the 10
/// significant digits of the Workbench coordinates (|K u| ≤ 1e-8 · max|K| · |u|).
#[test]
fn rigid_motions_built_from_the_node_list_are_in_the_null_space_of_k() {
    for model in [rotor(), bar(&ImportOptions::default())] {
        let k = to_dense(&model.k);
        let kmax = k.abs().max();
        for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
            for (t, w) in [(axis, Vector3::zeros()), (Vector3::zeros(), axis)] {
                let u = rigid(&model, t, w);
                let r = (&k * &u).amax() / (kmax * u.amax());
                println!("{}: |K u| / (max|K| |u|) = {r:e}", model.source);
                assert!(r <= 1e-8, "{r:e}");
            }
        }
    }
}

fn total_mass(model: &FeModel, axis: Vector3<f64>) -> f64 {
    let u = rigid(model, axis, Vector3::zeros());
    u.dot(&(to_dense(&model.m) * &u))
}

/// The consistent mass of the bar sums to ρ V; a point mass adds to it exactly.
#[test]
fn total_mass_is_rho_v_and_a_point_mass_adds_to_it() {
    let rho_v = 7850.0 * 0.2 * 0.02 * 0.02;
    let plain = bar(&ImportOptions::default());
    let tip = plain
        .mesh
        .nodes
        .positions
        .iter()
        .position(|p| p.x == 0.2)
        .unwrap();
    let options = ImportOptions {
        point_masses: vec![PointMass {
            node: plain.mesh.nodes.ids[tip].clone(),
            mass: 0.5,
            inertia: None,
        }],
        ..ImportOptions::default()
    };
    let loaded = bar(&options);
    for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
        let m0 = total_mass(&plain, axis);
        assert!(
            ((m0 - rho_v) / rho_v).abs() <= 1e-12,
            "{m0} vs ρV = {rho_v}"
        );
        let m1 = total_mass(&loaded, axis);
        assert!(((m1 - m0 - 0.5) / m1).abs() <= 1e-12, "{m1} vs {m0} + 0.5");
    }
}

#[test]
fn stiffness_scale_scales_frequencies_by_its_square_root_and_units_cancel() {
    let base = clamped_hz(&bar(&ImportOptions::default()), 10);
    let stiff = clamped_hz(
        &bar(&ImportOptions {
            stiffness_scale: 4.0,
            ..ImportOptions::default()
        }),
        10,
    );
    let doubled: Vec<f64> = base.iter().map(|f| 2.0 * f).collect();
    assert!(max_rel(&stiff, &doubled) <= 1e-12);
    // A model in mm/t/s read with the factors to SI: same frequencies, coordinates × 1e-3.
    let si = ImportOptions {
        length_scale: 1e-3,
        mass_scale: 1e3,
        stiffness_scale: 1e3,
        ..ImportOptions::default()
    };
    let scaled = bar(&si);
    assert!(max_rel(&clamped_hz(&scaled, 10), &base) <= 1e-12);
    let plain = bar(&ImportOptions::default());
    for (a, b) in scaled
        .mesh
        .nodes
        .positions
        .iter()
        .zip(&plain.mesh.nodes.positions)
    {
        assert_eq!(*a, b * 1e-3);
    }
}

#[test]
fn point_masses_are_refused_where_the_node_cannot_carry_them() {
    let options = |node: &str, inertia| ImportOptions {
        point_masses: vec![PointMass {
            node: node.into(),
            mass: 1.0,
            inertia,
        }],
        ..ImportOptions::default()
    };
    let e = import::read_calculix(
        &data("bar_mesh.inp"),
        &data("bar_free.dof"),
        &data("bar_free.sti"),
        &data("bar_free.mas"),
        &options("5", Some([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])),
    )
    .unwrap_err();
    println!("{e}");
    assert!(matches!(&e, FeError::Import { field, .. } if field == "point_masses[0].inertia"));
    assert!(e.to_string().contains("lacks rotational DOFs"));
    let e = import::read_calculix(
        &data("bar_mesh.inp"),
        &data("bar_free.dof"),
        &data("bar_free.sti"),
        &data("bar_free.mas"),
        &options("999", None),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("point_masses[0].node: node 999 is not in the model"),
        "{e}"
    );
}

/// On a node with rotational DOFs the inertia tensor lands on Rx, Ry, Rz.
#[test]
fn a_point_inertia_fills_the_rotational_block() {
    let nodes = "1 0 0 0\n";
    let dofs = "1 ux\n1 uy\n1 uz\n1 rx\n1 ry\n1 rz\n";
    let diag = "%%MatrixMarket matrix coordinate real symmetric\n6 6 6\n1 1 1\n2 2 1\n3 3 1\n4 4 1\n5 5 1\n6 6 1\n";
    let options = ImportOptions {
        point_masses: vec![PointMass {
            node: "1".into(),
            mass: 2.0,
            inertia: Some([3.0, 4.0, 5.0, 0.5, 0.25, 0.125]),
        }],
        ..ImportOptions::default()
    };
    let model = import::parse_generic(
        Source::new(nodes, "n"),
        Source::new(dofs, "d"),
        Source::new(diag, "k"),
        Source::new(diag, "m"),
        &options,
    )
    .unwrap();
    let m = to_dense(&model.m);
    #[rustfmt::skip]
    let want = DMatrix::from_row_slice(6, 6, &[
        3.0, 0.0, 0.0, 0.0,   0.0,   0.0,
        0.0, 3.0, 0.0, 0.0,   0.0,   0.0,
        0.0, 0.0, 3.0, 0.0,   0.0,   0.0,
        0.0, 0.0, 0.0, 4.0,   0.5,   0.125,
        0.0, 0.0, 0.0, 0.5,   5.0,   0.25,
        0.0, 0.0, 0.0, 0.125, 0.25,  6.0,
    ]);
    assert_eq!(m, want);
}
