//! The test binary's allocator: the system allocator, counting per thread what each
//! thread allocates and still holds, so that a test can see what an instance costs on
//! its own thread while other tests run in parallel.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct PerThreadCount;

/// What the allocator has counted on one thread.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Bytes allocated and not yet freed (negative if the thread frees memory that
    /// another thread allocated).
    pub live_bytes: isize,
    /// alloc, alloc_zeroed and realloc calls so far.
    pub allocations: u64,
    /// Bytes those calls asked for (a realloc counts its new size).
    pub allocated_bytes: u64,
}

thread_local! {
    static COUNTS: Cell<Counts> = const {
        Cell::new(Counts {
            live_bytes: 0,
            allocations: 0,
            allocated_bytes: 0,
        })
    };
}

fn count(delta: isize, allocated: Option<usize>) {
    // try_with: no panic while the thread's locals are being destroyed.
    let _ = COUNTS.try_with(|c| {
        let mut counts = c.get();
        counts.live_bytes += delta;
        if let Some(size) = allocated {
            counts.allocations += 1;
            counts.allocated_bytes += size as u64;
        }
        c.set(counts);
    });
}

unsafe impl GlobalAlloc for PerThreadCount {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            count(layout.size() as isize, Some(layout.size()));
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            count(layout.size() as isize, Some(layout.size()));
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        System.dealloc(p, layout);
        count(-(layout.size() as isize), None);
    }

    unsafe fn realloc(&self, p: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        let q = System.realloc(p, layout, size);
        if !q.is_null() {
            count(size as isize - layout.size() as isize, Some(size));
        }
        q
    }
}

#[global_allocator]
static ALLOCATOR: PerThreadCount = PerThreadCount;

/// The counts of the calling thread.
pub fn counts() -> Counts {
    COUNTS.with(Cell::get)
}

/// Bytes the calling thread has allocated and not freed.
pub fn live_bytes() -> isize {
    counts().live_bytes
}
