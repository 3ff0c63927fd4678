//! `dermis`: the desktop app and its headless commands.

mod cli;
mod cmd;
mod demo;
mod paths;
mod window;

use std::process::ExitCode;

use clap::Parser;

#[global_allocator]
static ALLOCATOR: dermis_engine::heap::Counting = dermis_engine::heap::Counting;

fn main() -> ExitCode {
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("warn,wgpu_hal::gles::egl=off"),
    )
    .init();
    // Bad input is reported as one line, never as a panic with a backtrace.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        let line = msg.lines().next().unwrap_or("");
        eprintln!(
            "dermis: internal error: {line} (at {})",
            info.location().map_or("?".into(), |l| l.to_string())
        );
    }));
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            let text = e.to_string();
            let line = text.lines().next().unwrap_or("invalid arguments");
            eprintln!("dermis: {line}");
            return ExitCode::from(2);
        }
    };
    // Headless commands and windows alike: winit's and wgpu's Wayland probes print errors
    // without an XDG_RUNTIME_DIR.
    quiet_wayland_probe();
    match cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("dermis: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Where `XDG_RUNTIME_DIR` is unset (containers, CI, `xvfb-run`), Mesa's Vulkan device-select
/// layer (`libVkLayer_MESA_device_select`, in `vkEnumeratePhysicalDevices`) probes for a
/// Wayland display with `wl_display_connect`, and libwayland prints `error: XDG_RUNTIME_DIR
/// is invalid or not set in the environment.` (once per enumeration: twice per run) — for
/// offscreen commands, which need no display, and for the window on X11 alike. So point it at
/// a private, empty directory (`$TMPDIR/dermis-runtime-UID`, mode 0700, owned by this user,
/// reused by later runs) before any GPU instance exists: the probe then finds no Wayland
/// socket and stays quiet. Nothing is lost: without `XDG_RUNTIME_DIR` no Wayland socket named
/// by `WAYLAND_DISPLAY` could be found anyway (an absolute `WAYLAND_DISPLAY` still works), and
/// X11 does not use it. Runs on the main thread before any other thread is started.
#[cfg(target_os = "linux")]
fn quiet_wayland_probe() {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt};
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|v| !v.is_empty()) {
        return;
    }
    let Ok(uid) = std::fs::metadata("/proc/self").map(|m| m.uid()) else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("dermis-runtime-{uid}"));
    match std::fs::DirBuilder::new().mode(0o700).create(&dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(_) => return,
    }
    // Only a real directory of ours that nobody else can enter (not a planted symlink).
    let ours = std::fs::symlink_metadata(&dir)
        .is_ok_and(|m| m.is_dir() && m.uid() == uid && m.mode() & 0o077 == 0);
    if ours {
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

#[cfg(not(target_os = "linux"))]
fn quiet_wayland_probe() {}
