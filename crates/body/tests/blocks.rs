//! `FlexibleBody::inertia_blocks` holds the same bits as `inertia`'s dense M̄ and Q̄_v, block
//! by block, for every kernel (both routes, both dimensions, linear and FS0, truncated terms).

mod common;
use common::*;
use flexmbd_body::{Dim, FlexibleBody, InertiaMethod, InertiaTerms, ReducedBody};

/// The spatial entry of each rigid row of the body's layout.
fn entries(dim: Dim) -> &'static [usize] {
    match dim {
        Dim::Spatial => &[0, 1, 2, 3, 4, 5],
        Dim::Planar => &[0, 1, 5],
    }
}

fn check(name: &str, dim: Dim, rb: &ReducedBody, terms: Option<InertiaTerms>, seed: u64) {
    let mut body = FlexibleBody::new(rb).unwrap();
    if let Some(t) = terms {
        body.set_inertia_terms(t, "test").unwrap();
    }
    let n = body.n_modes();
    let e = entries(dim);
    let rs = e.len();
    let mut r = rng(seed);
    let mut blocks = body.relative_blocks();
    for method in [InertiaMethod::BMatrix, InertiaMethod::ShapeIntegrals] {
        if method == InertiaMethod::BMatrix && terms.is_some() {
            continue;
        }
        for _ in 0..4 {
            let st = random_state(&mut r, dim, n);
            let (m, q) = eval(&mut body, &st.view(), method);
            body.inertia_blocks(&st.view(), method, &mut blocks);
            let what = format!("{name} {method:?}");
            for (i, &ei) in e.iter().enumerate() {
                assert_eq!(blocks.rigid_force[ei], q[i], "{what}: Q̄ rigid {ei}");
                for (j, &ej) in e.iter().enumerate() {
                    assert_eq!(blocks.rigid[(ei, ej)], m[(i, j)], "{what}: M̄ ({ei}, {ej})");
                }
                for k in 0..n {
                    assert_eq!(blocks.coupling[k][ei], m[(i, rs + k)], "{what}: M̄_ry");
                    assert_eq!(blocks.coupling[k][ei], m[(rs + k, i)], "{what}: M̄_yr");
                }
            }
            for k in 0..n {
                assert_eq!(blocks.modal_force[k], q[rs + k], "{what}: Q̄_y {k}");
                for l in 0..n {
                    let v = blocks.modal_mass[k * n + l];
                    assert_eq!(v, m[(rs + k, rs + l)], "{what}: M̄_yy ({k}, {l})");
                }
            }
            // The entries a planar body does not keep stay zero.
            for i in (0..6).filter(|i| !e.contains(i)) {
                assert_eq!(blocks.rigid.row(i).amax(), 0.0, "{what}: row {i}");
                assert_eq!(blocks.rigid_force[i], 0.0, "{what}: force {i}");
                assert!(
                    blocks.coupling.iter().all(|u| u[i] == 0.0),
                    "{what}: coupling {i}"
                );
            }
        }
    }
}

#[test]
fn blocks_hold_the_dense_terms_bit_for_bit() {
    let truncated = InertiaTerms {
        order: 1,
        velocity: false,
        coupling: true,
    };
    for dim in [Dim::Spatial, Dim::Planar] {
        for (seed, (name, rb)) in beams(dim).into_iter().enumerate() {
            check(name, dim, &rb, None, seed as u64);
            check(name, dim, &rb, Some(truncated), 10 + seed as u64);
        }
        let (fs, _) = spin_up_body(dim, 4, 3);
        check("FS0 spin-up", dim, &fs, None, 20);
        check(
            "rigid",
            dim,
            &random_body(&mut rng(30), dim, 0, 9),
            None,
            30,
        );
    }
}
