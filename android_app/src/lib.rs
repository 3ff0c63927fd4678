//! dermis for Android: a native-activity `cdylib` (`libdermis_android.so`) built and packaged
//! by `cargo xtask apk`.
//!
//! On other targets the crate is only the re-exported [`lifecycle`] state machine (so
//! `cargo test` / `cargo clippy` on the host cover it); the Android glue and the GPU code are
//! compiled for `target_os = "android"` only, since android-activity refuses other targets.

/// The lifecycle state machine lives in the core (platform-free, tested on the desktop).
pub use dermis_game::lifecycle;

/// Heap allocations are counted (the soak reports them per frame) and the Rust heap's live
/// bytes measured, as on the desktop.
#[cfg(target_os = "android")]
#[global_allocator]
static ALLOCATOR: dermis_engine::heap::Counting = dermis_engine::heap::Counting;

#[cfg(target_os = "android")]
mod android;
#[cfg(target_os = "android")]
mod app;
#[cfg(target_os = "android")]
mod assets;
#[cfg(target_os = "android")]
mod display;
#[cfg(target_os = "android")]
mod intent;
#[cfg(target_os = "android")]
mod ndk_dl;
#[cfg(target_os = "android")]
mod soak;
