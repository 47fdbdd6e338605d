//! The IAVSD Iltis benchmark vehicle (thesis ch. 2, scene C0 of docs/scenes.md §3.3): the
//! nominal loads and the static equilibrium beside S9's numbers, the linearised vibration beside
//! the frequencies derived in scenes.md §3.2, and the runs over the benchmark cosine bump at
//! 5 and 10 m/s beside S9's extremes, both formulations, with their CPU times.

use flexmbd::model::{FormulationKind, Scene, parse_set};
use flexmbd::output::History;
use flexmbd::simulation::{self, Summary};

use super::StudyResult;
use crate::Settings;
use crate::chart::{LineChart, Series};
use crate::report::Report;

const FORMS: [(FormulationKind, &str); 2] = [
    (FormulationKind::Absolute, "absolute"),
    (FormulationKind::Relative, "relative"),
];

/// Nominal chassis centre-of-mass height (scenes.md §2.1).
const NOMINAL_Z: f64 = 0.570;

type Failure = Box<dyn std::error::Error>;

fn load(file: &str, formulation: FormulationKind, sets: &[&str]) -> Result<Scene, Failure> {
    let mut scene = Scene::load(crate::workspace_root().join("models").join(file))?;
    scene.solver.formulation = formulation;
    let sets = sets
        .iter()
        .map(|s| parse_set(s))
        .collect::<Result<Vec<_>, _>>()?;
    scene.apply_sets(&sets)?;
    Ok(scene)
}

/// The sensor `name` of a history, as (t, value) pairs.
fn column(history: &History, name: &str) -> Result<Vec<(f64, f64)>, Failure> {
    let k = history
        .header
        .iter()
        .position(|n| n == name)
        .ok_or_else(|| format!("no sensor `{name}`"))?;
    Ok(history.rows.iter().map(|r| (r[0], r[k])).collect())
}

fn extreme(points: &[(f64, f64)], max: bool) -> (f64, f64) {
    let pick = |a: &(f64, f64), b: &(f64, f64)| {
        if max {
            a.1.total_cmp(&b.1)
        } else {
            b.1.total_cmp(&a.1)
        }
    };
    points.iter().copied().max_by(pick).unwrap_or((0.0, 0.0))
}

/// Median-CPU run of `scene` over `reps` runs, with its history.
fn measure(scene: &Scene, reps: usize) -> Result<(Summary, History), Failure> {
    let mut runs = Vec::new();
    for _ in 0..reps {
        let (summary, history) = simulation::run(scene, |_| {})?;
        if summary.status != "ok" {
            return Err(format!("{}: {}", scene.name, summary.message.unwrap_or_default()).into());
        }
        runs.push((summary, history));
    }
    runs.sort_by(|a, b| a.0.cpu_seconds.total_cmp(&b.0.cpu_seconds));
    Ok(runs.swap_remove(runs.len() / 2))
}

/// The static-equilibrium and nominal-load table (scenes.md §2.6, §3.2).
fn statics(report: &mut Report) -> StudyResult {
    // (label, sensor, scale, S9 value, printed digits)
    let rows_spec: [(&str, &str, f64, f64, usize); 8] = [
        (
            "chassis centre of mass from nominal (mm)",
            "chassis_z",
            1e3,
            -7.083,
            3,
        ),
        (
            "chassis pitch, nose down (°)",
            "chassis_pitch",
            180.0 / std::f64::consts::PI,
            0.1465,
            4,
        ),
        ("front tyre load (N)", "tyre_fl", 1.0, 3831.31, 2),
        ("rear tyre load (N)", "tyre_rl", 1.0, 3591.91, 2),
        ("front strut force (N)", "strut_fl", 1.0, -335.29, 2),
        ("rear strut force (N)", "strut_rl", 1.0, -241.64, 2),
        ("front leaf element (N)", "leaf_fl", 1.0, -3068.62, 2),
        ("rear leaf element (N)", "leaf_rl", 1.0, -2885.51, 2),
    ];
    let mut values = Vec::new();
    for &(form, _) in &FORMS {
        let scene = load("iltis_vehicle_benchmark.ron", form, &[])?;
        let e = flexmbd::equilibrium::equilibrium(&scene)?;
        values.push(e);
    }
    let mut rows = Vec::new();
    for &(label, sensor, scale, s9, digits) in &rows_spec {
        let mut row = vec![label.to_string(), format!("{s9:.digits$}")];
        for e in &values {
            let mut v = e
                .sensor(sensor)
                .ok_or_else(|| format!("no sensor `{sensor}`"))?;
            if sensor == "chassis_z" {
                v -= NOMINAL_Z;
            }
            row.push(format!("{:.digits$}", v * scale));
        }
        rows.push(row);
    }
    // Nominal loads: the sensors at t = 0 of a start from the nominal (design) position.
    let nominal_spec: [(&str, &str, f64); 4] = [
        ("nominal: leaf element (N)", "leaf_fl", -2728.86),
        ("nominal: strut spring (N)", "strut_fl", -128.03),
        ("nominal: front tyre (N)", "tyre_fl", 3829.50),
        ("nominal: rear tyre (N)", "tyre_rl", 3593.52),
    ];
    let mut nominal = Vec::new();
    for &(form, _) in &FORMS {
        let scene = load(
            "iltis_vehicle_benchmark.ron",
            form,
            &["solver.initial_state=Given", "solver.duration=0.001"],
        )?;
        let (_, history) = simulation::run(&scene, |_| {})?;
        nominal.push(history);
    }
    for &(label, sensor, s9) in &nominal_spec {
        let mut row = vec![label.to_string(), format!("{s9:.2}")];
        for h in &nominal {
            row.push(format!("{:.2}", column(h, sensor)?[0].1));
        }
        rows.push(row);
    }
    report.text(
        "**Benchmark checks.** The static equilibrium of scene C0 on a flat road found by \
         `flexmbd equilibrium models/iltis_vehicle_benchmark.ron` (S9: `2_Equilibrium_Report.txt`, \
         scenes.md §3.2), and the element forces at the nominal (design) position, which is not an \
         equilibrium (S9 `1_Nominal_Report.txt`, scenes.md §2.6), in both formulations.",
    );
    report.table(&["quantity", "S9", "absolute", "relative"], &rows);
    Ok(())
}

/// Linearised free vibration with the dampers removed (scenes.md §3.2, DERIVED values).
fn vibration(report: &mut Report) -> StudyResult {
    let undamped: Vec<String> = ["fl", "fr", "rl", "rr"]
        .iter()
        .map(|c| format!("forces.strut_{c}.damper=Zero"))
        .collect();
    let sets: Vec<&str> = undamped.iter().map(String::as_str).collect();
    let mut rows = Vec::new();
    let reference = [1.590, 1.849, 14.42, 14.43];
    let mut found = Vec::new();
    for &(form, name) in &FORMS {
        let scene = load("iltis_vehicle_benchmark.ron", form, &sets)?;
        let v = flexmbd::vibration::vibration(&scene)?;
        let mut f = v.frequencies("oscillatory");
        f.sort_by(f64::total_cmp);
        found.push((name, f));
    }
    for (k, r) in reference.iter().enumerate() {
        let mut row = vec![
            [
                "pitch-dominant",
                "bounce-dominant",
                "wheel hop, front",
                "wheel hop, rear",
            ][k]
                .to_string(),
            format!("{r:.3}"),
        ];
        for (_, f) in &found {
            // The nearest frequency found (the table pairs by value: roll and the
            // antisymmetric wheel hops are modes the symmetric derivation does not list).
            let near = f
                .iter()
                .copied()
                .min_by(|a, b| (a - r).abs().total_cmp(&(b - r).abs()))
                .unwrap_or(f64::NAN);
            row.push(format!("{near:.3} ({:+.2} %)", 100.0 * (near - r) / r));
        }
        rows.push(row);
    }
    report.text(
        "**Linearised free vibration** about that equilibrium, strut dampers removed \
         (`flexmbd eigen` with `--set forces.strut_c.damper=Zero`): the symmetric frequencies \
         derived in scenes.md §3.2, and the nearest undamped frequency found, in Hz.",
    );
    report.table(&["mode", "scenes.md §3.2", "absolute", "relative"], &rows);
    let all: Vec<String> = found
        .iter()
        .map(|(name, f)| {
            let list: Vec<String> = f.iter().map(|x| format!("{x:.3}")).collect();
            format!("{name}: {}", list.join(", "))
        })
        .collect();
    report.text(&format!(
        "Every oscillatory mode found (Hz) — {}.",
        all.join("; ")
    ));
    Ok(())
}

/// One bump run per formulation at `speed`.
struct BumpRun {
    form: &'static str,
    summary: Summary,
    history: History,
}

fn bump_runs(speed: f64, reps: usize) -> Result<Vec<BumpRun>, Failure> {
    let mut out = Vec::new();
    for &(form, name) in &FORMS {
        // The forward speed and the lateral tyre dampers C_α/V (scenes.md §3.4).
        let sets = flexmbd_test_support::iltis::bump_at_speed(speed);
        let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
        let scene = load("iltis_bump.ron", form, &sets)?;
        eprintln!("   bump at {speed} m/s, {name}");
        let (summary, history) = measure(&scene, reps)?;
        out.push(BumpRun {
            form: name,
            summary,
            history,
        });
    }
    Ok(out)
}

/// The extremes of S9's in-phase 5 m/s bump (scenes.md §3.2) beside ours.
fn bump_table(report: &mut Report, runs: &[BumpRun], fast: &[BumpRun]) -> StudyResult {
    let degrees = 180.0 / std::f64::consts::PI;
    let mut rows: Vec<Vec<String>> = vec![
        vec![
            "peak rise of the centre of mass (mm)".into(),
            "127.8 at 0.725 s".into(),
        ],
        vec!["pitch minimum (°)".into(), "−6.35 at 0.538 s".into()],
        vec!["pitch maximum (°)".into(), "+7.64 at 1.033 s".into()],
        vec![
            "front tyre force range (N)".into(),
            "1300.5 … 6202.4".into(),
        ],
        vec!["rear tyre force range (N)".into(), "1360.1 … 5664.2".into()],
        vec!["10 m/s: peak rise (mm)".into(), "314.1".into()],
        vec![
            "10 m/s: smallest tyre force (N)".into(),
            "0 (lift-off)".into(),
        ],
    ];
    for (run, fast) in runs.iter().zip(fast) {
        let z = column(&run.history, "chassis_z")?;
        let z0 = z[0].1;
        let (t_rise, rise) = extreme(&z, true);
        let pitch = column(&run.history, "chassis_pitch")?;
        let (t_lo, lo) = extreme(&pitch, false);
        let (t_hi, hi) = extreme(&pitch, true);
        let front = column(&run.history, "tyre_fl")?;
        let rear = column(&run.history, "tyre_rl")?;
        let zf = column(&fast.history, "chassis_z")?;
        let lift = ["tyre_fl", "tyre_fr", "tyre_rl", "tyre_rr"]
            .iter()
            .map(|n| column(&fast.history, n).map(|c| extreme(&c, false).1))
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        let cells = [
            format!("{:.1} at {t_rise:.3} s", (rise - z0) * 1e3),
            format!("{:.2} at {t_lo:.3} s", lo * degrees),
            format!("{:+.2} at {t_hi:.3} s", hi * degrees),
            format!(
                "{:.1} … {:.1}",
                extreme(&front, false).1,
                extreme(&front, true).1
            ),
            format!(
                "{:.1} … {:.1}",
                extreme(&rear, false).1,
                extreme(&rear, true).1
            ),
            format!("{:.1}", (extreme(&zf, true).1 - zf[0].1) * 1e3),
            format!("{lift:.1}"),
        ];
        for (row, cell) in rows.iter_mut().zip(cells) {
            row.push(cell);
        }
    }
    report.text(
        "**The benchmark cosine bump** (0.20 m high, 5 m long, both tracks in phase; \
         `models/iltis_bump.ron`: from the static equilibrium, every body moving forward at 5 m/s, \
         the tyre force radial and normal to the profile as S9's `GroundContact.c`, and for S9's \
         Calspan slip force a lateral damper C_α/V at each wheel (scenes.md §3.4), h = 1 ms, 2.5 s). S9's extremes are read from its output at about 0.02 s intervals (scenes.md §3.2) \
         and S9 integrates with Dopri5: agreement to a few per cent is what the comparison can show.",
    );
    report.table(&["quantity", "S9", "absolute", "relative"], &rows);
    Ok(())
}

fn bump_charts(report: &mut Report, runs: &[BumpRun]) -> StudyResult {
    let degrees = 180.0 / std::f64::consts::PI;
    let chart = |title: &str, y_label: &str, series: Vec<Series>| LineChart {
        title: title.into(),
        x_label: "time (s)".into(),
        y_label: y_label.into(),
        log_x: false,
        log_y: false,
        series,
    };
    let mut heave = Vec::new();
    let mut tyres = Vec::new();
    for (k, run) in runs.iter().enumerate() {
        let z = column(&run.history, "chassis_z")?;
        let z0 = z[0].1;
        heave.push(Series {
            label: format!("centre-of-mass rise (mm), {}", run.form),
            points: z.iter().map(|&(t, v)| (t, (v - z0) * 1e3)).collect(),
            dashed: k == 1,
            colour: 0,
        });
        heave.push(Series {
            label: format!("pitch (° × 10), {}", run.form),
            points: column(&run.history, "chassis_pitch")?
                .iter()
                .map(|&(t, v)| (t, v * degrees * 10.0))
                .collect(),
            dashed: k == 1,
            colour: 1,
        });
        for (c, name) in [(2, "tyre_fl"), (3, "tyre_rl")] {
            tyres.push(Series {
                label: format!("{name} (N), {}", run.form),
                points: column(&run.history, name)?,
                dashed: k == 1,
                colour: c,
            });
        }
    }
    let path = report.chart_path("iltis_bump_chassis.svg");
    chart(
        "Iltis over the cosine bump at 5 m/s: chassis",
        "rise (mm), pitch (° × 10, nose down positive)",
        heave,
    )
    .write_svg(&path)?;
    report.image(
        "iltis_bump_chassis.svg",
        "chassis rise and pitch over the bump, both formulations",
    );
    let path = report.chart_path("iltis_bump_tyres.svg");
    chart(
        "Iltis over the cosine bump at 5 m/s: tyre forces",
        "force (N)",
        tyres,
    )
    .write_svg(&path)?;
    report.image(
        "iltis_bump_tyres.svg",
        "front and rear tyre forces over the bump, both formulations",
    );
    Ok(())
}

fn cpu_table(report: &mut Report, runs: &[BumpRun], reps: usize) {
    let rows: Vec<Vec<String>> = runs
        .iter()
        .map(|r| {
            let s = &r.summary;
            vec![
                r.form.to_string(),
                s.n_coordinates.to_string(),
                s.n_constraints.to_string(),
                format!("{:.1}", s.cpu_seconds * 1e3),
                format!("{:.0}", s.realtime_factor),
                format!("{:.2}", s.newton_iterations as f64 / s.steps.max(1) as f64),
                format!("{:.0} %", 100.0 * s.time_evaluation / s.cpu_seconds),
                format!("{:.0} %", 100.0 * s.time_factorization / s.cpu_seconds),
            ]
        })
        .collect();
    report.text(&format!(
        "**Speed** of the 2.5 s bump run at h = 1 ms (2500 steps), one core, median of {reps} runs; \
         the issue's target is 25 ms (100× real time) in the faster formulation. Evaluation = the \
         formulation's passes, factorisation = forming, factorising and solving the Newton matrix."
    ));
    report.table(
        &[
            "formulation",
            "coordinates",
            "constraints",
            "CPU (ms)",
            "real-time factor",
            "Newton iterations per step",
            "evaluation",
            "factorisation",
        ],
        &rows,
    );
}

/// Run the study and append its section to the report.
pub fn run(settings: &Settings, report: &mut Report) -> StudyResult {
    let reps = if settings.quick { 3 } else { 7 };
    report.text(
        "The IAVSD \"Bombardier Iltis\" benchmark vehicle as S9 implements it in Robotran \
         (`models/iltis_vehicle_benchmark.ron`, generated by `models/generate_iltis.py` from \
         scenes.md §2.1–§3.3): a free chassis, four A-arms and four wheel carriers (rigid, S9's \
         masses), the massless leaf-spring links and tie rods as constraints, the strut's cubic \
         spring and piecewise-quartic damper, the leaf element along chassis z with its 70 mm bump \
         stop, and vertical tyres without damping. Scene C0 of scenes.md §3.3; the thesis's flexible \
         configurations are the next issue's.",
    );
    statics(report)?;
    vibration(report)?;
    let slow = bump_runs(5.0, reps)?;
    let fast = bump_runs(10.0, 1)?;
    bump_table(report, &slow, &fast)?;
    bump_charts(report, &slow)?;
    cpu_table(report, &slow, reps);
    Ok(())
}
