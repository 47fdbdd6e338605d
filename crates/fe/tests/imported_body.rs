//! Imported bodies (issue 25 items 2–3): the sparse reduction of an FE export against an
//! independent solver on the same matrices (SciPy's dense `eigh`, written by
//! tests/data/import/generate.py), Craig–Bampton's exactness with every interior mode,
//! the interfaces' constraints in the modes, the mass cloud against the FE mass and the
//! analytic inertia of the bar, and the refusals.

use std::path::{Path, PathBuf};

use flexmbd_fe::FeError;
use flexmbd_fe::import::ImportOptions;
use flexmbd_fe::imported::{
    Coupling, ImportSource, ImportedBody, ImportedBodySpec, ImportedFrame, InterfaceSpec,
    NodeSelection, Xyz, import_body,
};
use flexmbd_fe::modal::generalized_eigen;
use flexmbd_fe::spec::Damping;
use nalgebra::{DMatrix, Vector3};

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/import")
}

/// Reference frequencies (Hz) of `kind` from a generate.py reference file.
fn reference(file: &Path, kind: Option<&str>) -> Vec<f64> {
    std::fs::read_to_string(file)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .filter_map(|l| {
            let mut parts = l.split_whitespace();
            match kind {
                Some(k) => {
                    (parts.next() == Some(k)).then(|| parts.next().unwrap().parse().unwrap())
                }
                None => Some(l.trim().parse().unwrap()),
            }
        })
        .collect()
}

/// The CalculiX export of the steel bar 0.2 × 0.02 × 0.02 m (28 nodes, C3D8).
fn bar_source() -> ImportSource {
    ImportSource::Calculix {
        input: "bar_mesh.inp".into(),
        dofs: "bar_free.dof".into(),
        stiffness: "bar_free.sti".into(),
        mass: "bar_free.mas".into(),
    }
}

fn plane_x(name: &str, x: f64, coupling: Coupling) -> InterfaceSpec {
    InterfaceSpec {
        name: name.into(),
        nodes: NodeSelection::Plane {
            point: Xyz([x, 0.0, 0.0]),
            normal: Xyz([1.0, 0.0, 0.0]),
            tolerance: 1e-6,
        },
        coupling,
    }
}

fn bar_spec(
    frame: ImportedFrame,
    boundary: &[&str],
    tip: Coupling,
    normal_modes: usize,
) -> ImportedBodySpec {
    ImportedBodySpec {
        source: bar_source(),
        options: ImportOptions::default(),
        interfaces: vec![
            plane_x("root", 0.0, Coupling::Rbe2),
            plane_x("tip", 0.2, tip),
        ],
        frame,
        reference: Default::default(),
        boundary: boundary.iter().map(|b| b.to_string()).collect(),
        normal_modes,
        mode_selection: Default::default(),
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        damping: Damping::None,
    }
}

fn import(spec: &ImportedBodySpec) -> Result<ImportedBody, FeError> {
    import_body(spec, &data_dir(), "bar")
}

fn col3(m: &DMatrix<f64>, j: usize) -> Vector3<f64> {
    Vector3::new(m[(0, j)], m[(1, j)], m[(2, j)])
}

fn assert_close(ours: &[f64], theirs: &[f64], tol: f64, what: &str) {
    assert_eq!(ours.len(), theirs.len(), "{what}");
    for (k, (a, b)) in ours.iter().zip(theirs).enumerate() {
        assert!(((a - b) / b).abs() <= tol, "{what} [{k}]: {a} against {b}");
    }
}

/// Clamped at the root spider (RBE2 on the 4 nodes at x = 0 with the frame there is the
/// clamp of SciPy's reference): the fixed-interface frequencies are the clamped bar's.
#[test]
fn clamped_frequencies_agree_with_scipy() {
    let spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &[],
        Coupling::Rbe3,
        10,
    );
    let body = import(&spec).unwrap();
    let ours = &body.body.inventory.normal_frequencies_hz;
    let scipy = reference(
        &data_dir().join("bar_scipy_frequencies.txt"),
        Some("clamped"),
    );
    assert_close(ours, &scipy, 1e-6, "clamped");
}

/// Free-free: the six rigid-body modes are dropped and the elastic ones agree with SciPy's
/// (interfaces at both ends, RBE3, which add no stiffness).
#[test]
fn free_free_frequencies_agree_with_scipy() {
    let mut spec = bar_spec(ImportedFrame::FreeFree, &[], Coupling::Rbe3, 6);
    spec.interfaces[0].coupling = Coupling::Rbe3;
    let body = import(&spec).unwrap();
    let ours = &body.body.inventory.normal_frequencies_hz;
    let scipy = reference(&data_dir().join("bar_scipy_frequencies.txt"), Some("free"));
    assert_close(ours, &scipy[6..], 1e-6, "free-free");
    // Free-free modes are M-orthogonal to the rigid motions: ∫ X dm = 0 and ∫ r̄ × X dm = 0.
    let si = &body.body.shape_integrals;
    let scale = si.mass * 0.2;
    assert!(si.s.amax() <= 1e-9 * si.mass, "S = {}", si.s);
    for j in 0..6 {
        let moment = Vector3::new(
            si.s_a[1][(2, j)] - si.s_a[2][(1, j)],
            si.s_a[2][(0, j)] - si.s_a[0][(2, j)],
            si.s_a[0][(1, j)] - si.s_a[1][(0, j)],
        );
        assert!(moment.norm() <= 1e-9 * scale, "mode {j}: {moment}");
    }
}

/// The Ansys export of Exudyn's rotor (115 nodes, 345 DOFs): free-free elastic frequencies
/// against SciPy's on the same matrices.
#[test]
fn ansys_rotor_free_free_agrees_with_scipy() {
    let spec = ImportedBodySpec {
        source: ImportSource::Ansys {
            nodes: "exudyn/rotorAnsysNodalCoordinates.txt".into(),
            mapping: "exudyn/rotorAnsysMatrixDofMappingVector.txt".into(),
            stiffness: "exudyn/rotorAnsysStiffnessMatrixSparse.txt".into(),
            mass: "exudyn/rotorAnsysMassMatrixSparse.txt".into(),
        },
        options: ImportOptions::default(),
        interfaces: Vec::new(),
        frame: ImportedFrame::FreeFree,
        reference: Default::default(),
        boundary: Vec::new(),
        normal_modes: 10,
        mode_selection: Default::default(),
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        damping: Damping::None,
    };
    let body = import_body(&spec, &data_dir(), "rotor").unwrap();
    let scipy = reference(&data_dir().join("exudyn/rotor_scipy_frequencies.txt"), None);
    assert_close(
        &body.body.inventory.normal_frequencies_hz,
        &scipy[6..],
        1e-6,
        "rotor",
    );
}

/// Craig–Bampton with every interior mode is exact: an RBE3 tip interface adds no stiffness
/// and its six coordinates replace six of the tip nodes' DOFs, so (K_ff, M_ff) of the root-
/// clamped bar with the tip's static modes has the clamped bar's own frequencies.
#[test]
fn craig_bampton_with_every_interior_mode_is_exact() {
    // 84 DOFs − 12 clamped at the root − 6 tip coordinates taken from the tip nodes.
    let all = 84 - 12 - 6;
    let spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &["tip"],
        Coupling::Rbe3,
        all,
    );
    let body = import(&spec).unwrap();
    let rb = &body.body;
    assert_eq!(rb.n_modes(), 6 + all);
    let pairs = generalized_eigen(&rb.k_ff, &rb.m_ff, "K_ff, M_ff").unwrap();
    let scipy = reference(
        &data_dir().join("bar_scipy_frequencies.txt"),
        Some("clamped"),
    );
    assert_close(
        &pairs.frequencies_hz()[..10],
        &scipy,
        1e-8,
        "CB, every mode",
    );
    // With a few normal modes the reduced frequencies bound the exact ones from above.
    let spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &["tip"],
        Coupling::Rbe3,
        4,
    );
    let rb = import(&spec).unwrap().body;
    let few = generalized_eigen(&rb.k_ff, &rb.m_ff, "K_ff, M_ff")
        .unwrap()
        .frequencies_hz();
    for (k, (a, b)) in few.iter().zip(&scipy).take(4).enumerate() {
        assert!(*a >= b * (1.0 - 1e-9), "[{k}] {a} below {b}");
    }
}

/// The interfaces' constraints hold in every mode: an RBE2 node moves rigidly with its point
/// (u_s = u_P + θ_P × d_s), an RBE3 point moves with its nodes' mean translation and their
/// least-squares rotation; the frame's point does not move.
#[test]
fn modes_keep_the_interface_constraints() {
    for coupling in [Coupling::Rbe2, Coupling::Rbe3] {
        let spec = bar_spec(
            ImportedFrame::Interface("root".into()),
            &["tip"],
            coupling,
            4,
        );
        let body = import(&spec).unwrap();
        let nodes = &body.body.nodes;
        let n = body.body.n_modes();
        assert_eq!(body.interfaces[1].0, "tip");
        let tip = body.interfaces[1].1;
        assert!(
            (tip - Vector3::new(0.2, 0.01, 0.01)).norm() < 1e-12,
            "{tip}"
        );
        assert_eq!(nodes[0].translation.amax(), 0.0);
        assert_eq!(nodes[0].rotation.amax(), 0.0);
        let tip_nodes: Vec<usize> = (2..nodes.len())
            .filter(|&k| (nodes[k].position.x - 0.2).abs() < 1e-9)
            .collect();
        assert_eq!(tip_nodes.len(), 4);
        let (up, thp) = (&nodes[1].translation, &nodes[1].rotation);
        for j in 0..n {
            let (u_p, th_p) = (col3(up, j), col3(thp, j));
            match coupling {
                Coupling::Rbe2 => {
                    for &s in &tip_nodes {
                        let d = nodes[s].position - tip;
                        let expected = u_p + th_p.cross(&d);
                        let got = col3(&nodes[s].translation, j);
                        assert!((got - expected).norm() <= 1e-12 * (1.0 + expected.norm()));
                    }
                }
                Coupling::Rbe3 => {
                    let mean: Vector3<f64> = tip_nodes
                        .iter()
                        .map(|&s| col3(&nodes[s].translation, j))
                        .sum::<Vector3<f64>>()
                        / 4.0;
                    assert!(
                        (mean - u_p).norm() <= 1e-12 * (1.0 + u_p.norm()),
                        "mode {j}"
                    );
                }
            }
        }
    }
}

/// The mass cloud is the sparse mass matrix rewritten exactly: its modal mass is M_ff, its
/// mass ρ V, and (trilinear bricks interpolate x exactly) its inertia the box's,
/// m (b² + c²)/12 about the centre of mass.
#[test]
fn the_cloud_is_the_fe_mass() {
    let spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &["tip"],
        Coupling::Rbe2,
        6,
    );
    let rb = import(&spec).unwrap().body;
    let cloud_mass = flexmbd_fe::cloud::cloud_mass(&rb.cloud);
    let scale = rb.m_ff.amax();
    assert!(
        (&cloud_mass - &rb.m_ff).amax() <= 1e-12 * scale,
        "{}",
        &cloud_mass - &rb.m_ff
    );
    let si = &rb.shape_integrals;
    let m = 7850.0 * 0.2 * 0.02 * 0.02;
    assert!((si.mass / m - 1.0).abs() < 1e-13, "{}", si.mass);
    let c = si.center_of_mass();
    assert!((c - Vector3::new(0.1, 0.01, 0.01)).norm() < 1e-14, "{c}");
    let i = si.inertia_about_center_of_mass();
    let expected = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![
        m * (0.02_f64.powi(2) * 2.0) / 12.0,
        m * (0.2_f64.powi(2) + 0.02_f64.powi(2)) / 12.0,
        m * (0.2_f64.powi(2) + 0.02_f64.powi(2)) / 12.0,
    ]));
    for a in 0..3 {
        for b in 0..3 {
            assert!(
                (i[(a, b)] - expected[(a, b)]).abs() <= 1e-12 * expected.amax(),
                "{i}"
            );
        }
    }
}

/// The Abaqus export (part, instance, `CLAMP` node set of the assembly, `*MATRIX GENERATE`
/// layout) reduces to the same body as the CalculiX one.
#[test]
fn abaqus_and_calculix_exports_give_the_same_body() {
    let calculix = import(&bar_spec(
        ImportedFrame::Interface("root".into()),
        &[],
        Coupling::Rbe2,
        4,
    ))
    .unwrap();
    let mut spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &[],
        Coupling::Rbe2,
        4,
    );
    spec.source = ImportSource::Abaqus {
        input: "bar_part.inp".into(),
        stiffness: "bar_STIF1.mtx".into(),
        mass: "bar_MASS1.mtx".into(),
    };
    spec.interfaces[0].nodes = NodeSelection::Set("clamp".into());
    let abaqus = import(&spec).unwrap();
    assert_close(
        &abaqus.body.inventory.normal_frequencies_hz,
        &calculix.body.inventory.normal_frequencies_hz,
        1e-10,
        "abaqus against calculix",
    );
    assert!((abaqus.body.mass() / calculix.body.mass() - 1.0).abs() < 1e-14);
}

/// The same body twice gives the same bits.
#[test]
fn reduction_is_deterministic() {
    let spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &["tip"],
        Coupling::Rbe3,
        5,
    );
    let (a, b) = (import(&spec).unwrap().body, import(&spec).unwrap().body);
    assert_eq!(a, b);
}

fn refusal(spec: &ImportedBodySpec) -> String {
    import(spec).map(|_| ()).unwrap_err().to_string()
}

#[test]
fn bad_interfaces_and_frames_are_refused_by_name() {
    let base = bar_spec(
        ImportedFrame::Interface("root".into()),
        &["tip"],
        Coupling::Rbe2,
        4,
    );
    let mut s = base.clone();
    s.interfaces[1] = plane_x("tip", 0.5, Coupling::Rbe2);
    assert!(
        refusal(&s).contains("bar.interfaces[tip].nodes")
            && refusal(&s).contains("selects no node")
    );
    let mut s = base.clone();
    s.interfaces[1] = plane_x("tip", 0.0, Coupling::Rbe2);
    assert!(
        refusal(&s).contains("also in interface root"),
        "{}",
        refusal(&s)
    );
    let mut s = base.clone();
    s.interfaces[1].nodes = NodeSelection::Nearest(Xyz([0.2, 0.0, 0.0]));
    assert!(refusal(&s).contains("rotation free"), "{}", refusal(&s));
    let mut s = base.clone();
    s.frame = ImportedFrame::Interface("hub".into());
    assert!(refusal(&s).contains("bar.frame") && refusal(&s).contains("no interface"));
    let mut s = base.clone();
    s.boundary = vec!["root".into()];
    assert!(refusal(&s).contains("frame's interface"), "{}", refusal(&s));
    let mut s = base.clone();
    s.frame = ImportedFrame::FreeFree;
    assert!(refusal(&s).contains("clamped frame"), "{}", refusal(&s));
    let mut s = base.clone();
    s.mode_selection = flexmbd_fe::ModeSelection::ProperOrthogonal;
    assert!(refusal(&s).contains("mode_selection"), "{}", refusal(&s));
    let mut s = base.clone();
    s.interfaces[0].nodes = NodeSelection::Set("HUB".into());
    assert!(refusal(&s).contains("no such node set"), "{}", refusal(&s));
    let mut s = base;
    s.normal_modes = 1000;
    assert!(refusal(&s).contains("1000"), "{}", refusal(&s));
}

/// A free-free body needs six rigid-body modes: the bar held in its export (springs to
/// ground on one node's three translations, as stiff as the node's own) is refused as
/// supported.
#[test]
fn a_supported_model_is_not_free_free() {
    let mut spec = bar_spec(ImportedFrame::FreeFree, &[], Coupling::Rbe2, 4);
    spec.interfaces.clear();
    let mut model = spec.source.read(&data_dir(), &spec.options).unwrap();
    let mut k = model.k.to_dense();
    for r in 0..3 {
        k[[r, r]] *= 2.0;
    }
    model.k = sprs::CsMat::csc_from_dense(k.view(), 0.0);
    let err = flexmbd_fe::imported::reduce_imported(&spec, &model, "bar").unwrap_err();
    assert!(err.to_string().contains("six rigid-body modes"), "{err}");
}

/// Finite but huge values that the readers accept are refused by the reduction, never
/// returned as a body with NaN in it (the reader fuzzer's findings): a node at 1e160 m, and
/// an off-diagonal stiffness of −1e308.
#[test]
fn huge_values_are_refused_not_reduced_to_nan() {
    let spec = bar_spec(
        ImportedFrame::Interface("root".into()),
        &["tip"],
        Coupling::Rbe2,
        4,
    );
    let read = || spec.source.read(&data_dir(), &spec.options).unwrap();
    let reduce = |model| flexmbd_fe::imported::reduce_imported(&spec, &model, "bar");
    let mut far = read();
    far.mesh.nodes.positions[8].x = 1e160;
    let err = reduce(far).unwrap_err().to_string();
    assert!(err.contains("bar: node") && err.contains("1e160"), "{err}");
    let mut stiff = read();
    let mut k = stiff.k.to_dense();
    k[[7, 3]] = -1e308;
    k[[3, 7]] = -1e308;
    stiff.k = sprs::CsMat::csc_from_dense(k.view(), 0.0);
    let err = reduce(stiff).unwrap_err().to_string();
    assert!(err.contains("overflowed"), "{err}");
}
