//! The counting allocator sees an allocation (so a no-allocation test can fail).

#[global_allocator]
static GLOBAL: flexmbd_test_support::CountingAllocator = flexmbd_test_support::CountingAllocator;

#[test]
fn an_allocation_is_counted_and_a_copy_is_not() {
    let before = flexmbd_test_support::allocations();
    let v: Vec<f64> = Vec::with_capacity(16);
    let after = flexmbd_test_support::allocations();
    assert!(
        after > before,
        "the allocation of {} slots was not counted",
        v.capacity()
    );
    let mut w = [0.0f64; 16];
    let before = flexmbd_test_support::allocations();
    w.copy_from_slice(&[1.0; 16]);
    assert_eq!(flexmbd_test_support::allocations(), before);
    std::hint::black_box(&w);
}
