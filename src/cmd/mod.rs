pub mod bench;
pub mod play;
pub mod pose;
pub mod render;
pub mod sss;
pub mod stats;
