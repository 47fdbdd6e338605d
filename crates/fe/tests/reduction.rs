//! Craig–Bampton reduction, static modes, rigid-body motion, cloud and shape
//! integrals, K_G, determinism (docs/methods.md §1.3–§1.4, §2.3, §2.7, §6.1–§6.2, §8).

mod common;

use common::*;
use flexmbd_core::Dim;
use flexmbd_fe::assembly::{Mesh, to_dense};
use flexmbd_fe::cloud::{build_cloud, cloud_mass};
use flexmbd_fe::{
    BeamBodySpec, Damping, Dof, NodeDof, ReferenceFrame, Section, preprocess, reduce,
};
use nalgebra::{DMatrix, DVector, Vector3};

fn nd(node: usize, dof: Dof) -> NodeDof {
    NodeDof { node, dof }
}

fn max_abs(a: &DMatrix<f64>) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn tip_spec(dim: Dim, section: Section, boundary: Vec<NodeDof>, n_d: usize) -> BeamBodySpec {
    let mut s = cantilever(dim, section, 20, n_d);
    s.boundary = boundary;
    s
}

/// Solve K_ff η = Xᵀ f for a load f on the full FE model.
fn static_response(spec: &BeamBodySpec, load: &[(usize, f64)]) -> DVector<f64> {
    let p = preprocess(spec).unwrap();
    let mut f = DVector::zeros(p.mesh.n_dofs());
    for &(i, v) in load {
        f[i] = v;
    }
    let rhs = p.body.modes.transpose() * f;
    p.body.k_ff.clone().lu().solve(&rhs).unwrap()
}

#[test]
fn static_modes_reproduce_cantilever_tip_force_and_moment_2d() {
    let i = 1e-4 * 1e-4 / 12.0;
    let ei = E * i;
    let spec = tip_spec(
        Dim::Planar,
        square10(),
        vec![nd(20, Dof::Uy), nd(20, Dof::Rz)],
        3,
    );
    let n = spec.n_fe_dofs();
    let (p, mo) = (2.5, 1.5);
    let eta = static_response(&spec, &[(n - 2, p)]);
    let (d, r) = (p / (3.0 * ei), p / (2.0 * ei));
    println!(
        "tip force: v {:.12e} (exact {:.12e}), θ {:.12e} (exact {:.12e})",
        eta[0], d, eta[1], r
    );
    assert!(rel(eta[0], d) < 1e-10 && rel(eta[1], r) < 1e-10);
    assert!(
        eta.rows(2, 3).amax() < 1e-10 * eta[0].abs(),
        "normal modes not excited"
    );
    let eta = static_response(&spec, &[(n - 1, mo)]);
    assert!(rel(eta[0], mo / (2.0 * ei)) < 1e-10);
    assert!(rel(eta[1], mo / ei) < 1e-10);
}

#[test]
fn static_modes_reproduce_cantilever_tip_force_and_moment_3d() {
    let iz = 0.02 * 0.01f64.powi(3) / 12.0;
    let iy = 0.01 * 0.02f64.powi(3) / 12.0;
    let b = vec![
        nd(20, Dof::Uy),
        nd(20, Dof::Rz),
        nd(20, Dof::Uz),
        nd(20, Dof::Ry),
    ];
    let spec = tip_spec(Dim::Spatial, rect10x20(), b, 4);
    let base = 20 * 6;
    // Force along z at the tip: w = PL³/(3EI_y), θy = −w′ = −PL²/(2EI_y).
    let eta = static_response(&spec, &[(base + 2, 3.0)]);
    assert!(rel(eta[2], 3.0 / (3.0 * E * iy)) < 1e-10);
    assert!(rel(eta[3], -3.0 / (2.0 * E * iy)) < 1e-10);
    assert!(eta[0].abs() < 1e-12 * eta[2].abs() && eta[1].abs() < 1e-12 * eta[3].abs());
    // Moment about z: v = ML²/(2EI_z), θz = ML/(EI_z).
    let eta = static_response(&spec, &[(base + 5, 0.7)]);
    assert!(rel(eta[0], 0.7 / (2.0 * E * iz)) < 1e-10);
    assert!(rel(eta[1], 0.7 / (E * iz)) < 1e-10);
    // Moment about y: θy = ML/(EI_y), w = −ML²/(2EI_y).
    let eta = static_response(&spec, &[(base + 4, 0.7)]);
    assert!(rel(eta[3], 0.7 / (E * iy)) < 1e-10);
    assert!(rel(eta[2], -0.7 / (2.0 * E * iy)) < 1e-10);
}

#[test]
fn unit_tip_deflection_mode_is_the_cubic() {
    // docs/methods.md §8 item 1: (3x²L − x³)/(2L³), tip rotation free.
    let spec = tip_spec(Dim::Planar, square10(), vec![nd(20, Dof::Uy)], 0);
    let body = reduce(&spec).unwrap();
    for (k, node) in body.nodes.iter().enumerate() {
        let x = node.position.x;
        let exact = (3.0 * x * x - x * x * x) / 2.0;
        assert!((node.translation[(1, 0)] - exact).abs() < 1e-12, "node {k}");
        assert_eq!(node.translation[(0, 0)], 0.0);
    }
}

#[test]
fn craig_bampton_properties_four_bar_bar() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../models/four_bar_bar_2d.ron"
    );
    let spec = BeamBodySpec::from_file(path).unwrap();
    let p = preprocess(&spec).unwrap();
    let b = &p.body;
    assert_eq!(b.inventory.n_modes(), 4);
    assert_eq!(
        b.inventory.static_modes,
        vec![nd(10, Dof::Ux), nd(10, Dof::Uy)]
    );
    assert_eq!(b.inventory.n_fe_dofs, 33);
    println!(
        "four-bar bar: normal modes {:?} Hz, mass {}",
        b.inventory.normal_frequencies_hz,
        b.mass()
    );
    assert!((b.mass() - 1.0).abs() < 1e-4);
    // Normal modes mass-normalised.
    let mdd = b.m_ff.view((2, 2), (2, 2));
    assert!((mdd - DMatrix::identity(2, 2)).amax() < 1e-12);
    // Static–dynamic stiffness coupling vanishes.
    let ksd = b.k_ff.view((0, 2), (2, 2)).amax();
    let scale = max_abs(&b.k_ff);
    println!("static-dynamic coupling {ksd:e} against {scale:e}");
    assert!(ksd < 1e-9 * scale);
    // Ω² block.
    for j in 0..2 {
        let w = 2.0 * std::f64::consts::PI * b.inventory.normal_frequencies_hz[j];
        assert!(rel(b.k_ff[(2 + j, 2 + j)], w * w) < 1e-10);
    }
    // Boundary node rows of X are exactly [I 0]; frame rows exactly 0.
    let x = &b.modes;
    for c in 0..4 {
        assert_eq!(x[(30, c)], if c == 0 { 1.0 } else { 0.0 });
        assert_eq!(x[(31, c)], if c == 1 { 1.0 } else { 0.0 });
        for r in 0..3 {
            assert_eq!(x[(r, c)], 0.0);
        }
    }
    // v_B mode = (3x²L − x³)/(2L³) (docs/methods.md §1.4 prototype check).
    for node in &b.nodes {
        let xx = node.position.x;
        assert!((node.translation[(1, 1)] - (3.0 * xx * xx - xx.powi(3)) / 2.0).abs() < 1e-12);
    }
    // K_ff positive definite.
    let e = nalgebra::SymmetricEigen::new(b.k_ff.clone());
    assert!(e.eigenvalues.min() > 0.0);
}

#[test]
fn chord_frame_gives_pinned_pinned_modes() {
    // Chord frame r = {u_A, v_A, v_B}, b = {u_B}: fixed-interface modes pinned–pinned, 25.9 Hz (scenes.md §1).
    let mut spec = cantilever(
        Dim::Planar,
        Section::Circle {
            diameter: 0.0127357,
        },
        10,
        2,
    );
    spec.frame = ReferenceFrame::Chord { a: 0, b: 10 };
    spec.boundary = vec![nd(10, Dof::Ux)];
    let b = reduce(&spec).unwrap();
    let f = b.inventory.normal_frequencies_hz[0];
    println!("chord frame first normal mode {f} Hz");
    assert!((f - 25.9).abs() < 0.05);
    // scenes.md §1 reading: chord frame, static modes θ_A, θ_B, clamped–clamped modes 58.6, 162 Hz.
    spec.boundary = vec![nd(0, Dof::Rz), nd(10, Dof::Rz)];
    let b = reduce(&spec).unwrap();
    let f = &b.inventory.normal_frequencies_hz;
    println!("chord frame, end-rotation static modes: {f:?} Hz");
    assert!((f[0] - 58.6).abs() < 0.1 && (f[1] - 162.0).abs() < 0.5);
    // The chord keeps length L: u_B = v_B = 0 in every mode.
    assert!(b.nodes[10].translation.amax() < 1e-12);
}

fn rigid_check(spec: &BeamBodySpec) {
    spec.validate().unwrap();
    let mesh = Mesh::from_spec(spec);
    let a = mesh.assemble(mesh.default_mass_model());
    let k = to_dense(&a.k);
    let kmax = max_abs(&k);
    let cases = [
        (Vector3::new(0.3, -0.2, 0.7), Vector3::zeros()),
        (Vector3::zeros(), Vector3::new(0.0, 0.0, 0.4)),
        (Vector3::new(-1.0, 0.5, 0.2), Vector3::new(0.3, -0.6, 0.25)),
    ];
    for (t, th) in cases {
        let (t, th) = if spec.dim == Dim::Planar {
            (Vector3::new(t.x, t.y, 0.0), Vector3::new(0.0, 0.0, th.z))
        } else {
            (t, th)
        };
        let u = mesh.rigid_field(&t, &th);
        let f = &k * &u;
        let energy = 0.5 * u.dot(&f);
        let r = f.amax() / (kmax * u.amax());
        assert!(r < 1e-13, "{:?}: elastic force {r:e}", spec.geometry.points);
        assert!(energy.abs() < 1e-13 * kmax * u.norm_squared());
    }
}

#[test]
fn rigid_motion_has_no_elastic_force() {
    let poly = [
        [0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.2, 0.9, 0.0],
    ];
    let poly3 = [
        [0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.4, 0.3],
        [0.5, 0.4, 1.0],
        [1.0, -0.2, 0.1],
    ];
    rigid_check(&cantilever(Dim::Planar, square10(), 10, 0));
    rigid_check(&beam(
        Dim::Planar,
        square10(),
        &poly,
        4,
        ReferenceFrame::default(),
        vec![],
        0,
    ));
    rigid_check(&cantilever(Dim::Spatial, rect10x20(), 10, 0));
    rigid_check(&beam(
        Dim::Spatial,
        rect10x20(),
        &poly3,
        4,
        ReferenceFrame::default(),
        vec![],
        0,
    ));
}

/// Σ w XᵀX = XᵀMX with X = I (the whole FE mass), default mass model.
fn cloud_identity(spec: &BeamBodySpec) -> f64 {
    spec.validate().unwrap();
    let mesh = Mesh::from_spec(spec);
    let m = to_dense(&mesh.assemble(mesh.default_mass_model()).m);
    let x = DMatrix::identity(mesh.n_dofs(), mesh.n_dofs());
    let mc = cloud_mass(&build_cloud(&mesh, &x));
    (mc - &m).norm() / m.norm()
}

#[test]
fn mass_cloud_reproduces_fe_mass_exactly() {
    let l_shape = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.5, 0.0]];
    let l3 = [
        [0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.0, 0.5],
        [0.2, 0.3, 0.6],
    ];
    for (name, s) in [
        ("2D straight", cantilever(Dim::Planar, square10(), 8, 0)),
        (
            "2D L",
            beam(
                Dim::Planar,
                square10(),
                &l_shape,
                4,
                ReferenceFrame::default(),
                vec![],
                0,
            ),
        ),
        ("3D straight", cantilever(Dim::Spatial, rect10x20(), 8, 0)),
        (
            "3D L",
            beam(
                Dim::Spatial,
                rect10x20(),
                &l3,
                4,
                ReferenceFrame::default(),
                vec![],
                0,
            ),
        ),
    ] {
        let r = cloud_identity(&s);
        println!("{name}: |Σ w XᵀX − M| / |M| = {r:e}");
        assert!(r < 1e-14, "{name}: {r:e}");
    }
}

#[test]
fn shape_integrals_identities() {
    let l3 = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.5, 0.0]];
    let specs = [
        cantilever(Dim::Planar, square10(), 10, 4),
        cantilever(Dim::Spatial, rect10x20(), 10, 6),
        beam(
            Dim::Spatial,
            rect10x20(),
            &l3,
            5,
            ReferenceFrame::default(),
            vec![nd(10, Dof::Uz), nd(10, Dof::Rx)],
            4,
        ),
    ];
    for spec in &specs {
        let b = reduce(spec).unwrap();
        let s = &b.shape_integrals;
        let sum = &s.s_ab[0][0] + &s.s_ab[1][1] + &s.s_ab[2][2];
        let r = (&sum - &b.m_ff).norm() / b.m_ff.norm();
        assert!(r < 1e-13, "S11+S22+S33 vs M_ff: {r:e}");
        for a in 0..3 {
            for c in 0..3 {
                assert!((&s.s_ab[c][a] - s.s_ab[a][c].transpose()).amax() < 1e-15 * b.m_ff.amax());
            }
        }
        let (area, len) = match (&spec.section, spec.geometry.points.len()) {
            (Section::Rectangle { width, height }, 2) => (width * height, 1.0),
            (Section::Rectangle { width, height }, _) => (width * height, 1.0),
            _ => unreachable!(),
        };
        assert!(rel(s.mass, RHO * area * len) < 1e-14);
    }
    // Straight 3D beam along x: rigid inertia about the axis = ρ I_p L, centre of mass at L/2.
    let b = reduce(&specs[1]).unwrap();
    let p = &b.shape_integrals.second_moment;
    let ip = 0.01 * 0.02 * (0.01f64.powi(2) + 0.02f64.powi(2)) / 12.0;
    assert!(rel(p[(1, 1)] + p[(2, 2)], RHO * ip * 1.0) < 1e-12);
    let m = b.shape_integrals.mass;
    assert!(rel(b.shape_integrals.first_moment.x, 0.5 * m) < 1e-14);
    assert!(rel(p[(0, 0)], m / 3.0) < 1e-13);
}

#[test]
fn geometric_stiffness_one_element_hand_check() {
    let mut spec = cantilever(Dim::Planar, square10(), 1, 0);
    spec.boundary = vec![nd(1, Dof::Ux), nd(1, Dof::Uy), nd(1, Dof::Rz)];
    let b = reduce(&spec).unwrap();
    let kg = &b.stiffening.k_g;
    assert_eq!(kg.len(), 3);
    let (ea, l) = (E * 1e-4, 1.0);
    let c = ea / l / (30.0 * l);
    let expect = DMatrix::from_row_slice(
        3,
        3,
        &[
            0.0,
            0.0,
            0.0,
            0.0,
            36.0 * c,
            -3.0 * l * c,
            0.0,
            -3.0 * l * c,
            4.0 * l * l * c,
        ],
    );
    assert!((&kg[0] - &expect).amax() < 1e-12 * expect.amax());
    assert_eq!(kg[1], DMatrix::zeros(3, 3));
    assert_eq!(kg[2], DMatrix::zeros(3, 3));
}

#[test]
fn geometric_stiffness_symmetric_and_zero_for_bending_modes() {
    // Straight cantilever with tip static modes (axial + bending) and normal modes.
    for dim in [Dim::Planar, Dim::Spatial] {
        let bnd = match dim {
            Dim::Planar => vec![nd(10, Dof::Ux), nd(10, Dof::Uy)],
            Dim::Spatial => vec![nd(10, Dof::Ux), nd(10, Dof::Uy), nd(10, Dof::Uz)],
        };
        let mut spec = cantilever(dim, rect10x20(), 10, 4);
        spec.boundary = bnd;
        let b = reduce(&spec).unwrap();
        let kg = &b.stiffening.k_g;
        let axial = kg[0].amax();
        assert!(axial > 0.0);
        for (k, m) in kg.iter().enumerate() {
            assert_eq!(m, &m.transpose(), "K_G{k} symmetric");
            let x = b.modes.column(k);
            let axial_part: f64 = (0..x.len())
                .step_by(dim.n_rigid())
                .map(|i| x[i].abs())
                .fold(0.0, f64::max);
            if axial_part < 1e-12 {
                assert!(
                    m.amax() < 1e-10 * axial,
                    "{dim} mode {k} is bending: |K_G| = {:e}",
                    m.amax()
                );
            }
        }
        // Axial static mode: K_G0 = EA/L · (bending-mode Gram of K_σ) is positive semidefinite.
        let e = nalgebra::SymmetricEigen::new(kg[0].clone());
        assert!(e.eigenvalues.min() > -1e-9 * axial);
    }
}

#[test]
fn damping_choices() {
    let mut spec = cantilever(Dim::Planar, square10(), 10, 3);
    spec.boundary = vec![nd(10, Dof::Uy)];
    spec.damping = Damping::StiffnessProportional { a_k: 1e-4 };
    let b = reduce(&spec).unwrap();
    assert!((&b.c_ff - &b.k_ff * 1e-4).amax() < 1e-15 * b.c_ff.amax());
    spec.damping = Damping::ModalRatio {
        zeta: 0.02,
        a_k_static: 1e-4,
    };
    let b = reduce(&spec).unwrap();
    assert!(rel(b.c_ff[(0, 0)], 1e-4 * b.k_ff[(0, 0)]) < 1e-15);
    let w1 = 2.0 * std::f64::consts::PI * b.inventory.normal_frequencies_hz[0];
    assert!(rel(b.c_ff[(1, 1)], 2.0 * 0.02 * w1) < 1e-12);
    assert_eq!(b.c_ff[(0, 1)], 0.0);
}

#[test]
fn reduction_is_deterministic() {
    let l3 = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.5, 0.5, 0.2]];
    let spec = beam(
        Dim::Spatial,
        rect10x20(),
        &l3,
        6,
        ReferenceFrame::default(),
        vec![nd(12, Dof::Uy), nd(12, Dof::Rx)],
        6,
    );
    let a = reduce(&spec).unwrap();
    let b = reduce(&spec).unwrap();
    assert_eq!(a, b);
}
