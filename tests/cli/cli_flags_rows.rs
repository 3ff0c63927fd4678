//! The command-line table: every flag of every command and what it takes. Two tests read it:
//! `tests/cli/cli_flags.rs` runs the binary with bad (and valid negative) values and bad output
//! paths for every row; the binary's own unit test (`src/cli.rs`) checks the rows against
//! clap's `Cli::command()`, so a flag added without a row (or a row left after its flag is
//! gone) fails.
#![allow(dead_code)]

/// What a flag takes, and so which values the table test gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// A whole number (no negative is valid).
    Count,
    /// A number: a valid negative value where one exists, and an invalid one.
    Number {
        good_negative: Option<&'static str>,
        bad_negative: &'static str,
    },
    /// `WxH`.
    Size,
    /// `X,Y,Z`: a valid negative position and an invalid one.
    Vec3 {
        good_negative: &'static str,
        bad_negative: &'static str,
    },
    /// Comma-separated numbers (none negative).
    NumberList,
    /// Three numbers `R,G,B` (none negative).
    Rgb,
    /// A file written; `ext` when the name must end in it.
    OutFile { ext: Option<&'static str> },
    /// A directory written into (created when missing).
    OutDir,
    /// A file read.
    InFile,
    /// A name from a fixed list (shading model, material).
    Name,
    /// A switch (no value).
    Switch,
}

impl Kind {
    /// Whether the flag takes a number (or numbers): its negative values must reach its
    /// parser (clap's `allow_hyphen_values`), never clap's "unexpected argument".
    pub fn is_numeric(self) -> bool {
        matches!(
            self,
            Kind::Count
                | Kind::Number { .. }
                | Kind::Size
                | Kind::Vec3 { .. }
                | Kind::NumberList
                | Kind::Rgb
        )
    }
}

/// One flag of one command.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    /// The subcommand path (`"bench shading"`; `""`: the game, `dermis` alone).
    pub cmd: &'static str,
    /// The long flag, without `--`.
    pub flag: &'static str,
    pub kind: Kind,
    /// Other arguments the command needs to get past parsing to the flag's own check (an
    /// output path, a required flag); `{tmp}` is a scratch directory.
    pub needs: &'static [&'static str],
}

const fn row(cmd: &'static str, flag: &'static str, kind: Kind) -> Row {
    Row {
        cmd,
        flag,
        kind,
        needs: &[],
    }
}

const fn with(
    cmd: &'static str,
    flag: &'static str,
    kind: Kind,
    needs: &'static [&'static str],
) -> Row {
    Row {
        cmd,
        flag,
        kind,
        needs,
    }
}

const NUM: Kind = Kind::Number {
    good_negative: None,
    bad_negative: "-1",
};
const G: Kind = Kind::Number {
    good_negative: Some("-0.5"),
    bad_negative: "-1",
};
const PNG: Kind = Kind::OutFile { ext: Some("png") };
/// A glTF file whose skin declares its optics (`--model` of the measurement commands).
const SKIN_FILE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/character.glb");
const RENDER_OUT: &[&str] = &["--out", "{tmp}/never.png"];

pub const ROWS: &[Row] = &[
    // The game (`dermis`) and the demo.
    row("", "frames", Kind::Count),
    row("", "screenshot", PNG),
    row("", "model", Kind::InFile),
    row("", "shading", Kind::Name),
    row("", "autoplay", Kind::Switch),
    row("", "seed", Kind::Count),
    row("", "settings", Kind::OutFile { ext: None }),
    row("", "skin", Kind::Name),
    row("", "idle-clip", Kind::Name),
    row("", "run-clip", Kind::Name),
    row("", "jump-clip", Kind::Name),
    row("", "death-clip", Kind::Name),
    row("demo", "frames", Kind::Count),
    row("demo", "screenshot", PNG),
    row("demo", "model", Kind::InFile),
    row("demo", "shading", Kind::Name),
    row("demo", "material", Kind::Name),
    // Headless.
    row("play", "model", Kind::InFile),
    row("play", "skin", Kind::Name),
    row("play", "idle-clip", Kind::Name),
    row("play", "run-clip", Kind::Name),
    row("play", "jump-clip", Kind::Name),
    row("play", "death-clip", Kind::Name),
    row("play", "autoplay", Kind::Switch),
    row("play", "frames", Kind::Count),
    row("play", "seed", Kind::Count),
    row("play", "shading", Kind::Name),
    row("play", "size", Kind::Size),
    row("play", "fps", NUM),
    row("play", "screenshots", Kind::OutDir),
    row("play", "json", Kind::Switch),
    row("render", "shading", Kind::Name),
    with("render", "skin", Kind::Name, RENDER_OUT),
    row("render", "material", Kind::Name),
    with("render", "model", Kind::InFile, RENDER_OUT),
    row("render", "clip", Kind::Count),
    row("render", "time", NUM),
    row("render", "size", Kind::Size),
    row(
        "render",
        "light",
        Kind::Vec3 {
            good_negative: "-0.5",
            bad_negative: "-1e5",
        },
    ),
    row("render", "no-props", Kind::Switch),
    row("render", "out", PNG),
    row("render", "scene", Kind::Name),
    row("render", "face-light", Kind::Name),
    row("render", "plain", Kind::Switch),
    with(
        "render",
        "hdr",
        Kind::OutFile { ext: Some("pfm") },
        RENDER_OUT,
    ),
    with("render", "export", Kind::OutDir, &["--scene", "head"]),
    row("pose", "model", Kind::InFile),
    row("pose", "clip", Kind::Count),
    row("pose", "time", NUM),
    row("pose", "vertices", Kind::NumberList),
    row("pose", "json", Kind::Switch),
    row("sss", "material", Kind::Name),
    row("sss", "eta", NUM),
    row("sss", "g", G),
    with("sss", "sigma-a", Kind::Rgb, &["--sigma-s", "1,1,1"]),
    with("sss", "sigma-s", Kind::Rgb, &["--sigma-a", "0.1,0.1,0.1"]),
    with("sss", "albedo", Kind::Rgb, &["--mfp-mm", "1,1,1"]),
    with("sss", "mfp-mm", Kind::Rgb, &["--albedo", "0.5,0.5,0.5"]),
    row("sss", "model", Kind::InFile),
    with("sss", "skin-material", Kind::Name, &["--model", SKIN_FILE]),
    row("sss", "photons", Kind::Count),
    row("sss", "seed", Kind::Count),
    row("sss", "json", Kind::Switch),
    row("reference", "out", Kind::OutDir),
    row("reference", "photons", Kind::Count),
    with(
        "reference",
        "material",
        Kind::Name,
        &["--out", "{tmp}/reference"],
    ),
    with("reference", "eta", NUM, &["--out", "{tmp}/reference"]),
    with("reference", "g", G, &["--out", "{tmp}/reference"]),
    with(
        "reference",
        "sigma-a",
        Kind::Rgb,
        &["--out", "{tmp}/reference", "--sigma-s", "1,1,1"],
    ),
    with(
        "reference",
        "sigma-s",
        Kind::Rgb,
        &["--out", "{tmp}/reference", "--sigma-a", "0.1,0.1,0.1"],
    ),
    with(
        "reference",
        "albedo",
        Kind::Rgb,
        &["--out", "{tmp}/reference", "--mfp-mm", "1,1,1"],
    ),
    with(
        "reference",
        "mfp-mm",
        Kind::Rgb,
        &["--out", "{tmp}/reference", "--albedo", "0.5,0.5,0.5"],
    ),
    with(
        "reference",
        "model",
        Kind::InFile,
        &["--out", "{tmp}/reference"],
    ),
    with(
        "reference",
        "skin-material",
        Kind::Name,
        &["--out", "{tmp}/reference", "--model", SKIN_FILE],
    ),
    row("reference", "seed", Kind::Count),
    row("reference", "scene", Kind::Name),
    row("reference", "face-light", Kind::Name),
    row(
        "reference",
        "light",
        Kind::Vec3 {
            good_negative: "-0.5",
            bad_negative: "-1e5",
        },
    ),
    row("reference", "threads", Kind::Count),
    row("lut", "out", Kind::OutDir),
    row("lut", "tables-only", Kind::Switch),
    row("lut", "albedo-only", Kind::Switch),
    row("lut", "no-albedo", Kind::Switch),
    row("lut", "grid", Kind::Name),
    row("albedo", "eta", Kind::NumberList),
    row("albedo", "g", G),
    row("albedo", "photons", Kind::Count),
    row("albedo", "seed", Kind::Count),
    row("albedo", "json", Kind::Switch),
    row("albedo", "sweep", Kind::OutFile { ext: Some("json") }),
    row("texturing", "out", Kind::OutDir),
    row("texturing", "photons", Kind::Count),
    row("texturing", "seed", Kind::Count),
    row("texturing", "patch-only", Kind::Switch),
    row("profile", "shading", Kind::Name),
    row("profile", "all", Kind::Switch),
    with(
        "profile",
        "material",
        Kind::Name,
        &["--light-height-mm", "5"],
    ),
    with("profile", "eta", NUM, &["--light-height-mm", "5"]),
    with("profile", "g", G, &["--light-height-mm", "5"]),
    with(
        "profile",
        "sigma-a",
        Kind::Rgb,
        &["--light-height-mm", "5", "--sigma-s", "1,1,1"],
    ),
    with(
        "profile",
        "sigma-s",
        Kind::Rgb,
        &["--light-height-mm", "5", "--sigma-a", "0.1,0.1,0.1"],
    ),
    with(
        "profile",
        "albedo",
        Kind::Rgb,
        &["--light-height-mm", "5", "--mfp-mm", "1,1,1"],
    ),
    with(
        "profile",
        "mfp-mm",
        Kind::Rgb,
        &["--light-height-mm", "5", "--albedo", "0.5,0.5,0.5"],
    ),
    with(
        "profile",
        "model",
        Kind::InFile,
        &["--light-height-mm", "5"],
    ),
    with(
        "profile",
        "skin-material",
        Kind::Name,
        &["--light-height-mm", "5", "--model", SKIN_FILE],
    ),
    row("profile", "light-height-mm", NUM),
    row("profile", "edges-mm", Kind::NumberList),
    row("profile", "json", Kind::Switch),
    row("shaders", "spirv", Kind::OutDir),
    row("shaders", "wgsl", Kind::Switch),
    row("surfaces", "count", Kind::Count),
    row("bench frame", "rounds", Kind::Count),
    row("bench frame", "frames", Kind::Count),
    row("bench frame", "out", Kind::OutFile { ext: Some("json") }),
    row("bench frame", "first-frame-only", Kind::Switch),
    row("bench frame", "json", Kind::Switch),
    row("bench frame", "mali", Kind::InFile),
    with(
        "bench frame",
        "pipeline-cache",
        Kind::OutDir,
        &["--first-frame-only"],
    ),
    row("bench textures", "rounds", Kind::Count),
    row("bench textures", "json", Kind::Switch),
    row("bench tables", "json", Kind::Switch),
    row("bench tables", "out", Kind::OutFile { ext: Some("json") }),
    row("bench tables", "materials", Kind::Count),
    row("bench face", "out", Kind::OutDir),
    with(
        "bench face",
        "cache",
        Kind::InFile,
        &["--out", "{tmp}/face"],
    ),
    row("bench face", "no-normal-map", Kind::Switch),
    with(
        "bench face",
        "sweep",
        Kind::InFile,
        &["--out", "{tmp}/face"],
    ),
    row("bench shading", "out", Kind::OutDir),
    row("bench shading", "rounds", Kind::Count),
    row("bench shading", "direct-bake", Kind::Switch),
    with(
        "bench shading",
        "mali",
        Kind::InFile,
        &["--out", "{tmp}/bench"],
    ),
    with(
        "bench shading",
        "reference",
        Kind::InFile,
        &["--out", "{tmp}/bench"],
    ),
    with(
        "bench shading",
        "photons",
        Kind::Count,
        &["--out", "{tmp}/bench"],
    ),
    with(
        "bench shading",
        "material",
        Kind::Name,
        &["--out", "{tmp}/bench"],
    ),
    with("bench shading", "eta", NUM, &["--out", "{tmp}/bench"]),
    with("bench shading", "g", G, &["--out", "{tmp}/bench"]),
    with(
        "bench shading",
        "sigma-a",
        Kind::Rgb,
        &["--out", "{tmp}/bench", "--sigma-s", "1,1,1"],
    ),
    with(
        "bench shading",
        "sigma-s",
        Kind::Rgb,
        &["--out", "{tmp}/bench", "--sigma-a", "0.1,0.1,0.1"],
    ),
    with(
        "bench shading",
        "albedo",
        Kind::Rgb,
        &["--out", "{tmp}/bench", "--mfp-mm", "1,1,1"],
    ),
    with(
        "bench shading",
        "mfp-mm",
        Kind::Rgb,
        &["--out", "{tmp}/bench", "--albedo", "0.5,0.5,0.5"],
    ),
    with(
        "bench shading",
        "model",
        Kind::InFile,
        &["--out", "{tmp}/bench"],
    ),
    with(
        "bench shading",
        "skin-material",
        Kind::Name,
        &["--out", "{tmp}/bench", "--model", SKIN_FILE],
    ),
    row("bench effects", "rounds", Kind::Count),
    row("bench effects", "frames", Kind::Count),
    row("bench effects", "shading", Kind::Name),
    row("bench effects", "size", Kind::Size),
    row("bench effects", "json", Kind::Switch),
    row("soak", "seconds", NUM),
    row("soak", "shading", Kind::Name),
    row("soak", "size", Kind::Size),
    row("soak", "target-fps", NUM),
    row("soak", "uncapped", Kind::Switch),
    row("soak", "out", Kind::OutDir),
    row("soak", "seed", Kind::Count),
    row("soak", "no-governor", Kind::Switch),
    row("soak", "no-scheduling", Kind::Switch),
];
