//! The parts of the Rust runtime the engine relies on, checked wherever the core's tests run:
//! on the desktop and, through `cargo xtask android-test`, on Android bionic under qemu
//! (unwinding through many frames, `should_panic`, panics reported through `join`, TLS
//! destructors, a large allocation, files in the temporary folder).

use std::sync::atomic::{AtomicU32, Ordering};

#[test]
#[should_panic(expected = "deliberate")]
fn should_panic_sees_the_panic() {
    panic!("deliberate");
}

struct CountDrop<'a>(&'a AtomicU32);

impl Drop for CountDrop<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::SeqCst);
    }
}

#[inline(never)]
fn recurse(depth: u32, drops: &AtomicU32) -> u32 {
    let _guard = CountDrop(drops);
    if depth == 0 {
        panic!("bottom of the stack");
    }
    // Not a tail call: the frame stays on the stack.
    std::hint::black_box(recurse(depth - 1, drops)) + 1
}

#[test]
fn unwinding_through_20_frames_runs_every_drop() {
    let drops = AtomicU32::new(0);
    let r = std::panic::catch_unwind(|| recurse(20, &drops));
    assert!(r.is_err());
    assert_eq!(drops.load(Ordering::SeqCst), 21);
}

#[test]
fn a_thread_panic_reaches_join() {
    let r = std::thread::spawn(|| -> u32 { panic!("in the thread") }).join();
    let payload = r.expect_err("the thread panicked");
    assert_eq!(payload.downcast_ref::<&str>(), Some(&"in the thread"));
}

#[test]
fn thread_local_destructors_run_at_thread_exit() {
    static DROPS: AtomicU32 = AtomicU32::new(0);
    struct Local;
    impl Drop for Local {
        fn drop(&mut self) {
            DROPS.fetch_add(1, Ordering::SeqCst);
        }
    }
    thread_local!(static LOCAL: Local = const { Local });
    let threads: Vec<_> = (0..4)
        .map(|_| std::thread::spawn(|| LOCAL.with(|_| {})))
        .collect();
    for t in threads {
        t.join().unwrap();
    }
    assert_eq!(DROPS.load(Ordering::SeqCst), 4);
}

#[test]
fn a_128_mib_allocation_is_usable() {
    const LEN: usize = 128 << 20;
    let mut v = vec![0u8; LEN];
    for i in (0..LEN).step_by(4096) {
        v[i] = (i / 4096) as u8;
    }
    let sum: u64 = v.iter().step_by(4096).map(|&b| u64::from(b)).sum();
    let expect: u64 = (0..LEN / 4096).map(|i| u64::from(i as u8)).sum();
    assert_eq!(sum, expect);
}

#[test]
fn files_in_the_temporary_folder() {
    let dir = std::env::temp_dir().join(format!("dermis-platform-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("probe.bin");
    let data: Vec<u8> = (0..=255).collect();
    std::fs::write(&path, &data).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), data);
    std::fs::remove_dir_all(&dir).unwrap();
}
