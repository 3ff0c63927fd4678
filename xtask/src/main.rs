//! `cargo xtask <task>`: project tasks.
//!
//! * `assets [--out DIR]`: regenerate the character and props in `assets/` (reproducible).
//! * `ui-atlas`: regenerate the UI atlas and bitmap font in `assets/ui/`.
//! * `apk [--release]`: build the signed Android APK.
//! * `android-test`: the engine's and the game's tests and the APK's library on Android bionic under qemu.
//! * `device-run`: install the APK on a connected phone, run a soak, collect its report.

mod android_test;
mod apk;
mod assets;
mod build_features;
mod device_run;
mod textures;
mod ui_atlas;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("assets") => assets::run(&args[1..]),
        Some("apk") => apk::run(&args[1..]),
        Some("android-test") => android_test::run(&args[1..]),
        Some("device-run") => device_run::run(&args[1..]),
        Some("ui-atlas") => ui_atlas::run(&args[1..]),
        _ => Err(
            "usage: cargo xtask <assets|ui-atlas|apk|android-test|device-run> [args]".to_string(),
        ),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
