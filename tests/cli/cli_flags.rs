//! The command-line table test: for every flag of every command (`cli_flags_rows.rs`, checked
//! against clap's own `Cli::command()` by the binary's unit test), bad values — a negative
//! where none is valid, NaN, infinities, a huge number, a word — and bad output paths — a
//! missing parent that cannot be made, an unwritable place, a file where a directory must be,
//! the wrong extension — each give one line naming the flag or the path and a non-zero exit,
//! before any work: nothing on stdout, no GPU adapter opened (the core logs `adapter:` at info
//! level, which these runs enable), no output file. Valid negative values (`--g -0.5`,
//! `--light -0.5,2,1`) are accepted: the error is then about a later, unknown argument.

use crate::cli_flags_rows as rows;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use rows::{Kind, Row, ROWS};

/// An argument no command takes (a stray word, not a flag): when the values before it were
/// accepted, clap's complaint is about it.
const POISON: &str = "dermis-table-poison";

/// Far beyond any check's time, far below any work's (a Monte Carlo bake, a GPU device on
/// lavapipe): a bound that says "before the work", not a performance claim.
const BEFORE_WORK: Duration = Duration::from_secs(30);

struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("dermis-flags-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("file"), b"not a directory").unwrap();
        Self(dir)
    }

    fn path(&self, rel: &str) -> String {
        self.0.join(rel).to_str().unwrap().to_string()
    }

    /// The files and folders in the scratch directory besides `file`.
    fn written(&self) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(&self.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != "file")
            .collect();
        names.sort();
        names
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `row.cmd` as arguments.
fn command(row: &Row) -> Vec<String> {
    row.cmd.split_whitespace().map(str::to_string).collect()
}

fn needs(row: &Row, tmp: &Scratch) -> Vec<String> {
    row.needs
        .iter()
        .map(|a| a.replace("{tmp}", tmp.0.to_str().unwrap()))
        .collect()
}

/// Runs dermis with the GPU's info log on and no display; returns (success, stdout, stderr).
fn dermis(args: &[String]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(args)
        .env(
            "RUST_LOG",
            "warn,dermis_engine::render::gpu=info,wgpu_hal::gles::egl=off",
        )
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Messages that mean a value reached clap's or the standard library's generic handling, not
/// the project's parsers.
const GENERIC: [&str; 4] = [
    "invalid digit",
    "invalid float literal",
    "cannot parse",
    "number too large",
];

/// Runs `args` and checks the failure: one line on stderr holding every `needle`, non-zero
/// exit, nothing on stdout, no GPU opened, within [`BEFORE_WORK`]. Returns the line.
fn one_line_error(args: &[String], needles: &[&str]) -> String {
    let start = Instant::now();
    let (ok, stdout, stderr) = dermis(args);
    let took = start.elapsed();
    assert!(!ok, "{args:?} succeeded");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{args:?}: want one line, got:\n{stderr}");
    let line = lines[0];
    assert!(line.starts_with("dermis: "), "{args:?}: {line}");
    for n in needles {
        assert!(line.contains(n), "{args:?}: `{n}` not in: {line}");
    }
    for g in GENERIC {
        assert!(!line.contains(g), "{args:?}: generic message: {line}");
    }
    assert!(
        !line.contains("panicked") && !line.contains("internal error"),
        "{line}"
    );
    assert!(stdout.is_empty(), "{args:?}: work started:\n{stdout}");
    assert!(!stderr.contains("adapter:"), "{args:?}: a GPU was opened");
    assert!(took < BEFORE_WORK, "{args:?}: refused only after {took:?}");
    line.to_string()
}

/// The bad values of a numeric kind, each written the way the flag takes it.
fn bad_values(kind: Kind) -> Vec<String> {
    let (template, negative) = match kind {
        Kind::Count | Kind::Size | Kind::NumberList | Kind::Rgb => (
            match kind {
                Kind::Size => "{}x10",
                Kind::NumberList => "1,{}",
                Kind::Rgb => "{},1,1",
                _ => "{}",
            },
            "-1",
        ),
        Kind::Number { bad_negative, .. } => ("{}", bad_negative),
        Kind::Vec3 { bad_negative, .. } => ("{},2,1", bad_negative),
        _ => unreachable!("{kind:?} is not numeric"),
    };
    [
        negative, "NaN", "nan", "inf", "-inf", "1e30", "1e400", "lots",
    ]
    .iter()
    .map(|v| template.replace("{}", v))
    .collect()
}

fn good_negative(kind: Kind) -> Option<String> {
    match kind {
        Kind::Number { good_negative, .. } => good_negative.map(str::to_string),
        Kind::Vec3 { good_negative, .. } => Some(format!("{good_negative},2,1")),
        _ => None,
    }
}

#[test]
fn numeric_flags_refuse_bad_values_with_the_projects_message() {
    let tmp = Scratch::new("numeric");
    let mut cases = 0;
    for row in ROWS.iter().filter(|r| r.kind.is_numeric()) {
        let flag = format!("--{}", row.flag);
        for value in bad_values(row.kind) {
            for args in [
                [command(row), vec![flag.clone(), value.clone()]].concat(),
                [command(row), vec![format!("{flag}={value}")]].concat(),
            ] {
                let line = one_line_error(&args, &[&flag]);
                assert!(line.contains("invalid value"), "{args:?}: {line}");
                cases += 1;
            }
        }
    }
    assert!(tmp.written().is_empty(), "{:?}", tmp.written());
    assert!(cases > 300, "{cases}");
}

#[test]
fn valid_negative_values_are_accepted() {
    let mut seen = 0;
    for row in ROWS {
        let Some(value) = good_negative(row.kind) else {
            continue;
        };
        let args = [
            command(row),
            vec![format!("--{}", row.flag), value.clone(), POISON.into()],
        ]
        .concat();
        // The value was taken: clap's complaint is the argument after it.
        let line = one_line_error(&args, &[POISON]);
        assert!(!line.contains(&value), "{args:?}: {line}");
        seen += 1;
    }
    assert!(seen >= 3, "{seen}");
}

#[test]
fn names_and_input_files_are_checked_first() {
    let tmp = Scratch::new("inputs");
    for row in ROWS {
        let value = match row.kind {
            Kind::Name => "bogus".to_string(),
            Kind::InFile => tmp.path("missing.glb"),
            _ => continue,
        };
        let args = [
            command(row),
            needs(row, &tmp),
            vec![format!("--{}", row.flag), value],
        ]
        .concat();
        let needle = if row.kind == Kind::Name {
            "bogus"
        } else {
            "missing.glb"
        };
        one_line_error(&args, &[needle]);
        assert!(
            !Path::new(&tmp.path("never.png")).exists(),
            "{args:?} wrote its output"
        );
    }
}

/// Bad places for an output, with a word the error must hold.
fn bad_outputs(kind: Kind, tmp: &Scratch) -> Vec<(String, String)> {
    let mut cases = Vec::new();
    match kind {
        Kind::OutFile { ext } => {
            let e = ext.unwrap_or("txt");
            cases.push((format!("/proc/dermis-no/x.{e}"), "dermis-no".into()));
            cases.push((format!("/proc/x.{e}"), "/proc".into()));
            cases.push((tmp.path(&format!("file/x.{e}")), "file".into()));
            cases.push((tmp.path(""), tmp.path("")));
            if let Some(e) = ext {
                cases.push((tmp.path("x.wrong"), format!("use .{e}")));
            }
        }
        Kind::OutDir => {
            cases.push(("/proc/dermis-no/d".into(), "dermis-no".into()));
            cases.push(("/proc".into(), "/proc".into()));
            cases.push((tmp.path("file"), "not a directory".into()));
            cases.push((tmp.path("file/d"), "file".into()));
        }
        _ => {}
    }
    cases
}

#[test]
fn output_paths_are_checked_before_the_work() {
    let tmp = Scratch::new("outputs");
    let mut cases = 0;
    for row in ROWS {
        for (path, needle) in bad_outputs(row.kind, &tmp) {
            let args = [
                command(row),
                needs(row, &tmp),
                vec![format!("--{}", row.flag), path.clone()],
            ]
            .concat();
            one_line_error(&args, &[needle.trim_end_matches('/')]);
            assert!(tmp.written().is_empty(), "{args:?}: {:?}", tmp.written());
            cases += 1;
        }
    }
    assert!(cases >= 40, "{cases}");
}

/// A clip the model does not have is refused from the model file, before the GPU (it was
/// refused after ~8 s of GPU setup); the same render with a clip it has opens the GPU, which
/// the `adapter:` log line shows (so its absence above means something).
#[test]
fn render_refuses_a_missing_clip_before_the_gpu() {
    let tmp = Scratch::new("clip");
    let png = tmp.path("r.png");
    let args = |clip: &str| -> Vec<String> {
        ["render", "--size", "8x8", "--clip", clip, "--out", &png]
            .iter()
            .map(|s| s.to_string())
            .collect()
    };
    one_line_error(&args("99"), &["clip 99 out of range"]);
    assert!(tmp.written().is_empty());
    let (ok, _, stderr) = dermis(&args("0"));
    if !ok && stderr.contains("no GPU adapter found") {
        eprintln!("skipping the GPU half: no GPU adapter: {stderr}");
        return;
    }
    assert!(ok, "{stderr}");
    assert!(stderr.contains("adapter:"), "no adapter line: {stderr}");
    assert!(Path::new(&png).is_file());
}

/// The game's and the demo's flags are their own: `demo` takes no game flag, the game no
/// demo flag, and a game flag before a command is refused rather than dropped.
#[test]
fn game_and_demo_flags_are_split() {
    for (args, needle) in [
        (&["demo", "--seed", "3"][..], "--seed"),
        (&["demo", "--autoplay"], "--autoplay"),
        (&["demo", "--settings", "s.txt"], "--settings"),
        (&["--material", "skin1"], "--material"),
        (&["--seed", "3", "demo"], "demo"),
    ] {
        let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        one_line_error(&args, &[needle]);
    }
    let (ok, help, _) = dermis(&["demo".into(), "--help".into()]);
    assert!(ok);
    for game_only in ["--seed", "--autoplay", "--settings"] {
        assert!(!help.contains(game_only), "demo --help lists {game_only}");
    }
}
