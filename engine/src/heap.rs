//! Where the process's memory goes, for the soak: a counting global allocator (allocations
//! and live bytes of the Rust heap), the C allocator's in-use bytes (which include the GPU
//! driver's own allocations: Mesa, a phone's Vulkan driver), and the resident set.
//!
//! A binary opts in with
//! ```no_run
//! #[global_allocator]
//! static ALLOCATOR: dermis_engine::heap::Counting = dermis_engine::heap::Counting;
//! # fn main() {}
//! ```
//! Without it [`allocations`] and [`live_bytes`] stay 0 and the reports say "not counted".
//! The cost is two relaxed atomic adds per allocation.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicI64, AtomicU64, Ordering};

/// The system allocator, counting.
pub struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);
static LIVE: AtomicI64 = AtomicI64::new(0);
static ACTIVE: AtomicBool = AtomicBool::new(false);

// SAFETY: every call forwards to `System` with the caller's arguments; the counters do not
// touch the memory.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(1, layout.size() as i64);
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as i64, Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(1, layout.size() as i64);
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(1, new_size as i64 - layout.size() as i64);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[inline]
fn count(n: u64, bytes: i64) {
    ALLOCATIONS.fetch_add(n, Ordering::Relaxed);
    LIVE.fetch_add(bytes, Ordering::Relaxed);
    if !ACTIVE.load(Ordering::Relaxed) {
        ACTIVE.store(true, Ordering::Relaxed);
    }
}

/// Heap allocations so far (all threads): 0 when [`Counting`] is not the global allocator.
pub fn allocations() -> u64 {
    ALLOCATIONS.load(Ordering::Relaxed)
}

/// Whether [`Counting`] is the global allocator (it has seen an allocation).
pub fn counting() -> bool {
    ACTIVE.load(Ordering::Relaxed)
}

/// Bytes the Rust heap holds now (`None` when not counted). Allocations made before the
/// allocator was installed do not exist: it is installed before `main`.
pub fn live_bytes() -> Option<u64> {
    counting().then(|| LIVE.load(Ordering::Relaxed).max(0) as u64)
}

/// One sample of the process's memory, MiB (`None` where the platform cannot tell).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct MemorySample {
    /// Resident set (`/proc/self/statm`).
    pub rss_mb: Option<f64>,
    /// Live bytes of the Rust heap ([`Counting`]).
    pub rust_heap_mb: Option<f64>,
    /// Bytes in use in the C allocator (glibc's and bionic's `mallinfo`): the Rust heap plus
    /// everything C code (the GPU driver) allocated.
    pub malloc_mb: Option<f64>,
}

const MIB: f64 = 1024.0 * 1024.0;

impl MemorySample {
    /// Reads everything now; `page` is [`page_bytes`].
    pub fn now(page: f64) -> Self {
        Self {
            rss_mb: resident_mb(page),
            rust_heap_mb: live_bytes().map(|b| b as f64 / MIB),
            malloc_mb: malloc_in_use().map(|b| b as f64 / MIB),
        }
    }
}

/// Resident memory in MiB (`None` where /proc is missing).
pub fn resident_mb(page_bytes: f64) -> Option<f64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: f64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    Some(pages * page_bytes / MIB)
}

/// Page size: statm's resident pages against status's VmRSS (kB), rounded to a power of two;
/// 4096 when /proc cannot tell.
pub fn page_bytes() -> f64 {
    let calibrate = || -> Option<f64> {
        let status = std::fs::read_to_string("/proc/self/status").ok()?;
        let kb: f64 = status
            .lines()
            .find(|l| l.starts_with("VmRSS:"))?
            .split_whitespace()
            .nth(1)?
            .parse()
            .ok()?;
        let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
        let pages: f64 = statm.split_whitespace().nth(1)?.parse().ok()?;
        (pages > 0.0).then(|| 2f64.powf((kb * 1024.0 / pages).log2().round()))
    };
    calibrate().unwrap_or(4096.0)
}

/// Bytes in use in the C allocator: `uordblks + hblkhd` (small and mmapped blocks in use,
/// every arena).
#[cfg(any(all(target_os = "linux", target_env = "gnu"), target_os = "android"))]
pub fn malloc_in_use() -> Option<u64> {
    // glibc's `struct mallinfo2` and bionic's `struct mallinfo`: ten `size_t` fields.
    #[repr(C)]
    #[derive(Default)]
    struct MallInfo {
        arena: usize,
        ordblks: usize,
        smblks: usize,
        hblks: usize,
        hblkhd: usize,
        usmblks: usize,
        fsmblks: usize,
        uordblks: usize,
        fordblks: usize,
        keepcost: usize,
    }
    extern "C" {
        #[cfg(target_env = "gnu")]
        #[link_name = "mallinfo2"]
        fn mallinfo_sizes() -> MallInfo;
        #[cfg(target_os = "android")]
        #[link_name = "mallinfo"]
        fn mallinfo_sizes() -> MallInfo;
    }
    // SAFETY: both take no arguments and return the struct by value; on bionic `mallinfo`'s
    // fields are `size_t`, as in glibc's `mallinfo2` (glibc ≥ 2.33).
    let m = unsafe { mallinfo_sizes() };
    Some((m.uordblks + m.hblkhd) as u64)
}

/// Bytes in use in the C allocator: not available on this platform.
#[cfg(not(any(all(target_os = "linux", target_env = "gnu"), target_os = "android")))]
pub fn malloc_in_use() -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_sample_reads_this_process() {
        let s = MemorySample::now(page_bytes());
        if cfg!(any(target_os = "linux", target_os = "android")) {
            let rss = s.rss_mb.expect("statm");
            assert!(rss > 0.5 && rss < 1e6, "{rss}");
            // Other tests allocate and free concurrently: a block far larger than they hold
            // (calloc'd, so its pages are never touched) and half of it as the bound.
            let before = malloc_in_use().expect("mallinfo");
            let block = std::hint::black_box(vec![0u8; 1 << 29]);
            let after = malloc_in_use().expect("mallinfo");
            assert!(after >= before + (1 << 28), "{before} → {after}");
            drop(block);
        }
        // The test harness does not install `Counting`.
        assert_eq!(s.rust_heap_mb, None);
    }
}
