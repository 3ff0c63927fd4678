//! dermis-game's integration tests, one binary: the runner's rules, the session (pause,
//! cameras, determinism), the menu and the UI on every screen size, the showroom and the
//! governor. They need no GPU or window, and also run on Android bionic under qemu
//! (`cargo xtask android-test`).
mod camera_close;
mod camera_replay;
#[path = "../../../tests/shared/external.rs"]
mod external;
mod game_determinism;
mod game_pause;
mod game_rules;
mod governor;
mod menu_small_screens;
mod screen;
mod showroom_subject;
mod ui_cache;
mod ui_safe_area;
