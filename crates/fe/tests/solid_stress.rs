//! Stress recovery on a solid cantilever against the beam's bending-stress formula.
//!
//! A steel bar 0.2 × 0.01 × 0.01 m of 20 × 2 × 2 C3D20 bricks (`SolidBox::mesh`), reduced
//! with its root face clamped (rigid spider) and Craig–Bampton static modes of its tip face
//! (RBE3) plus 2 normal modes. A quasi-static end load P = 100 N along +z on the tip point:
//! the reduced static response q = K_ff⁻¹ X_tipᵀ P, then the nodal stress S q from the modal
//! stress shapes (`solid::stress`). At mid-span, x = L/2, the top fibre carries
//! σ_xx = −P (L − x) c / I (c = h/2, I = h⁴/12: −60 MPa; Euler–Bernoulli, Saint-Venant far
//! from both ends), shear free at the surface, so von Mises = |σ_xx|; the bottom fibre
//! +60 MPa. (The neutral axis's shear, 3P/(2A) = 1.5 MPa by beam theory, is printed but not
//! asserted: see the test.)

use flexmbd_fe::import::ImportOptions;
use flexmbd_fe::imported::{
    Coupling, ImportSource, ImportedBodySpec, ImportedFrame, InterfaceSpec, NodeSelection,
    reduce_imported,
};
use flexmbd_fe::solid::stress::{largest_principal, von_mises};
use flexmbd_fe::solid::{MassMatrix, SolidKind, body_stress_shapes, solid_model};
use flexmbd_fe::solid_box::SolidBox;
use nalgebra::{DVector, Vector3};

#[test]
fn cantilever_bending_stress_matches_the_beam_formula() {
    let (l, h, p) = (0.2, 0.01, 100.0);
    let b = SolidBox::steel([l, h, h], [20, 2, 2]);
    let mut mesh = b.mesh(SolidKind::Hex20).unwrap();
    let near = |a: f64, v: f64| (a - v).abs() < 1e-9;
    let pos = mesh.nodes.positions.clone();
    let set = |f: &dyn Fn(&Vector3<f64>) -> bool| -> Vec<usize> {
        (0..pos.len()).filter(|&n| f(&pos[n])).collect()
    };
    mesh.node_sets
        .insert("root".into(), set(&|p| near(p.x, 0.0)));
    mesh.node_sets.insert("tip".into(), set(&|p| near(p.x, l)));
    let top = set(&|p| near(p.x, l / 2.0) && near(p.z, h));
    let bottom = set(&|p| near(p.x, l / 2.0) && near(p.z, 0.0));
    let centre = set(&|p| near(p.x, l / 2.0) && near(p.z, h / 2.0) && near(p.y, h / 2.0));
    assert!(top.len() == 5 && bottom.len() == 5 && centre.len() == 1);
    let material = b.material();
    let model = solid_model(
        &mesh,
        "bar",
        &material,
        MassMatrix::Consistent,
        &ImportOptions::default(),
    )
    .unwrap();
    let interface = |name: &str, coupling| InterfaceSpec {
        name: name.into(),
        nodes: NodeSelection::Set(name.into()),
        coupling,
    };
    let spec = ImportedBodySpec {
        source: ImportSource::Solid {
            mesh: "bar.msh".into(),
            material,
            mass_matrix: MassMatrix::Consistent,
        },
        options: ImportOptions::default(),
        interfaces: vec![
            interface("root", Coupling::Rbe2),
            interface("tip", Coupling::Rbe3),
        ],
        frame: ImportedFrame::Interface("root".into()),
        reference: Default::default(),
        boundary: vec!["tip".into()],
        normal_modes: 2,
        mode_selection: Default::default(),
        mode_candidates: None,
        pilot_duration: None,
        pilot: None,
        damping: Default::default(),
    };
    let body = reduce_imported(&spec, &model, "bar").unwrap();
    let shapes =
        body_stress_shapes(&model, &material, &body.body, body.interfaces.len(), "bar").unwrap();
    // Node row 1 is the tip interface point.
    let x_tip = &body.body.nodes[1].translation;
    let f = x_tip.transpose() * Vector3::new(0.0, 0.0, p);
    let q: DVector<f64> = body.body.k_ff.clone().lu().solve(&f).unwrap();
    let beam = p * (l / 2.0) * (h / 2.0) / (h.powi(4) / 12.0);
    let stress = |n: usize| shapes.stress(n, q.as_slice());
    let max_vm = |nodes: &[usize]| {
        nodes
            .iter()
            .map(|&n| von_mises(&stress(n)))
            .fold(0.0, f64::max)
    };
    let (vm_top, vm_bottom) = (max_vm(&top), max_vm(&bottom));
    let sxx_top: Vec<f64> = top.iter().map(|&n| stress(n)[0]).collect();
    let principal_bottom = bottom
        .iter()
        .map(|&n| largest_principal(&stress(n)))
        .fold(f64::MIN, f64::max);
    let tau = stress(centre[0])[5];
    println!(
        "beam formula {beam:.6e} Pa; top sigma_xx {sxx_top:?}; max von Mises top {vm_top:.6e}, \
         bottom {vm_bottom:.6e}; bottom largest principal {principal_bottom:.6e}; \
         centre tau_zx {tau:.6e} (beam 3P/2A = {:.6e})",
        1.5 * p / (h * h)
    );
    for s in &sxx_top {
        assert!((s / -beam - 1.0).abs() < 1e-3, "{s:e}");
    }
    assert!((vm_top / beam - 1.0).abs() < 1e-3);
    assert!((vm_bottom / beam - 1.0).abs() < 1e-3);
    assert!((principal_bottom / beam - 1.0).abs() < 1e-3);
    // The shear at the neutral axis is not asserted: measured 1.95 MPa on this mesh and
    // 1.84 MPa on 20 × 4 × 4 against about 1.4–1.5 MPa (3P/2A = 1.5 MPa; the square
    // section's elasticity solution is lower at the centre, higher at the sides). At a node
    // γ_zx = ∂u_x/∂z + ∂w/∂x is the small difference of two rotations about 600 times
    // larger, each carrying its interpolation error: displacement-based shear at nodes
    // converges slowly, and the averaging recovery here does nothing about it.
    assert!(tau > 0.0);
}
