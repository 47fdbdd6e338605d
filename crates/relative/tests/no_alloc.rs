//! The per-step path (evaluation passes and the ALI3-P step) allocates nothing
//! (counting global allocator).

// A counting global allocator is an `unsafe impl GlobalAlloc`; it only forwards to `System`.
#![allow(unsafe_code)]

mod common;
use common::*;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use flexmbd_core::{Formulation, Request, SystemTerms};
use flexmbd_integrators::Ali3p;
use nalgebra::DVector;

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
fn steps_and_evaluations_do_not_allocate() {
    let mut scenes = vec![four_bar(0), four_bar(5), model("flexible_pendulum.ron")];
    for extra in ["double_pendulum_3d.ron", "flexible_pendulum_3d.ron"] {
        if std::path::Path::new(&format!(
            "{}/../../models/{extra}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .exists()
        {
            scenes.push(model(extra));
        }
    }
    for scene in scenes {
        let mut f = flexmbd_relative::compile(&scene).unwrap();
        let (n, m) = (f.n_coordinates(), f.n_constraints());
        let mut s = Ali3p::new(&mut f, 0.0, settings(&scene, 1e-3)).unwrap();
        s.step(&mut f).unwrap();
        let mut terms = SystemTerms::new(n, m);
        let (q, qd) = (
            DVector::from_element(n, 0.01),
            DVector::from_element(n, 0.2),
        );
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        for _ in 0..50 {
            s.step(&mut f).unwrap();
        }
        terms.clear(Request::ALL);
        f.evaluate(0.1, &q, &qd, Request::ALL, &mut terms);
        let count = ALLOCATIONS.load(Ordering::SeqCst) - before;
        assert_eq!(count, 0, "{}: {count} allocations in 50 steps", scene.name);
    }
}
