//! Beam frames (`flexmbd_fe::frame`): named nodes and members with their own sections.
//!
//! - A polyline written as a frame of one-element members is the same FE model, bit for bit;
//!   one member of n elements has the same frequencies.
//! - A stepped cantilever (two members, two sections) deflects under a tip load as the
//!   closed form of Euler–Bernoulli theory says (Hermite elements are nodally exact).
//! - The A-arm of docs/scenes.md §2.8 (a V with a bracket from an interior node): its mass
//!   6.000 kg, centre of mass and inertia as scenes.md derives them.
//! - Bad frames are refused by field and value.

use flexmbd_core::Dim;
use flexmbd_fe::frame::{FrameNode, Member};
use flexmbd_fe::{BeamBodySpec, Dof, Material, NodeDof, Section, preprocess};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

fn steel() -> Material {
    Material {
        young_modulus: 2.1e11,
        density: 7850.0,
        poisson_ratio: Some(0.3),
        shear_modulus: None,
    }
}

fn node(name: &str, position: [f64; 3]) -> FrameNode {
    FrameNode::new(name, position)
}

fn member(from: &str, to: &str, elements: usize) -> Member {
    Member::new(from, to, elements)
}

/// A 3D frame body of steel with `section`, clamped at node 0, no modes.
fn frame(section: Section, nodes: Vec<FrameNode>, members: Vec<Member>) -> BeamBodySpec {
    BeamBodySpec::frame(Dim::Spatial, steel(), section, nodes, members)
}

fn tube() -> Section {
    // scenes.md §2.8: the A-arm's tube, OD 50 mm × 7.94 mm wall.
    Section::General {
        area: 1.0487e-3,
        iy: 2.402e-7,
        iz: 2.402e-7,
        torsion_j: 4.804e-7,
    }
}

#[test]
fn a_polyline_written_as_a_frame_is_the_same_fe_model() {
    let points = [
        [0.0, 0.0, 0.0],
        [0.4, 0.1, 0.0],
        [0.7, 0.1, 0.2],
        [1.0, 0.3, 0.2],
    ];
    let mut polyline = BeamBodySpec::straight(Dim::Spatial, steel(), tube(), 1.0, 1);
    polyline.geometry.points = points.iter().map(|p| p.to_vec()).collect();
    polyline.boundary = vec![NodeDof {
        node: 3,
        dof: Dof::Uz,
    }];
    polyline.normal_modes = 4;
    let names = ["a", "b", "c", "d"];
    let mut as_frame = frame(
        tube(),
        names.iter().zip(points).map(|(n, p)| node(n, p)).collect(),
        names.windows(2).map(|w| member(w[0], w[1], 1)).collect(),
    );
    as_frame.boundary = polyline.boundary.clone();
    as_frame.normal_modes = 4;
    polyline.validate().unwrap();
    as_frame.validate().unwrap();
    let (p, f) = (
        preprocess(&polyline).unwrap(),
        preprocess(&as_frame).unwrap(),
    );
    assert_eq!(p.mesh, f.mesh);
    assert_eq!(p.body.k_ff, f.body.k_ff);
    assert_eq!(p.body.m_ff, f.body.m_ff);
    assert_eq!(p.body.shape_integrals, f.body.shape_integrals);

    // One straight member of 8 elements against the 8-element polyline: nodes numbered
    // differently (named ends first), the same model.
    let mut straight = BeamBodySpec::straight(Dim::Spatial, steel(), tube(), 1.0, 8);
    straight.boundary = vec![NodeDof {
        node: 8,
        dof: Dof::Uz,
    }];
    straight.normal_modes = 3;
    let mut one_member = frame(
        tube(),
        vec![node("root", [0.0; 3]), node("tip", [1.0, 0.0, 0.0])],
        vec![member("root", "tip", 8)],
    );
    one_member.boundary = vec![NodeDof {
        node: 1,
        dof: Dof::Uz,
    }];
    one_member.normal_modes = 3;
    let (a, b) = (
        preprocess(&straight).unwrap(),
        preprocess(&one_member).unwrap(),
    );
    let (fa, fb) = (
        &a.body.inventory.normal_frequencies_hz,
        &b.body.inventory.normal_frequencies_hz,
    );
    for (x, y) in fa.iter().zip(fb) {
        assert!((x - y).abs() < 1e-9 * x, "{fa:?} vs {fb:?}");
    }
}

/// The full FE model's static deflection u under the nodal load `f`, with every DOF of
/// node 0 clamped: K_ff u_f = f_f on the other DOFs (no reduction).
fn static_deflection(spec: &BeamBodySpec, f: &DVector<f64>) -> DVector<f64> {
    let p = preprocess(spec).unwrap();
    let k = p.mesh.assemble(p.mesh.default_mass_model()).k.to_dense();
    let n = k.nrows();
    let free: Vec<usize> = (6..n).collect();
    let kff = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let ff = DVector::from_fn(free.len(), |i, _| f[free[i]]);
    let uf = kff.lu().solve(&ff).unwrap();
    let mut u = DVector::zeros(n);
    for (i, &d) in free.iter().enumerate() {
        u[d] = uf[i];
    }
    u
}

#[test]
fn a_stepped_cantilever_of_two_sections_deflects_as_the_closed_form() {
    // Root member 0.6 m of a 20 mm circle, tip member 0.4 m of a 12 mm circle, load P down z
    // at the tip. Junction: w1 = P a³/(3EI₁) + P b a²/(2EI₁), θ1 = P a²/(2EI₁) + P b a/EI₁;
    // tip: w = w1 + θ1 b + P b³/(3EI₂).
    let (a, b, p) = (0.6, 0.4, 250.0);
    let thin = Section::Circle { diameter: 0.012 };
    let tip_member = member("joint", "tip", 3).section(thin);
    let spec = frame(
        Section::Circle { diameter: 0.02 },
        vec![
            node("root", [0.0; 3]),
            node("tip", [a + b, 0.0, 0.0]),
            node("joint", [a, 0.0, 0.0]),
        ],
        vec![member("root", "joint", 5), tip_member],
    );
    spec.validate().unwrap();
    let n_dofs = spec.n_fe_dofs();
    let mut f = DVector::zeros(n_dofs);
    f[6 + 2] = -p; // node 1 ("tip"), Uz
    let u = static_deflection(&spec, &f);
    let e = 2.1e11;
    let i = |d: f64| std::f64::consts::PI * d.powi(4) / 64.0;
    let (ei1, ei2) = (e * i(0.02), e * i(0.012));
    let w1 = p * a.powi(3) / (3.0 * ei1) + p * b * a * a / (2.0 * ei1);
    let t1 = p * a * a / (2.0 * ei1) + p * b * a / ei1;
    let expected = -(w1 + t1 * b + p * b.powi(3) / (3.0 * ei2));
    let got = u[6 + 2];
    assert!(
        (got - expected).abs() < 1e-9 * expected.abs(),
        "tip {got:e} m, closed form {expected:e} m"
    );
    // The joint (node 2) deflects as the stiff root member alone says.
    assert!(
        (u[12 + 2] + w1).abs() < 1e-9 * w1,
        "joint {:e} vs {:e}",
        u[14],
        -w1
    );
}

/// The A-arm of scenes.md §2.8 in its own axes: origin at the ball joint B, x forward,
/// y along B → A0 (the pivot axis's midpoint), z = x × y.
fn a_arm() -> BeamBodySpec {
    // scenes.md §2.3 and §2.8 (vehicle frame V, m).
    let b = Vector3::new(0.970, 0.572, 0.229);
    let a0 = Vector3::new(0.970, 0.259, 0.302);
    let p_front = Vector3::new(0.970 + 0.108, 0.259, 0.302);
    let p_rear = Vector3::new(0.970 - 0.108, 0.259, 0.302);
    let s1 = Vector3::new(1.045, 0.500, 0.241);
    let n_s = b + (p_front - b) * 0.22665;
    let (x, y) = (Vector3::x(), (a0 - b).normalize());
    let axes = Matrix3::from_rows(&[x.transpose(), y.transpose(), x.cross(&y).transpose()]);
    let local = |p: Vector3<f64>| {
        let r = axes * (p - b);
        [r.x, r.y, r.z]
    };
    let mut spec = frame(
        tube(),
        vec![
            node("B", local(b)),
            node("P+", local(p_front)),
            node("P-", local(p_rear)),
            node("N_S", local(n_s)),
            node("S1", local(s1)),
        ],
        vec![
            member("B", "N_S", 1),
            member("N_S", "P+", 3),
            member("B", "P-", 4),
            member("N_S", "S1", 1),
        ],
    );
    spec.frame = flexmbd_fe::ReferenceFrame::Clamped {
        node: spec.frame_node("P+").unwrap(),
    };
    spec
}

#[test]
fn the_a_arm_frame_has_the_mass_properties_scenes_md_derives() {
    let spec = a_arm();
    spec.validate().unwrap();
    let p = preprocess(&spec).unwrap();
    let si = &p.body.shape_integrals;
    // scenes.md §2.8: total beam length 0.7289 m × ρA 8.232 kg/m = 6.000 kg.
    assert!((si.mass - 6.000).abs() < 5e-4, "mass {}", si.mass);
    let c = si.center_of_mass();
    // Centre of mass (0.0035, 0.1546, −0.0002) m from B, printed to 0.1 mm. scenes.md counts z
    // up from the arm plane (the bracket end S1, 4.7 mm below the arm axis, pulls the centre
    // of mass down); here z = x × y points down, hence the sign.
    for (got, want) in c.iter().zip([0.0035, 0.1546, 0.0002]) {
        assert!((got - want).abs() < 5e-5, "centre of mass {c:?}");
    }
    // Inertia about the centre of mass, arm axes: Ixx 0.0511, Iyy 0.0228, Izz 0.0738 kg·m²,
    // derived for centre-line masses. The FE body also has each tube section's own inertia,
    // ρ L [I_p d dᵀ + I (𝟙 − d dᵀ)] for a member of length L along d (I_p = 2I): 4ρI·0.7289 m
    // = 0.0055 kg·m² in the trace. Without it the diagonal is scenes.md's to its digits.
    let inertia = si.inertia_about_center_of_mass();
    let (rho, i) = (7850.0, 2.402e-7);
    let mesh = &p.mesh;
    let sections: Matrix3<f64> = mesh
        .elements
        .iter()
        .map(|el| {
            let d = (mesh.nodes[el.nodes[1]] - mesh.nodes[el.nodes[0]]) / el.length;
            let ddt = d * d.transpose();
            (ddt * (2.0 * i) + (Matrix3::identity() - ddt) * i) * (rho * el.length)
        })
        .sum();
    assert!((sections.trace() - 4.0 * rho * i * 0.7289).abs() < 1e-5);
    let centre_line = inertia - sections;
    for (k, want) in [0.0511, 0.0228, 0.0738].into_iter().enumerate() {
        let got = centre_line[(k, k)];
        assert!((got - want).abs() < 5e-5, "I{k}{k} {got} vs {want}");
    }
}

#[test]
fn bad_frames_are_refused_by_field_and_value() {
    type Spoil = Box<dyn Fn(&mut BeamBodySpec)>;
    let cases: Vec<(&str, Spoil, [&str; 2])> = vec![
        (
            "an interface node that does not exist",
            Box::new(|s| s.geometry.members[1].to = "P3".into()),
            ["geometry.members[1].to", "P3"],
        ),
        (
            "an element joining a node to itself",
            Box::new(|s| s.geometry.members[2].to = "B".into()),
            ["geometry.members[2].to", "itself"],
        ),
        (
            "a disconnected frame",
            Box::new(|s| s.geometry.members.truncate(3)),
            ["geometry.nodes[4]", "S1"],
        ),
        (
            "a name given twice",
            Box::new(|s| s.geometry.nodes[3].name = "B".into()),
            ["geometry.nodes[3].name", "already"],
        ),
        (
            "both a polyline and a frame",
            Box::new(|s| s.geometry.points = vec![vec![0.0; 3], vec![1.0, 0.0, 0.0]]),
            ["geometry.points", "not both"],
        ),
        (
            "a member's bad section",
            Box::new(|s| s.geometry.members[0].section = Some(Section::Circle { diameter: -0.01 })),
            ["geometry.members[0].section.diameter", "-0.01"],
        ),
        (
            "a member of zero elements",
            Box::new(|s| s.geometry.members[3].elements = Some(0)),
            ["geometry.members[3].elements", "0"],
        ),
        (
            "a frame node off the mesh",
            Box::new(|s| s.frame = flexmbd_fe::ReferenceFrame::Clamped { node: 99 }),
            ["frame.node", "99"],
        ),
    ];
    for (what, spoil, [field, value]) in cases {
        let mut spec = a_arm();
        spoil(&mut spec);
        let e = spec.validate().unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(value), "{what}: {e}");
    }
}

#[test]
fn a_frame_goes_through_ron_text_and_back() {
    let spec = a_arm();
    let text = ron::ser::to_string(&spec).unwrap();
    let back = BeamBodySpec::from_ron_str(&text, "a_arm.ron").unwrap();
    assert_eq!(back.geometry, spec.geometry);
    // A polyline's text has no frame fields at all.
    let straight = BeamBodySpec::straight(Dim::Planar, steel(), tube(), 1.0, 4);
    let text = ron::ser::to_string(&straight).unwrap();
    assert!(
        !text.contains("nodes") && !text.contains("members"),
        "{text}"
    );
}
