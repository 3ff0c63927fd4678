pub mod bench;
pub mod pose;
pub mod render;
pub mod stats;
