//! Command-line interface.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use dermis_engine::shading::{Material, ShadingModel};

use crate::cmd;
use crate::cmd::args::{self, parse_material, parse_model};

#[derive(Parser, Debug)]
#[command(
    name = "dermis",
    version,
    about = "A skinned character with selectable subsurface-scattering skin shaders",
    // `dermis --seed 3 demo` would drop the game's flag silently: refused instead.
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub game: GameArgs,
}

/// What every window takes (the game's and the demo's).
#[derive(clap::Args, Debug, Clone)]
pub struct WindowArgs {
    /// Quit after this many presented frames (at least 1).
    #[arg(long, value_parser = args::parse_frames, allow_hyphen_values = true)]
    pub frames: Option<u64>,
    /// Save the last presented frame to this PNG.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// A glTF character instead of the project's own.
    #[arg(long)]
    pub model: Option<PathBuf>,
}

/// The runner game in a window (`dermis` with no command).
#[derive(clap::Args, Debug, Clone)]
pub struct GameArgs {
    #[command(flatten)]
    pub window: WindowArgs,
    #[arg(
        long,
        value_parser = parse_model,
        help = args::shading_help(&format!(
            "Shading model (default: the player's saved choice, else `{}`)",
            ShadingModel::DEFAULT
        ))
    )]
    pub shading: Option<ShadingModel>,
    /// Let the autoplay bot play.
    #[arg(long)]
    pub autoplay: bool,
    /// Seed of the run (obstacles, bot).
    #[arg(long, default_value_t = 1, value_parser = args::parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Settings file, read and saved (default: $XDG_CONFIG_HOME/dermis/settings.txt; checked
    /// writable before the window opens).
    #[arg(long)]
    pub settings: Option<PathBuf>,
    #[command(flatten)]
    pub character: args::CharacterArgs,
}

/// The showroom demo in a window (`dermis demo`).
#[derive(clap::Args, Debug, Clone)]
pub struct DemoArgs {
    #[command(flatten)]
    pub window: WindowArgs,
    #[arg(
        long,
        default_value_t = ShadingModel::DEFAULT,
        value_parser = parse_model,
        help = args::shading_help("Initial shading model")
    )]
    pub shading: ShadingModel,
    /// Initial material preset (skin1 | white-coat).
    #[arg(long, default_value = "skin1", value_parser = parse_material)]
    pub material: Material,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// The showroom demo: the character on a floor with props (no game).
    Demo(DemoArgs),
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
        #[arg(long, default_value_t = 0, value_parser = args::parse_index, allow_hyphen_values = true)]
        clip: usize,
        /// Time in seconds (≥ 0; clamped to the clip).
        #[arg(long, default_value = "0", value_parser = args::parse_time, allow_hyphen_values = true)]
        time: f32,
        /// Comma-separated vertex indices (default: all).
        #[arg(long, value_delimiter = ',', value_parser = args::parse_index, allow_hyphen_values = true)]
        vertices: Option<Vec<usize>>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Total diffuse reflectance of every model next to a Monte Carlo reference.
    Sss(cmd::sss::SssArgs),
    /// The multi-scatter albedo A ↔ reduced albedo α' map against the Monte Carlo (and the
    /// KHR_materials_volume_scatter draft's relation).
    Albedo(cmd::albedo::AlbedoArgs),
    /// The albedo map through the subsurface medium: the textured Monte Carlo's uniform patch
    /// and albedo-step profiles (writes albedo-step.json).
    Texturing(cmd::texturing::TexturingArgs),
    /// Generate the path-traced reference data set (tools/reference/<material>.json).
    Reference(cmd::reference::ReferenceArgs),
    /// Bake the optics tables the core ships (assets/sss/: the A ↔ α' table, the presets'
    /// tables and LUTs, and with --grid the grids every other material's are interpolated from).
    Lut(cmd::lut::LutArgs),
    /// Radial exitance profile M(r) of a flat medium under a point light, per shading model.
    Profile(cmd::profile::ProfileArgs),
    /// Write each composed shader as SPIR-V (NAME.vert.spv / NAME.frag.spv) into a directory.
    Shaders(cmd::shaders::ShadersArgs),
    /// Self-test: create, present to and drop N window surfaces; print GPU object counts.
    #[command(hide = true)]
    Surfaces {
        #[arg(long, default_value_t = 50, value_parser = args::parse_surfaces, allow_hyphen_values = true)]
        count: u32,
    },
    /// Benchmarks that print numbers (JSON + a table).
    Bench(cmd::bench::BenchArgs),
    /// Play on autoplay for N seconds and report sustained frame time, pacing and memory.
    Soak(cmd::soak::SoakArgs),
}

/// The window's output checks, before anything is loaded.
fn check_window(w: &WindowArgs) -> Result<(), String> {
    match &w.screenshot {
        Some(path) => args::check_out_file(path, Some("png")),
        None => Ok(()),
    }
}

/// The game's: the window's, and the settings file must be writable (it is saved on every
/// change): a `--settings` file that can never be saved is refused, the default one is
/// warned about (the game still runs; its choices and best score are not kept).
fn check_game(g: &GameArgs) -> Result<(), String> {
    check_window(&g.window)?;
    match &g.settings {
        Some(path) => args::check_out_file(path, None).map_err(|e| format!("--settings {e}")),
        None => {
            match crate::window::settings_path() {
                Some(path) => {
                    if let Err(e) = args::check_out_file(&path, None) {
                        eprintln!("dermis: warning: settings will not be saved: {e}");
                    }
                }
                None => eprintln!(
                    "dermis: warning: settings will not be saved: neither XDG_CONFIG_HOME nor \
                     HOME is set (use --settings FILE)"
                ),
            }
            Ok(())
        }
    }
}

pub fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        None => {
            check_game(&cli.game)?;
            crate::window::run_game(cli.game)
        }
        Some(Command::Demo(args)) => {
            check_window(&args.window)?;
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
        Some(Command::Albedo(args)) => cmd::albedo::run(args),
        Some(Command::Texturing(args)) => cmd::texturing::run(args),
        Some(Command::Reference(args)) => cmd::reference::run(args),
        Some(Command::Lut(args)) => cmd::lut::run(args),
        Some(Command::Profile(args)) => cmd::profile::run(args),
        Some(Command::Shaders(args)) => cmd::shaders::run(args),
        Some(Command::Surfaces { count }) => cmd::surfaces::run(count),
        Some(Command::Soak(args)) => cmd::soak::run(args),
    }
}

/// The command-line table the table test (`tests/cli/cli_flags.rs`) runs.
#[cfg(test)]
#[path = "../tests/cli/cli_flags_rows.rs"]
mod rows;

#[cfg(test)]
mod tests {
    use super::rows::{Kind, ROWS};
    use super::Cli;
    use clap::CommandFactory;

    /// Every flag clap knows, as (command path, long name, takes a value, hyphen values).
    fn flags(cmd: &clap::Command, path: &str, out: &mut Vec<(String, String, bool, bool)>) {
        for a in cmd.get_arguments() {
            let Some(long) = a.get_long() else { continue };
            if matches!(long, "help" | "version") {
                continue;
            }
            out.push((
                path.to_string(),
                long.to_string(),
                a.get_action().takes_values(),
                a.is_allow_hyphen_values_set(),
            ));
        }
        for sub in cmd.get_subcommands() {
            let name = sub.get_name();
            let sub_path = match path {
                "" => name.to_string(),
                _ => format!("{path} {name}"),
            };
            flags(sub, &sub_path, out);
        }
    }

    /// Every flag of every command has one row in the table, and every row a flag: a new
    /// flag without a row fails here. Numeric flags let negative values reach their parsers;
    /// the others do not swallow the next flag.
    #[test]
    fn the_table_covers_every_flag_of_every_command() {
        let mut found = Vec::new();
        flags(&Cli::command(), "", &mut found);
        let mut problems = Vec::new();
        for (cmd, flag, takes_value, hyphen) in &found {
            let rows: Vec<_> = ROWS
                .iter()
                .filter(|r| r.cmd == cmd && r.flag == flag)
                .collect();
            let [row] = rows[..] else {
                problems.push(format!(
                    "`{cmd} --{flag}`: {} rows in tests/cli/cli_flags_rows.rs (want 1)",
                    rows.len()
                ));
                continue;
            };
            if *takes_value == (row.kind == Kind::Switch) {
                problems.push(format!(
                    "`{cmd} --{flag}`: takes a value: {takes_value}, row {:?}",
                    row.kind
                ));
            }
            if *hyphen != row.kind.is_numeric() {
                problems.push(format!(
                    "`{cmd} --{flag}`: allow_hyphen_values is {hyphen}, want {}",
                    row.kind.is_numeric()
                ));
            }
        }
        for r in ROWS {
            if !found.iter().any(|(c, f, ..)| c == r.cmd && f == r.flag) {
                problems.push(format!("row `{} --{}`: no such flag", r.cmd, r.flag));
            }
        }
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }

    /// The README's command table (`## Command line`): its first cell per row, as (command
    /// path, the usage text).
    fn readme_rows() -> Vec<(String, String)> {
        let readme = include_str!("../README.md");
        let section = readme
            .split("\n## Command line\n")
            .nth(1)
            .and_then(|s| s.split("\n## ").next())
            .expect("README has a `## Command line` section");
        section
            .lines()
            .filter_map(|l| l.strip_prefix("| `dermis"))
            .filter_map(|l| l.split('`').next())
            .map(|usage| {
                let path: Vec<&str> = usage
                    .split_whitespace()
                    .take_while(|w| !w.starts_with(['[', '-']))
                    .collect();
                (path.join(" "), usage.to_string())
            })
            .collect()
    }

    /// Every command `--help` shows has one row in the README's command table, and the row
    /// names every flag its `--help` lists (the table lagged behind `--help` twice).
    #[test]
    fn the_readme_table_lists_every_flag() {
        let rows = readme_rows();
        let mut found = Vec::new();
        let mut visible = vec![(String::new(), Cli::command())];
        let mut problems = Vec::new();
        while let Some((path, cmd)) = visible.pop() {
            for sub in cmd.get_subcommands().filter(|c| !c.is_hide_set()) {
                let name = sub.get_name();
                let sub_path = match path.as_str() {
                    "" => name.to_string(),
                    _ => format!("{path} {name}"),
                };
                visible.push((sub_path, sub.clone()));
            }
            let longs: Vec<&str> = cmd
                .get_arguments()
                .filter(|a| !a.is_hide_set())
                .filter_map(|a| a.get_long())
                .filter(|l| !matches!(*l, "help" | "version"))
                .collect();
            if longs.is_empty() {
                continue;
            }
            let mine: Vec<_> = rows.iter().filter(|(p, _)| *p == path).collect();
            let [(_, usage)] = mine[..] else {
                problems.push(format!(
                    "`dermis {path}`: {} README rows (want 1)",
                    mine.len()
                ));
                continue;
            };
            for long in longs {
                let named = usage.match_indices(&format!("--{long}")).any(|(i, m)| {
                    let next = usage[i + m.len()..].chars().next();
                    !next.is_some_and(|c| c.is_alphanumeric() || c == '-')
                });
                if !named {
                    problems.push(format!("`dermis {path}`: README row lacks --{long}"));
                }
            }
            found.push(path);
        }
        assert!(found.len() > 10, "{found:?}");
        assert!(problems.is_empty(), "{}", problems.join("\n"));
    }
}
