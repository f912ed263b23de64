//! The hot loops allocate nothing: finger closing and capsule queries, checked with a counting
//! global allocator.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use prehensile_core::finger_closing::{close_fingers, ClosingParams};
use prehensile_core::Workspace;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn finger_closing_allocates_nothing() {
    let hand = common::hand("human");
    let object = common::object("mug");
    let mut ws = Workspace::new(&hand);
    let root = common::free_root(&hand, &object, "power", &mut ws);
    let movement = hand.movement("power").unwrap();
    let params = ClosingParams::default();
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for _ in 0..10 {
        close_fingers(&hand, &object, movement, &root, &params, &mut ws);
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert!(ws.counters.queries > 0);
    assert_eq!(
        after - before,
        0,
        "finger closing allocated {} times",
        after - before
    );
}
