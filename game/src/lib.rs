//! dermis-game: the runner game on top of the engine (`dermis-engine`), which cannot name it.
//!
//! - [`rules`]: the runner's rules (track, player, bot): plain data, it draws nothing;
//! - [`app`]: the session around them — input mapping, menu and screens, the showroom,
//!   settings, the loader thread — and the frame the shells run, top to bottom: update →
//!   extract (a plain `FramePacket`) → the renderer's prepare → encode → submit/present;
//! - [`governor`]: the frame-time governor and its tiers;
//! - [`soak`]: the sustained-frame-rate recorder and its report;
//! - [`lifecycle`]: the Android activity lifecycle as a pure state machine.

pub mod app;
pub mod governor;
pub mod lifecycle;
pub mod rules;
pub mod soak;
