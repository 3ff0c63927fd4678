//! `cargo xtask device-run`: a soak on a real phone in one command.
//!
//! 1. finds `adb` (`$ADB`, else `adb` on `PATH`) and exactly one device (`--serial` /
//!    `$ANDROID_SERIAL` picks one of several);
//! 2. `adb install -r` the release APK (built first with `cargo xtask apk --release` when
//!    missing);
//! 3. clears logcat, stops the app, removes the previous `soak.json`, and starts the activity
//!    with the soak extras (`--ei soak_seconds N --es shading NAME --ei target_fps F`, read by
//!    `android_app/src/intent.rs`);
//! 4. polls every 2 s until `soak.json` says `"status": "complete"`; half-way through it takes
//!    a screenshot (`adb exec-out screencap -p`);
//! 5. pulls `soak.json`, saves logcat (`adb logcat -d`), prints the `soak:` summary lines.
//!
//! Any failure — adb missing, no device, install refused, the app crashed, finished early or
//! timed out — is one line, followed by the relevant logcat excerpt.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

pub(crate) const PACKAGE: &str = "org.dermis.app";
const ACTIVITY: &str = "org.dermis.app/android.app.NativeActivity";
/// `getExternalFilesDir(null)` of the app, where `soak.json` goes.
const REMOTE_DIR: &str = "/sdcard/Android/data/org.dermis.app/files";
/// Logcat lines kept in an error's excerpt.
const EXCERPT_LINES: usize = 25;

const USAGE: &str = "\
usage: cargo xtask device-run [--seconds N] [--shading NAME] [--fps N] [--serial SERIAL]
                              [--apk FILE] [--out DIR] [--startup-timeout SECS]

Installs the APK on the connected phone, runs a soak of N seconds (the bot plays), pulls
soak.json, saves logcat and a screenshot, and prints the summary.
  --seconds N          soak length (default 60)
  --shading NAME       shading model (default oss)
  --fps N              target frame rate (default 60)
  --serial SERIAL      the device when several are connected (default $ANDROID_SERIAL)
  --apk FILE           the APK (default target/apk/dermis-release.apk, built if missing)
  --out DIR            where soak.json, logcat.txt and screenshot.png go
                       (default target/device-run)
  --startup-timeout S  extra seconds allowed for start-up, asset loading and the report
                       (default 180)
Environment:
  ADB                  the adb executable (default: adb on PATH)";

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Options {
    pub seconds: u32,
    pub shading: String,
    pub fps: u32,
    pub serial: Option<String>,
    pub apk: Option<PathBuf>,
    pub out: Option<PathBuf>,
    pub startup_timeout: Duration,
    /// How often the device is polled (tests shorten it).
    pub poll: Duration,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            seconds: 60,
            shading: "oss".into(),
            fps: 60,
            serial: None,
            apk: None,
            out: None,
            startup_timeout: Duration::from_secs(180),
            poll: Duration::from_secs(2),
        }
    }
}

pub(crate) fn parse_args(args: &[String]) -> Result<Option<Options>, String> {
    let mut o = Options::default();
    let mut it = args.iter();
    fn value<'a>(it: &mut std::slice::Iter<'a, String>, flag: &str) -> Result<&'a str, String> {
        it.next()
            .map(String::as_str)
            .ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))
    }
    fn number(v: &str, flag: &str) -> Result<u32, String> {
        match v.parse::<u32>() {
            Ok(n) if n > 0 => Ok(n),
            _ => Err(format!("{flag}: `{v}` is not a positive integer")),
        }
    }
    while let Some(a) = it.next() {
        match a.as_str() {
            "--seconds" => o.seconds = number(value(&mut it, a)?, a)?,
            "--fps" => o.fps = number(value(&mut it, a)?, a)?,
            "--shading" => {
                let v = value(&mut it, a)?;
                if v.is_empty() || !v.chars().all(|c| c.is_ascii_alphanumeric() || c == '-') {
                    return Err(format!("--shading: `{v}` is not a shading model name"));
                }
                o.shading = v.to_string();
            }
            "--serial" => o.serial = Some(value(&mut it, a)?.to_string()),
            "--apk" => o.apk = Some(PathBuf::from(value(&mut it, a)?)),
            "--out" => o.out = Some(PathBuf::from(value(&mut it, a)?)),
            "--startup-timeout" => {
                o.startup_timeout = Duration::from_secs(number(value(&mut it, a)?, a)?.into());
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                return Ok(None);
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    if o.serial.is_none() {
        o.serial = std::env::var("ANDROID_SERIAL")
            .ok()
            .filter(|s| !s.is_empty());
    }
    Ok(Some(o))
}

pub fn run(args: &[String]) -> Result<(), String> {
    let Some(opts) = parse_args(args)? else {
        return Ok(());
    };
    let root = crate::apk::workspace_root();
    let target = crate::apk::target_dir(&root);
    let apk = match &opts.apk {
        Some(p) => p.clone(),
        None => {
            let p = target.join("apk/dermis-release.apk");
            if !p.is_file() {
                println!("device-run: {} missing, building it", p.display());
                crate::apk::run(&["--release".to_string()])?;
            }
            p
        }
    };
    let out = opts
        .out
        .clone()
        .unwrap_or_else(|| target.join("device-run"));
    let adb = std::env::var_os("ADB")
        .filter(|s| !s.is_empty())
        .map_or_else(|| PathBuf::from("adb"), PathBuf::from);
    let report = device_run(&adb, &apk, &out, &opts)?;
    print!("{report}");
    Ok(())
}

/// One `adb` invocation's result.
struct Adb<'a> {
    exe: &'a Path,
    serial: Option<String>,
}

impl Adb<'_> {
    fn command(&self, args: &[&str]) -> Command {
        let mut cmd = Command::new(self.exe);
        if let Some(s) = &self.serial {
            cmd.args(["-s", s]);
        }
        cmd.args(args).stdin(Stdio::null());
        cmd
    }

    fn output(&self, args: &[&str]) -> Result<Output, String> {
        self.command(args)
            .output()
            .map_err(|e| adb_spawn_error(self.exe, &e))
    }

    /// stdout + stderr as text, and whether adb exited successfully.
    fn text(&self, args: &[&str]) -> Result<(bool, String), String> {
        let o = self.output(args)?;
        let mut s = String::from_utf8_lossy(&o.stdout).into_owned();
        s.push_str(&String::from_utf8_lossy(&o.stderr));
        Ok((o.status.success(), s))
    }

    fn logcat(&self) -> String {
        self.text(&["logcat", "-d", "-v", "threadtime"])
            .map(|(_, s)| s)
            .unwrap_or_default()
    }
}

fn adb_spawn_error(exe: &Path, e: &std::io::Error) -> String {
    if e.kind() == std::io::ErrorKind::NotFound {
        format!(
            "adb not found (`{}`): install Android platform-tools (Debian: apt-get install adb) \
             or set ADB to its path",
            exe.display()
        )
    } else {
        format!("{}: {e}", exe.display())
    }
}

/// The devices `adb devices` lists: (serial, state).
pub(crate) fn parse_devices(text: &str) -> Vec<(String, String)> {
    text.lines()
        .filter(|l| !l.starts_with("List of devices") && !l.starts_with('*'))
        .filter_map(|l| {
            let mut parts = l.split_whitespace();
            Some((parts.next()?.to_string(), parts.next()?.to_string()))
        })
        .collect()
}

/// The one device to use, or why there is none.
pub(crate) fn pick_device(
    devices: &[(String, String)],
    serial: Option<&str>,
) -> Result<String, String> {
    let state_error = |s: &str, state: &str| match state {
        "unauthorized" => {
            format!("device {s} is unauthorized: unlock it and accept the USB debugging prompt")
        }
        "offline" => format!("device {s} is offline: reconnect it (or `adb kill-server`)"),
        other => format!("device {s} is `{other}`, not ready"),
    };
    if let Some(want) = serial {
        return match devices.iter().find(|(s, _)| s == want) {
            Some((s, st)) if st == "device" => Ok(s.clone()),
            Some((s, st)) => Err(state_error(s, st)),
            None => Err(format!(
                "device {want} not connected (adb devices lists: {})",
                list(devices)
            )),
        };
    }
    match devices {
        [] => Err(
            "no device: `adb devices` lists none (connect a phone with USB debugging on, or \
             start an emulator)"
                .into(),
        ),
        [(s, st)] if st == "device" => Ok(s.clone()),
        [(s, st)] => Err(state_error(s, st)),
        _ => Err(format!(
            "{} devices connected ({}): choose one with --serial or ANDROID_SERIAL",
            devices.len(),
            list(devices)
        )),
    }
}

fn list(devices: &[(String, String)]) -> String {
    if devices.is_empty() {
        return "none".into();
    }
    devices
        .iter()
        .map(|(s, st)| format!("{s} {st}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The lines of `logcat` that tell what went wrong: the app's own (tag `dermis`), crashes
/// (`AndroidRuntime`, `DEBUG` tombstones, `libc` fatal signals), the activity manager's lines
/// about the package — the last [`EXCERPT_LINES`] of them.
pub(crate) fn excerpt(logcat: &str) -> String {
    let relevant: Vec<&str> = logcat
        .lines()
        .filter(|l| {
            l.contains(" dermis")
                || l.contains("/dermis")
                || l.contains("AndroidRuntime")
                || l.contains(" DEBUG ")
                || l.contains("DEBUG  ")
                || l.contains("Fatal signal")
                || (l.contains(PACKAGE)
                    && (l.contains("ActivityManager")
                        || l.contains("ActivityTaskManager")
                        || l.contains("died")))
        })
        .collect();
    let tail = &relevant[relevant.len().saturating_sub(EXCERPT_LINES)..];
    if tail.is_empty() {
        return "  (no logcat lines from the app)\n".into();
    }
    tail.iter().fold(String::new(), |mut s, l| {
        let _ = writeln!(s, "  {l}");
        s
    })
}

/// A crash or an early finish in `logcat`, as a short reason.
pub(crate) fn crash_in(logcat: &str) -> Option<String> {
    for l in logcat.lines() {
        if l.contains("Fatal signal") {
            return Some("the app crashed (fatal signal)".into());
        }
        if l.contains("FATAL EXCEPTION") {
            return Some("the app crashed (Java exception)".into());
        }
        if l.contains("panic in thread") {
            return Some("the app panicked".into());
        }
        if l.contains(&format!("ANR in {PACKAGE}")) {
            return Some("the app stopped responding (ANR)".into());
        }
        if (l.contains(" E dermis") || l.contains("E/dermis")) && l.contains("; finishing") {
            let msg = l.split(": ").skip(1).collect::<Vec<_>>().join(": ");
            return Some(format!("the app refused the soak: {}", msg.trim()));
        }
    }
    None
}

/// The `soak:` lines the app logs at the end (the desktop's summary format).
pub(crate) fn summary_lines(logcat: &str) -> Vec<String> {
    logcat
        .lines()
        .filter_map(|l| {
            let at = l.find("soak: ")?;
            (l.contains("dermis")).then(|| l[at..].to_string())
        })
        .collect()
}

fn fail(what: String, adb: &Adb) -> String {
    format!("{what}; logcat excerpt:\n{}", excerpt(&adb.logcat()))
}

/// Everything after argument parsing: returns the text to print.
pub(crate) fn device_run(
    adb_exe: &Path,
    apk: &Path,
    out: &Path,
    opts: &Options,
) -> Result<String, String> {
    if !apk.is_file() {
        return Err(format!(
            "{} missing: build it with `cargo xtask apk --release`",
            apk.display()
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut adb = Adb {
        exe: adb_exe,
        serial: None,
    };
    let (ok, devices) = adb.text(&["devices"])?;
    if !ok {
        return Err(format!("`adb devices` failed: {}", first_line(&devices)));
    }
    let serial = pick_device(&parse_devices(&devices), opts.serial.as_deref())?;
    adb.serial = Some(serial.clone());
    let mut log = format!("device-run: device {serial}\n");

    // Install.
    let apk_s = apk.to_string_lossy();
    let (ok, text) = adb.text(&["install", "-r", &apk_s])?;
    if !ok || !text.contains("Success") {
        let reason = text
            .lines()
            .find(|l| l.contains("Failure") || l.contains("INSTALL_") || l.contains("error"))
            .unwrap_or_else(|| first_line(&text));
        return Err(format!("install refused: {}", reason.trim()));
    }
    let _ = writeln!(log, "device-run: installed {}", apk.display());

    // A clean start: no old log, no running instance, no old report.
    let _ = adb.text(&["logcat", "-c"]);
    let _ = adb.text(&["shell", "am", "force-stop", PACKAGE]);
    let remote = format!("{REMOTE_DIR}/soak.json");
    let _ = adb.text(&["shell", "rm", "-f", &remote]);
    for name in ["soak.json", "logcat.txt", "screenshot.png"] {
        let _ = std::fs::remove_file(out.join(name));
    }

    let (secs, fps) = (opts.seconds.to_string(), opts.fps.to_string());
    let (ok, text) = adb.text(&[
        "shell",
        "am",
        "start",
        "-W",
        "-n",
        ACTIVITY,
        "--ei",
        "soak_seconds",
        &secs,
        "--es",
        "shading",
        &opts.shading,
        "--ei",
        "target_fps",
        &fps,
    ])?;
    if !ok || text.contains("Error") || text.contains("Exception") {
        // `am` prints "Error type 3" before the line that says what is wrong.
        let reason = text
            .lines()
            .find(|l| l.trim_start().starts_with("Error:"))
            .or_else(|| {
                text.lines()
                    .find(|l| l.contains("Error") || l.contains("Exception"))
            })
            .unwrap_or_else(|| first_line(&text));
        return Err(fail(
            format!("the activity did not start: {}", reason.trim()),
            &adb,
        ));
    }
    let _ = writeln!(
        log,
        "device-run: soak started: {} s, shading {}, {} fps; waiting",
        opts.seconds, opts.shading, opts.fps
    );
    print!("{log}");
    log.clear();

    // Wait for the complete report, watching for crashes.
    let t0 = Instant::now();
    let limit = Duration::from_secs(opts.seconds.into()) + opts.startup_timeout;
    let screenshot_at = Duration::from_secs_f64(f64::from(opts.seconds) * 0.5)
        .min(Duration::from_secs(30))
        + Duration::from_secs(5).min(opts.poll * 3);
    let mut screenshot: Option<Result<(), String>> = None;
    loop {
        std::thread::sleep(opts.poll);
        let (_, report) = adb.text(&["shell", "cat", &remote])?;
        if report_status(&report).as_deref() == Some("complete") {
            break;
        }
        let logcat = adb.logcat();
        if let Some(why) = crash_in(&logcat) {
            return Err(format!("{why}; logcat excerpt:\n{}", excerpt(&logcat)));
        }
        let (_, pid) = adb.text(&["shell", "pidof", PACKAGE])?;
        if pid.trim().is_empty() {
            return Err(fail(
                format!(
                    "the app is not running any more after {:.0} s and wrote no complete \
                     soak.json (crashed or killed)",
                    t0.elapsed().as_secs_f64()
                ),
                &adb,
            ));
        }
        if screenshot.is_none() && t0.elapsed() >= screenshot_at {
            screenshot = Some(take_screenshot(&adb, &out.join("screenshot.png")));
        }
        if t0.elapsed() > limit {
            return Err(fail(
                format!(
                    "timed out after {:.0} s without a complete soak.json",
                    t0.elapsed().as_secs_f64()
                ),
                &adb,
            ));
        }
    }

    // Collect.
    let local = out.join("soak.json");
    let local_s = local.to_string_lossy();
    let (ok, text) = adb.text(&["pull", &remote, &local_s])?;
    if !ok || !local.is_file() {
        return Err(fail(
            format!("adb pull {remote} failed: {}", first_line(&text)),
            &adb,
        ));
    }
    let logcat = adb.logcat();
    let logcat_path = out.join("logcat.txt");
    std::fs::write(&logcat_path, &logcat).map_err(|e| format!("{}: {e}", logcat_path.display()))?;

    let _ = writeln!(
        log,
        "device-run: soak complete in {:.0} s",
        t0.elapsed().as_secs_f64()
    );
    let lines = summary_lines(&logcat);
    if lines.is_empty() {
        let _ = writeln!(log, "  (no `soak:` lines in logcat; see soak.json)");
    }
    for l in lines {
        let _ = writeln!(log, "  {l}");
    }
    let _ = writeln!(log, "device-run: report   {}", local.display());
    let _ = writeln!(log, "device-run: logcat   {}", logcat_path.display());
    match screenshot {
        Some(Ok(())) => {
            let _ = writeln!(
                log,
                "device-run: screen   {}",
                out.join("screenshot.png").display()
            );
        }
        Some(Err(e)) => {
            let _ = writeln!(log, "device-run: no screenshot: {e}");
        }
        None => {
            let _ = writeln!(log, "device-run: no screenshot (the soak ended first)");
        }
    }
    Ok(log)
}

fn first_line(s: &str) -> &str {
    s.lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .trim()
}

/// `status` of a soak report (`None` when the text is not one: no file yet, half-written).
pub(crate) fn report_status(text: &str) -> Option<String> {
    let v: serde_json::Value = serde_json::from_str(text).ok()?;
    v["status"].as_str().map(str::to_string)
}

/// `adb exec-out screencap -p` into `path` (a PNG).
fn take_screenshot(adb: &Adb, path: &Path) -> Result<(), String> {
    let o = adb.output(&["exec-out", "screencap", "-p"])?;
    if !o.status.success() || !o.stdout.starts_with(b"\x89PNG") {
        return Err(format!(
            "screencap gave no PNG: {}",
            first_line(&String::from_utf8_lossy(&o.stderr))
        ));
    }
    std::fs::write(path, &o.stdout).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests;
