//! Test support shared by the flexmbd crates: the standard sample bodies and states of the
//! benchmarks and the report (`samples`, behind the feature of that name), the scenes and runs
//! of the physics tests (`scenes`, likewise), the Iltis bump at another speed (`iltis`), and a global allocator that counts the
//! allocations of each thread, for the tests that hold "the per-step path allocates
//! nothing". A test binary installs it with
//!
//! ```ignore
//! #[global_allocator]
//! static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;
//! ```
//!
//! and compares [`allocations`] before and after the code under test, or counts those of a
//! closure with [`allocations_in`]. Counting per thread
//! keeps tests that run in parallel in one binary from seeing each other's allocations.

#![warn(missing_docs)]
// `GlobalAlloc` is an unsafe trait; this implementation only counts and forwards to `System`.
#![allow(unsafe_code)]

pub mod iltis;
#[cfg(feature = "samples")]
pub mod samples;
#[cfg(feature = "scenes")]
pub mod scenes;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

fn bump() {
    // `try_with`: allocations during thread teardown, after the counter is gone, are not counted.
    let _ = COUNT.try_with(|c| c.set(c.get() + 1));
}

/// The system allocator, counting allocations and reallocations per thread.
pub struct CountingAllocator;

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Allocations (and reallocations) made by the current thread so far.
pub fn allocations() -> usize {
    COUNT.with(|c| c.get())
}

/// The allocations (and reallocations) the current thread makes while running `code`.
pub fn allocations_in(code: impl FnOnce()) -> usize {
    let before = allocations();
    code();
    allocations() - before
}
