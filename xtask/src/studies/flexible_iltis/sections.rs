//! The flexible Iltis study's report sections: the histories of scenes B and C as the thesis's
//! figures, the CPU table and chart against the number of flexible bodies, where relative
//! overtakes absolute, and the mesh-size study on the 12-flexible-body vehicle.

use flexmbd::fe::spec::ReferenceFrame;
use flexmbd::model::BodyModel;
use flexmbd::simulation::{History, Summary};

use super::{Case, FORMS, Failure, LEAF_AT_STOP, METHODS, Which, find, median_runs, scene};
use crate::Settings;
use crate::chart::{LineChart, Series};
use crate::report::Report;
use crate::studies::StudyResult;

/// The sensor `name` of a history as (t, value × scale) pairs.
fn column(history: &History, name: &str, scale: f64) -> Result<Vec<(f64, f64)>, Failure> {
    let k = history
        .header
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| format!("no sensor `{name}`"))?;
    Ok(history.rows.iter().map(|r| (r[0], r[k] * scale)).collect())
}

fn time_chart(title: &str, y_label: &str, series: Vec<Series>) -> LineChart {
    LineChart {
        title: title.into(),
        x_label: "time (s)".into(),
        y_label: y_label.into(),
        log_x: false,
        log_y: false,
        series,
    }
}

/// Chassis and front-left wheel-centre heights (mm) of `which` with each of `ks` flexible
/// bodies, both formulations overlaid (relative dashed; shape integrals).
fn heights(cases: &[Case], which: Which, ks: &[usize]) -> Result<Vec<Series>, Failure> {
    let mut series = Vec::new();
    for (i, &k) in ks.iter().enumerate() {
        for (f, &(_, form)) in FORMS.iter().enumerate() {
            let h = &find(cases, which, k, form, "shape-integrals").history;
            for (q, (name, what)) in [("chassis_z", "chassis"), ("wheel_fl_z", "wheel FL")]
                .into_iter()
                .enumerate()
            {
                series.push(Series {
                    label: format!("{what}, {k} flexible, {form}"),
                    points: column(h, name, 1e3)?,
                    dashed: f == 1,
                    colour: 2 * i + q,
                });
            }
        }
    }
    Ok(series)
}

/// The most compressive leaf force of a history and when; whether the bump stop closed.
fn leaf_sentence(h: &History, sensor: &str, what: &str) -> Result<String, Failure> {
    let leaf = column(h, sensor, 1.0)?;
    let (t, f) = leaf
        .iter()
        .copied()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((f64::NAN, f64::NAN));
    let first = leaf.iter().find(|p| p.1 < LEAF_AT_STOP).map(|p| p.0);
    Ok(match first {
        Some(t0) => format!(
            "{what}: **reached** from t = {t0:.3} s (`{sensor}` down to {f:.0} N at {t:.3} s)"
        ),
        None => format!("{what}: not reached (`{sensor}` at most {f:.0} N, at {t:.3} s)"),
    })
}

/// Scene B's figures: the heights and the A-arm deflection, 0 and 3 flexible bodies.
pub(super) fn suspension_histories(report: &mut Report, cases: &[Case]) -> StudyResult {
    report.text(
        "**Scene B, the drop.** Vertical positions of the quarter chassis and of the front-left \
         wheel centre (mm), rigid and with 3 flexible bodies, absolute (solid) and relative \
         (dashed) overlaid; shape integrals. The road steps down 20 cm at 0.5 s.",
    );
    let path = report.chart_path("flexible_iltis_b_heights.svg");
    time_chart(
        "Scene B: chassis and wheel centre, 0 and 3 flexible bodies",
        "height (mm)",
        heights(cases, Which::Suspension, &[0, 3])?,
    )
    .write_svg(&path)?;
    report.image(
        "flexible_iltis_b_heights.svg",
        "scene B chassis and wheel-centre heights",
    );
    let mut series = Vec::new();
    for (f, &(_, form)) in FORMS.iter().enumerate() {
        let h = &find(cases, Which::Suspension, 3, form, "shape-integrals").history;
        series.push(Series {
            label: format!("3 flexible, {form}"),
            points: column(h, "aarm_fl_deflection", 1e3)?,
            dashed: f == 1,
            colour: f,
        });
    }
    let path = report.chart_path("flexible_iltis_b_deflection.svg");
    time_chart(
        "Scene B: A-arm deflection at the ball joint, 3 flexible bodies",
        "deflection normal to the arm plane (mm)",
        series,
    )
    .write_svg(&path)?;
    report.image(
        "flexible_iltis_b_deflection.svg",
        "scene B A-arm deflection",
    );
    let mut lines = Vec::new();
    for k in [0, 3] {
        for &(_, form) in &FORMS {
            let h = &find(cases, Which::Suspension, k, form, "shape-integrals").history;
            lines.push(leaf_sentence(
                h,
                "leaf_fl",
                &format!("{k} flexible, {form}"),
            )?);
        }
    }
    report.text(&format!(
        "The A-arm deflection (`aarm_fl_deflection`) is zero with the arm rigid. The leaf bump \
         stop (70 mm of jounce: the leaf element beyond {LEAF_AT_STOP} N) on landing — {}.",
        lines.join("; ")
    ));
    Ok(())
}

/// Scene C's figure: chassis and front-left wheel centre, 0 and 12 flexible bodies.
pub(super) fn vehicle_histories(report: &mut Report, cases: &[Case]) -> StudyResult {
    report.text(
        "**Scene C, the vehicle.** Chassis centre of mass and front-left wheel centre (mm), rigid \
         and with 12 flexible bodies, absolute (solid) and relative (dashed); shape integrals.",
    );
    let path = report.chart_path("flexible_iltis_c_heights.svg");
    time_chart(
        "Scene C: chassis and wheel centre, 0 and 12 flexible bodies",
        "height (mm)",
        heights(cases, Which::Vehicle, &[0, 12])?,
    )
    .write_svg(&path)?;
    report.image(
        "flexible_iltis_c_heights.svg",
        "scene C chassis and wheel-centre heights",
    );
    let mut lines = Vec::new();
    for k in [0, 12] {
        let h = &find(cases, Which::Vehicle, k, "relative", "shape-integrals").history;
        for sensor in ["leaf_fl", "leaf_rl"] {
            lines.push(leaf_sentence(
                h,
                sensor,
                &format!("{k} flexible, relative"),
            )?);
        }
    }
    let mut largest = 0.0_f64;
    for k in [0, 12] {
        let a = &find(cases, Which::Vehicle, k, "absolute", "shape-integrals").history;
        let r = &find(cases, Which::Vehicle, k, "relative", "shape-integrals").history;
        for name in ["chassis_z", "wheel_fl_z"] {
            let (ca, cr) = (column(a, name, 1.0)?, column(r, name, 1.0)?);
            let range = ca.iter().map(|p| p.1).fold(f64::MIN, f64::max)
                - ca.iter().map(|p| p.1).fold(f64::MAX, f64::min);
            let d = ca
                .iter()
                .zip(&cr)
                .map(|(x, y)| (x.1 - y.1).abs())
                .fold(0.0, f64::max);
            largest = largest.max(d / range);
        }
    }
    report.text(&format!(
        "The formulations' largest difference in these four heights is {largest:.1e} of their \
         range. The leaf bump stops — {}.",
        lines.join("; ")
    ));
    Ok(())
}

fn pct(part: f64, whole: f64) -> String {
    format!("{:.0} %", 100.0 * part / whole)
}

/// CPU per simulated second, real-time factor, coordinates and the split by phase.
pub(super) fn cpu_table(report: &mut Report, cases: &[Case], reps: usize) {
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            let s = &c.median;
            vec![
                c.which.label().to_string(),
                c.k.to_string(),
                c.form.to_string(),
                c.method.to_string(),
                s.n_coordinates.to_string(),
                format!("{:.3}", c.cpu_per_second()),
                format!("{:.1}", 1.0 / c.cpu_per_second()),
                format!(
                    "{} / {} / {}",
                    pct(s.time_evaluation, s.cpu_seconds),
                    pct(s.time_factorization, s.cpu_seconds),
                    pct(s.time_projection, s.cpu_seconds)
                ),
                format!("{:.2}", s.newton_iterations as f64 / s.steps.max(1) as f64),
            ]
        })
        .collect();
    let how = if reps > 1 {
        format!("median of {reps} runs")
    } else {
        "one run".to_string()
    };
    report.text(&format!(
        "**CPU time against the number of flexible bodies** k (scene B: k = 0 … 3; scene C: corner \
         by corner FL, FR, RL, RR, each A-arm, leaf link, tie rod, §3.4, so k = 4 is the FL \
         corner and the FR A-arm), one core, h = 1 ms, {how}. CPU is per \
         simulated second; the real-time factor is its inverse. Evaluation = the formulation's \
         passes (inertia terms included), factorisation = forming, factorising and solving the \
         Newton matrix, projections = the velocity and acceleration projections of ALI3-P; the \
         phases are timed one step in several and weighted, estimates that need not add to \
         100 %."
    ));
    report.table(
        &[
            "scene",
            "k",
            "formulation",
            "inertia",
            "coordinates",
            "CPU (s per s)",
            "real-time factor",
            "evaluation / factorisation / projections",
            "Newton it./step",
        ],
        &rows,
    );
}

/// Log CPU per simulated second against k, every scene × formulation × inertia route.
pub(super) fn cpu_chart(report: &mut Report, cases: &[Case]) -> StudyResult {
    let mut series = Vec::new();
    for (w, which) in [Which::Suspension, Which::Vehicle].into_iter().enumerate() {
        for (f, &(_, form)) in FORMS.iter().enumerate() {
            for (m, &(_, method)) in METHODS.iter().enumerate() {
                let points: Vec<(f64, f64)> = cases
                    .iter()
                    .filter(|c| c.which == which && c.form == form && c.method == method)
                    .map(|c| (c.k as f64, c.cpu_per_second()))
                    .collect();
                series.push(Series {
                    label: format!("scene {}, {form}, {method}", which.label()),
                    points,
                    dashed: m == 0,
                    colour: 2 * w + f,
                });
            }
        }
    }
    let path = report.chart_path("flexible_iltis_cpu.svg");
    LineChart {
        title: "Flexible Iltis: CPU per simulated second against flexible bodies".into(),
        x_label: "flexible bodies k".into(),
        y_label: "CPU (s per simulated s)".into(),
        log_x: false,
        log_y: true,
        series,
    }
    .write_svg(&path)?;
    report.image(
        "flexible_iltis_cpu.svg",
        "CPU per simulated second against the number of flexible bodies (b-matrix dashed)",
    );
    Ok(())
}

/// Where relative overtakes absolute, and the thesis's statements of docs/scenes.md §7.2.
pub(super) fn crossover(report: &mut Report, cases: &[Case]) {
    let mut lines = Vec::new();
    let mut si_faster = 0;
    let mut flexible = 0;
    for which in [Which::Suspension, Which::Vehicle] {
        let ks: Vec<usize> = cases
            .iter()
            .filter(|c| c.which == which && c.form == "relative" && c.method == "b-matrix")
            .map(|c| c.k)
            .collect();
        let ratios: Vec<String> = ks
            .iter()
            .map(|&k| {
                let a = find(cases, which, k, "absolute", "shape-integrals").cpu_median();
                let r = find(cases, which, k, "relative", "shape-integrals").cpu_median();
                format!("k = {k}: {:.1}×", a / r)
            })
            .collect();
        lines.push(format!("scene {}: {}", which.label(), ratios.join(", ")));
        for &k in ks.iter().filter(|&&k| k > 0) {
            for &(_, form) in &FORMS {
                let b = find(cases, which, k, form, "b-matrix");
                let s = find(cases, which, k, form, "shape-integrals");
                flexible += 1;
                si_faster += usize::from(s.cpu_median() < b.cpu_median());
            }
        }
    }
    // The evaluation's share of all flexible runs of one formulation and route together (the
    // phases are sampled every few steps, so one run's share is noisy).
    let share = |form: &str, method: &str| {
        let runs = cases
            .iter()
            .filter(|c| c.k > 0 && c.form == form && c.method == method);
        let (e, t) = runs.fold((0.0, 0.0), |(e, t), c| {
            (e + c.median.time_evaluation, t + c.median.cpu_seconds)
        });
        100.0 * e / t
    };
    report.text(&format!(
        "**Where relative overtakes absolute.** Absolute CPU over relative CPU (shape integrals): \
         {}. The relative formulation is ahead at every k, rigid included, so there is no \
         crossover to find: the thesis's \"relative is more efficient for large systems\" \
         (scenes.md §7.2, figures only) holds here at every size, by a margin that narrows as \
         elastic coordinates are added (they cost both formulations alike, while the absolute \
         formulation's extra coordinates are the rigid bodies'). Shape integrals are faster than \
         the B-matrix projection in {si_faster} of the {flexible} flexible configurations \
         (thesis: always faster). The evaluation pass, where the inertia terms are, takes \
         {:.0} % of the flexible runs' CPU with the B-matrix in the relative formulation and \
         {:.0} % with shape integrals (absolute: {:.0} % and {:.0} %): the thesis's \"inertia \
         terms the bottleneck, up to 80 %\" is the B-matrix route's picture; in the absolute \
         formulation the factorisation and projections dominate instead.",
        lines.join("; "),
        share("relative", "b-matrix"),
        share("relative", "shape-integrals"),
        share("absolute", "b-matrix"),
        share("absolute", "shape-integrals"),
    ));
}

/// Set every flexible beam body's elements per member (frame) or per segment (polyline) to `n`.
/// A frame's named nodes come first, so its node numbers stand; a polyline's node numbers are
/// mesh nodes and are renumbered (a segment end j·p becomes j·n).
fn set_elements(scene: &mut flexmbd::model::Scene, n: usize) -> Result<(), Failure> {
    for body in scene.bodies.iter_mut().filter(|b| b.flexible) {
        let BodyModel::Beam(spec) = &mut body.model else {
            continue;
        };
        let old = spec.geometry.elements_per_segment.max(1);
        spec.geometry.elements_per_segment = n;
        if spec.geometry.is_frame() {
            for member in &mut spec.geometry.members {
                member.elements = Some(n);
            }
            continue;
        }
        let name = body.name.clone();
        let renumber = |node: &mut usize| -> Result<(), Failure> {
            if !node.is_multiple_of(old) {
                return Err(format!("{name}: node {node} is not a segment end").into());
            }
            *node = *node / old * n;
            Ok(())
        };
        for d in &mut spec.boundary {
            renumber(&mut d.node)?;
        }
        match &mut spec.frame {
            ReferenceFrame::Clamped { node } => renumber(node)?,
            ReferenceFrame::Chord { a, b } => {
                renumber(a)?;
                renumber(b)?;
            }
            ReferenceFrame::Dofs(dofs) => {
                for d in dofs {
                    renumber(&mut d.node)?;
                }
            }
        }
    }
    Ok(())
}

/// The mesh study's runs: per formulation, per n of `grid`, per inertia route, the summary of
/// the median of `reps` runs of `duration` s of scene C with 12 flexible bodies.
fn mesh_runs(grid: &[usize], duration: f64, reps: usize) -> Result<Vec<Summary>, Failure> {
    let mut runs = Vec::new();
    for &(fk, form) in &FORMS {
        for &n in grid {
            for &(method, name) in &METHODS {
                let mut sc = scene(Which::Vehicle, 12, fk, method, Some(duration))?;
                set_elements(&mut sc, n)?;
                runs.push((format!("mesh study, {form}, {name}, {n} elements"), sc));
            }
        }
    }
    median_runs(&runs, reps)
}

/// The mesh-size study of docs/scenes.md §4 on scene C with 12 flexible bodies, each CPU
/// figure the median of `reps` runs.
pub(super) fn mesh_study(settings: &Settings, report: &mut Report, reps: usize) -> StudyResult {
    let (grid, duration): (&[usize], f64) = if settings.quick {
        (&[1, 5, 20], 0.5)
    } else {
        (&[1, 2, 5, 10, 20, 50], 8.0)
    };
    let mut summaries = mesh_runs(grid, duration, reps)?.into_iter();
    let mut rows = Vec::new();
    let mut crossings = Vec::new();
    let mut preprocessing_share = 0.0_f64;
    for &(_, form) in &FORMS {
        let mut per_n = Vec::new();
        for &n in grid {
            let mut cpu = [0.0; 2];
            for (m, &(_, name)) in METHODS.iter().enumerate() {
                let s = summaries.next().ok_or("a mesh run is missing")?;
                cpu[m] = s.cpu_seconds / s.simulated_seconds;
                // The share the 8 s run would spend preprocessing.
                let whole = s.preprocessing_seconds + cpu[m] * 8.0;
                preprocessing_share = preprocessing_share.max(s.preprocessing_seconds / whole);
                rows.push(vec![
                    n.to_string(),
                    form.to_string(),
                    name.to_string(),
                    s.n_coordinates.to_string(),
                    format!("{:.3}", s.preprocessing_seconds),
                    format!("{:.3}", cpu[m]),
                    pct(s.time_evaluation, s.cpu_seconds),
                ]);
            }
            per_n.push((n, cpu));
        }
        let first_si = per_n.iter().find(|(_, c)| c[1] < c[0]).map(|p| p.0);
        if per_n.iter().all(|(_, c)| c[1] < c[0]) {
            crossings.push(format!(
                "{form}: shape integrals faster at every n of the grid"
            ));
            continue;
        }
        crossings.push(match first_si {
            Some(n) => format!("{form}: shape integrals ahead from n = {n}"),
            None => format!("{form}: the B-matrix ahead at every mesh of the grid"),
        });
    }
    let how = if reps > 1 {
        format!("the median of {reps} runs each (preprocessing from the same run)")
    } else {
        "one run each".to_string()
    };
    report.text(&format!(
        "**Mesh size on the 12-flexible-body vehicle** (docs/scenes.md §4): every member of the \
         A-arm frames and every segment of the links and tie rods cut into n elements (the \
         bracket members too), the same static and fixed-interface modes, so the coordinates do \
         not change; {duration} s of scene C, {how}. Preprocessing (the FE \
         model, its reduction and the inertia invariants) beside the integration's CPU per \
         simulated second."
    ));
    report.table(
        &[
            "elements per member",
            "formulation",
            "inertia",
            "coordinates",
            "preprocessing (s)",
            "CPU (s per s)",
            "evaluation",
        ],
        &rows,
    );
    report.text(&format!(
        "{}. Preprocessing is at most {:.1} % of an 8 s run's CPU. Thesis (scenes.md §7.2): the \
         B-matrix is fine below about 10 elements, shape integrals win above about 20, and \
         preprocessing has no significant impact.",
        crossings.join("; "),
        100.0 * preprocessing_share
    ));
    Ok(())
}
