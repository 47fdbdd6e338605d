//! The scenes and runs the physics tests share (feature `scenes`): the models of `models/`,
//! the double four-bar with k flexible bars, the slider-crank with a second spring, the ALI3-P
//! settings a scene's solver asks for, a compiled formulation, a run that records the sensors,
//! all the system terms at a state, the difference of two runs' sensor columns, and the
//! checks of spring forces against the spring energy (Q = −∂V/∂q) and of their damping
//! (C = −∂Q/∂q̇).

use flexmbd_core::{CompiledScene, Formulation, Request, State, SystemTerms};
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use flexmbd_model::{
    BodyModel, Constraint, Force, FormulationKind, Inertia, JointKind, Marker, ModelError,
    PreparedScene, Scene, V3,
};
use nalgebra::DVector;

/// The double four-bar's bars, in the order `four_bar(k)` makes them flexible (scenes.md §1).
pub const FOUR_BAR_BARS: [&str; 5] = ["crank1", "coupler1", "crank2", "coupler2", "crank3"];

/// The directory of the project's models.
pub fn models_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

/// A model of `models/`, loaded and validated (panics with the loader's error otherwise).
pub fn model(file: &str) -> Scene {
    Scene::load(models_dir().join(file)).unwrap_or_else(|e| panic!("models/{file}: {e}"))
}

/// A model of `models/` in formulation `form` with the `--set` overrides `sets`.
pub fn model_with(file: &str, form: flexmbd_model::FormulationKind, sets: &[String]) -> Scene {
    let mut scene = model(file);
    scene.solver.formulation = form;
    let sets: Vec<_> = sets
        .iter()
        .map(|s| flexmbd_model::parse_set(s).unwrap_or_else(|e| panic!("{s}: {e}")))
        .collect();
    scene
        .apply_sets(&sets)
        .unwrap_or_else(|e| panic!("models/{file}: {e}"));
    scene
}

/// The double four-bar (`models/double_four_bar.ron`) with its first `flexible` bars flexible.
pub fn four_bar(flexible: usize) -> Scene {
    let mut scene = model("double_four_bar.ron");
    for body in scene
        .bodies
        .iter_mut()
        .filter(|b| FOUR_BAR_BARS[..flexible].contains(&b.name.as_str()))
    {
        body.flexible = true;
    }
    scene
}

/// The slider-crank (`models/slider_crank.ron`) with a second spring–damper, from node C of
/// the rod to the ground (so the modal columns of the spring Jacobian are exercised).
pub fn slider_crank_with_rod_spring() -> Scene {
    let mut s = model("slider_crank.ron");
    s.forces.push(Force::SpringDamper {
        name: "rod_spring".into(),
        body1: "rod".into(),
        marker1: "C".into(),
        body2: "ground".into(),
        marker2: "O".into(),
        stiffness: 40.0,
        damping: 2.0,
        free_length: Some(1.0),
    });
    s
}

/// The flexible 3D pendulum (`models/flexible_pendulum_3d.ron`) with a scene constraint of
/// each kind on its tip node: a `Distance` to a ground point, and a ground point held in the
/// plane through the tip normal to the beam's z axis (turned by the node's rotation).
pub fn flexible_pendulum_3d_with_constraints() -> Scene {
    let mut s = model("flexible_pendulum_3d.ron");
    s.ground.extend([
        Marker {
            name: "far".into(),
            position: V3([1.5, 0.5, 0.3]),
        },
        Marker {
            name: "Q".into(),
            position: V3([1.0, 0.4, 0.0]),
        },
    ]);
    s.constraints = vec![
        Constraint::Distance {
            name: "rod".into(),
            body1: "ground".into(),
            marker1: "far".into(),
            body2: "beam".into(),
            marker2: "tip".into(),
            length: None,
        },
        Constraint::PointInPlane {
            name: "plane".into(),
            body1: "beam".into(),
            marker1: "tip".into(),
            normal: V3([0.0, 0.0, 1.0]),
            body2: "ground".into(),
            marker2: "Q".into(),
        },
    ];
    s.validate().unwrap();
    s
}

/// `scene` prepared and compiled by a formulation's `compile` (panics on an error).
pub fn compiled<F>(scene: &Scene, compile: fn(&PreparedScene) -> Result<F, ModelError>) -> F {
    PreparedScene::new(scene).and_then(|p| compile(&p)).unwrap()
}

/// The column of the sensor `name` in the scene's sensor rows (panics if there is none).
pub fn sensor_column(scene: &Scene, name: &str) -> usize {
    scene
        .sensors
        .iter()
        .position(|x| x.name == name)
        .unwrap_or_else(|| panic!("{}: no sensor {name}", scene.name))
}

/// `scene` compiled by `compile` with its force elements and without them (the springs' own
/// terms are the differences of the two).
pub fn with_and_without_forces<F>(
    scene: &Scene,
    compile: fn(&PreparedScene) -> Result<F, ModelError>,
) -> (F, F) {
    let mut without = scene.clone();
    without.forces.clear();
    (compiled(scene, compile), compiled(&without, compile))
}

/// A planar scene of rigid bars and revolute joints written in 3D: revolute axes along z,
/// each body the rigid body with the planar body's mass properties (rod-like: a tiny axial
/// inertia about body x).
pub fn planar_scene_in_3d(planar: &Scene) -> Scene {
    let mut s = planar.clone();
    s.dim = flexmbd_core::Dim::Spatial;
    let prepared = PreparedScene::new(planar).unwrap();
    for (b, p) in s.bodies.iter_mut().zip(prepared.bodies()) {
        let body = &p.body;
        let (m, c) = (body.mass(), body.center_of_mass());
        let pz = body.second_moment();
        // About the centre of mass: I_zz = P_xx + P_yy − m (c_x² + c_y²).
        let izz = pz[(0, 0)] + pz[(1, 1)] - m * (c.x * c.x + c.y * c.y);
        let ixx = 1e-6 * izz;
        b.model = BodyModel::Rigid {
            mass: m,
            center_of_mass: V3([c.x, c.y, 0.0]),
            inertia: Inertia::Full([[ixx, 0.0, 0.0], [0.0, izz, 0.0], [0.0, 0.0, izz]]),
        };
        b.flexible = false;
    }
    for j in &mut s.joints {
        j.kind = JointKind::Revolute {
            axis: Some(V3([0.0, 0.0, 1.0])),
        };
    }
    s.validate().unwrap();
    s
}

/// The ALI3-P settings of a scene's solver at step `h`.
pub fn settings(scene: &Scene, h: f64) -> Ali3pSettings {
    Ali3pSettings {
        step: h,
        tol_q: scene.solver.newton_tolerance,
        tol_phi: scene.solver.newton_tolerance,
        max_iterations: scene.solver.max_iterations,
        penalty: scene.solver.penalty,
        ..Default::default()
    }
}

/// ALI3-P on `formulation` from t = 0 at step `h`, the other settings default.
pub fn ali3p_at<F: Formulation>(formulation: &mut F, h: f64) -> Ali3p {
    Ali3p::new(
        formulation,
        0.0,
        Ali3pSettings {
            step: h,
            ..Default::default()
        },
    )
    .unwrap()
}

/// The sensor rows of `formulation` at the integrator's state and every `every` steps of
/// `steps` steps; `at_row(formulation, integrator)` is called at each row after the first (to
/// track ‖Φ‖, say).
pub fn record<F: CompiledScene>(
    formulation: &mut F,
    integrator: &mut Ali3p,
    steps: usize,
    every: usize,
    mut at_row: impl FnMut(&mut F, &Ali3p),
) -> Vec<Vec<f64>> {
    let mut row = vec![0.0; formulation.sensor_names().len()];
    formulation.sensors(integrator.state(), &mut row);
    let mut rows = vec![row.clone()];
    for k in 1..=steps {
        integrator.step(formulation).unwrap();
        if k % every == 0 {
            formulation.sensors(integrator.state(), &mut row);
            rows.push(row.clone());
            at_row(formulation, integrator);
        }
    }
    rows
}

/// Run a compiled formulation for `duration` at step `h`: the sensor rows every `every`
/// steps (and at t = 0), and the largest ‖Φ‖∞ seen at those instants.
pub fn run_with<F: CompiledScene>(
    formulation: &mut F,
    scene: &Scene,
    h: f64,
    duration: f64,
    every: usize,
) -> (Vec<Vec<f64>>, f64) {
    let mut integrator = Ali3p::new(formulation, 0.0, settings(scene, h)).unwrap();
    let steps = (duration / h).round() as usize;
    let mut phi_max = 0.0f64;
    let mut terms = SystemTerms::new(formulation.n_coordinates(), formulation.n_constraints());
    let rows = record(
        formulation,
        &mut integrator,
        steps,
        every,
        |f, integrator| {
            terms.clear(Request::CONSTRAINTS);
            f.evaluate(integrator.state(), Request::CONSTRAINTS, &mut terms);
            phi_max = phi_max.max(terms.phi.amax());
        },
    );
    (rows, phi_max)
}

/// Run `scene` compiled by a formulation's `compile`: the rows and the largest ‖Φ‖∞ of
/// [`run_with`].
pub fn run_compiled<F: CompiledScene>(
    scene: &Scene,
    compile: fn(&PreparedScene) -> Result<F, ModelError>,
    h: f64,
    duration: f64,
    every: usize,
) -> (Vec<Vec<f64>>, f64) {
    run_with(&mut compiled(scene, compile), scene, h, duration, every)
}

/// Run `scene` with its formulation set to `kind`, compiled by that formulation's `compile`:
/// the rows and the largest ‖Φ‖∞ of [`run_with`].
pub fn run_as<F: CompiledScene>(
    scene: &Scene,
    kind: FormulationKind,
    compile: fn(&PreparedScene) -> Result<F, ModelError>,
    h: f64,
    duration: f64,
    every: usize,
) -> (Vec<Vec<f64>>, f64) {
    let mut s = scene.clone();
    s.solver.formulation = kind;
    run_compiled(&s, compile, h, duration, every)
}

/// Column `c` of two runs' sensor rows: (max over time of |a − b|, the range max − min of a).
pub fn column_difference(a: &[Vec<f64>], b: &[Vec<f64>], c: usize) -> (f64, f64) {
    let (lo, hi) = a
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, u), x| (l.min(x[c]), u.max(x[c])));
    let d = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x[c] - y[c]).abs())
        .fold(0.0, f64::max);
    (d, hi - lo)
}

/// The largest [`column_difference`] relative to the range over the columns `cols`.
pub fn worst_difference(a: &[Vec<f64>], b: &[Vec<f64>], cols: &[usize]) -> f64 {
    let mut worst = 0.0f64;
    for &c in cols {
        let (d, range) = column_difference(a, b, c);
        worst = worst.max(d / range);
    }
    worst
}

/// All the system terms of `f` at (t, q, q̇), into fresh storage.
pub fn terms_at(
    f: &mut impl Formulation,
    t: f64,
    q: &DVector<f64>,
    qd: &DVector<f64>,
) -> SystemTerms {
    let mut terms = SystemTerms::new(f.n_coordinates(), f.n_constraints());
    terms.clear(Request::ALL);
    f.evaluate(State::new(t, q, qd), Request::ALL, &mut terms);
    terms
}

/// The spring–dampers' forces at (q, 0) against their energy: `with` and `without` are a scene
/// compiled with and without its force elements ([`with_and_without_forces`]), the energy is
/// its sensor in column `energy_column`. Returns max over j of |Q_j + ∂V/∂q_j| (∂V/∂q_j by
/// central differences of step `eps(j)`) and |Q|∞, Q the springs' forces (the difference of
/// the two formulations' forces, as V is of their energies).
pub fn spring_gradient_error<F: CompiledScene>(
    with: &mut F,
    without: &mut F,
    energy_column: usize,
    q: &DVector<f64>,
    eps: impl Fn(usize) -> f64,
) -> (f64, f64) {
    let n = q.len();
    let zero = DVector::zeros(n);
    let q_spring = terms_at(with, 0.0, q, &zero).forces - terms_at(without, 0.0, q, &zero).forces;
    let energy = |f: &mut F, q: &DVector<f64>| {
        let mut out = vec![0.0; f.sensor_names().len()];
        f.sensors(State::new(0.0, q, &zero), &mut out);
        out[energy_column]
    };
    let err = energy_gradient_error(
        n,
        eps,
        |j| q_spring[j],
        |j, e| {
            let mut qe = q.clone();
            qe[j] += e;
            (energy(with, &qe), energy(without, &qe))
        },
    );
    (err, q_spring.amax())
}

/// max over i, j of |C_ij − (−∂Q_i/∂q̇_j)| of the spring–dampers at (q, q̇), `with` and
/// `without` as in [`spring_gradient_error`] (Q is linear in q̇, so a unit step is exact).
pub fn spring_damping_error(
    with: &mut impl Formulation,
    without: &mut impl Formulation,
    q: &DVector<f64>,
    qd: &DVector<f64>,
) -> f64 {
    damping_error(q.len(), |j| {
        let mut qd_step = qd.clone();
        if let Some(j) = j {
            qd_step[j] += 1.0;
        }
        (
            terms_at(with, 0.0, q, &qd_step),
            terms_at(without, 0.0, q, &qd_step),
        )
    })
}

/// max over j of |Q_j + ∂V/∂q_j| for the spring forces `q_spring(j)`, with ∂V/∂q_j the central
/// difference of step `eps(j)` of the spring energy: `energies(j, e)` is the energy with and
/// without the springs at q + e·e_j, and V the difference of the two.
fn energy_gradient_error(
    n: usize,
    eps: impl Fn(usize) -> f64,
    q_spring: impl Fn(usize) -> f64,
    mut energies: impl FnMut(usize, f64) -> (f64, f64),
) -> f64 {
    let mut err = 0.0f64;
    for j in 0..n {
        let eps = eps(j);
        let (with_p, without_p) = energies(j, eps);
        let (with_m, without_m) = energies(j, -eps);
        let dv = (with_p - without_p - with_m + without_m) / (2.0 * eps);
        err = err.max((q_spring(j) + dv).abs());
    }
    err
}

/// max over i, j of |C_ij − (−∂Q_i/∂q̇_j)| for the springs (Q is linear in q̇, so a unit step
/// is exact): `terms(None)` are the terms with and without the springs at (q, q̇), `terms(Some(j))`
/// those at (q, q̇ + e_j); Q and C of the springs are the differences of the two.
fn damping_error(
    n: usize,
    mut terms: impl FnMut(Option<usize>) -> (SystemTerms, SystemTerms),
) -> f64 {
    let (ta, tb) = terms(None);
    let mut err = 0.0f64;
    for j in 0..n {
        let (pa, pb) = terms(Some(j));
        for i in 0..n {
            let fd = -((pa.forces[i] - pb.forces[i]) - (ta.forces[i] - tb.forces[i]));
            let c = ta.damping[(i, j)] - tb.damping[(i, j)];
            err = err.max((fd - c).abs());
        }
    }
    err
}

/// The largest |a − b| over time and the columns `cols` of two runs' sensor rows.
pub fn largest_difference(a: &[Vec<f64>], b: &[Vec<f64>], cols: &[usize]) -> f64 {
    cols.iter()
        .map(|&c| column_difference(a, b, c).0)
        .fold(0.0, f64::max)
}

/// The largest |x − x(0)| over time of column `c` of a run's sensor rows (an energy's drift).
pub fn drift(rows: &[Vec<f64>], c: usize) -> f64 {
    let x0 = rows[0][c];
    rows.iter().map(|r| (r[c] - x0).abs()).fold(0.0, f64::max)
}

/// The energy drift of a run of the flexible pendulum (`models/flexible_pendulum.ron`, the
/// energy in column 5): in J, and relative to the potential energy released from
/// horizontal, m g L / 2.
pub fn flexible_pendulum_energy_drift(rows: &[Vec<f64>]) -> (f64, f64) {
    let drift = drift(rows, 5);
    let scale = 1.0 * 9.81 * 0.5;
    (drift, drift / scale)
}

/// A vehicle corner in the scene syntax of issue 13: two free bodies, a chassis and a wheel
/// carrier, joined by a strut (polynomial spring, piecewise damper) and a leaf element along
/// the chassis z axis, the carrier on a tyre on a cosine bump and one on a stepped table road,
/// with angle and element-force sensors.
pub const VEHICLE_CORNER: &str = r#"(
    name: "corner", dim: Spatial, gravity: [0.0, 0.0, -9.81],
    bodies: [
        (name: "chassis", origin: [0.0, 0.0, 0.6],
         model: Rigid(mass: 300.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([50.0, 200.0, 220.0])),
         markers: [(name: "S0_fl", position: [0.1, 0.5, 0.2]), (name: "E_fl", position: [0.0, 0.6, 0.137])]),
        (name: "carrier_fl", origin: [0.0, 0.7, 0.356],
         model: Rigid(mass: 57.35, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([1.0, 2.0, 1.0])),
         markers: [(name: "S1_fl", position: [0.05, -0.1, -0.15]), (name: "U_fl", position: [0.0, -0.1, 0.2]),
                   (name: "W_fl", position: [0.0, 0.0, 0.0])]),
    ],
    joints: [
        (name: "float", kind: Free, body1: "ground", marker1: "O", body2: "chassis", marker2: "S0_fl"),
        (name: "float_carrier", kind: Free, body1: "ground", marker1: "W", body2: "carrier_fl", marker2: "W_fl"),
    ],
    ground: [(name: "O", position: [0.1, 0.5, 0.8]), (name: "W", position: [0.0, 0.7, 0.356])],
    forces: [
        Link(name: "strut_fl", body1: "chassis", marker1: "S0_fl", body2: "carrier_fl", marker2: "S1_fl",
             spring: Polynomial(coefficients: [-4.0092e6, 2.8397e7, -6.7061e7, 5.2796e7]),
             damper: Piecewise(breakpoints: [-0.20, 0.21], pieces: [Polynomial(coefficients: [-416.42, 1844.3]), Polynomial(coefficients: [0.0, 9945.627, 33955.72, -59832.25, -395651.0]), Polynomial(coefficients: [1919.1638, 1634.727])]),
             axis: None),
        Link(name: "leaf_fl", body1: "chassis", marker1: "E_fl", body2: "carrier_fl", marker2: "U_fl",
             spring: Piecewise(breakpoints: [0.106], pieces: [Polynomial(about: 0.106, coefficients: [-5242.276, 1.0e7]), Polynomial(about: 0.1, coefficients: [-5457.712, 35906.0])]),
             damper: Zero,
             axis: Some((0.0, 0.0, -1.0))),
        Tyre(name: "tyre_fl", body: "carrier_fl", marker: "W_fl", road: "left", radius: 0.364325, stiffness: 460000.0, contact: Vertical, lateral_damping: 0.0),
        Tyre(name: "tyre_bump", body: "carrier_fl", marker: "W_fl", road: "ramp", radius: 0.364325, stiffness: 460000.0, contact: ProfileNormal),
    ],
    roads: [
        Road(name: "left", profile: CosineBump(start: 0.97, length: 5.0, height: 0.2)),
        Road(name: "flat", profile: Flat),
        Road(name: "ramp", profile: Table(x: [0.0, 3.0, 4.0, 10.0, 10.0, 20.0, 20.0], z: [0.0, 0.0, 0.1, 0.1, 0.0, 0.0, -0.1])),
    ],
    sensors: [
        Sensor(name: "chassis_pitch", kind: Angle(body: "chassis", axis: Y)),
        Sensor(name: "tyre_fl", kind: ElementForce(force: "tyre_fl")),
        Sensor(name: "strut_fl", kind: ElementForce(force: "strut_fl")),
    ],
    solver: (step: 1e-3, duration: 0.01),
)"#;

/// A planar rigid bar of 2 kg pinned at one end, hanging straight down: centre of mass 0.6 m
/// below the pin, J_G = 0.24 kg·m², the tip 1.2 m below; sensors `tip_x`, `tip_y`.
pub const HANGING_PENDULUM: &str = r#"(
    name: "pendulum", dim: Planar, gravity: [0.0, -9.81],
    ground: [(name: "O", position: [0.0, 0.0])],
    bodies: [(name: "bar", origin: [0.0, 0.0], orientation: Angle(-1.5707963267948966),
        model: Rigid(mass: 2.0, center_of_mass: [0.6, 0.0], inertia: Planar(0.24)),
        markers: [(name: "O", position: [0.0, 0.0]), (name: "tip", position: [1.2, 0.0])])],
    joints: [(name: "pin", kind: Revolute(), body1: "ground", marker1: "O", body2: "bar", marker2: "O")],
    sensors: [(name: "tip_x", kind: Position(body: "bar", marker: "tip", component: X)),
              (name: "tip_y", kind: Position(body: "bar", marker: "tip", component: Y))],
    solver: (step: 1e-3, duration: 1.0),
)"#;
