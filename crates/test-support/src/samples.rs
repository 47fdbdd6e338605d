//! Standard bodies and states shared by the report (`xtask`) and the benchmarks,
//! so both measure exactly the same thing (feature `samples`).

use flexmbd_body::{BodyState, NaturalState};
use flexmbd_core::Dim;
use flexmbd_fe::BeamBodySpec;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// A steel cantilever, L = 1 m, clamped at x = 0, `modes` normal modes, `elements` elements
/// (2D: 10 mm square; 3D: 10 mm × 20 mm so the bending planes differ).
pub fn cantilever(dim: Dim, elements: usize, modes: usize) -> BeamBodySpec {
    let (points, section) = match dim {
        Dim::Planar => (
            "[[0.0, 0.0], [1.0, 0.0]]",
            "Rectangle(width: 0.01, height: 0.01)",
        ),
        Dim::Spatial => (
            "[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]",
            "Rectangle(width: 0.01, height: 0.02)",
        ),
    };
    let text = format!(
        "(dim: {dim:?}, material: (young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3)), \
         section: {section}, geometry: (points: {points}, elements_per_segment: {elements}), \
         frame: Clamped(node: 0), normal_modes: {modes})"
    );
    BeamBodySpec::from_ron_str(&text, "fixture cantilever").expect("the fixture's own spec parses")
}

/// A fixed, non-trivial state (deterministic).
pub struct Probe {
    y: Vec<f64>,
    yd: Vec<f64>,
    r0: Vector3<f64>,
    a: Matrix3<f64>,
    omega: Vector3<f64>,
    s_dot: Vector3<f64>,
}

impl Probe {
    /// The state used for every measurement of a body with `n` modes.
    pub fn new(dim: Dim, n: usize) -> Self {
        let y = (0..n).map(|i| 1e-3 * (1.0 + i as f64).sin()).collect();
        let yd = (0..n).map(|i| 1e-2 * (2.0 + i as f64).cos()).collect();
        match dim {
            Dim::Planar => Probe {
                y,
                yd,
                r0: Vector3::new(0.3, -0.2, 0.0),
                a: *Rotation3::from_axis_angle(&Vector3::z_axis(), 0.7).matrix(),
                omega: Vector3::new(0.0, 0.0, 1.3),
                s_dot: Vector3::new(0.4, 0.1, 0.0),
            },
            Dim::Spatial => Probe {
                y,
                yd,
                r0: Vector3::new(0.3, -0.2, 0.5),
                a: *Rotation3::from_euler_angles(0.3, -0.5, 0.9).matrix(),
                omega: Vector3::new(0.7, -1.1, 1.3),
                s_dot: Vector3::new(0.4, 0.1, -0.3),
            },
        }
    }
    /// The same state in natural coordinates (on the constraint manifold): `ṙ0 = ṡ + ω × r0`,
    /// `Ȧ = ω̃ A`.
    pub fn natural_state(&self, dim: Dim) -> NaturalState<'_> {
        let r0_dot = self.s_dot + self.omega.cross(&self.r0);
        let a_dot = self.omega.cross_matrix() * self.a;
        match dim {
            Dim::Planar => NaturalState::planar(
                self.r0.xy(),
                self.a.column(0).xy(),
                r0_dot.xy(),
                a_dot.column(0).xy(),
                &self.y,
                &self.yd,
            ),
            Dim::Spatial => NaturalState {
                r0: self.r0,
                a: self.a,
                r0_dot,
                a_dot,
                y: &self.y,
                y_dot: &self.yd,
            },
        }
    }
    /// As a body state.
    pub fn state(&self) -> BodyState<'_> {
        BodyState {
            r0: self.r0,
            a: self.a,
            omega: self.omega,
            s_dot: self.s_dot,
            y: &self.y,
            y_dot: &self.yd,
        }
    }
}

/// The imported steel bar of hex8 bricks (CalculiX export of `crates/fe/tests/data/import`,
/// 0.2 × 0.02 × 0.02 m): clamped at its root face with static modes of its tip face (RBE2
/// spiders), or free-free (`free_free`: the six rigid-body modes removed, so the Buckens
/// conditions hold), with 4 normal modes.
pub fn imported_bar(free_free: bool) -> flexmbd_fe::ReducedBody {
    use flexmbd_fe::imported::{
        Coupling, ImportSource, ImportedBodySpec, ImportedFrame, InterfaceSpec, NodeSelection, Xyz,
        import_body,
    };
    let plane = |name: &str, x: f64| InterfaceSpec {
        name: name.into(),
        nodes: NodeSelection::Plane {
            point: Xyz([x, 0.0, 0.0]),
            normal: Xyz([1.0, 0.0, 0.0]),
            tolerance: 1e-6,
        },
        coupling: Coupling::Rbe2,
    };
    let (frame, boundary) = if free_free {
        (ImportedFrame::FreeFree, vec![])
    } else {
        (ImportedFrame::Interface("root".into()), vec!["tip".into()])
    };
    let spec = ImportedBodySpec {
        source: ImportSource::Calculix {
            input: "bar_mesh.inp".into(),
            dofs: "bar_free.dof".into(),
            stiffness: "bar_free.sti".into(),
            mass: "bar_free.mas".into(),
        },
        options: Default::default(),
        interfaces: vec![plane("root", 0.0), plane("tip", 0.2)],
        frame,
        boundary,
        normal_modes: 4,
        mode_selection: Default::default(),
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        damping: Default::default(),
        reference: Default::default(),
    };
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fe/tests/data/import");
    import_body(&spec, &data, "bar")
        .expect("the fixture's own export reduces")
        .body
}
