//! `cargo xtask android-test`: the native code on real Android bionic, without a phone.
//!
//! 1. Builds the engine's and the game's tests (their unit tests and `engine/tests/`, `game/tests/`: every test that needs no
//!    GPU or window) for `aarch64-linux-android` with the APK's toolchain and link flags
//!    ([`apk::toolchain`]: the generated sysroot, Debian's clang/lld and arm64 libunwind, or
//!    the NDK), in the profile `android-test` (release without LTO, with debug assertions and
//!    overflow checks like the desktop's test profile; `panic = "unwind"`, which libtest needs).
//! 2. Runs every test binary under Debian's `qemu-user-static` on the bionic userland in
//!    `../shared/android-rootfs/api26` (Android 8.0 linker64/libc/libdl, see its SOURCE.md)
//!    and prints libtest's summary per binary and the totals.
//! 3. Checks the packaged `lib/arm64-v8a/libdermis_android.so` of the release APK: its
//!    imports against the real system libraries, symbol versions included (only
//!    `@LIBANDROID` ones may remain: the userland has no libandroid.so), and
//!    `dlopen(RTLD_NOW)` on the userland with a stub `libandroid.so` generated from the
//!    symbol table for this check only.
//!
//! Exits non-zero if any test fails, a binary crashes or times out, or a check fails.

mod imports;
mod qemu_run;

use qemu_run::{run_tests, Counts};

use crate::apk::{self, sysroot, tools, Toolchain};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const PROFILE: &str = "android-test";
/// The platform-free crates whose tests run on bionic.
const PACKAGES: [&str; 2] = ["dermis-engine", "dermis-game"];
const DLOPEN_CHECK: &str = include_str!("dlopen_check.c");

const USAGE: &str = "\
usage: cargo xtask android-test [--build-only] [--no-so] [--apk FILE | --so FILE]
                                [--jobs N] [--timeout SECS] [--no-ndk]

Builds dermis-engine's and dermis-game's unit and integration tests for aarch64-linux-android with the APK's
toolchain (profile android-test: release, no LTO), runs each test binary under
qemu-aarch64-static on the bionic userland, and checks the APK's native library
(symbol-version-aware imports against the real system libraries, dlopen(RTLD_NOW)).
  --build-only     build the test binaries, run nothing
  --no-so          skip the checks of the APK's library
  --apk FILE       APK whose lib/arm64-v8a/libdermis_android.so is checked
                   (default target/apk/dermis-release.apk, built if missing)
  --so FILE        check this library instead of the APK's
  --jobs N         test binaries run at once under qemu (default: the number of CPUs)
  --timeout SECS   limit per test binary (default 1200)
  --no-ndk         ignore ANDROID_NDK_HOME / ANDROID_NDK_ROOT (as `cargo xtask apk --no-ndk`)
Environment:
  DERMIS_ANDROID_ROOTFS   the userland (default ../shared/android-rootfs/api26)
  DERMIS_QEMU             qemu user-mode emulator (default qemu-aarch64-static)
  and those of `cargo xtask apk --help` (toolchain).";

struct Options {
    build_only: bool,
    no_so: bool,
    apk: Option<PathBuf>,
    so: Option<PathBuf>,
    jobs: usize,
    timeout: Duration,
    no_ndk: bool,
}

pub fn run(args: &[String]) -> Result<(), String> {
    let mut opts = Options {
        build_only: false,
        no_so: false,
        apk: None,
        so: None,
        jobs: std::thread::available_parallelism().map_or(2, |n| n.get()),
        timeout: Duration::from_secs(1200),
        no_ndk: false,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| format!("{name} needs a value\n{USAGE}"))
        };
        match a.as_str() {
            "--build-only" => opts.build_only = true,
            "--no-so" => opts.no_so = true,
            "--no-ndk" => opts.no_ndk = true,
            "--apk" => opts.apk = Some(PathBuf::from(value("--apk")?)),
            "--so" => opts.so = Some(PathBuf::from(value("--so")?)),
            "--jobs" => {
                opts.jobs = value("--jobs")?
                    .parse::<usize>()
                    .map_err(|_| "--jobs needs a number".to_string())?
                    .max(1)
            }
            "--timeout" => {
                opts.timeout = Duration::from_secs(
                    value("--timeout")?
                        .parse()
                        .map_err(|_| "--timeout needs seconds".to_string())?,
                )
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }

    let t0 = Instant::now();
    let root = apk::workspace_root();
    let target = apk::target_dir(&root);
    let work = target.join("android-test");
    let api = apk::min_sdk(&root)?;
    let table = apk::load_table(&root)?;
    let rootfs = rootfs(&root)?;
    let qemu = qemu()?;
    let tc = apk::toolchain(&root, api, &table, opts.no_ndk)?;
    println!("android-test: toolchain: {}", tc.description);
    println!("android-test: userland: {}", rootfs.display());

    // 1. Build.
    let t_build = Instant::now();
    let binaries = build_tests(&root, &tc)?;
    let check = build_dlopen_check(&tc, api, &work)?;
    let build_time = t_build.elapsed();
    println!(
        "android-test: built {} test binaries in {:.0}s",
        binaries.len(),
        build_time.as_secs_f64()
    );
    if opts.build_only {
        for b in &binaries {
            println!("  {}", b.exe.display());
        }
        return Ok(());
    }

    // 2. Run.
    let t_run = Instant::now();
    let results = run_tests(&qemu, &rootfs, &work, &binaries, &opts)?;
    let run_time = t_run.elapsed();

    // 3. The APK's library.
    let t_so = Instant::now();
    let so_result = if opts.no_so {
        println!("\n=== APK library: SKIPPED (--no-so)");
        Ok(())
    } else {
        check_library(
            &root, &tc, &table, api, &qemu, &rootfs, &work, &check, &opts,
        )
    };
    let so_time = t_so.elapsed();

    // Summary.
    let mut total = Counts::default();
    let mut bad = Vec::new();
    println!("\n=== android-test summary (bionic API 26 userland under qemu)");
    for r in &results {
        total.add(&r.counts);
        let status = match &r.error {
            None => "ok  ",
            Some(_) => "FAIL",
        };
        println!(
            "  {status} {:<34} {:>4} passed {:>3} failed {:>3} ignored  {:>6.1}s{}",
            r.name,
            r.counts.passed,
            r.counts.failed,
            r.counts.ignored,
            r.time.as_secs_f64(),
            r.error
                .as_ref()
                .map_or(String::new(), |e| format!("  ({e})"))
        );
        if r.error.is_some() {
            bad.push(r.name.clone());
        }
    }
    println!(
        "  total: {} test binaries, {} passed, {} failed, {} ignored",
        results.len(),
        total.passed,
        total.failed,
        total.ignored
    );
    match &so_result {
        Ok(()) if opts.no_so => {}
        Ok(()) => println!("  APK library: imports and dlopen(RTLD_NOW) OK"),
        Err(e) => println!("  APK library: FAILED: {e}"),
    }
    println!(
        "  timings: build {:.0}s, test runs {:.0}s, library checks {:.0}s, total {:.0}s",
        build_time.as_secs_f64(),
        run_time.as_secs_f64(),
        so_time.as_secs_f64(),
        t0.elapsed().as_secs_f64()
    );
    if !bad.is_empty() {
        return Err(format!(
            "{} test binar{} failed on bionic: {} (logs in {})",
            bad.len(),
            if bad.len() == 1 { "y" } else { "ies" },
            bad.join(", "),
            work.join("logs").display()
        ));
    }
    so_result.map_err(|e| format!("APK library check failed: {e}"))
}

fn rootfs(root: &Path) -> Result<PathBuf, String> {
    let dir = match std::env::var_os("DERMIS_ANDROID_ROOTFS") {
        Some(d) => PathBuf::from(d),
        None => root.join("../shared/android-rootfs/api26"),
    };
    let linker = dir.join("system/bin/linker64");
    if !linker.is_file() {
        return Err(format!(
            "no bionic userland: {} missing (see ../shared/android-rootfs/SOURCE.md, or set \
             DERMIS_ANDROID_ROOTFS)",
            linker.display()
        ));
    }
    // Absolute: the test binaries run with their package folder as working directory.
    dir.canonicalize()
        .map_err(|e| format!("{}: {e}", dir.display()))
}

fn qemu() -> Result<PathBuf, String> {
    let name = std::env::var("DERMIS_QEMU").unwrap_or_else(|_| "qemu-aarch64-static".into());
    tools::require(&name, "apt-get install qemu-user-static")
}

/// A test executable cargo built.
struct TestBinary {
    /// `unittests/<crate>` for a library's, else `tests/<name>` for an integration test.
    name: String,
    exe: PathBuf,
    /// The package folder: cargo runs tests there.
    cwd: PathBuf,
}

/// The cargo command building (or describing) the tests for Android.
fn cargo_tests(root: &Path, tc: &Toolchain) -> Command {
    let mut cmd = apk::cargo();
    cmd.current_dir(root).arg("test");
    for package in PACKAGES {
        cmd.args(["-p", package]);
    }
    cmd.args(["--target", apk::TARGET, "--profile", PROFILE, "--locked"]);
    // A profile of this command only (the workspace's Cargo.toml is left alone): optimised
    // like release, the desktop tests' checks. No LTO: on 2 cores the build takes ~5 min from
    // scratch, against ~11 with thin LTO (each test binary is an LTO link of wgpu and naga).
    for setting in [
        "inherits=\"release\"",
        "lto=\"off\"",
        "debug=false",
        "debug-assertions=true",
        "overflow-checks=true",
    ] {
        cmd.arg("--config")
            .arg(format!("profile.{PROFILE}.{setting}"));
    }
    cmd.env(
        format!(
            "CARGO_TARGET_{}_LINKER",
            apk::TARGET.to_uppercase().replace('-', "_")
        ),
        &tc.linker,
    );
    // The APK passes its link arguments to the final crate only; here every test binary is a
    // final crate. Target flags only (`--target` keeps them off build scripts and macros).
    let flags: Vec<String> = tc
        .link_args
        .iter()
        .map(|a| format!("-Clink-arg={a}"))
        .collect();
    cmd.env("CARGO_ENCODED_RUSTFLAGS", flags.join("\u{1f}"))
        .env_remove("RUSTFLAGS");
    for (k, v) in &tc.env {
        cmd.env(k, v);
    }
    cmd
}

fn build_tests(root: &Path, tc: &Toolchain) -> Result<Vec<TestBinary>, String> {
    let mut cmd = cargo_tests(root, tc);
    cmd.args(["--no-run", "--message-format=json-render-diagnostics"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    let out = cmd.output().map_err(|e| format!("cannot run cargo: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "building the tests for {} failed ({})",
            apk::TARGET,
            out.status
        ));
    }
    let mut binaries = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if msg["reason"] != "compiler-artifact" || msg["profile"]["test"] != true {
            continue;
        }
        let Some(exe) = msg["executable"].as_str() else {
            continue;
        };
        let kinds = msg["target"]["kind"]
            .as_array()
            .cloned()
            .unwrap_or_default();
        let name = if kinds.iter().any(|k| k == "test") {
            format!("tests/{}", msg["target"]["name"].as_str().unwrap_or("?"))
        } else {
            // One per crate: the name is also the log's file name, so two crates' unit tests
            // running side by side must not share it.
            format!(
                "unittests/{}",
                msg["target"]["name"].as_str().unwrap_or("?")
            )
        };
        let manifest = PathBuf::from(msg["manifest_path"].as_str().unwrap_or_default());
        binaries.push(TestBinary {
            name,
            exe: PathBuf::from(exe),
            cwd: manifest
                .parent()
                .map_or_else(|| root.to_path_buf(), Path::to_path_buf),
        });
    }
    if binaries.is_empty() {
        return Err("cargo built no test binaries".into());
    }
    // The unit tests take longest under qemu: first, so the integration tests run beside them.
    let unit = |b: &TestBinary| !b.name.starts_with("unittests/");
    binaries.sort_by(|a, b| (unit(a), &a.name).cmp(&(unit(b), &b.name)));
    Ok(binaries)
}

/// The dlopen check: a small C executable linked like the tests.
fn build_dlopen_check(tc: &Toolchain, api: u32, work: &Path) -> Result<PathBuf, String> {
    let src = work.join("src/dlopen_check.c");
    let exe = work.join("bin/dlopen_check");
    tools::write(&src, DLOPEN_CHECK)?;
    tools::mkdir(exe.parent().unwrap())?;
    tools::run(
        Command::new(&tc.linker)
            .args(&tc.link_args)
            .arg(format!("-DDERMIS_API_LEVEL={api}"))
            .args(["-O2", "-fPIE", "-pie", "-ffreestanding", "-nodefaultlibs"])
            .arg("-o")
            .arg(&exe)
            .arg(&src)
            .args(["-ldl", "-lc"]),
    )?;
    Ok(exe)
}

/// The release APK's library (built when missing), or `--so`.
fn library(root: &Path, work: &Path, opts: &Options) -> Result<PathBuf, String> {
    if let Some(so) = &opts.so {
        return Ok(so.clone());
    }
    let apk_path = match &opts.apk {
        Some(p) => p.clone(),
        None => {
            let p = apk::target_dir(root).join("apk/dermis-release.apk");
            if !p.is_file() {
                println!(
                    "android-test: {} missing: building it (`cargo xtask apk --release`)",
                    p.display()
                );
                apk::run(&["--release".to_string()])?;
            }
            p
        }
    };
    let entry = format!("lib/arm64-v8a/lib{}.so", apk::LIB_NAME);
    let so = work.join(format!("lib{}.so", apk::LIB_NAME));
    let unzip = tools::require("unzip", "apt-get install unzip")?;
    let out = tools::output(Command::new(unzip).arg("-p").arg(&apk_path).arg(&entry))?;
    if out.stdout.is_empty() {
        return Err(format!("{} has no {entry}", apk_path.display()));
    }
    tools::write(&so, &out.stdout)?;
    println!("android-test: checking {entry} of {}", apk_path.display());
    Ok(so)
}

#[allow(clippy::too_many_arguments)]
fn check_library(
    root: &Path,
    tc: &Toolchain,
    table: &[apk::symbols::Symbol],
    api: u32,
    qemu: &Path,
    rootfs: &Path,
    work: &Path,
    check: &Path,
    opts: &Options,
) -> Result<(), String> {
    println!("\n=== APK library");
    let so = library(root, work, opts)?;

    // Imports, symbol versions included, against the real system libraries.
    let report = imports::check(&tc.readelf, &so, &rootfs.join("system/lib64"))?;
    print!("{}", report.text);
    let import_result = if report.failures == 0 {
        println!(
            "imports OK: {} undefined symbols; all resolve against {} except the {} from {} \
             (not in the userland: left to the device)",
            report.imports,
            report.found_libraries.join(" "),
            report.left.len(),
            report.missing_libraries.join(" ")
        );
        Ok(())
    } else {
        Err(format!(
            "{} import(s) unresolved outside @LIBANDROID",
            report.failures
        ))
    };

    // dlopen(RTLD_NOW) with stubs for the libraries the userland lacks.
    let llvm = sysroot::Llvm::find()?;
    let stubs = work.join("stubs");
    for lib in &report.missing_libraries {
        let name = lib.trim_end_matches(".so");
        if !apk::symbols::LIBRARIES.contains(&name) {
            return Err(format!(
                "no stub for {lib}: not a platform library of the table"
            ));
        }
        sysroot::stub_library(&llvm, table, name, api, &work.join("stub-src"), &stubs)?;
    }
    let out = Command::new(qemu)
        .arg("-L")
        .arg(rootfs)
        .arg(check)
        .arg(&so)
        .env(
            "LD_LIBRARY_PATH",
            format!("/system/lib64:{}", stubs.display()),
        )
        .output()
        .map_err(|e| format!("cannot run {}: {e}", qemu.display()))?;
    print!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let dlopen_result = if out.status.success() {
        println!(
            "dlopen OK with stub {} (the {} symbols left to the device: {})",
            report.missing_libraries.join(" "),
            report.left.len(),
            report.left.join(" ")
        );
        Ok(())
    } else {
        Err(format!("dlopen(RTLD_NOW) failed ({})", out.status))
    };
    import_result.and(dlopen_result)
}
