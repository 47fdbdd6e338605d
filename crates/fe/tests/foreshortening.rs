//! F(x) = ∫₀ˣ (g_v g_vᵀ + g_w g_wᵀ) dξ of FS0 (docs/methods.md §6.3) on the spin-up beam
//! (docs/scenes.md §5): at the cloud points and nodes against a dense midpoint quadrature,
//! symmetry, the root, the ordering of the cloud, and the refusal of a bent beam.

use flexmbd_core::Dim;
use flexmbd_fe::foreshortening::{dense_quadrature, foreshortening};
use flexmbd_fe::{BeamBodySpec, Preprocessed, preprocess};
use nalgebra::DMatrix;

fn beam(dim: Dim, points: &str, elements: usize, modes: usize) -> Preprocessed {
    let d = match dim {
        Dim::Planar => "Planar",
        Dim::Spatial => "Spatial",
    };
    let text = format!(
        "(dim: {d}, material: (young_modulus: 7e10, density: 3000.0, poisson_ratio: None, shear_modulus: Some(3.5e10)),
          section: General(area: 4e-4, iy: 2e-7, iz: 2e-7, torsion_j: 4e-7),
          geometry: (points: {points}, elements_per_segment: {elements}),
          frame: Clamped(node: 0), boundary: [], normal_modes: {modes})"
    );
    preprocess(&BeamBodySpec::from_ron_str(&text, "spin-up beam").unwrap()).unwrap()
}

fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

#[test]
fn f_at_cloud_points_and_nodes_matches_dense_quadrature() {
    for (dim, pts, modes) in [
        (Dim::Planar, "[[0.0, 0.0], [10.0, 0.0]]", 4),
        (Dim::Spatial, "[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]", 8),
    ] {
        let p = beam(dim, pts, 20, modes);
        let fs = foreshortening(&p.mesh, &p.body.modes).unwrap();
        let cloud = &p.body.cloud;
        assert_eq!(fs.cloud.len(), cloud.len());
        assert_eq!(fs.nodes.len(), p.mesh.nodes.len());
        assert_eq!(fs.axis, nalgebra::Vector3::x());
        assert_eq!(fs.nodes[0].amax(), 0.0);
        let mut worst = 0.0_f64;
        // Every 7th cloud point (dense quadrature is slow) and every 4th node.
        for k in (0..cloud.len()).step_by(7) {
            let x = cloud.positions[k].x;
            let dense = dense_quadrature(&p.mesh, &p.body.modes, x, 4000);
            worst = worst.max(rel(&fs.cloud[k], &dense));
            assert_eq!(fs.cloud[k], fs.cloud[k].transpose());
        }
        for (i, f) in fs.nodes.iter().enumerate().skip(1).step_by(4) {
            let dense = dense_quadrature(&p.mesh, &p.body.modes, p.mesh.nodes[i].x, 4000);
            worst = worst.max(rel(f, &dense));
        }
        eprintln!("FS0 {dim:?}: F vs dense quadrature, max relative error {worst:.2e}");
        // Midpoint rule with h = 0.5 m / 4000: error ~ h² |G''| / 24 ~ 1e-9 relative.
        assert!(worst < 1e-7, "{dim:?}: {worst}");
        // F grows monotonically along the beam (G is positive semidefinite).
        let last = fs.nodes.last().unwrap();
        for i in 0..modes {
            assert!(last[(i, i)] > fs.nodes[10][(i, i)]);
        }
        // In 3D the 4 section points of a station share F.
        if dim == Dim::Spatial {
            assert_eq!(fs.cloud[0], fs.cloud[3]);
        }
    }
}

#[test]
fn bent_beam_is_refused() {
    let p = beam(Dim::Planar, "[[0.0, 0.0], [5.0, 0.0], [5.0, 5.0]]", 4, 3);
    let e = foreshortening(&p.mesh, &p.body.modes).unwrap_err();
    assert!(e.to_string().contains("straight"), "{e}");
}
