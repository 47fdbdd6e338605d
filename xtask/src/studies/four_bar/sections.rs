//! The sections of the double four-bar study's report (the measurements are the parent module's).

use super::*;

/// The table of coordinate counts against the thesis's.
pub(super) fn coordinates(report: &mut Report, cases: &[Case]) {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    report.text("### Coordinates\n");
    let rows: Vec<Vec<String>> = (0..=5)
        .map(|k| {
            let (a, r) = (
                case(k, "absolute", "shape-integrals"),
                case(k, "relative", "shape-integrals"),
            );
            vec![
                k.to_string(),
                if k == 0 {
                    "none".into()
                } else {
                    BARS[..k].join(", ")
                },
                a.median.n_coordinates.to_string(),
                a.median.n_constraints.to_string(),
                THESIS_ABS_COORDS[k].to_string(),
                r.median.n_coordinates.to_string(),
                r.median.n_constraints.to_string(),
                THESIS_REL_COORDS[k].to_string(),
            ]
        })
        .collect();
    report.table(
        &[
            "k",
            "flexible bars",
            "ours, absolute: n",
            "ours, absolute: m",
            "thesis, absolute: n",
            "ours, relative: n",
            "ours, relative: m",
            "thesis, relative: n",
        ],
        &rows,
    );
    let counts_ok = (0..=5).all(|k| {
        case(k, "absolute", "shape-integrals").median.n_coordinates == 6 + 6 * k
            && case(k, "relative", "shape-integrals").median.n_coordinates == 5 + 4 * k
    });
    report.text(&format!(
        "n: coordinates, m: constraint equations. Our modelling gives 6 + 6k coordinates in the absolute \
         formulation and 5 + 4k in the relative one{}: each flexible bar carries 2 static + 2 normal modal \
         coordinates (4) and, in the absolute formulation, its own unit vector u (2), its frame point being \
         the shared basic point of its first pin; the thesis's 6 + 7k and 5 + 3k come out with three modal \
         coordinates per bar (docs/design.md, \"Coordinate counts of the double four-bar\"; scenes.md §1 \
         \"Flexible-body model\"). The relative formulation has 5 tree-joint coordinates and closes the \
         two loops with 2 cut joints (4 equations) whatever k.",
        if counts_ok {
            ""
        } else {
            " (**not** what this run produced: see the table)"
        }
    ));
}

/// The CPU times of the 5 s runs against the thesis's, and the energy drift.
pub(super) fn cpu_times(report: &mut Report, cases: &[Case], reps: usize) {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    report.text("### CPU time of the 5 s run\n");
    let mut rows = Vec::new();
    for &(_, form) in &FORMS {
        for k in 0..=5 {
            for &(_, name) in &METHODS {
                let c = case(k, form, name);
                let t = c.cpu_median();
                let thesis = thesis_cpu(form)[k];
                if let Some(failed) = &c.failed {
                    let mut row = vec![
                        form.to_string(),
                        k.to_string(),
                        name.to_string(),
                        format!("**{failed}**"),
                    ];
                    row.extend([dash(), dash(), format!("{thesis:.2}")]);
                    row.extend([dash(), dash(), dash(), dash()]);
                    rows.push(row);
                    continue;
                }
                rows.push(vec![
                    form.to_string(),
                    k.to_string(),
                    name.to_string(),
                    format!("{:.3}", t),
                    format!("{:.3}–{:.3}", c.cpu[0], c.cpu[c.cpu.len() - 1]),
                    format!("{:.0}", c.median.realtime_factor),
                    format!("{thesis:.2}"),
                    times(thesis / t),
                    format!("{:.2}", c.newton_per_step()),
                    c.median.accepted_unconverged.to_string(),
                    format!("{:.1e}", c.energy_drift()),
                ]);
            }
        }
    }
    report.table(
        &[
            "formulation",
            "k",
            "inertia",
            &format!("ours (s, median of {reps})"),
            "range (s)",
            "real-time factor",
            "thesis (s)",
            "thesis / ours",
            "Newton it. / step",
            "steps accepted at the limit",
            "energy drift / 1.5 J",
        ],
        &rows,
    );
    let ratio =
        |k: usize, form: &str| thesis_cpu(form)[k] / case(k, form, "shape-integrals").cpu_median();
    let growth = |form: &str, name: &str| {
        case(5, form, name).cpu_median() / case(0, form, name).cpu_median()
    };
    let rel_abs = |k: usize| {
        case(k, "relative", "shape-integrals").cpu_median()
            / case(k, "absolute", "shape-integrals").cpu_median()
    };
    report.text(&format!(
        "CPU time is the wall-clock time of the integration steps on one core (preprocessing and output \
         excluded), median of {reps} runs taken round by round. The thesis's times are from 2008 hardware \
         and another code, so only the ratios mean something (scenes.md §6). With shape integrals we are \
         {} (absolute) and {} (relative) faster than the thesis on the rigid mechanism, {} and {} with \
         five flexible bars. From k = 0 to 5 our absolute time grows {} (b-matrix) and {} (shape \
         integrals), the thesis's {:.0}×; our relative time grows {} and {}, the thesis's {:.0}×. \
         Relative / absolute (shape integrals): {:.2} at k = 0, {:.2} at k = 5 (thesis: {:.2} and {:.2}; \
         scenes.md §7.1 expects the relative formulation to win above about 25 variables). \
         `steps accepted at the limit`: steps that reached the Newton iteration limit with ‖Φ‖ ≤ 1e-6 \
         (the singular configuration every half turn, scenes.md §1 \"Geometry\"; ALI3-P raises α \
         there when the multiplier update converges slowly, so every step now meets the tolerance). \
         `energy drift`: largest |E(t) − E(0)| over the run relative to the initial kinetic energy.",
        times(ratio(0, "absolute")),
        times(ratio(0, "relative")),
        times(ratio(5, "absolute")),
        times(ratio(5, "relative")),
        times(growth("absolute", "b-matrix")),
        times(growth("absolute", "shape-integrals")),
        THESIS_ABS_CPU[5] / THESIS_ABS_CPU[0],
        times(growth("relative", "b-matrix")),
        times(growth("relative", "shape-integrals")),
        THESIS_REL_CPU[5] / THESIS_REL_CPU[0],
        rel_abs(0),
        rel_abs(5),
        THESIS_REL_CPU[0] / THESIS_ABS_CPU[0],
        THESIS_REL_CPU[5] / THESIS_ABS_CPU[5],
    ));
    energy_drift(report, cases);
}

/// Where the time of a step goes (shape integrals).
pub(super) fn time_split(report: &mut Report, cases: &[Case]) {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    report.text("### Where the time goes (shape integrals)\n");
    let mut rows = Vec::new();
    for &(_, form) in &FORMS {
        for k in 0..=5 {
            let s = &case(k, form, "shape-integrals").median;
            let steps = s.steps.max(1) as f64;
            rows.push(vec![
                form.to_string(),
                k.to_string(),
                format!("{:.1}", s.cpu_seconds / steps * 1e6),
                format!("{:.2}", s.newton_iterations as f64 / steps),
                format!("{:.2}", s.factorizations as f64 / steps),
                pct(s.time_evaluation, s.cpu_seconds),
                pct(s.time_factorization, s.cpu_seconds),
                pct(s.time_projection, s.cpu_seconds),
            ]);
        }
    }
    report.table(
        &[
            "formulation",
            "k",
            "µs / step",
            "Newton it. / step",
            "factorisations / step",
            "evaluation",
            "Newton: form, factorise, solve",
            "projections",
        ],
        &rows,
    );
    report.text(
        "Shares of the CPU time of the median run, as the integrator's counters report them (sampled \
         every 8th step and scaled, docs/design.md \"The integrator\"): `evaluation` is every call of the \
         formulation (M, Q, tangents, Φ, Φ_q, …), including the two made by the projections; \
         `projections` is the rest of the velocity and acceleration projections (one more \
         factorisation and two solves); what is left to 100 % is the integrator's own vector work. \
         Every Newton iteration re-evaluates the tangents and refactorises the leading matrix (full \
         Newton), and each step factorises once more for the projections.",
    );
}

/// The two inertia routes, and the two formulations, against each other.
pub(super) fn inertia_routes(report: &mut Report, cases: &[Case]) {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    report.text("### The two inertia routes agree\n");
    let mut rows = Vec::new();
    for &(_, form) in &FORMS {
        for k in 0..=5 {
            let (a, b) = (case(k, form, "b-matrix"), case(k, form, "shape-integrals"));
            let b0 = |c: &Case| match &c.failed {
                Some(f) => f.clone(),
                None => format!("({:.6}, {:.6})", c.b0_end().0, c.b0_end().1),
            };
            rows.push(vec![
                form.to_string(),
                k.to_string(),
                b0(a),
                b0(b),
                format!(
                    "{}{}",
                    match largest_b0_difference(&a.history, &b.history) {
                        0.0 => "0 (identical)".to_string(),
                        d => format!("{d:.1e}"),
                    },
                    if a.failed.is_some() || b.failed.is_some() {
                        " (until the failure)"
                    } else {
                        ""
                    }
                ),
            ]);
        }
    }
    report.table(
        &[
            "formulation",
            "k",
            "B0(5 s), b-matrix (m)",
            "B0(5 s), shape integrals (m)",
            "largest ‖ΔB0‖ over the run (m)",
        ],
        &rows,
    );
    let worst = FORMS
        .iter()
        .flat_map(|&(_, form)| (0..=5).map(move |k| (k, form)))
        .map(|(k, form)| {
            largest_b0_difference(
                &case(k, form, "b-matrix").history,
                &case(k, form, "shape-integrals").history,
            )
        })
        .fold(0.0, f64::max);
    let cross = |k: usize| {
        largest_b0_difference(
            &case(k, "absolute", "shape-integrals").history,
            &case(k, "relative", "shape-integrals").history,
        )
    };
    let flex_shift = {
        let (r, f) = (
            case(0, "absolute", "shape-integrals").b0_end(),
            case(5, "absolute", "shape-integrals").b0_end(),
        );
        (r.0 - f.0).hypot(r.1 - f.1)
    };
    report.text(&format!(
        "`‖ΔB0‖` is the distance between the two routes' B0 at the same instant, compared at every step. \
         Both routes act on the same mass cloud and agree to round-off at every state (docs/design.md, \
         \"One mass model for both inertia routes\"); over 5 000 steps the trajectories stay within \
         {worst:.1e} m of each other. The two formulations, which integrate different coordinates, \
         differ by at most {:.1e} m (k = 0) and {:.1e} m (k = 5) over the run. For scale: five flexible \
         bars move B0(5 s) by {flex_shift:.1e} m from the rigid run.",
        cross(0),
        cross(5),
    ));
}

/// The rigid mechanism at 10 s against the converged reference (scenes.md §1).
pub(super) fn rigid_checks(report: &mut Report, rigid: &[(&str, Rigid)]) {
    report.text("### Rigid check at 10 s\n");
    let mut rows = Vec::new();
    for (form, r) in rigid {
        rows.push(vec![
            form.to_string(),
            format!("({:.5}, {:.5})", r.b0.0, r.b0.1),
            format!("{:.1e}", r.pos_err),
            format!("{:+.1e}", r.along),
            format!("({:.5}, {:.5})", r.v0.0, r.v0.1),
            format!("{:.1e}", r.vel_err),
            format!("{:.1e}", r.drift),
        ]);
    }
    rows.push(vec![
        "reference (S3)".into(),
        format!("({:.5}, {:.5})", REF_B0_10S.0, REF_B0_10S.1),
        dash(),
        dash(),
        format!("({:.5}, {:.5})", REF_B0_VEL_10S.0, REF_B0_VEL_10S.1),
        dash(),
        "0 (no damping)".into(),
    ]);
    report.table(
        &[
            "k = 0, h = 1 ms",
            "B0(10 s) (m)",
            "position difference (m)",
            "of which along the path (m)",
            "B0 velocity (m/s)",
            "velocity difference (m/s)",
            "largest energy drift / 1.5 J",
        ],
        &rows,
    );
    report.text(
        "The reference is the converged rigid N = 2 solution at t = 10 s of scenes.md §1 \"Reference \
         values for the rigid case\" (S3: generalized-α, h down to 1.25e-4 s); it is a check of our runs, \
         not a thesis value. `along the path`: the component of the position difference along the \
         reference velocity (negative: ours lags); when it is nearly all of the difference, the \
         trapezoidal rule at h = 1 ms is a little out of phase after 10 s, not off the path. The energy \
         drift is the largest |E(t) − E(0)| over the 10 s relative to the initial kinetic energy 1.5 J \
         (scenes.md §1 \"Loads and initial conditions\").",
    );
}

/// The chart of CPU time against the number of flexible bars.
pub(super) fn cpu_chart(report: &mut Report, cases: &[Case]) -> StudyResult {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    let mut series = Vec::new();
    for (fi, &(_, form)) in FORMS.iter().enumerate() {
        for (mi, &(_, name)) in METHODS.iter().enumerate() {
            series.push(Series {
                label: format!("ours, {form}, {name}"),
                points: (0..=5)
                    .map(|k| (k as f64, case(k, form, name).cpu_median()))
                    .collect(),
                dashed: mi == 0,
                colour: fi,
            });
        }
        series.push(Series {
            label: format!("thesis, {form} (2008 hardware)"),
            points: (0..=5).map(|k| (k as f64, thesis_cpu(form)[k])).collect(),
            dashed: false,
            colour: 2 + fi,
        });
    }
    let chart = LineChart {
        title: "Double four-bar: CPU time of the 5 s run".into(),
        x_label: "flexible bars k".into(),
        y_label: "CPU time (s)".into(),
        log_x: false,
        log_y: true,
        series,
    };
    let path = report.chart_path("four_bar_cpu.svg");
    chart.write_svg(&path)?;
    report.image(
        "four_bar_cpu.svg",
        "CPU time of the 5 s run against the number of flexible bars",
    );
    report.text("Dashed: b-matrix; solid: shape integrals.");
    Ok(())
}

/// B0_x against time, rigid and flexible, and their difference.
pub(super) fn b0_charts(report: &mut Report, cases: &[Case]) -> StudyResult {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    // B0_x(t), every 20 ms (the history has every step).
    let trace = |c: &Case| -> Vec<(f64, f64)> {
        let t = c.history.column("t").unwrap_or_default();
        let x = c.history.column("B0_x").unwrap_or_default();
        t.iter()
            .zip(&x)
            .step_by(20)
            .map(|(&t, &x)| (t, x))
            .collect()
    };
    let (c0, c5) = (
        case(0, "absolute", "shape-integrals"),
        case(5, "absolute", "shape-integrals"),
    );
    let chart = LineChart {
        title: "Double four-bar: B0_x(t), rigid and five flexible bars".into(),
        x_label: "t (s)".into(),
        y_label: "B0_x (m)".into(),
        log_x: false,
        log_y: false,
        series: vec![
            Series {
                label: "k = 0 (rigid)".into(),
                points: trace(c0),
                dashed: false,
                colour: 0,
            },
            Series {
                label: "k = 5 (all bars flexible)".into(),
                points: trace(c5),
                dashed: true,
                colour: 1,
            },
        ],
    };
    let path = report.chart_path("four_bar_b0x.svg");
    chart.write_svg(&path)?;
    report.image("four_bar_b0x.svg", "B0_x against time, k = 0 and k = 5");

    // The flexible motion itself: k = 5 minus k = 0, every 2 ms over a window around
    // the first passage through the singular configuration.
    let window = |name: &str| -> Vec<(f64, f64)> {
        let t = c0.history.column("t").unwrap_or_default();
        let a = c0.history.column(name).unwrap_or_default();
        let b = c5.history.column(name).unwrap_or_default();
        (0..t.len().min(a.len()).min(b.len()))
            .step_by(2)
            .filter(|&i| (DEV_WINDOW.0..=DEV_WINDOW.1).contains(&t[i]))
            .map(|i| (t[i], (b[i] - a[i]) * 1e3))
            .collect()
    };
    let chart = LineChart {
        title: "Double four-bar: B0 of five flexible bars minus B0 rigid".into(),
        x_label: "t (s)".into(),
        y_label: "B0(k = 5) − B0(k = 0) (mm)".into(),
        log_x: false,
        log_y: false,
        series: vec![
            Series {
                label: "x".into(),
                points: window("B0_x"),
                dashed: false,
                colour: 0,
            },
            Series {
                label: "y".into(),
                points: window("B0_y"),
                dashed: true,
                colour: 1,
            },
        ],
    };
    let path = report.chart_path("four_bar_b0_flex.svg");
    chart.write_svg(&path)?;
    report.text(&format!(
        "The two B0_x curves lie on top of each other at this scale. The difference below (absolute, shape \
         integrals, every 2 ms, {:.1}–{:.1} s) shows the flexible motion: the bars' lowest modes ring \
         at a few tens of hertz on top of a slower deviation of about a millimetre, largest between the \
         cranks' lowest position (t ≈ 1.0 s) and the singular configuration (all bars horizontal, \
         B0_x = −1 m, t ≈ 1.2 s).",
        DEV_WINDOW.0, DEV_WINDOW.1
    ));
    report.image(
        "four_bar_b0_flex.svg",
        "B0 with five flexible bars minus B0 rigid, in mm",
    );
    Ok(())
}

/// The energy drift of the shape-integral runs, and why it is there.
fn energy_drift(report: &mut Report, cases: &[Case]) {
    let case = |k: usize, form: &str, name: &str| find(cases, k, form, name);
    let mut drift_lines = Vec::new();
    for &(_, form) in &FORMS {
        let (k_worst, worst_drift) = (0..=5)
            .map(|k| (k, case(k, form, "shape-integrals").energy_drift()))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let e = case(k_worst, form, "shape-integrals")
            .history
            .column("energy")
            .unwrap_or_default();
        let end_drift = (e.last().copied().unwrap_or(f64::NAN)
            - e.first().copied().unwrap_or(f64::NAN))
            / KINETIC_0;
        drift_lines.push(format!(
            "{form}: rigid {:.1e}, largest at k = {k_worst}: {worst_drift:.1e}, where \
             E(5 s) − E(0) = {end_drift:+.1e} × 1.5 J",
            case(0, form, "shape-integrals").energy_drift(),
        ));
    }
    report.text(&format!(
        "The model has no damping, so E (kinetic + gravitational + elastic) should stay at E(0). \
         Largest drift relative to the initial kinetic energy, shape integrals: {}. \
         The cause is the bars' undamped axial static modes (about 2.5 kHz, ωh ≈ 16 at h = 1 ms): \
         the trapezoidal rule keeps them bounded but not resolved, so energy moves in and out of \
         them in a step-dependent way during the fast passages (E swings by about a percent within \
         a few milliseconds as the cranks swing through their lowest position). Measured: with a \
         small stiffness-proportional damping (a_K = 2e-5 s, ζ = 0.16 at 2.5 kHz and 0.0025 at the \
         40 Hz bending mode) the runs converge at second order again (docs/design.md, relative \
         formulation, \"Known limits\").",
        drift_lines.join("; ")
    ));
}
