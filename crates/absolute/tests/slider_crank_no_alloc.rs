//! The step loop of the flexible slider-crank (prismatic joint, spring–damper, state-dependent
//! tangents) allocates nothing after set-up, with both inertia routes (counting allocator).

// A counting global allocator is an `unsafe impl GlobalAlloc`; it only forwards to `System`.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use flexmbd_body::InertiaMethod;
use flexmbd_integrators::{Ali3p, Ali3pSettings};
use flexmbd_model::Scene;

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
fn slider_crank_steps_allocate_nothing() {
    for method in [InertiaMethod::ShapeIntegrals, InertiaMethod::BMatrix] {
        let mut scene = Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../models/slider_crank.ron"
        ))
        .unwrap();
        scene.bodies[0].flexible = true;
        scene.solver.inertia = method;
        let mut f = flexmbd_absolute::compile(&scene).unwrap();
        let mut s = Ali3p::new(&mut f, 0.0, Ali3pSettings::default()).unwrap();
        s.step(&mut f).unwrap();
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for _ in 0..300 {
            s.step(&mut f).unwrap();
        }
        let allocated = ALLOCATIONS.load(Ordering::SeqCst) - before;
        assert_eq!(
            allocated, 0,
            "{method:?}: the step loop allocated {allocated} times"
        );
    }
}
