//! A global allocator that counts allocations, for the tests that keep hot loops from
//! allocating (here and in the crates above): a test binary installs it with
//! `#[global_allocator] static COUNT: CountingAllocator = CountingAllocator;` and reads
//! [`allocations`] around the loop. Not for production use: it adds an atomic increment to
//! every allocation.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    // A const-initialized cell: reading it allocates nothing, so the allocator may use it.
    static ON_THIS_THREAD: Cell<usize> = const { Cell::new(0) };
}

/// The system allocator, counting every allocation.
pub struct CountingAllocator;

// SAFETY: every call is forwarded unchanged to the system allocator.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // A thread being torn down has no cell left: its allocations count only above.
        let _ = ON_THIS_THREAD.try_with(|n| n.set(n.get() + 1));
        // SAFETY: the caller's contract is the system allocator's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc` above, which is the system allocator's.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// Allocations so far in this process (all threads) while [`CountingAllocator`] is installed.
pub fn allocations() -> usize {
    ALLOCATIONS.load(Ordering::SeqCst)
}

/// Allocations so far on the calling thread while [`CountingAllocator`] is installed: what a
/// loop run on this thread allocated, whatever other threads of the process (the test
/// harness's, a pool's still winding down) do meanwhile.
pub fn allocations_on_this_thread() -> usize {
    ON_THIS_THREAD.with(Cell::get)
}
