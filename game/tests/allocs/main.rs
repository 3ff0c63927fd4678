//! The tests that count heap allocations, in one binary with one global allocator: the
//! animation frame, the game's and the UI's frames, the showroom's menu frame, the hostile
//! glTF corpus (no large allocation before a size is checked) and — on the desktop, with a
//! GPU — the whole game frame through the real renderer.
//!
//! The allocator counts per thread (each test does its work on its own thread, so tests that
//! run at once do not see each other's allocations), notes each thread's largest single
//! allocation, and forwards to the engine's counting allocator (`heap::Counting`: the
//! process-wide counts the frame's allocation counter reads). The test that reads the
//! process-wide counts takes [`exclusive`]; every other test takes [`shared`].

use std::alloc::{GlobalAlloc, Layout};
use std::cell::Cell;
use std::sync::{RwLock, RwLockReadGuard, RwLockWriteGuard};

use dermis_engine::heap::Counting;

#[path = "../../../tests/shared/external.rs"]
mod external;

mod anim;
mod game;
#[cfg(not(target_os = "android"))]
mod gpu_steady;
mod hostile;
mod showroom;

thread_local! {
    static ALLOCS: Cell<u64> = const { Cell::new(0) };
    static LARGEST: Cell<usize> = const { Cell::new(0) };
}

fn note(size: usize) {
    let _ = ALLOCS.try_with(|a| a.set(a.get() + 1));
    let _ = LARGEST.try_with(|l| l.set(l.get().max(size)));
    #[cfg(not(target_os = "android"))]
    gpu_steady::watch();
}

struct Tracking;

// SAFETY: every call forwards to the engine's counting allocator (the system allocator) with
// the caller's arguments; the bookkeeping touches only const-initialised thread-locals (and,
// on a watched thread, the attribution, which guards itself against recursion).
unsafe impl GlobalAlloc for Tracking {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        unsafe { Counting.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        unsafe { Counting.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { Counting.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        unsafe { Counting.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Tracking = Tracking;

/// Heap allocations (and reallocations) made by this thread so far.
pub fn thread_allocations() -> u64 {
    ALLOCS.with(Cell::get)
}

/// Starts a new record of this thread's largest single allocation.
pub fn reset_largest() {
    LARGEST.with(|l| l.set(0));
}

/// This thread's largest single allocation (bytes) since [`reset_largest`].
pub fn largest() -> usize {
    LARGEST.with(Cell::get)
}

static PROCESS: RwLock<()> = RwLock::new(());

/// For a test that counts its own thread's allocations: runs beside the others like it.
pub fn shared() -> RwLockReadGuard<'static, ()> {
    PROCESS.read().unwrap_or_else(|e| e.into_inner())
}

/// For a test that reads the process-wide counts: runs alone.
pub fn exclusive() -> RwLockWriteGuard<'static, ()> {
    PROCESS.write().unwrap_or_else(|e| e.into_inner())
}
