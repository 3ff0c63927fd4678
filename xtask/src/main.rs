//! `cargo xtask <task>`: project tasks.
//!
//! * `assets [--out DIR]`: regenerate the character and props in `assets/` (reproducible).
//! * `ui-atlas`: regenerate the UI atlas and bitmap font in `assets/ui/`.
//! * `apk [--release]`: build the signed Android APK.

mod apk;
mod assets;
mod ui_atlas;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("assets") => assets::run(&args[1..]),
        Some("apk") => apk::run(&args[1..]),
        Some("ui-atlas") => ui_atlas::run(&args[1..]),
        _ => Err("usage: cargo xtask <assets|ui-atlas|apk> [args]".to_string()),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
