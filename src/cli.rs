//! Command-line interface.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use dermis_core::shading::{Material, ShadingModel};

use crate::cmd;
use crate::cmd::args;

#[derive(Parser, Debug)]
#[command(
    name = "dermis",
    version,
    about = "A skinned character with selectable subsurface-scattering skin shaders"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub window: WindowArgs,
}

#[derive(clap::Args, Debug, Clone)]
pub struct WindowArgs {
    /// Quit after this many presented frames (at least 1).
    #[arg(long, value_parser = args::parse_frames, allow_negative_numbers = true)]
    pub frames: Option<u64>,
    /// Save the last presented frame to this PNG.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    #[arg(
        long,
        value_parser = parse_model,
        help = args::shading_help(&format!(
            "Shading model (default: the player's saved choice in the game, else `{}`)",
            ShadingModel::DEFAULT
        ))
    )]
    pub shading: Option<ShadingModel>,
    /// Initial material preset (skin1 | white-coat).
    #[arg(long, default_value = "skin1", value_parser = parse_material)]
    pub material: Material,
    /// A glTF character instead of the project's own.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Let the autoplay bot play.
    #[arg(long)]
    pub autoplay: bool,
    /// Seed of the run (obstacles, bot).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Settings file (default: $XDG_CONFIG_HOME/dermis/settings.txt).
    #[arg(long)]
    pub settings: Option<PathBuf>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// The showroom demo: the character on a floor with props (no game).
    Demo(WindowArgs),
    /// Play headless (no window) and print a summary of frame cost and allocations.
    Play(cmd::play::PlayArgs),
    /// Render one frame offscreen to a PNG (no display needed).
    Render(cmd::render::RenderArgs),
    /// Print skinned world-space vertex positions of the first skinned mesh.
    Pose {
        /// glTF file (.glb or .gltf).
        #[arg(long)]
        model: PathBuf,
        /// Animation clip index.
        #[arg(long, default_value_t = 0)]
        clip: usize,
        /// Time in seconds (≥ 0; clamped to the clip).
        #[arg(long, default_value = "0", value_parser = args::parse_time, allow_negative_numbers = true)]
        time: f32,
        /// Comma-separated vertex indices (default: all).
        #[arg(long, value_delimiter = ',')]
        vertices: Option<Vec<usize>>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Total diffuse reflectance of every model next to a Monte Carlo reference.
    Sss(cmd::sss::SssArgs),
    /// Generate the path-traced reference data set (tools/reference/<material>.json).
    Reference(cmd::reference::ReferenceArgs),
    /// Bake the spatial models' tables and LUTs the core ships (assets/sss/<material>-eta<η>.*).
    Lut(cmd::lut::LutArgs),
    /// Radial exitance profile M(r) of a flat medium under a point light, per shading model.
    Profile(cmd::profile::ProfileArgs),
    /// Write each composed shader as SPIR-V (NAME.vert.spv / NAME.frag.spv) into a directory.
    Shaders(cmd::shaders::ShadersArgs),
    /// Self-test: create, present to and drop N window surfaces; print GPU object counts.
    #[command(hide = true)]
    Surfaces {
        #[arg(long, default_value_t = 50, value_parser = parse_count, allow_negative_numbers = true)]
        count: u32,
    },
    /// Benchmarks that print numbers (JSON + a table).
    Bench(cmd::bench::BenchArgs),
    /// Play on autoplay for N seconds and report sustained frame time, pacing and memory.
    Soak(cmd::soak::SoakArgs),
}

pub fn parse_model(s: &str) -> Result<ShadingModel, String> {
    s.parse()
}

pub fn parse_material(s: &str) -> Result<Material, String> {
    Material::preset(s).ok_or_else(|| format!("unknown material `{s}` (known: skin1, white-coat)"))
}

/// `surfaces --count`: 1..=1000.
fn parse_count(s: &str) -> Result<u32, String> {
    args::int_in(s, 1, 1000)
}

/// The window's output check, before anything is loaded.
fn check_window(w: &WindowArgs) -> Result<(), String> {
    match &w.screenshot {
        Some(path) => args::check_out_file(path, Some("png")),
        None => Ok(()),
    }
}

impl Cli {
    /// Whether the command renders offscreen only (no window: no display server is needed).
    pub fn is_headless_gpu(&self) -> bool {
        matches!(
            self.command,
            Some(
                Command::Play(_)
                    | Command::Render(_)
                    | Command::Profile(_)
                    | Command::Bench(_)
                    | Command::Soak(_)
            )
        )
    }
}

pub fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        None => {
            check_window(&cli.window)?;
            crate::window::run_game(cli.window)
        }
        Some(Command::Demo(mut args)) => {
            check_window(&args)?;
            if args.shading.is_none() {
                args.shading = Some(ShadingModel::DEFAULT);
            }
            crate::window::run_demo(args)
        }
        Some(Command::Play(args)) => cmd::play::run(args),
        Some(Command::Render(args)) => cmd::render::run(args),
        Some(Command::Pose {
            model,
            clip,
            time,
            vertices,
            json,
        }) => {
            let out = cmd::pose::run(&model, clip, time, vertices, json)?;
            println!("{out}");
            Ok(())
        }
        Some(Command::Bench(args)) => cmd::bench::run(args),
        Some(Command::Sss(args)) => cmd::sss::run(args),
        Some(Command::Reference(args)) => cmd::reference::run(args),
        Some(Command::Lut(args)) => cmd::lut::run(args),
        Some(Command::Profile(args)) => cmd::profile::run(args),
        Some(Command::Shaders(args)) => cmd::shaders::run(args),
        Some(Command::Surfaces { count }) => cmd::surfaces::run(count),
        Some(Command::Soak(args)) => cmd::soak::run(args),
    }
}
