//! The 2D spin-up beam (docs/scenes.md §5; docs/methods.md §6.5) with foreshortening, FS0
//! (docs/methods.md §6.3: 4 bending modes, no axial modes, inertia by the scene's default
//! route, shape integrals, relative formulation), against the ANCF reference of `flexmbd-ancf` (16 elements, h = 1 ms;
//! it matches the independent Exudyn reference to < 0.001 mm, docs/methods.md §7).
//!
//! Bounds, from the docs/methods.md §6.3 prototype (max over 20 s of |Δu_x| / |Δu_y|:
//! 0.515 / 2.13 mm, ~1.0 Newton iterations per step with K = K_L):
//! - |Δu_x| is the centrifugal stretch FS0 cannot show (no axial modes),
//!   Ω_s² ρA L³ / (3 EA) = 36 · 1.2 · 1000 / 8.4e7 = 0.514 mm once at full speed, so it is
//!   bounded from both sides around that figure over 20 s, and the error at t = 20 s
//!   (steady spin) is that stretch within 0.05 mm.
//! - |Δu_y| of a few mm: the prototype's 2.13 mm plus 10 %.
//! - Newton: the prototype's 1.0 iterations per step (K = K_L), below 1.1.
//!
//! Measured here: 0.515 / 2.134 mm, 1.000 Newton iterations per step, 0.4 s CPU for 20 s.

use flexmbd::model::{DriverHandling, FormulationKind, Scene, Stiffening};
use flexmbd::simulation::run;
use flexmbd_ancf::{CableSpec, History, run_spin_up};
use flexmbd_body::InertiaMethod;
use flexmbd_core::Dim;

const L: f64 = 10.0;

fn scene(duration: f64) -> Scene {
    scene_of("spin_up_beam_2d.ron", duration)
}

fn scene_of(file: &str, duration: f64) -> Scene {
    let mut scene = flexmbd_test_support::scenes::model(file);
    scene.solver.stiffening = Stiffening::Foreshortening;
    scene.solver.formulation = FormulationKind::Relative;
    scene.solver.duration = duration;
    scene
}

struct Outcome {
    label: String,
    err: [f64; 3],
    final_err: [f64; 2],
    min_ux: f64,
    newton_per_step: f64,
    cpu: f64,
    n_coordinates: usize,
}

fn fs0_against_reference(duration: f64) -> Outcome {
    fs0_run(scene(duration))
}

fn fs0_run(scene: Scene) -> Outcome {
    let duration = scene.solver.duration;
    let r: History = run_spin_up(
        &CableSpec::spin_up_beam(Dim::Planar, 16),
        1e-3,
        duration,
        0.01,
    )
    .unwrap();
    let disp = |name: &str| {
        scene
            .sensors
            .iter()
            .find(|s| s.name == name)
            .is_some_and(|s| s.displacement)
    };
    // u_x = tip_x − L unless the sensor already reports the displacement.
    let x_off = if disp("tip_x") { 0.0 } else { L };
    let (summary, h) = run(&scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    assert_eq!(summary.stiffening, "foreshortening");
    let (x, y, t) = (
        h.column("tip_x").unwrap(),
        h.column("tip_y").unwrap(),
        h.column("t").unwrap(),
    );
    assert_eq!(x.len(), r.t.len());
    let mut err = [0.0_f64; 3];
    let mut min_ux = f64::INFINITY;
    // 3D: the out-of-plane tip displacement, against the planar reference's 0.
    if let Some(z) = h.column("tip_z") {
        err[2] = z.iter().fold(0.0, |m, v| m.max(v.abs()));
    }
    for k in 0..x.len() {
        assert!((t[k] - r.t[k]).abs() < 1e-9);
        let ux = x[k] - x_off;
        assert!(ux.is_finite() && y[k].is_finite());
        min_ux = min_ux.min(ux);
        err[0] = err[0].max((ux - r.tip[k][0]).abs());
        err[1] = err[1].max((y[k] - r.tip[k][1]).abs());
    }
    let last = x.len() - 1;
    Outcome {
        label: format!("{} {:?}", summary.formulation, scene.dim),
        err,
        final_err: [
            (x[last] - x_off - r.tip[last][0]).abs(),
            (y[last] - r.tip[last][1]).abs(),
        ],
        min_ux,
        newton_per_step: summary.newton_iterations as f64 / summary.steps.max(1) as f64,
        cpu: summary.cpu_seconds,
        n_coordinates: summary.n_coordinates,
    }
}

fn report(o: &Outcome, duration: f64) -> (f64, f64) {
    let (ex, ey) = (o.err[0] * 1e3, o.err[1] * 1e3);
    eprintln!(
        "FS0 {} {duration} s: |Δu_x| {ex:.3} mm, |Δu_y| {ey:.3} mm (at the end {:.3} / \
         {:.3} mm), min u_x {:.2} mm, {:.3} Newton/step, CPU {:.2} s, {} coordinates",
        o.label,
        o.final_err[0] * 1e3,
        o.final_err[1] * 1e3,
        o.min_ux * 1e3,
        o.newton_per_step,
        o.cpu,
        o.n_coordinates
    );
    (ex, ey)
}

#[test]
fn full_20_s_fs0_errors_against_reference() {
    // The whole 20 s (reference and FS0) takes about 2 s in release.
    let o = fs0_against_reference(20.0);
    let (ex, ey) = report(&o, 20.0);
    // 4 bending modes: FS0 keeps no axial modes, and the driven hub angle is not an
    // unknown (`solver.drivers`).
    assert_eq!(o.n_coordinates, 4);
    // FS0 shows the foreshortening (the reference reaches u_x = −18.8 mm at 6.74 s;
    // FNL1, without it, is 18.9 mm off).
    assert!(o.min_ux < -0.015, "min u_x = {} m", o.min_ux);
    // The centrifugal stretch Ω_s²ρAL³/(3EA) = 0.514 mm that FS0 cannot show; the
    // final-time error (steady spin) is that stretch.
    assert!((0.45..0.6).contains(&ex), "|Δu_x| = {ex} mm");
    let fx = o.final_err[0] * 1e3;
    assert!((fx - 0.514).abs() < 0.05, "final |Δu_x| = {fx} mm");
    assert!(ey < 2.13 * 1.1, "|Δu_y| = {ey} mm");
    assert!(o.newton_per_step < 1.1, "{} Newton/step", o.newton_per_step);
}

#[test]
fn spatial_fs0_without_gravity_equals_planar() {
    // 3D, 4 + 4 bending modes and no axial modes (docs/scenes.md §5), gravity off: the motion
    // stays in the plane and matches the 2D reference as the 2D model does (the ANCF
    // 3D cable without gravity equals the 2D one, flexmbd-ancf tests).
    let mut s = scene_of("spin_up_beam_3d.ron", 20.0);
    s.gravity = flexmbd::model::V3([0.0; 3]);
    let o = fs0_run(s);
    let (ex, ey) = report(&o, 20.0);
    // 4 + 4 bending modes; the driven hub angle is not an unknown.
    assert_eq!(o.n_coordinates, 8);
    assert!(o.err[2] < 1e-9, "out of plane {} m", o.err[2]);
    assert!((0.45..0.6).contains(&ex), "|Δu_x| = {ex} mm");
    assert!(ey < 2.13 * 1.1, "|Δu_y| = {ey} mm");
    assert!(o.newton_per_step < 1.1, "{} Newton/step", o.newton_per_step);
}

/// Tip sensor histories of a run.
fn tip_history(scene: &Scene) -> Vec<Vec<f64>> {
    let (summary, h) = run(scene, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    ["tip_ux", "tip_uy", "tip_uz"]
        .iter()
        .filter_map(|c| h.column(c))
        .collect()
}

fn max_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.iter().zip(y).map(|(u, v)| (u - v).abs()))
        .fold(0.0, f64::max)
}

#[test]
fn inertia_routes_give_the_same_runs() {
    // B-matrix and shape-integral runs agree wherever both apply: the two routes agree to
    // round-off per evaluation (flexmbd-body tests/fs0_routes.rs), so whole runs differ
    // by round-off carried through Newton's stop test. 3 s of spin-up (the deflection is
    // growing), 2D and 3D (with gravity), relative and absolute.
    for (file, form) in [
        ("spin_up_beam_2d.ron", FormulationKind::Relative),
        ("spin_up_beam_2d.ron", FormulationKind::Absolute),
        ("spin_up_beam_3d.ron", FormulationKind::Relative),
        ("spin_up_beam_3d.ron", FormulationKind::Absolute),
    ] {
        let mut s = scene_of(file, 3.0);
        s.solver.formulation = form;
        s.solver.inertia = InertiaMethod::BMatrix;
        let a = tip_history(&s);
        s.solver.inertia = InertiaMethod::ShapeIntegrals;
        let b = tip_history(&s);
        let scale = a.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        let d = max_diff(&a, &b);
        eprintln!(
            "FS0 {file} {form:?}: routes differ by {d:.2e} m over 3 s (tip scale {scale:.3e} m)"
        );
        assert!(d < ROUTE_TOL, "{file} {form:?}: {d} m");
    }
}

/// Measured 1.8e-15 / 8.9e-13 m (2D relative / absolute, tip scale 0.22 m), 1.2e-14 /
/// 1.8e-15 m (3D, tip scale 1.05 m); 1e-11 m leaves a margin of 11 and is three orders
/// under what Newton's tolerance allows a step (ε_q max(1, ‖q‖∞) ≈ 1e-8 m). The bound is
/// the run's own sensitivity to round-off, not the routes': changing only the rounding of
/// the small Cholesky solves (n ≤ 12, multiplies by 1/L_jj for divisions) moves the 2D
/// absolute run by 3.1e-13 m (B-matrix) and 7.8e-13 m (shape integrals) over the 3 s, with
/// the same 3000 Newton iterations; before it, the two routes' round-off happened to
/// coincide to 1.8e-15 m. (Before the ALI3-P projections were solved in increment form,
/// their solve round-off made it 4e-12 to 1e-11 m in 3D.)
const ROUTE_TOL: f64 = 1e-11;

#[test]
fn fs0_refusals_are_clear() {
    // A joint beyond the root: the tip is a sensor point, not a joint.
    let mut s = scene(0.01);
    // A ground point where the tip is, so that the joined markers coincide at t = 0.
    let tip = s.undeformed_position("beam", "tip", None).unwrap();
    s.ground.push(flexmbd::model::Marker {
        name: "tip pin".into(),
        position: flexmbd::model::V3([tip.x, tip.y, 0.0]),
    });
    let mut j = s.joints[0].clone();
    j.name = "tip pin".into();
    j.marker1 = "tip pin".into();
    j.marker2 = "tip".into();
    j.kind = flexmbd::model::JointKind::Revolute { axis: None };
    s.joints.push(j);
    let e = run(&s, |_| {}).unwrap_err().to_string();
    assert!(e.contains("beyond the root"), "{e}");
}

#[test]
fn planar_absolute_fs0_near_reference() {
    // The same FS0 body in natural coordinates (planar route (a) with X̂_k). Measured
    // 0.515 / 2.137 mm, 1.77 Newton iterations per step.
    let mut s = scene(20.0);
    s.solver.formulation = FormulationKind::Absolute;
    let o = fs0_run(s);
    let (ex, ey) = report(&o, 20.0);
    assert!(o.min_ux < -0.015, "min u_x = {} m", o.min_ux);
    assert!((0.45..0.6).contains(&ex), "|Δu_x| = {ex} mm");
    assert!(ey < 2.13 * 1.1, "|Δu_y| = {ey} mm");
}

/// Tip displacement histories (tip_ux, tip_uy, tip_uz) of the 3D scene at step h.
fn spatial_tips(form: FormulationKind, h: f64, duration: f64) -> (Vec<Vec<f64>>, f64) {
    let mut s = scene_of("spin_up_beam_3d.ron", duration);
    s.solver.formulation = form;
    s.solver.step = h;
    // The hub's driver as a constraint row in both formulations, so that they discretise the
    // same equations in different coordinates (without the rows both have the beam's modes
    // alone, `tests/driven_coordinates.rs`).
    s.solver.drivers = DriverHandling::Constraint;
    // Newton near round-off, so the comparison sees the step error, not the stop test.
    s.solver.newton_tolerance = 1e-13;
    let (summary, hist) = run(&s, |_| {}).unwrap();
    assert_eq!(summary.status, "ok", "{:?}", summary.message);
    let t = hist.column("t").unwrap();
    // Keep the samples on the common 0.01 s grid.
    let keep: Vec<usize> = (0..t.len())
        .filter(|&k| ((t[k] / 0.01).round() * 0.01 - t[k]).abs() < 1e-9)
        .collect();
    let cols = ["tip_ux", "tip_uy", "tip_uz"]
        .iter()
        .map(|c| {
            let v = hist.column(c).unwrap();
            keep.iter().map(|&k| v[k]).collect()
        })
        .collect();
    (cols, summary.cpu_seconds)
}

#[test]
fn spatial_absolute_equals_relative() {
    // The 3D spin-up beam with gravity (docs/scenes.md §5 scene F, started at rest as the scene
    // file does), FS0, in natural and in relative coordinates. Both integrate the same
    // equations with the trapezoidal rule in different coordinates, so the tip histories
    // differ by the step error, which falls as h² (ALI3-P is second order).
    let d = 2.0;
    let mut diffs = Vec::new();
    for h in [4e-3, 2e-3, 1e-3, 5e-4] {
        let (a, ca) = spatial_tips(FormulationKind::Absolute, h, d);
        let (r, cr) = spatial_tips(FormulationKind::Relative, h, d);
        let scale = r.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        let e = max_diff(&a, &r);
        eprintln!(
            "FS0 3D with gravity, {d} s, h = {h:e}: |absolute − relative| {e:.3e} m (tip scale \
             {scale:.3} m; CPU {ca:.2} / {cr:.2} s)"
        );
        diffs.push(e);
    }
    // The tip hangs 1.05 m below the hub (tip scale): the comparison is not trivial.
    // Measured: 1.36e-8, 3.37e-9, 8.14e-10, 1.72e-10 m at h = 4, 2, 1, 0.5 ms, second order
    // all the way (ratios 4.0, 4.1, 4.7; require > 3). (Before the ALI3-P projections were
    // solved in increment form, the last halving stopped at a round-off floor of ~2.5e-10.)
    assert!(diffs.windows(2).all(|w| w[0] / w[1] > 3.0), "{diffs:?}");
    assert!(
        diffs[2] < ABS_REL_TOL && diffs[3] < ABS_REL_TOL,
        "{diffs:?}"
    );
}

/// |absolute − relative| at h ≤ 1 ms over the 2 s above: measured ≤ 2.53e-10 m, bound 1e-9 m
/// (margin 4).
const ABS_REL_TOL: f64 = 1e-9;

#[test]
fn spatial_absolute_fs0_without_gravity_equals_planar() {
    // As `spatial_fs0_without_gravity_equals_planar`, in natural coordinates.
    let mut s = scene_of("spin_up_beam_3d.ron", 20.0);
    s.gravity = flexmbd::model::V3([0.0; 3]);
    s.solver.formulation = FormulationKind::Absolute;
    let o = fs0_run(s);
    let (ex, ey) = report(&o, 20.0);
    assert!(o.err[2] < 1e-9, "out of plane {} m", o.err[2]);
    assert!((0.45..0.6).contains(&ex), "|Δu_x| = {ex} mm");
    assert!(ey < 2.13 * 1.1, "|Δu_y| = {ey} mm");
}

#[test]
fn rigidly_moving_fs0_body_stays_undeformed() {
    // A free FS0 beam (no joints, no gravity) translating and spinning about its own axis
    // moves rigidly: at y = ẏ = 0 the FS0 terms vanish and the section points' centrifugal
    // loads cancel, so no modal force arises and the beam-frame tip displacement stays 0.
    for form in [FormulationKind::Absolute, FormulationKind::Relative] {
        let mut s = scene_of("spin_up_beam_3d.ron", 1.0);
        s.gravity = flexmbd::model::V3([0.0; 3]);
        s.joints.clear();
        s.drivers.clear();
        s.sensors.retain(|x| x.name.starts_with("tip_u"));
        s.solver.formulation = form;
        // Free, unloaded: there is no static equilibrium to start from.
        s.solver.initial_state = flexmbd::model::InitialState::Given;
        s.bodies[0].velocity.linear = flexmbd::model::V3([1.0, -2.0, 0.5]);
        s.bodies[0].velocity.angular = flexmbd::model::V3([0.3, 0.0, 0.0]);
        let t = tip_history(&s);
        let worst = t.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        eprintln!("FS0 free rigid motion {form:?}: max |tip displacement| {worst:.2e} m");
        assert!(worst < 1e-12, "{form:?}: {worst} m");
    }
}
