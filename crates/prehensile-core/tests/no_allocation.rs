//! The hot loops allocate nothing: finger closing and capsule queries, checked with a counting
//! global allocator.

mod common;

use prehensile_core::finger_closing::{close_fingers, ClosingParams};
use prehensile_core::Workspace;
use prehensile_testkit::allocation_count::{allocations_on_this_thread, CountingAllocator};

#[global_allocator]
static COUNT: CountingAllocator = CountingAllocator;

#[test]
fn finger_closing_allocates_nothing() {
    let hand = common::hand("human");
    let object = common::object("mug");
    let mut ws = Workspace::new(&hand);
    let root = common::free_root(&hand, &object, "power", &mut ws);
    let movement = hand.movement("power").unwrap();
    let params = ClosingParams::default();
    let before = allocations_on_this_thread();
    for _ in 0..10 {
        close_fingers(&hand, &object, movement, &root, &params, &mut ws);
    }
    let after = allocations_on_this_thread();
    assert!(ws.counters.queries > 0);
    assert_eq!(
        after - before,
        0,
        "finger closing allocated {} times",
        after - before
    );
}
