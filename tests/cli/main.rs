//! The `dermis` binary's integration tests, one binary: every command and flag (errors,
//! outputs, the window under Xvfb, the soak report, the gallery), and the checks on the
//! repository's structure the compiler cannot make (`layering`).
mod adding_a_model;
mod cli_errors;
mod cli_flags;
mod cli_flags_rows;
#[path = "../shared/external.rs"]
mod external;
mod gallery;
mod layering;
mod lifecycle_gpu;
mod profile;
mod soak_report;
mod window_smoke;
