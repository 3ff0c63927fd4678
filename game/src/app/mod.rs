//! The app around the runner game: the [`Session`] (input mapping, the menus and screens, the
//! showroom, the settings file, the governor's scheduling, the follow camera), and its GPU
//! side ([`GameGpu`], [`GameFrame`]): what the shells (desktop window, Android, `play`, the
//! soak) run. Each frame the session hands the GPU side a plain
//! [`FramePacket`](dermis_engine::scene::FramePacket) (the extract step); the session itself touches
//! no GPU object, and nothing from the GPU side calls back into it. The game's rules (`crate::rules`) know nothing of it or of the renderer.

mod frame;
mod gpu;
mod load;
pub mod menu;
mod screens;
pub mod session;
mod settings;
pub mod showroom;

pub use frame::{soak_sample, AfterEncode, GameFrame};
pub use gpu::{GameGpu, ShowroomHead, HEAD};
pub use load::{GameLoad, GameSetup, Loaded};
pub use menu::MenuLayout;
pub use screens::{GameUi, UiOutcome};
pub use session::{FrameInfo, Key, Session, Viewport};
pub use settings::Settings;
pub use showroom::{Showroom, Subject};
