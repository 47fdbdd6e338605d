//! The ALI3-P step loop on the cable allocates nothing after set-up, sensors included
//! (counting global allocator).

// A counting global allocator is an `unsafe impl GlobalAlloc`; it only forwards to `System`.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use flexmbd_ancf::{Cable, CableSpec};
use flexmbd_core::{Dim, Formulation};
use flexmbd_integrators::{Ali3p, Ali3pSettings};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

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
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for _ in 0..300 {
            s.step(&mut cable).unwrap();
            cable.sensors(s.t, &s.q, &s.qd, &mut out);
        }
        let after = ALLOCATIONS.load(Ordering::SeqCst);
        assert_eq!(after - before, 0, "{dim}: {} allocations", after - before);
        assert!(s.stats.newton_iterations >= 300 && out.iter().all(|v| v.is_finite()));
    }
}
