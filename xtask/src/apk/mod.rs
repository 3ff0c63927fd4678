//! `cargo xtask apk [--release]`: builds a signed, aligned arm64-v8a APK of `android_app/`.
//!
//! Two toolchain paths:
//! 1. `ANDROID_NDK_HOME` (or `ANDROID_NDK_ROOT`) set: the NDK's clang links (untested here).
//! 2. Otherwise (CI, any Debian/Ubuntu machine): Debian's clang/lld/llvm (19 preferred) link
//!    against a sysroot generated under `target/android-sysroot/` from the committed symbol
//!    table `tools/ndk-table/ndk-symbols.tsv` (see [`symbols`] and [`sysroot`]).
//!
//! Packaging uses Debian's `aapt`, `zipalign`, `apksigner` and
//! `/usr/share/android-framework-res/framework-res.apk`.
//!
//! Other forms:
//! - `cargo xtask apk --check-table`: re-derive the table from `../shared/ndk-symbols` and
//!   compare (skipped, with a message, when the maps are absent);
//! - `cargo xtask apk --write-table`: regenerate the table from the maps;
//! - `cargo xtask apk --check-imports <lib.so>`: every undefined symbol of the library must be
//!   in the table at an API level ≤ the manifest's minSdk.

mod glb_images;
mod package;
pub(crate) mod symbols;
pub(crate) mod sysroot;
pub(crate) mod tools;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

pub(crate) const TARGET: &str = "aarch64-linux-android";
const CRATE: &str = "dermis-android";
pub(crate) const LIB_NAME: &str = "dermis_android";

const USAGE: &str = "\
usage: cargo xtask apk [--release] [--thin-lto] [--no-ndk]
       cargo xtask apk --check-table | --write-table
       cargo xtask apk --check-imports <lib.so>
       cargo xtask apk --clippy

Builds target/apk/dermis-{debug,release}.apk (arm64-v8a, signed v2+v3, zipaligned to 16384).
  --release   release profile for size: fat LTO, opt-level s, one codegen unit,
              panic=abort, stripped (the APK CI checks against the 6 MB budget)
  --thin-lto  release with thin LTO: faster to build, ~0.5 MB bigger (over budget)
              (`--fat-lto`, the default now, is still accepted)
  --no-ndk    ignore ANDROID_NDK_HOME / ANDROID_NDK_ROOT and use the Debian toolchain
  --clippy    clippy -D warnings on dermis-android for aarch64-linux-android (release
              profile, so it shares host build scripts and proc-macros with `--release`)
Environment:
  ANDROID_NDK_HOME / ANDROID_NDK_ROOT   use the NDK's clang (untested path)
  DERMIS_CLANG                          clang to use without the NDK (default: clang-19..16)
  DERMIS_LIBUNWIND                      arm64 libunwind.a or libunwind-19-dev_*_arm64.deb
  DERMIS_NDK_SYMBOLS                    symbol maps dir (default: ../shared/ndk-symbols)
  DERMIS_KEYSTORE, DERMIS_KEYSTORE_PASS, DERMIS_KEY_ALIAS, DERMIS_KEY_PASS
                                        release signing key (else the debug key, with a warning)
  DERMIS_APK_VERBOSE                    print every command";

struct Options {
    release: bool,
    fat_lto: bool,
    no_ndk: bool,
}

pub fn run(args: &[String]) -> Result<(), String> {
    let root = workspace_root();
    let mut opts = Options {
        release: false,
        fat_lto: false,
        no_ndk: false,
    };
    let mut thin_lto = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--release" | "--fat-lto" => opts.release = true,
            "--thin-lto" => thin_lto = true,
            "--no-ndk" => opts.no_ndk = true,
            "--check-table" => return check_table(&root, false),
            "--write-table" => return check_table(&root, true),
            "--clippy" => return clippy(&root),
            "--check-imports" => {
                let so = it.next().ok_or("--check-imports needs a path")?;
                return check_imports_cmd(&root, Path::new(so));
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    // Fat LTO unless asked otherwise: thin LTO leaves the APK ~0.5 MB over the 6 MB budget.
    opts.release |= thin_lto;
    opts.fat_lto = opts.release && !thin_lto;
    build(&root, &opts)
}

/// The profile settings of an APK release build (environment overrides of
/// `[profile.release]`, so the workspace's desktop release profile is left alone), chosen
/// for size (issue 11, APK ≤ 6 MB): with opt-level "s", one codegen unit (and no JPEG
/// decoder, `dermis-engine` without default features) the stripped library went from 6.8 MB
/// (thin LTO, opt-level 3) to 5.0 MB with thin LTO and 4.5 MB with fat LTO; panic = "abort"
/// drops the landing pads (the unwind tables stay: the panic hook logs a backtrace).
fn release_profile_env(cmd: &mut Command, fat_lto: bool) {
    cmd.env(
        "CARGO_PROFILE_RELEASE_LTO",
        if fat_lto { "fat" } else { "thin" },
    )
    .env("CARGO_PROFILE_RELEASE_PANIC", "abort")
    .env("CARGO_PROFILE_RELEASE_DEBUG", "false")
    .env("CARGO_PROFILE_RELEASE_OPT_LEVEL", "s")
    .env("CARGO_PROFILE_RELEASE_CODEGEN_UNITS", "1");
}

pub(crate) fn cargo() -> Command {
    Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
}

/// `--clippy`: no linking, so no toolchain is needed.
fn clippy(root: &Path) -> Result<(), String> {
    let mut cmd = cargo();
    cmd.current_dir(root).args([
        "clippy",
        "--release",
        "-p",
        CRATE,
        "--no-deps",
        "--target",
        TARGET,
        "--all-targets",
        "--",
        "-D",
        "warnings",
    ]);
    release_profile_env(&mut cmd, true);
    tools::run(&mut cmd)
}

pub(crate) fn workspace_root() -> PathBuf {
    let xtask = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    xtask.parent().map(Path::to_path_buf).unwrap_or(xtask)
}

pub(crate) fn target_dir(root: &Path) -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) => root.join(d),
        None => root.join("target"),
    }
}

fn table_path(root: &Path) -> PathBuf {
    root.join("tools/ndk-table/ndk-symbols.tsv")
}

fn maps_dir(root: &Path) -> PathBuf {
    match std::env::var_os("DERMIS_NDK_SYMBOLS") {
        Some(d) => PathBuf::from(d),
        None => root.join("../shared/ndk-symbols"),
    }
}

/// `--check-table` / `--write-table`.
fn check_table(root: &Path, write: bool) -> Result<(), String> {
    let maps = maps_dir(root);
    if !maps.join("libc.map.txt").is_file() {
        if write {
            return Err(format!("no symbol maps at {}", maps.display()));
        }
        println!(
            "table check SKIPPED: no symbol maps at {} (the committed table is used as is)",
            maps.display()
        );
        return Ok(());
    }
    let derived = symbols::to_tsv(&symbols::table_from_maps(&maps)?);
    let path = table_path(root);
    if write {
        tools::write(&path, &derived)?;
        println!("wrote {}", path.display());
        return Ok(());
    }
    let committed =
        std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    if committed == derived {
        let n = derived.lines().filter(|l| !l.starts_with('#')).count();
        println!(
            "table check OK: {} matches the maps ({n} symbols)",
            path.display()
        );
        Ok(())
    } else {
        Err(format!(
            "{} does not match the maps in {}; run `cargo xtask apk --write-table`",
            path.display(),
            maps.display()
        ))
    }
}

/// The table: the committed one (checked against the maps when they are present).
pub(crate) fn load_table(root: &Path) -> Result<Vec<symbols::Symbol>, String> {
    let path = table_path(root);
    match std::fs::read_to_string(&path) {
        Ok(text) => {
            check_table(root, false)?;
            symbols::from_tsv(&text)
        }
        Err(_) => {
            let maps = maps_dir(root);
            eprintln!(
                "apk: {} missing, deriving from {}",
                path.display(),
                maps.display()
            );
            symbols::table_from_maps(&maps)
        }
    }
}

fn manifest_path(root: &Path) -> PathBuf {
    root.join("android_app/AndroidManifest.xml")
}

/// `android:minSdkVersion` from the manifest (the single source of the API level).
pub(crate) fn min_sdk(root: &Path) -> Result<u32, String> {
    let path = manifest_path(root);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let key = "android:minSdkVersion=\"";
    let start = text
        .find(key)
        .ok_or_else(|| format!("{}: no android:minSdkVersion", path.display()))?
        + key.len();
    let end = text[start..]
        .find('"')
        .ok_or("unterminated minSdkVersion")?;
    text[start..start + end]
        .parse()
        .map_err(|_| format!("{}: bad minSdkVersion", path.display()))
}

fn check_imports_cmd(root: &Path, so: &Path) -> Result<(), String> {
    let table = load_table(root)?;
    let api = min_sdk(root)?;
    let readelf = tools::first_of(
        &(16..=19)
            .rev()
            .map(|v| format!("llvm-readelf-{v}"))
            .chain(["llvm-readelf".to_string()])
            .collect::<Vec<_>>(),
    )
    .ok_or("llvm-readelf not found (apt-get install llvm-19)")?;
    check_imports(&readelf, &table, so, api)
}

fn check_imports(
    readelf: &Path,
    table: &[symbols::Symbol],
    so: &Path,
    api: u32,
) -> Result<(), String> {
    let out = tools::output(Command::new(readelf).args(["--dyn-syms", "--wide"]).arg(so))?;
    let imports = symbols::parse_readelf_imports(&String::from_utf8_lossy(&out.stdout));
    let (report, failures) = symbols::check_imports(table, &imports, api);
    print!("{report}");
    if failures == 0 {
        println!(
            "imports OK: all {} undefined symbols of {} are in the platform maps at API <= {api}",
            imports.len(),
            so.display()
        );
        Ok(())
    } else {
        Err(format!(
            "{failures} undefined symbol(s) not available at API {api}"
        ))
    }
}

/// How the `.so` (and the executables of `cargo xtask android-test`) are linked.
pub(crate) struct Toolchain {
    pub linker: PathBuf,
    pub link_args: Vec<String>,
    pub strip: PathBuf,
    pub readelf: PathBuf,
    /// Extra environment for cargo (C compiler for build scripts using the `cc` crate).
    pub env: Vec<(String, PathBuf)>,
    pub description: String,
}

/// The toolchain `cargo xtask apk` links with: the NDK's when `ANDROID_NDK_HOME` /
/// `ANDROID_NDK_ROOT` is set (unless `no_ndk`), else Debian's clang with the generated
/// sysroot (built or refreshed here).
pub(crate) fn toolchain(
    root: &Path,
    api: u32,
    table: &[symbols::Symbol],
    no_ndk: bool,
) -> Result<Toolchain, String> {
    match ndk_home().filter(|_| !no_ndk) {
        Some(ndk) => ndk_toolchain(&ndk, api),
        None => debian_toolchain(root, &target_dir(root), api, table),
    }
}

fn ndk_home() -> Option<PathBuf> {
    ["ANDROID_NDK_HOME", "ANDROID_NDK_ROOT"]
        .iter()
        .filter_map(std::env::var_os)
        .map(PathBuf::from)
        .find(|p| !p.as_os_str().is_empty())
}

/// NDK r23+ layout: `toolchains/llvm/prebuilt/<host>/bin/{clang,llvm-strip,llvm-readelf}`.
/// Not tested by this project's CI (no NDK there).
fn ndk_toolchain(ndk: &Path, api: u32) -> Result<Toolchain, String> {
    let prebuilt = ndk.join("toolchains/llvm/prebuilt");
    let host = ["linux-x86_64", "darwin-x86_64", "windows-x86_64"]
        .iter()
        .map(|h| prebuilt.join(h))
        .find(|p| p.is_dir())
        .ok_or_else(|| format!("{}: no toolchains/llvm/prebuilt/<host>", ndk.display()))?;
    let bin = host.join("bin");
    let exe = |name: &str| {
        let p = bin.join(name);
        if p.is_file() {
            Ok(p)
        } else {
            Err(format!("{} missing in the NDK", p.display()))
        }
    };
    Ok(Toolchain {
        linker: exe("clang")?,
        link_args: vec![
            format!("--target={TARGET}{api}"),
            "-Wl,-z,max-page-size=16384".into(),
            "-Wl,--no-undefined".into(),
            "-Wl,--build-id".into(),
        ],
        strip: exe("llvm-strip")?,
        readelf: exe("llvm-readelf")?,
        env: vec![
            (
                "CC_aarch64_linux_android".into(),
                exe(&format!("{TARGET}{api}-clang"))?,
            ),
            ("AR_aarch64_linux_android".into(), exe("llvm-ar")?),
        ],
        description: format!("NDK at {}", ndk.display()),
    })
}

fn debian_toolchain(
    root: &Path,
    target: &Path,
    api: u32,
    table: &[symbols::Symbol],
) -> Result<Toolchain, String> {
    let llvm = sysroot::Llvm::find()?;
    let libunwind = sysroot::libunwind(&target.join("android-deps"))?;
    let sysroot = sysroot::build(
        &llvm,
        table,
        api,
        &target.join("android-sysroot"),
        &libunwind,
    )?;
    let _ = root;
    let suffix = llvm.version.map_or(String::new(), |v| format!("-{v}"));
    let readelf = tools::first_of(&[format!("llvm-readelf{suffix}"), "llvm-readelf".into()])
        .ok_or("llvm-readelf not found")?;
    Ok(Toolchain {
        link_args: vec![
            format!("--target={TARGET}{api}"),
            format!("--sysroot={}", sysroot.display()),
            "-fuse-ld=lld".into(),
            "-Wl,--no-dependent-libraries".into(),
            "-Wl,-z,max-page-size=16384".into(),
            "-Wl,--no-undefined".into(),
            "-Wl,--build-id".into(),
        ],
        description: format!(
            "no NDK: {} + generated sysroot {}",
            llvm.clang.display(),
            sysroot.display()
        ),
        linker: llvm.clang,
        strip: llvm.strip,
        readelf,
        env: Vec::new(),
    })
}

fn build(root: &Path, opts: &Options) -> Result<(), String> {
    let t0 = Instant::now();
    let target = target_dir(root);
    let api = min_sdk(root)?;
    let table = load_table(root)?;
    let tc = toolchain(root, api, &table, opts.no_ndk)?;
    println!("apk: toolchain: {}", tc.description);
    let t_sysroot = t0.elapsed();

    // Cross build. The link arguments go to the final crate only (`cargo rustc -- ...`), so
    // dependencies keep the fingerprints of a plain `cargo build --target aarch64-linux-android`.
    let profile = if opts.release { "release" } else { "debug" };
    let mut cmd = cargo();
    cmd.current_dir(root)
        .args(["rustc", "-p", CRATE, "--lib", "--target", TARGET]);
    if opts.release {
        cmd.arg("--release");
        release_profile_env(&mut cmd, opts.fat_lto);
    }
    cmd.env("CARGO_TARGET_AARCH64_LINUX_ANDROID_LINKER", &tc.linker);
    for (k, v) in &tc.env {
        cmd.env(k, v);
    }
    cmd.arg("--");
    for a in &tc.link_args {
        cmd.arg(format!("-Clink-arg={a}"));
    }
    let t1 = Instant::now();
    tools::run(&mut cmd)?;
    let t_cargo = t1.elapsed();

    let so = target
        .join(TARGET)
        .join(profile)
        .join(format!("lib{LIB_NAME}.so"));
    if !so.is_file() {
        return Err(format!("{} was not produced", so.display()));
    }
    check_imports(&tc.readelf, &table, &so, api)?;

    // Stage: stripped library + assets.
    let t2 = Instant::now();
    let work = target.join("apk").join(profile);
    let stage = work.join("root");
    if stage.exists() {
        std::fs::remove_dir_all(&stage).map_err(|e| format!("{}: {e}", stage.display()))?;
    }
    let staged_so = stage.join(format!("native/lib/arm64-v8a/lib{LIB_NAME}.so"));
    tools::mkdir(staged_so.parent().unwrap())?;
    tools::run(
        Command::new(&tc.strip)
            .arg("--strip-all")
            .arg(&so)
            .arg("-o")
            .arg(&staged_so),
    )?;
    let n_assets = package::stage_assets(&root.join("assets"), &stage.join("assets"))?;

    let apk = target.join("apk").join(format!("dermis-{profile}.apk"));
    package::package(&package::Package {
        manifest: &manifest_path(root),
        res: &root.join("android_app/res"),
        stage: &stage,
        work: &work,
        debug: !opts.release,
        min_sdk: api,
        keystore_dir: &target.join("android-keystore"),
        out: &apk,
    })?;
    let t_pkg = t2.elapsed();

    let size = std::fs::metadata(&apk).map(|m| m.len()).unwrap_or(0);
    let so_size = std::fs::metadata(&staged_so).map(|m| m.len()).unwrap_or(0);
    println!(
        "apk: {} ({:.2} MB; lib{LIB_NAME}.so {:.2} MB stripped; {n_assets} asset file(s))",
        apk.display(),
        size as f64 / 1e6,
        so_size as f64 / 1e6
    );
    println!(
        "apk: timings: toolchain/sysroot {:.1}s, cargo {:.1}s, package+sign {:.1}s, total {:.1}s",
        t_sysroot.as_secs_f64(),
        t_cargo.as_secs_f64(),
        t_pkg.as_secs_f64(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}
