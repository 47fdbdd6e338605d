//! Mode selection of imported bodies on the sparse pipeline (issue 25: participation and
//! load-dependent Ritz vectors for imported bodies; `flexmbd_fe::imported::selection`):
//!
//! 1. a built-in 3D beam's assembled K and M, written to Matrix Market and imported with
//!    single-node RBE2 interfaces at its root (the frame) and tip (a boundary), selects the
//!    same participation modes and spans the same Ritz space as the beam's dense path;
//! 2. on the imported solid bar, n load-dependent Ritz vectors with n the number of loads
//!    reproduce the exact static response to each load (an FE solve on the retained
//!    coordinates), and n − 1 do not;
//! 3. bad input is refused by name.

mod common;

use std::path::{Path, PathBuf};

use common::*;
use flexmbd_core::Dim;
use flexmbd_fe::import::{self, FeModel, ImportOptions};
use flexmbd_fe::imported::interfaces::{RetainedMap, resolve};
use flexmbd_fe::imported::reduction::{RetainedModes, project, reduce};
use flexmbd_fe::imported::{
    Coupling, ImportSource, ImportedBodySpec, ImportedFrame, InterfaceSpec, NodeSelection, Xyz,
    import_body,
};
use flexmbd_fe::sparse::write_matrix_market;
use flexmbd_fe::{Damping, Dof, ModeSelection, NodeDof, Preprocessed, preprocess};
use nalgebra::{DMatrix, DVector, Vector3};
use sprs::{CsMat, TriMat};

const ELEMENTS: usize = 40;

/// The 3D cantilever (1 m, 10 × 20 mm, 40 elements) clamped at node 0 with the tip's six
/// DOFs as boundary.
fn beam_spec(
    selection: ModeSelection,
    normal_modes: usize,
    candidates: Option<usize>,
) -> flexmbd_fe::BeamBodySpec {
    let mut spec = cantilever(Dim::Spatial, rect10x20(), ELEMENTS, normal_modes);
    spec.boundary = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]
        .into_iter()
        .map(|dof| NodeDof {
            node: ELEMENTS,
            dof,
        })
        .collect();
    spec.mode_selection = selection;
    spec.mode_candidates = candidates;
    spec
}

fn sparse(a: &DMatrix<f64>) -> CsMat<f64> {
    let mut t = TriMat::new(a.shape());
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if a[(i, j)] != 0.0 {
                t.add_triplet(i, j, a[(i, j)]);
            }
        }
    }
    t.to_csc()
}

/// Write the beam's nodes (ids 1…), DOF map (the beam's DOF order) and K, M to `dir` and
/// read them back as a generic Matrix Market export.
fn export_and_read(p: &Preprocessed, dir: &Path) -> FeModel {
    std::fs::create_dir_all(dir).unwrap();
    let mut nodes = String::new();
    let mut dofs = String::new();
    for (k, r) in p.mesh.nodes.iter().enumerate() {
        nodes += &format!("{} {:?} {:?} {:?}\n", k + 1, r.x, r.y, r.z);
        for d in ["ux", "uy", "uz", "rx", "ry", "rz"] {
            dofs += &format!("{} {d}\n", k + 1);
        }
    }
    std::fs::write(dir.join("nodes.txt"), nodes).unwrap();
    std::fs::write(dir.join("dofs.txt"), dofs).unwrap();
    write_matrix_market(&dir.join("k.mtx"), &p.k).unwrap();
    write_matrix_market(&dir.join("m.mtx"), &p.m).unwrap();
    import::read_generic(
        &dir.join("nodes.txt"),
        &dir.join("dofs.txt"),
        &dir.join("k.mtx"),
        &dir.join("m.mtx"),
        &ImportOptions::default(),
    )
    .unwrap()
}

fn node_interface(name: &str, id: usize) -> InterfaceSpec {
    InterfaceSpec {
        name: name.into(),
        nodes: NodeSelection::Ids(vec![id.to_string()]),
        coupling: Coupling::Rbe2,
    }
}

fn imported_spec(
    source: ImportSource,
    interfaces: Vec<InterfaceSpec>,
    frame: &str,
    boundary: &[&str],
    selection: ModeSelection,
    normal_modes: usize,
    candidates: Option<usize>,
) -> ImportedBodySpec {
    ImportedBodySpec {
        source,
        options: ImportOptions::default(),
        interfaces,
        frame: ImportedFrame::Interface(frame.into()),
        reference: Default::default(),
        boundary: boundary.iter().map(|b| b.to_string()).collect(),
        normal_modes,
        mode_selection: selection,
        mode_candidates: candidates,
        pilot_duration: None,
        pilot: None,
        damping: Damping::None,
    }
}

/// The imported reduction on the retained coordinates (the mass cloud, which refuses a
/// beam's rotary inertia, is not needed to compare the modes) and the map of beam DOF r
/// to its retained coordinate.
fn reduce_exported(model: &FeModel, spec: &ImportedBodySpec) -> (RetainedModes, Vec<usize>) {
    let interfaces = resolve(&spec.interfaces, model, "beam").unwrap();
    let map = RetainedMap::new(model, &interfaces, "beam").unwrap();
    let modes = reduce(spec, model, &interfaces, &map, "beam").unwrap();
    let n = model.n_dofs();
    let row: Vec<usize> = (0..n)
        .map(|r| match map.independent[r] {
            Some(c) => c,
            None => {
                let node = r / 6;
                let point = if node == 0 { 0 } else { 1 };
                map.point_start(point) + r % 6
            }
        })
        .collect();
    (modes, row)
}

fn worst_relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max)
}

/// The largest difference between the beam's mode columns and the imported ones (rows
/// mapped, each column compared up to sign) in the mass norm of `m`, relative to the
/// column's own mass norm (1 for a mass-normalised mode).
fn worst_mode_difference(
    beam: &DMatrix<f64>,
    imported: &DMatrix<f64>,
    row: &[usize],
    m: &DMatrix<f64>,
) -> f64 {
    assert_eq!(beam.ncols(), imported.ncols());
    let m_norm = |v: &DVector<f64>| v.dot(&(m * v)).sqrt();
    (0..beam.ncols())
        .map(|j| {
            let b = beam.column(j).into_owned();
            let i = DVector::from_fn(row.len(), |r, _| imported[(row[r], j)]);
            m_norm(&(&b - &i)).min(m_norm(&(&b + &i))) / m_norm(&b)
        })
        .fold(0.0, f64::max)
}

fn scratch_dir(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!(
        "flexmbd-imported-selection-{}-{name}",
        std::process::id()
    ))
}

#[test]
fn an_exported_beam_selects_the_beams_modes_and_ritz_vectors() {
    let dir = scratch_dir("beam");
    let lowest = preprocess(&beam_spec(ModeSelection::LowestFrequency, 6, None)).unwrap();
    let model = export_and_read(&lowest, &dir);
    let source = ImportSource::MatrixMarket {
        nodes: dir.join("nodes.txt"),
        dofs: dir.join("dofs.txt"),
        stiffness: dir.join("k.mtx"),
        mass: dir.join("m.mtx"),
    };
    let interfaces = vec![
        node_interface("root", 1),
        node_interface("tip", ELEMENTS + 1),
    ];
    for (selection, n, candidates) in [
        (ModeSelection::LowestFrequency, 6, None),
        (ModeSelection::Participation, 6, Some(16)),
        (ModeSelection::LoadRitz, 8, None),
        (ModeSelection::LoadRitz, 12, None),
    ] {
        let beam = preprocess(&beam_spec(selection, n, candidates)).unwrap();
        let spec = imported_spec(
            source.clone(),
            interfaces.clone(),
            "root",
            &["tip"],
            selection,
            n,
            candidates,
        );
        let (imported, row) = reduce_exported(&model, &spec);
        let w2 = worst_relative(&imported.omega_sq, &beam.reduction.omega_sq);
        let x = worst_mode_difference(
            &beam.reduction.x,
            &imported.x,
            &row,
            &flexmbd_fe::assembly::to_dense(&beam.m),
        );
        println!(
            "{} n = {n}: ω² {:?} rad²/s²; worst relative ω² difference {w2:.2e}, worst mode \
             difference {x:.2e}",
            selection.name(),
            beam.reduction
                .omega_sq
                .iter()
                .map(|w| format!("{w:.4e}"))
                .collect::<Vec<_>>()
        );
        assert!(w2 < 1e-8, "{}: {w2:e}", selection.name());
        // Ritz vectors come from exact solves and a small dense eigenproblem; normal modes
        // from the shift-invert Lanczos at its residual bound EIGEN_TOL = 1e-9, whose
        // vectors are accurate to about that residual over the relative gap to the next ω².
        let vector_tol = if selection == ModeSelection::LoadRitz {
            1e-8
        } else {
            1e-5
        };
        assert!(x < vector_tol, "{}: {x:e}", selection.name());
    }
    // The participation ranking chose other modes than the lowest six.
    let ranked = preprocess(&beam_spec(ModeSelection::Participation, 6, Some(16))).unwrap();
    assert_ne!(ranked.reduction.omega_sq, lowest.reduction.omega_sq);
    std::fs::remove_dir_all(&dir).ok();
}

fn bar_source() -> ImportSource {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/import");
    ImportSource::Calculix {
        input: data.join("bar_mesh.inp"),
        dofs: data.join("bar_free.dof"),
        stiffness: data.join("bar_free.sti"),
        mass: data.join("bar_free.mas"),
    }
}

fn plane_x(name: &str, x: f64) -> InterfaceSpec {
    InterfaceSpec {
        name: name.into(),
        nodes: NodeSelection::Plane {
            point: Xyz([x, 0.0, 0.0]),
            normal: Xyz([1.0, 0.0, 0.0]),
            tolerance: 1e-6,
        },
        coupling: Coupling::Rbe2,
    }
}

/// The CalculiX bar (0.2 × 0.02 × 0.02 m, 28 nodes) clamped at its root spider with the tip
/// spider's static modes.
fn bar_spec(selection: ModeSelection, normal_modes: usize) -> ImportedBodySpec {
    imported_spec(
        bar_source(),
        vec![plane_x("root", 0.0), plane_x("tip", 0.2)],
        "root",
        &["tip"],
        selection,
        normal_modes,
        None,
    )
}

/// The loads of a clamped imported body, formed here from their definition: the inertia
/// loads M u of the unit fields (translations, e_a × r̄, the six S r̄) and of the static
/// modes (the first six columns of X), on the FE DOFs.
fn bar_loads(model: &FeModel, x: &DMatrix<f64>) -> Vec<DVector<f64>> {
    let m = flexmbd_fe::assembly::to_dense(&model.m);
    let field = |f: &dyn Fn(&Vector3<f64>) -> Vector3<f64>| {
        DVector::from_iterator(
            model.n_dofs(),
            model.dofs.iter().map(|d| {
                let r = model.mesh.nodes.positions[d.node];
                let slot = [Dof::Ux, Dof::Uy, Dof::Uz].iter().position(|&a| a == d.dof);
                slot.map_or(0.0, |a| f(&r)[a])
            }),
        )
    };
    let mut fields = Vec::new();
    for a in 0..3 {
        fields.push(field(&|_| Vector3::ith(a, 1.0)));
        fields.push(field(&|r| Vector3::ith(a, 1.0).cross(r)));
        for b in a..3 {
            fields.push(field(&|r| {
                Vector3::ith(a, 1.0) * r[b] + Vector3::ith(b, 1.0) * r[a]
            }));
        }
    }
    fields.extend(x.columns(0, 6).column_iter().map(|c| c.into_owned()));
    fields.iter().map(|u| &m * u).collect()
}

/// The exact static response to `f` (FE DOFs) of the model with the interfaces' constraints
/// and the root point held: K̃ ũ = Tᵀ f on the retained coordinates but the root's six.
fn exact_response(model: &FeModel, spec: &ImportedBodySpec, f: &DVector<f64>) -> DVector<f64> {
    let interfaces = resolve(&spec.interfaces, model, "bar").unwrap();
    let map = RetainedMap::new(model, &interfaces, "bar").unwrap();
    let t = flexmbd_fe::assembly::to_dense(&map.t);
    let kt = flexmbd_fe::assembly::to_dense(&project(&model.k, &map.t));
    let root = map.point_start(0);
    let free: Vec<usize> = (0..kt.nrows())
        .filter(|c| !(root..root + 6).contains(c))
        .collect();
    let tf = t.transpose() * f;
    let k_ff = kt.select_rows(&free).select_columns(&free);
    let u_f = k_ff.cholesky().unwrap().solve(&tf.select_rows(&free));
    let mut u = DVector::zeros(kt.nrows());
    for (a, &c) in free.iter().enumerate() {
        u[c] = u_f[a];
    }
    t * u
}

/// Worst relative error of the reduced static response X K_ff⁻¹ Xᵀ f over `loads`.
fn worst_static_error(
    body: &flexmbd_fe::ReducedBody,
    exact: &[DVector<f64>],
    loads: &[DVector<f64>],
) -> f64 {
    let k = body.k_ff.clone().cholesky().unwrap();
    loads
        .iter()
        .zip(exact)
        .map(|(f, u)| {
            let reduced = &body.modes * k.solve(&(body.modes.transpose() * f));
            (reduced - u).amax() / u.amax()
        })
        .fold(0.0, f64::max)
}

#[test]
fn ritz_vectors_reproduce_every_loads_static_response() {
    let spec = bar_spec(ModeSelection::LoadRitz, 18);
    let model = spec.source.read(Path::new("/"), &spec.options).unwrap();
    let body = import_body(&spec, Path::new("/"), "bar").unwrap().body;
    let loads = bar_loads(&model, &body.modes);
    assert_eq!(loads.len(), 18);
    let exact: Vec<DVector<f64>> = loads
        .iter()
        .map(|f| exact_response(&model, &spec, f))
        .collect();
    let all = worst_static_error(&body, &exact, &loads);
    let short = import_body(
        &bar_spec(ModeSelection::LoadRitz, 17),
        Path::new("/"),
        "bar",
    )
    .unwrap()
    .body;
    let one_short = worst_static_error(&short, &exact, &loads);
    let lowest = import_body(
        &bar_spec(ModeSelection::LowestFrequency, 18),
        Path::new("/"),
        "bar",
    )
    .unwrap()
    .body;
    let normal = worst_static_error(&lowest, &exact, &loads);
    println!(
        "worst relative static error over the 18 loads: 18 Ritz vectors {all:.2e}, 17 Ritz \
         vectors {one_short:.2e}, 18 lowest normal modes {normal:.2e}"
    );
    assert!(all < 1e-9, "{all:e}");
    assert!(one_short > 1e-7, "{one_short:e}");
    assert!(normal > 1e-4, "{normal:e}");
}

#[track_caller]
fn refusal(spec: &ImportedBodySpec) -> String {
    import_body(spec, Path::new("/"), "bar")
        .map(|_| ())
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_selection_input_is_refused_by_name() {
    let mut s = bar_spec(ModeSelection::Participation, 4);
    s.mode_candidates = Some(1000);
    let e = refusal(&s);
    assert!(
        e.contains("bar.mode_candidates") && e.contains("1000") && e.contains("only 60"),
        "{e}"
    );
    s.frame = ImportedFrame::FreeFree;
    s.boundary.clear();
    let e = refusal(&s);
    assert!(
        e.contains("bar.mode_candidates") && e.contains("1000"),
        "{e}"
    );
    let mut s = bar_spec(ModeSelection::Participation, 1000);
    s.frame = ImportedFrame::FreeFree;
    s.boundary.clear();
    let e = refusal(&s);
    assert!(e.contains("1000"), "{e}");
    let mut s = bar_spec(ModeSelection::Participation, 4);
    s.mode_candidates = Some(3);
    let e = refusal(&s);
    assert!(
        e.contains("bar.mode_candidates") && e.contains("at least normal_modes"),
        "{e}"
    );
    let mut s = bar_spec(ModeSelection::LowestFrequency, 4);
    s.mode_candidates = Some(8);
    let e = refusal(&s);
    assert!(
        e.contains("bar.mode_candidates") && e.contains("only used with"),
        "{e}"
    );
    let e = refusal(&bar_spec(ModeSelection::ProperOrthogonal, 4));
    assert!(
        e.contains("bar.mode_selection") && e.contains("ProperOrthogonal"),
        "{e}"
    );
    let e = refusal(&bar_spec(ModeSelection::LoadRitz, 61));
    assert!(e.contains("bar.normal_modes") && e.contains("61"), "{e}");
    // Ritz vectors run out: twelve point masses on equal springs to ground, K = k 𝟙 and
    // M = m 𝟙, so K_ii⁻¹ M_ii = (m/k) 𝟙 and the Krylov sequence never leaves the span of
    // the first block, the static responses of the 12 unit fields (3 translations, 3
    // rotations, 6 centrifugal), fewer than the 27 interior DOFs.
    let dir = scratch_dir("springs");
    std::fs::create_dir_all(&dir).unwrap();
    let (mut nodes, mut dofs) = (String::new(), String::new());
    for k in 0..12 {
        let (x, y, z) = (k % 2, (k / 2) % 2, k / 4);
        nodes += &format!("{} {x} {y} {z}\n", k + 1);
        for d in ["ux", "uy", "uz"] {
            dofs += &format!("{} {d}\n", k + 1);
        }
    }
    std::fs::write(dir.join("nodes.txt"), nodes).unwrap();
    std::fs::write(dir.join("dofs.txt"), dofs).unwrap();
    let diagonal = |v: f64| sparse(&DMatrix::from_diagonal_element(36, 36, v));
    write_matrix_market(&dir.join("k.mtx"), &diagonal(1e6)).unwrap();
    write_matrix_market(&dir.join("m.mtx"), &diagonal(2.0)).unwrap();
    let source = ImportSource::MatrixMarket {
        nodes: dir.join("nodes.txt"),
        dofs: dir.join("dofs.txt"),
        stiffness: dir.join("k.mtx"),
        mass: dir.join("m.mtx"),
    };
    let base = InterfaceSpec {
        name: "base".into(),
        nodes: NodeSelection::Ids(vec!["1".into(), "2".into(), "3".into()]),
        coupling: Coupling::Rbe2,
    };
    let springs = |n| {
        imported_spec(
            source.clone(),
            vec![base.clone()],
            "base",
            &[],
            ModeSelection::LoadRitz,
            n,
            None,
        )
    };
    import_body(&springs(9), Path::new("/"), "springs").unwrap();
    let e = import_body(&springs(13), Path::new("/"), "springs")
        .map(|_| ())
        .unwrap_err()
        .to_string();
    println!("{e}");
    assert!(
        e.contains("normal_modes") && e.contains("spans only"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Free-free, no interfaces: the loads are the six centrifugal fields S r̄, which about the
/// centre of mass c are S (r̄ − c) plus a uniform field S c that no elastic mode feels. The
/// bar is symmetric under inversion through c, S (r̄ − c) is odd under it, so a mode that is
/// even (u(2c − r̄) = u(r̄): the first bending pair, the first torsion mode) takes no share,
/// and the ranking keeps only odd modes (axial, second bending, …).
#[test]
fn free_free_participation_keeps_the_modes_the_centrifugal_loads_excite() {
    let free = |selection, n, candidates| ImportedBodySpec {
        frame: ImportedFrame::FreeFree,
        reference: Default::default(),
        interfaces: Vec::new(),
        boundary: Vec::new(),
        mode_candidates: candidates,
        pilot_duration: None,
        pilot: None,
        ..bar_spec(selection, n)
    };
    let lowest = import_body(
        &free(ModeSelection::LowestFrequency, 12, None),
        Path::new("/"),
        "bar",
    )
    .unwrap()
    .body;
    let ranked = import_body(
        &free(ModeSelection::Participation, 4, Some(12)),
        Path::new("/"),
        "bar",
    )
    .unwrap()
    .body;
    let all = &lowest.inventory.normal_frequencies_hz;
    let kept = &ranked.inventory.normal_frequencies_hz;
    println!("lowest 12: {all:.1?} Hz\nkept by participation: {kept:.1?} Hz");
    for f in kept {
        assert!(
            all.iter().any(|a| ((a - f) / f).abs() < 1e-9),
            "{f} not a candidate"
        );
    }
    assert!(
        kept[0] > all[2] * (1.0 + 1e-6),
        "the first bending pair is kept"
    );
    let c = Vector3::new(0.1, 0.01, 0.01);
    let nodes = &ranked.nodes;
    let mirror = |s: usize| {
        let target: Vector3<f64> = 2.0 * c - nodes[s].position;
        (0..nodes.len())
            .find(|&t| (nodes[t].position - target).norm() < 1e-9)
            .unwrap()
    };
    for j in 0..kept.len() {
        let scale = (0..nodes.len())
            .map(|s| nodes[s].translation.column(j).norm())
            .fold(0.0, f64::max);
        let worst = (0..nodes.len())
            .map(|s| {
                (nodes[s].translation.column(j) + nodes[mirror(s)].translation.column(j)).norm()
            })
            .fold(0.0, f64::max);
        println!(
            "kept mode {j}: largest |u(r) + u(2c − r)| / max |u| = {:.1e}",
            worst / scale
        );
        assert!(
            worst < 1e-6 * scale,
            "kept mode {j} is not odd under inversion"
        );
    }
}

/// Free-free Ritz vectors: with n = the number of loads (6 centrifugal fields and unit
/// forces and moments at two RBE3 interfaces: 18), the reduced elastic response to each
/// load's self-equilibrated part g = f − M̃ Φ_r Φ_rᵀ f is the exact one, the solution of
/// K̃ x = g with Φ_rᵀ M̃ x = 0, here from the dense non-singular (K̃ + α M̃ Φ_r Φ_rᵀ M̃) x = g
/// (applying Φ_rᵀ: α Φ_rᵀ M̃ x = Φ_rᵀ g = 0, so K̃ x = g).
#[test]
fn free_free_ritz_vectors_reproduce_the_inertia_relief_response() {
    let free = |selection, n| ImportedBodySpec {
        frame: ImportedFrame::FreeFree,
        reference: Default::default(),
        interfaces: vec![
            InterfaceSpec {
                coupling: Coupling::Rbe3,
                ..plane_x("root", 0.0)
            },
            InterfaceSpec {
                coupling: Coupling::Rbe3,
                ..plane_x("tip", 0.2)
            },
        ],
        boundary: Vec::new(),
        ..bar_spec(selection, n)
    };
    let spec = free(ModeSelection::LoadRitz, 18);
    let model = spec.source.read(Path::new("/"), &spec.options).unwrap();
    let interfaces = resolve(&spec.interfaces, &model, "bar").unwrap();
    let map = RetainedMap::new(&model, &interfaces, "bar").unwrap();
    let kt = flexmbd_fe::assembly::to_dense(&project(&model.k, &map.t));
    let mt = flexmbd_fe::assembly::to_dense(&project(&model.m, &map.t));
    let pairs = flexmbd_fe::modal::generalized_eigen(&kt, &mt, "bar").unwrap();
    let rigid = pairs.vectors.columns(0, 6).into_owned();
    assert!(pairs.omega_sq[5].abs() < 1e-6 * pairs.omega_sq[6]);
    let m_rigid = &mt * &rigid;
    // α = the first elastic ω² keeps the rigid directions' eigenvalue at the elastic scale
    // (with α = 1 the matrix's condition, ~10¹³ here, spoils the reference).
    let alpha = pairs.omega_sq[6];
    let lu = (&kt + &m_rigid * m_rigid.transpose() * alpha).lu();
    // The loads, formed here: Tᵀ M S r̄ for the six S, unit loads at the two points.
    let t = flexmbd_fe::assembly::to_dense(&map.t);
    let m = flexmbd_fe::assembly::to_dense(&model.m);
    let mut loads = Vec::new();
    for a in 0..3 {
        for b in a..3 {
            let u = DVector::from_iterator(
                model.n_dofs(),
                model.dofs.iter().map(|d| {
                    let r = model.mesh.nodes.positions[d.node];
                    let s = Vector3::ith(a, 1.0) * r[b] + Vector3::ith(b, 1.0) * r[a];
                    [Dof::Ux, Dof::Uy, Dof::Uz]
                        .iter()
                        .position(|&x| x == d.dof)
                        .map_or(0.0, |k| s[k])
                }),
            );
            loads.push(t.transpose() * (&m * u));
        }
    }
    for p in 0..2 {
        for c in 0..6 {
            let mut f = DVector::zeros(map.n_retained());
            f[map.point_start(p) + c] = 1.0;
            loads.push(f);
        }
    }
    let worst = |selection, n| {
        let modes = reduce(&free(selection, n), &model, &interfaces, &map, "bar").unwrap();
        let k_ff = modes.k_ff.clone().cholesky().unwrap();
        loads
            .iter()
            .map(|f| {
                let g = f - &m_rigid * (rigid.transpose() * f);
                let exact = lu.solve(&g).unwrap();
                let reduced = &modes.x * k_ff.solve(&(modes.x.transpose() * &g));
                (reduced - &exact).amax() / exact.amax()
            })
            .fold(0.0, f64::max)
    };
    let all = worst(ModeSelection::LoadRitz, 18);
    let one_short = worst(ModeSelection::LoadRitz, 17);
    let lowest = worst(ModeSelection::LowestFrequency, 18);
    println!(
        "free-free, worst relative elastic response over the 18 loads: 18 Ritz vectors \
         {all:.2e}, 17 {one_short:.2e}, 18 lowest modes {lowest:.2e}"
    );
    assert!(all < 1e-9, "{all:e}");
    assert!(one_short > 1e-7, "{one_short:e}");
    assert!(lowest > 1e-4, "{lowest:e}");
}
