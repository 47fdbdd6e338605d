//! The ALI3-P step loop on the cable allocates nothing after set-up, sensors included
//! (counting global allocator).

use flexmbd_ancf::{Cable, CableSpec};
use flexmbd_core::{Dim, Observe};
use flexmbd_integrators::{Ali3p, Ali3pSettings};

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn steps_allocate_nothing() {
    for dim in [Dim::Planar, Dim::Spatial] {
        let mut cable = Cable::new(&CableSpec {
            t_s: 0.5,
            ..CableSpec::spin_up_beam(dim, 6)
        })
        .unwrap();
        if dim == Dim::Spatial {
            cable.solve_static(0.0, 10).unwrap();
        }
        let mut s = Ali3p::new(
            &mut cable,
            0.0,
            Ali3pSettings {
                step: 1e-3,
                ..Default::default()
            },
        )
        .unwrap();
        let mut out = vec![0.0; cable.sensor_names().len()];
        s.step(&mut cable).unwrap();
        let before = flexmbd_test_support::allocations();
        for _ in 0..300 {
            s.step(&mut cable).unwrap();
            cable.sensors(s.state(), &mut out);
        }
        let after = flexmbd_test_support::allocations();
        assert_eq!(after - before, 0, "{dim}: {} allocations", after - before);
        assert!(s.stats.newton_iterations >= 300 && out.iter().all(|v| v.is_finite()));
    }
}
