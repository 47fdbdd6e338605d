//! What each elastic model lets the integrator assume of the tangents, in every formulation
//! (`Formulation::constant_tangents`, `symmetric_tangent`, from `flexmbd_body::ElasticTangents`):
//! linear elasticity has constant, symmetric K and C; FNL2's tangents turn with the state but
//! stay symmetric; FNL1's stiffness tangent is neither constant nor symmetric.

mod common;
use common::*;
use flexmbd_core::Formulation;
use flexmbd_model::Stiffening;

#[test]
fn constant_and_symmetric_tangents_follow_the_elastic_model() {
    for file in ["spin_up_beam_2d.ron", "spin_up_beam_3d.ron"] {
        for (stiffening, constant, symmetric) in [
            (Stiffening::Linear, true, true),
            (Stiffening::Fnl2, false, true),
            (Stiffening::Fnl1, false, false),
        ] {
            let mut scene = model(file);
            scene.solver.stiffening = stiffening;
            let (a, r) = (absolute(&scene), relative(&scene));
            let flags = |f: &dyn Formulation| (f.constant_tangents(), f.symmetric_tangent());
            let expected = (constant, symmetric);
            assert_eq!(flags(&a), expected, "{file} {stiffening:?} absolute");
            assert_eq!(flags(&r), expected, "{file} {stiffening:?} relative");
        }
    }
}
