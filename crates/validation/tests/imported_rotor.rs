//! The unbalanced rotor (issue 25 item 7(a), models/unbalanced_rotor.ron): a steel rotor of
//! C3D20 hexahedra from an Abaqus `*MATRIX GENERATE` export (models/fe/README.md), free-free
//! modes, RBE3 journals on spring–damper bearings, a 10 g rim unbalance, spinning at 50 Hz.
//!
//! - its free-free frequencies are SciPy's on the same matrices to 1e-6 (and SciPy's are
//!   CalculiX's to its 7 printed digits);
//! - the absolute and relative formulations converge to one motion at O(h²);
//! - the B-matrix and shape-integral inertia routes agree to round-off;
//! - undamped, the energy is kept;
//! - the steady whirl of the disc, the bearing forces and the gravity sag lie between two
//!   linear Jeffcott estimates that bracket the shaft's bending compliance.

mod common;
use common::*;
use flexmbd_body::InertiaMethod;
use flexmbd_model::{Axis, BodyModel, Force, InterfaceQuantity, Law, Scene, Sensor, SensorKind};
use std::f64::consts::PI;

const SCENE: &str = "unbalanced_rotor.ron";

fn col(s: &Scene, name: &str) -> usize {
    sensor_column(s, name)
}

/// The reference frequencies of models/fe/rotor_scipy_frequencies.txt or
/// rotor_ccx_frequencies.txt: the values of the lines starting with `tag` (all lines if "").
fn reference(file: &str, tag: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(models_dir().join("fe").join(file)).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && l.starts_with(tag))
        .map(|l| l.trim_start_matches(tag).trim().parse::<f64>().unwrap())
        .collect()
}

#[test]
fn rotor_frequencies_are_scipys_and_calculixs() {
    let s = model(SCENE);
    let BodyModel::Imported(spec) = &s.bodies[0].model else {
        panic!("the rotor is an imported body")
    };
    let body = flexmbd_fe::imported::import_body(spec, &models_dir(), "rotor").unwrap();
    let hz = &body.body.inventory.normal_frequencies_hz;
    // SciPy's dense eigh on K and M with the scene's 10 g at node 444: six rigid-body modes, then
    // the elastic ones.
    let scipy = reference("rotor_scipy_frequencies.txt", "unbalance");
    assert_eq!(hz.len(), 8);
    let worst = hz
        .iter()
        .zip(&scipy[6..])
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!("rotor: free-free {hz:.4?} Hz; against SciPy within {worst:.1e}");
    assert!(worst < 1e-6, "{worst:e}");
    // The export as is (no unbalance): SciPy against CalculiX's own eigen-solution, printed to
    // 7 significant digits (a relative rounding of at most 5e-7 of the first digit's unit).
    let plain = reference("rotor_scipy_frequencies.txt", "plain");
    let ccx = reference("rotor_ccx_frequencies.txt", "");
    let worst_ccx = plain[6..]
        .iter()
        .zip(&ccx[6..])
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!("rotor: SciPy against CalculiX, 14 elastic modes: {worst_ccx:.1e}");
    assert!(worst_ccx < 5e-7, "{worst_ccx:e}");
    // Mass: the exported M (14.3079 kg, generate_rotor.py) plus the unbalance.
    let mass = body.body.mass();
    assert!((mass - 14.317940330398).abs() < 1e-9, "{mass}");
    // Against the drawn solid: the disc ring π(R_d² − R_s²) T ρ, the shaft π R_s² L ρ and the
    // 10 g at e = 0.125 m; the axial inertia ½ m_ring (R_d² + R_s²) + ½ m_shaft R_s² + m_u e²
    // (about the axis; the centre of mass is 87 µm off it, 1e-7 kg·m²). The mesh's circles are
    // 8 quadratic arcs each: the mass comes out 7.8e-4 and I_x 1.5e-3 below the drawn values.
    let (r_s, r_d, t, rho) = (0.02_f64, 0.125_f64, 0.025, 7850.0);
    let m_ring = PI * (r_d * r_d - r_s * r_s) * t * rho;
    let m_shaft = PI * r_s * r_s * 0.5 * rho;
    let i_x =
        0.5 * m_ring * (r_d * r_d + r_s * r_s) + 0.5 * m_shaft * r_s * r_s + 0.01 * 0.125 * 0.125;
    let i_fe = body.body.shape_integrals.inertia_about_center_of_mass()[(0, 0)];
    let cloud = &body.body.cloud;
    eprintln!(
        "rotor: mass {mass:.6} kg (drawn {:.6}), I_x {i_fe:.6e} kg m² (drawn {i_x:.6e}); mass cloud: {} points ({})",
        m_ring + m_shaft + 0.01,
        cloud.weights.len(),
        cloud.description
    );
    assert!((mass / (m_ring + m_shaft + 0.01) - 1.0).abs() < 2e-3);
    assert!((i_fe / i_x - 1.0).abs() < 3e-3);
}

/// Over two runs' rows, of the disc centre's y and z: the largest |a − b| (m) and the largest
/// relative to the column's range in `a`.
fn disc_difference(s: &Scene, a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
    let cols = [col(s, "disc_y"), col(s, "disc_z")];
    (
        largest_difference(a, b, &cols),
        worst_difference(a, b, &cols),
    )
}

#[test]
fn rotor_formulations_converge_to_one_motion() {
    let s = model(SCENE);
    let (a, r) = (absolute(&s), relative(&s));
    // absolute: 12 frame coordinates + 8 modes (6 constraints); relative: 6 + 8.
    assert_eq!(
        (
            flexmbd_core::Formulation::n_coordinates(&a),
            flexmbd_core::Formulation::n_coordinates(&r)
        ),
        (20, 14)
    );
    let (m, d): (Vec<f64>, Vec<f64>) = [5e-4f64, 2.5e-4, 1.25e-4]
        .iter()
        .map(|&h| {
            let every = (1e-3 / h).round() as usize;
            let (x, _) = run_absolute(&s, h, 0.1, every);
            let (y, _) = run_relative(&s, h, 0.1, every);
            disc_difference(&s, &x, &y)
        })
        .unzip();
    eprintln!(
        "rotor, 0.1 s (5 revolutions): max |disc_rel − disc_abs| at h = 0.5, 0.25, 0.125 ms: {:.2e} {:.2e} {:.2e} m, {:.1e} {:.1e} {:.1e} of the range",
        m[0], m[1], m[2], d[0], d[1], d[2]
    );
    // The difference is the absolute formulation's phase error of the spin, (Ω h)²/12 of the
    // angle (its unit vectors turn on the trapezoidal rule; the relative one integrates the
    // angle itself): O(h²), ×4 per halving.
    assert!(d[0] / d[1] > 3.5 && d[1] / d[2] > 3.5, "{d:?}");
    assert!(d[2] < 2e-3, "{d:?}");
}

#[test]
fn rotor_inertia_routes_agree() {
    let mut s = model(SCENE);
    let cols = [
        col(&s, "disc_y"),
        col(&s, "disc_z"),
        col(&s, "y0"),
        col(&s, "y1"),
    ];
    let (abs_si, _) = run_absolute(&s, 2.5e-4, 0.1, 4);
    let (rel_si, _) = run_relative(&s, 2.5e-4, 0.1, 4);
    s.solver.inertia = InertiaMethod::BMatrix;
    let (abs_b, _) = run_absolute(&s, 2.5e-4, 0.1, 4);
    let (rel_b, _) = run_relative(&s, 2.5e-4, 0.1, 4);
    let da = largest_difference(&abs_si, &abs_b, &cols);
    let dr = largest_difference(&rel_si, &rel_b, &cols);
    eprintln!(
        "rotor, 0.1 s: B-matrix against shape integrals: absolute {da:.1e}, relative {dr:.1e} (m, modal coordinates); {:.1e}, {:.1e} of the ranges",
        worst_difference(&abs_si, &abs_b, &cols),
        worst_difference(&rel_si, &rel_b, &cols)
    );
    // Round-off: the whirl is 2.6e-5 m, the modal coordinates 1e-5; 400 steps of Newton
    // iterations to 1e-9 on both routes.
    assert!(da < 1e-14 && dr < 1e-14, "{da:e} {dr:e}");
}

#[test]
fn undamped_rotor_keeps_its_energy() {
    let mut s = model(SCENE);
    for force in &mut s.forces {
        if let Force::Link { damper, .. } = force {
            *damper = Law::Zero;
        }
    }
    if let BodyModel::Imported(spec) = &mut s.bodies[0].model {
        spec.damping = flexmbd_fe::Damping::None;
    }
    // Newton to 1e-12 (the scene's 1e-9 is relative to |q|, and the relative formulation's
    // spin angle grows to 63 rad in 0.2 s: at 1e-9 the energy then wanders by ~1e-4 J whatever
    // the step, which would hide the O(h²) of the integrator).
    s.solver.newton_tolerance = 1e-12;
    let e = col(&s, "energy");
    let drift = |rows: &[Vec<f64>]| {
        let e0 = rows[0][e];
        rows.iter().map(|r| (r[e] - e0).abs()).fold(0.0, f64::max)
    };
    let e0 = run_absolute(&s, 2.5e-4, 0.0, 1).0[0][e];
    for (name, coarse, fine) in [
        (
            "absolute",
            drift(&run_absolute(&s, 2.5e-4, 0.2, 4).0),
            drift(&run_absolute(&s, 1.25e-4, 0.2, 8).0),
        ),
        (
            "relative",
            drift(&run_relative(&s, 2.5e-4, 0.2, 4).0),
            drift(&run_relative(&s, 1.25e-4, 0.2, 8).0),
        ),
    ] {
        eprintln!(
            "undamped rotor, {name}, 0.2 s: E(0) = {e0:.4} J, |E − E(0)| ≤ {coarse:.1e} J ({:.1e} of E(0)) at h = 0.25 ms, {fine:.1e} J at 0.125 ms",
            coarse / e0
        );
        // E(0) is the spin's ½ I_x Ω² = 3762 J; the whirl exchanges ~ k r² ~ 3e-3 J between
        // the springs, gravity and the motion. The drift is the integrator's: it falls by
        // more than 3 when the step halves, and at the scene's step it is below 1e-6 of E(0).
        assert!(coarse < 1e-6 * e0, "{name}: {coarse:e} J");
        assert!(fine < coarse / 3.0, "{name}: {coarse:e} {fine:e} J");
    }
}

/// A linear Jeffcott estimate of the rotor's synchronous response (Rayleigh–Ritz with two
/// shapes): φ₁ = 1, the rigid rotor on the four bearing springs, and φ₂ the static
/// deflection of the shaft simply supported at the bearing centres (x = 0.025, 0.475 m) under a
/// load at the disc, 1 at the disc, with Euler–Bernoulli bending (Ø 40 mm) plus Timoshenko
/// shear (Cowper's κ = 6(1+ν)/(7+6ν) for a solid circle) as its compliance. The disc's ring
/// (beyond the shaft) is a point mass at mid-span (the whirl is cylindrical: by symmetry the
/// disc does not tilt, so neither its rotary inertia nor the gyroscopic moment enter); the
/// shaft's mass is distributed; the unbalance m_u sits at the disc. In the rotor's spinning
/// frame the synchronous whirl is static: (K − Ω² M + iΩC) q = m_u e Ω² (1, 1), the −Ω² M the
/// centrifugal softening. `rigid_hub`: the shaft under the disc (25 mm) does not bend — the
/// stiff bound; otherwise it bends as a bare shaft — the compliant bound. The FE rotor's disc
/// stiffens the shaft partly, so its response lies between the two.
/// Returns (disc whirl radius, bearing force amplitude per bearing and direction, static
/// gravity sag of the disc).
fn jeffcott(rigid_hub: bool) -> (f64, f64, f64) {
    let (e, nu, rho) = (2.1e11, 0.3, 7850.0);
    let (r_s, r_d, t, l) = (0.02, 0.125, 0.025, 0.5);
    let (k, c, mu, ecc, g) = (5e6, 500.0, 0.010, 0.125, 9.81);
    let w = 2.0 * PI * 50.0;
    let (area, i) = (PI * r_s * r_s, PI * r_s.powi(4) / 4.0);
    let m_ring = PI * (r_d * r_d - r_s * r_s) * t * rho;
    let m_shaft = rho * area * l;
    let kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
    let shear_g = e / (2.0 * (1.0 + nu));
    // φ₂ by integrating the curvature of a unit load at x = 0.25 twice (trapezoidal rule).
    let n = 50_000;
    let dx = l / n as f64;
    let x: Vec<f64> = (0..=n).map(|j| j as f64 * dx).collect();
    let bends = |xj: f64| !(rigid_hub && (xj - 0.25).abs() < t / 2.0);
    let curv: Vec<f64> = x
        .iter()
        .map(|&xj| {
            let arm = (xj - 0.025).min(0.475 - xj).max(0.0);
            if bends(xj) { 0.5 * arm / (e * i) } else { 0.0 }
        })
        .collect();
    let (mut slope, mut defl) = (vec![0.0; n + 1], vec![0.0; n + 1]);
    for j in 1..=n {
        slope[j] = slope[j - 1] + 0.5 * dx * (curv[j] + curv[j - 1]);
        defl[j] = defl[j - 1] + 0.5 * dx * (slope[j] + slope[j - 1]);
    }
    let at = |xj: f64| (xj / dx).round() as usize;
    let (a, b) = (at(0.025), at(0.475));
    let chord = |j: usize| defl[a] + (defl[b] - defl[a]) * (x[j] - x[a]) / (x[b] - x[a]);
    let bend: Vec<f64> = (0..=n).map(|j| chord(j) - defl[j]).collect();
    let delta_b = bend[at(0.25)];
    let bent_length = if rigid_hub { 0.45 - t } else { 0.45 };
    let delta_s = 0.25 * bent_length / (kappa * shear_g * area);
    let k_s = 1.0 / (delta_b + delta_s);
    let phi: Vec<f64> = bend.iter().map(|v| v / delta_b).collect();
    let (s1, s2) = (
        phi.iter().sum::<f64>() * dx,
        phi.iter().map(|p| p * p).sum::<f64>() * dx,
    );
    let m11 = m_ring + m_shaft + mu;
    let m12 = m_ring + mu + rho * area * s1;
    let m22 = m_ring + mu + rho * area * s2;
    // (K − Ω² M + iΩC) q = f, C = diag(2c, 0), K = diag(2k, k_s): a complex 2 × 2 by Cramer.
    let (a11, a12, a22) = (
        (2.0 * k - w * w * m11, 2.0 * c * w),
        (-w * w * m12, 0.0),
        (k_s - w * w * m22, 0.0),
    );
    let mul = |p: (f64, f64), q: (f64, f64)| (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0);
    let sub = |p: (f64, f64), q: (f64, f64)| (p.0 - q.0, p.1 - q.1);
    let div = |p: (f64, f64), q: (f64, f64)| {
        let d = q.0 * q.0 + q.1 * q.1;
        ((p.0 * q.0 + p.1 * q.1) / d, (p.1 * q.0 - p.0 * q.1) / d)
    };
    let f = (mu * ecc * w * w, 0.0);
    let det = sub(mul(a11, a22), mul(a12, a12));
    let q1 = div(mul(f, sub(a22, a12)), det);
    let q2 = div(mul(f, sub(a11, a12)), det);
    let disc = ((q1.0 + q2.0).powi(2) + (q1.1 + q2.1).powi(2)).sqrt();
    let bearing = (q1.0 * q1.0 + q1.1 * q1.1).sqrt() * (k * k + c * c * w * w).sqrt();
    // Gravity: K q = g (m11, m12), static.
    let sag = g * m11 / (2.0 * k) + g * m12 / k_s;
    (disc, bearing, sag)
}

/// (whirl radius: the mean distance of (y, z) from its mean; the mean z) over `rows`.
fn whirl(rows: &[Vec<f64>], cy: usize, cz: usize) -> (f64, f64, f64) {
    let n = rows.len() as f64;
    let (my, mz) = (
        rows.iter().map(|r| r[cy]).sum::<f64>() / n,
        rows.iter().map(|r| r[cz]).sum::<f64>() / n,
    );
    let radii: Vec<f64> = rows
        .iter()
        .map(|r| (r[cy] - my).hypot(r[cz] - mz))
        .collect();
    let mean = radii.iter().sum::<f64>() / n;
    let spread = radii.iter().map(|r| (r - mean).abs()).fold(0.0, f64::max);
    (mean, spread, mz)
}

#[test]
fn rotor_whirl_lies_between_the_jeffcott_bounds() {
    let s = model(SCENE);
    let (stiff, compliant) = (jeffcott(true), jeffcott(false));
    eprintln!(
        "Jeffcott, rigid hub: whirl {:.4e} m, bearing {:.3} N, sag {:.4e} m; bare shaft: {:.4e} m, {:.3} N, {:.4e} m",
        stiff.0, stiff.1, stiff.2, compliant.0, compliant.1, compliant.2
    );
    let (dy, dz) = (col(&s, "disc_y"), col(&s, "disc_z"));
    let (by, bz) = (col(&s, "bearing_l_y"), col(&s, "bearing_r_z"));
    for (name, rows) in [
        ("absolute", run_absolute(&s, 2.5e-4, 0.5, 1).0),
        ("relative", run_relative(&s, 2.5e-4, 0.5, 1).0),
    ] {
        // The last 0.1 s (5 revolutions, 400 rows): the start's transients (the cylindrical
        // bearing mode, 109.2 Hz, 2.3 % damped by `flexmbd eigen`: e^(−0.023·2π·109·0.4) ~ 2e-3)
        // have died down to the 0.25 % spread of the radius.
        let last = &rows[rows.len() - 400..];
        let (radius, spread, mean_z) = whirl(last, dy, dz);
        let amplitude = |c: usize| {
            let (lo, hi) = last.iter().fold((f64::MAX, f64::MIN), |(lo, hi), r| {
                (lo.min(r[c]), hi.max(r[c]))
            });
            0.5 * (hi - lo)
        };
        let (fy, fz) = (amplitude(by), amplitude(bz));
        eprintln!(
            "{name}: disc whirl radius {radius:.4e} m (± {spread:.1e}), sag {:.4e} m, bearing force amplitude {fy:.3} N (y, left), {fz:.3} N (z, right)",
            -mean_z
        );
        // A circular synchronous whirl (isotropic bearings, axisymmetric rotor).
        assert!(spread < 0.01 * radius, "{spread:e}");
        // Between the bounds, each widened by 1 % for what neither model holds: the modes kept
        // (8; 12 change the whirl and the sag by +0.3 %), the remaining transient (0.25 %), the
        // journals' RBE3 spreading the bearing load over 50 mm instead of a point, the
        // octagonal section of the mesh. Measured: the whirl 2.3 % above the stiff bound and
        // 5.8 % below the compliant one, the sag 1.5 % and 4.3 %, the bearing force 0.5 % and 1.1 %.
        let between = |v: f64, lo: f64, hi: f64| v > 0.99 * lo && v < 1.01 * hi;
        assert!(between(radius, stiff.0, compliant.0), "{radius:e}");
        assert!(between(-mean_z, stiff.2, compliant.2), "{mean_z:e}");
        for f in [fy, fz] {
            assert!(between(f, stiff.1, compliant.1), "{f}");
        }
    }
}

/// The `InterfaceForce` sensors at the journals (added to the scene, ground components): each
/// is the rotor's own balance — its inertia from the floating-frame equations, gravity, and
/// the other journal's springs — and must equal what the journal's own spring–dampers apply
/// (−F a of each `Link` along ground axis a), with no moment about the journal centre (the
/// links act through it). Its steady amplitude lies between the Jeffcott bounds of the
/// unbalance response.
#[test]
fn rotor_journal_interface_forces_are_the_bearings_spring_forces() {
    let mut s = model(SCENE);
    // models/unbalanced_rotor.ron reads bearing_l's force and moment; add bearing_r's.
    for n in ["bearing_r_fy", "bearing_r_fz", "bearing_r_mx"] {
        assert!(!s.sensors.iter().any(|x| x.name == n));
    }
    for (n, component, quantity) in [
        ("bearing_r_fy", Axis::Y, InterfaceQuantity::Force),
        ("bearing_r_fz", Axis::Z, InterfaceQuantity::Force),
        ("bearing_r_my", Axis::Y, InterfaceQuantity::Moment),
    ] {
        s.sensors.push(Sensor {
            name: n.into(),
            kind: SensorKind::InterfaceForce {
                body: "rotor".into(),
                marker: "bearing_r".into(),
                component,
                quantity,
                frame: None,
            },
            displacement: false,
        });
    }
    let stiff = jeffcott(true);
    let compliant = jeffcott(false);
    // The sensor reads the step's q̈, which meets the equations of motion to the Newton
    // tolerance: at the scene's 1e-9 the interface force is 1.8e-3 N (absolute) and 2.4e-3 N
    // (relative) off the springs', in the start's transient; at 1e-12, 200 and 34 times closer.
    s.solver.newton_tolerance = 1e-12;
    let c = |n: &str| col(&s, n);
    let mut results = Vec::new();
    for (name, rows) in [
        ("absolute", run_absolute(&s, 2.5e-4, 0.5, 1).0),
        ("relative", run_relative(&s, 2.5e-4, 0.5, 1).0),
    ] {
        let mut worst = 0.0f64;
        let mut worst_moment = 0.0f64;
        let mut largest = 0.0f64;
        for r in &rows {
            for (interface, spring) in [
                ("bearing_l_fy", "bearing_l_y"),
                ("bearing_l_fz", "bearing_l_z"),
                ("bearing_l_fx", "bearing_l_x"),
                ("bearing_r_fy", "bearing_r_y"),
                ("bearing_r_fz", "bearing_r_z"),
            ] {
                worst = worst.max((r[c(interface)] + r[c(spring)]).abs());
                largest = largest.max(r[c(spring)].abs());
            }
            for m in ["bearing_l_my", "bearing_l_mz", "bearing_r_my"] {
                worst_moment = worst_moment.max(r[c(m)].abs());
            }
        }
        let last = &rows[rows.len() - 400..];
        let (lo, hi) = last.iter().fold((f64::MAX, f64::MIN), |(lo, hi), r| {
            (lo.min(r[c("bearing_l_fy")]), hi.max(r[c("bearing_l_fy")]))
        });
        let amplitude = 0.5 * (hi - lo);
        eprintln!(
            "{name}: journal interface force against the springs' {worst:.3e} N (largest spring force {largest:.1} N), moment about the journal up to {worst_moment:.3e} N m; steady amplitude {amplitude:.3} N (Jeffcott {:.3} … {:.3} N)",
            stiff.1, compliant.1
        );
        results.push((name, worst, worst_moment, largest, amplitude));
    }
    for (name, worst, worst_moment, largest, amplitude) in results {
        assert!(worst < 1e-6 * largest, "{name}: {worst:e} N");
        assert!(
            worst_moment < 1e-6 * largest * 0.45,
            "{name}: {worst_moment:e} N m"
        );
        assert!(
            amplitude > 0.99 * stiff.1 && amplitude < 1.01 * compliant.1,
            "{amplitude}"
        );
    }
}
