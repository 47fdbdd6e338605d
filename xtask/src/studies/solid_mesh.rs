//! Thesis ch. 3, "CPU-time vs. finite element mesh size", on solid meshes (issue 25 item
//! 7c): the pendulum of `models/imported_bar_pendulum.ron` with its bar remeshed as
//! 6k × k × k hex8 bricks (k = 1 is the CalculiX mesh of the scene), exported as Matrix
//! Market files and imported like a user's part; the modes stay 6 static + 4 normal. The cost
//! per step of the **B**-matrix route grows with the mass cloud (nodes plus coupled node pairs
//! of the consistent mass), that of the shape integrals does not; the preprocessing (reading,
//! sparse Craig–Bampton, the cloud and its integrals) grows with the mesh.

use std::path::{Path, PathBuf};

use flexmbd::body::InertiaMethod;
use flexmbd::fe::imported::ImportSource;
use flexmbd::fe::solid_box::SolidBox;
use flexmbd::fe::sparse::write_matrix_market;
use flexmbd::model::{BodyModel, FormulationKind, Scene};
use flexmbd::simulation::Summary;

use super::StudyResult;
use super::mesh_size::{VARIANTS, measure};
use crate::Settings;
use crate::chart::{LineChart, Series};
use crate::report::Report;

/// The step of the scene (0.2 ms) and the steps timed per run.
const STEP: f64 = 2e-4;
const STEPS: usize = 25;

/// The bar 0.2 × 0.02 × 0.02 m of the scene as 6k × k × k steel bricks.
fn bar(k: usize) -> SolidBox {
    SolidBox::steel([0.2, 0.02, 0.02], [6 * k, k, k])
}

/// Write the bar's export (node list, DOF map, K, M) into `dir`; its node count.
fn write_export(k: usize, dir: &Path) -> Result<usize, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(dir)?;
    let mesh = bar(k);
    let (stiffness, mass) = mesh.assemble()?;
    write_matrix_market(&dir.join("K.mtx"), &stiffness)?;
    write_matrix_market(&dir.join("M.mtx"), &mass)?;
    let mut nodes = String::from("# id x y z (m): solid_box, steel\n");
    let mut dofs = String::from("# node dof\n");
    for node in 0..mesh.n_nodes() {
        let [x, y, z] = mesh.node_position(node);
        nodes.push_str(&format!("{} {x:?} {y:?} {z:?}\n", node + 1));
        for dof in ["ux", "uy", "uz"] {
            dofs.push_str(&format!("{} {dof}\n", node + 1));
        }
    }
    std::fs::write(dir.join("nodes.txt"), nodes)?;
    std::fs::write(dir.join("dofs.txt"), dofs)?;
    Ok(mesh.n_nodes())
}

/// The pendulum scene with its bar read from `dir`, run for `STEPS` steps.
fn scene(
    dir: &Path,
    formulation: FormulationKind,
    method: InertiaMethod,
) -> Result<Scene, Box<dyn std::error::Error>> {
    let mut scene = Scene::load(crate::workspace_root().join("models/imported_bar_pendulum.ron"))?;
    let BodyModel::Imported(spec) = &mut scene.bodies[0].model else {
        return Err("models/imported_bar_pendulum.ron: its bar is not an imported body".into());
    };
    spec.source = ImportSource::MatrixMarket {
        nodes: dir.join("nodes.txt"),
        dofs: dir.join("dofs.txt"),
        stiffness: dir.join("K.mtx"),
        mass: dir.join("M.mtx"),
    };
    scene.solver.formulation = formulation;
    scene.solver.inertia = method;
    scene.solver.step = STEP;
    scene.solver.duration = STEP * STEPS as f64;
    scene.solver.output_interval = Some(scene.solver.duration);
    scene.validate()?;
    Ok(scene)
}

struct Point {
    nodes: usize,
    variant: usize,
    summary: Summary,
}

fn export_dir(k: usize) -> PathBuf {
    crate::workspace_root().join(format!("target/xtask/solid-mesh/k{k}"))
}

/// Run the study and append its section to the report.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    // Full: up to 90 625 nodes (k = 24); the largest meshes run once, their preprocessing
    // (a sparse Cholesky of 272 000 DOFs and its Lanczos solves) being most of the time.
    let (grid, reps): (Vec<usize>, usize) = if settings.quick {
        (vec![1, 2, 4, 8], 1)
    } else {
        (vec![1, 2, 4, 8, 12, 16, 24], 3)
    };
    let mut points = Vec::new();
    for &k in &grid {
        let dir = export_dir(k);
        let nodes = write_export(k, &dir)?;
        for (vi, &(formulation, method, label)) in VARIANTS.iter().enumerate() {
            eprintln!("   {nodes} nodes, {label}");
            let reps = if k >= 16 { 1 } else { reps };
            let summary = measure(&scene(&dir, formulation, method)?, reps)?;
            points.push(Point {
                nodes,
                variant: vi,
                summary,
            });
        }
    }
    report.text(&format!(
        "The imported bar pendulum (`models/imported_bar_pendulum.ron`: a steel bar 0.2 × 0.02 × 0.02 m \
         on a ball joint, clamped to its root face's RBE2 spider, the RBE3 tip face's 6 static modes and 4 \
         normal modes) with the bar remeshed as 6k × k × k hex8 bricks, written as Matrix Market files and \
         imported like a user's part. {STEPS} steps of h = {} ms per run, the median of {reps} run(s) \
         (one from k = 16). \
         Per step: CPU seconds of the whole run over its steps; preprocessing: reading the files, the sparse \
         Craig–Bampton reduction, the mass cloud (nodes and coupled node pairs of the consistent mass) and \
         its shape integrals, once per run. `--quick` stops at k = 8; the full grid, to k = 24 (90 625 \
         nodes), is `cargo xtask reproduce-thesis --only solid-mesh --out docs/results/solid-mesh`.",
        STEP * 1e3
    ));
    let per_step = |p: &Point| p.summary.cpu_seconds / p.summary.steps.max(1) as f64;
    let mut rows = Vec::new();
    for p in &points {
        let s = &p.summary;
        rows.push(vec![
            p.nodes.to_string(),
            (3 * p.nodes).to_string(),
            VARIANTS[p.variant].2.to_string(),
            format!("{:.3}", 1e3 * per_step(p)),
            format!("{:.3}", s.preprocessing_seconds),
        ]);
    }
    report.table(
        &[
            "nodes",
            "FE DOFs",
            "variant",
            "CPU ms per step",
            "preprocessing (s)",
        ],
        &rows,
    );
    let cost = |nodes: usize, v: usize| {
        points
            .iter()
            .find(|p| p.nodes == nodes && p.variant == v)
            .map(per_step)
            .unwrap_or(f64::NAN)
    };
    let node_counts: Vec<usize> = grid.iter().map(|&k| bar(k).n_nodes()).collect();
    let (first, last) = (node_counts[0], node_counts[node_counts.len() - 1]);
    report.text(&format!(
        "From {first} to {last} nodes the B-matrix route's step grows {:.0}× (absolute) and {:.0}× \
         (relative), the shape integrals' {:.1}× and {:.1}×: their cost is set by the modes, not the mesh \
         (the thesis's chapter 3 claim, on solids).",
        cost(last, 0) / cost(first, 0),
        cost(last, 2) / cost(first, 2),
        cost(last, 1) / cost(first, 1),
        cost(last, 3) / cost(first, 3),
    ));
    // Linked relative to the report when it lies under docs/results (the quick and the
    // full report), else by its absolute path.
    let results = crate::workspace_root().join("docs/results");
    let link = match report.dir.strip_prefix(&results) {
        Ok(below) => format!(
            "{}eigen-vs-scipy.md",
            "../".repeat(below.components().count())
        ),
        Err(_) => results.join("eigen-vs-scipy.md").display().to_string(),
    };
    report.text(&format!(
        "The preprocessing's sparse eigen-solver against SciPy's `eigsh` on the same matrices, \
         from 10³ to 5·10⁵ DOFs (time and peak memory; `benches/eigen_vs_scipy.py`, which needs \
         Python and SciPy and runs apart from this report): [{link}]({link})."
    ));
    let series = VARIANTS
        .iter()
        .enumerate()
        .map(|(vi, &(_, method, label))| Series {
            label: label.to_string(),
            points: node_counts
                .iter()
                .map(|&n| (n as f64, cost(n, vi)))
                .collect(),
            dashed: method == InertiaMethod::ShapeIntegrals,
            colour: vi / 2,
        })
        .collect();
    let chart = LineChart {
        title: "Imported solid bar: CPU time per step against FE mesh size".into(),
        x_label: "FE nodes".into(),
        y_label: "CPU seconds per step".into(),
        log_x: true,
        log_y: true,
        series,
    };
    let path = report.chart_path("solid_mesh.svg");
    chart.write_svg(&path)?;
    report.image(
        "solid_mesh.svg",
        "CPU time per step against solid mesh size, both formulations and inertia routes",
    );
    Ok(())
}
