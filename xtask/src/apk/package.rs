//! APK packaging with Debian's `aapt`, `zipalign` and `apksigner`.
//!
//! - `aapt package -I framework-res.apk` (Debian has no `android.jar`), `resources.arsc` and
//!   the `.so` stored (`-0 arsc -0 so`): targetSdk >= 30 refuses a compressed or unaligned
//!   `resources.arsc`, and a stored, page-aligned `.so` is loaded straight from the APK;
//! - `zipalign -f 16384` (Debian's zipalign has no `-P`; 16384 aligns every stored entry, the
//!   `.so` included, to 16 KB pages);
//! - `apksigner sign` with v2 + v3 (v1 is not needed for minSdk 26). The debug keystore is
//!   generated with `keytool` under `target/android-keystore/` (never committed); release
//!   builds use `DERMIS_KEYSTORE` & co. when set.

use super::tools;
use std::path::{Path, PathBuf};
use std::process::Command;

pub const FRAMEWORK_RES: &str = "/usr/share/android-framework-res/framework-res.apk";

pub struct Package<'a> {
    pub manifest: &'a Path,
    pub res: &'a Path,
    /// Holds `assets/…` and `native/lib/arm64-v8a/*.so`.
    pub stage: &'a Path,
    pub work: &'a Path,
    pub debug: bool,
    pub min_sdk: u32,
    pub keystore_dir: &'a Path,
    pub out: &'a Path,
}

/// Copies the repository's `assets/` into `dest` (every file but dot-files and `*.md`
/// documentation) as the phone reads them: textures as their ETC2 encodings only (every
/// Android GPU samples ETC2; no BC, no PNG/JPEG source beside an encoding), each `.glb`'s
/// embedded images replaced by a reference to their encoding ([`super::glb_images`]); the
/// scanned head with its licence. Returns the number of files.
pub fn stage_assets(src: &Path, dest: &Path) -> Result<usize, String> {
    let mut n = 0;
    if !src.is_dir() {
        return Ok(0);
    }
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let rd = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
        entries.sort();
        for p in entries {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            // `.lut`, `.tables`, `.table`: the optics tables are compiled into the library
            // (`include_bytes!`), a copy among the assets would be dead weight.
            let baked = [".lut", ".tables", ".table"]
                .iter()
                .any(|e| name.ends_with(e));
            // Block encodings the phone does not read (BC: desktop GPUs).
            let desktop = name.ends_with(".ktx2") && !name.ends_with(".etc2.ktx2");
            if name.starts_with('.') || name.ends_with(".md") || baked || desktop {
                continue;
            }
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            if !p.is_file() {
                continue;
            }
            let rel = p.strip_prefix(src).map_err(|e| e.to_string())?;
            // A standalone image (the head's maps) that has its ETC2 encodings: the source
            // stays on the desktop.
            let encodings = p.with_file_name(format!("{name}.textures"));
            let glb = name.ends_with(".glb");
            if !glb && has_etc2(&encodings) {
                continue;
            }
            if glb {
                let glb = std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()))?;
                let etc2 = |image: usize| etc2_encoding(&encodings, name, image);
                let (out, _) = super::glb_images::point_images_at(&glb, &etc2)
                    .map_err(|e| format!("{}: {e}", p.display()))?;
                let to = dest.join(rel);
                tools::mkdir(to.parent().unwrap_or(dest))?;
                std::fs::write(&to, out).map_err(|e| format!("{}: {e}", to.display()))?;
            } else {
                tools::copy(&p, &dest.join(rel))?;
            }
            n += 1;
        }
    }
    Ok(n)
}

fn etc2_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.flatten()
                .filter_map(|e| e.file_name().to_str().map(str::to_owned))
                .filter(|n| n.ends_with(".etc2.ktx2"))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

fn has_etc2(dir: &Path) -> bool {
    !etc2_files(dir).is_empty()
}

/// The URI (relative to the `.glb`) of image `image`'s ETC2 encoding, if it has one.
fn etc2_encoding(dir: &Path, glb: &str, image: usize) -> Option<String> {
    etc2_files(dir)
        .into_iter()
        .find(|n| n.starts_with(&format!("{image}-")))
        .map(|n| format!("{glb}.textures/{n}"))
}

struct SigningKey {
    keystore: PathBuf,
    alias: String,
    /// apksigner password specs (`pass:…` or `env:NAME`).
    ks_pass: String,
    key_pass: String,
}

fn debug_key(dir: &Path) -> Result<SigningKey, String> {
    let keystore = dir.join("debug.keystore");
    if !keystore.is_file() {
        tools::mkdir(dir)?;
        let keytool = tools::require("keytool", "apt-get install openjdk-17-jre-headless")?;
        println!("apk: generating debug keystore {}", keystore.display());
        tools::output(
            Command::new(keytool)
                .args(["-genkeypair", "-keystore"])
                .arg(&keystore)
                .args([
                    "-storetype",
                    "PKCS12",
                    "-storepass",
                    "android",
                    "-keypass",
                    "android",
                    "-alias",
                    "androiddebugkey",
                    "-keyalg",
                    "RSA",
                    "-keysize",
                    "2048",
                    "-validity",
                    "10000",
                    "-dname",
                    "CN=Android Debug,O=Android,C=US",
                ]),
        )?;
    }
    Ok(SigningKey {
        keystore,
        alias: "androiddebugkey".into(),
        ks_pass: "pass:android".into(),
        key_pass: "pass:android".into(),
    })
}

/// Release key from the environment: `DERMIS_KEYSTORE` (path), `DERMIS_KEYSTORE_PASS`,
/// `DERMIS_KEY_ALIAS`, optional `DERMIS_KEY_PASS` (defaults to the keystore password).
/// Passwords are handed to apksigner as `env:NAME`, never on the command line.
fn release_key() -> Result<Option<SigningKey>, String> {
    let Some(ks) = std::env::var_os("DERMIS_KEYSTORE") else {
        return Ok(None);
    };
    let need = |v: &str| {
        std::env::var(v)
            .map_err(|_| format!("DERMIS_KEYSTORE is set but {v} is not"))
            .map(|_| ())
    };
    need("DERMIS_KEYSTORE_PASS")?;
    let alias = std::env::var("DERMIS_KEY_ALIAS")
        .map_err(|_| "DERMIS_KEYSTORE is set but DERMIS_KEY_ALIAS is not".to_string())?;
    let key_pass = if std::env::var_os("DERMIS_KEY_PASS").is_some() {
        "env:DERMIS_KEY_PASS"
    } else {
        "env:DERMIS_KEYSTORE_PASS"
    };
    Ok(Some(SigningKey {
        keystore: PathBuf::from(ks),
        alias,
        ks_pass: "env:DERMIS_KEYSTORE_PASS".into(),
        key_pass: key_pass.into(),
    }))
}

pub fn package(p: &Package) -> Result<(), String> {
    let aapt = tools::require("aapt", "apt-get install aapt")?;
    let zipalign = tools::require("zipalign", "apt-get install zipalign")?;
    let apksigner = tools::require("apksigner", "apt-get install apksigner")?;
    if !Path::new(FRAMEWORK_RES).is_file() {
        return Err(format!(
            "{FRAMEWORK_RES} missing (apt-get install android-framework-res)"
        ));
    }
    tools::mkdir(p.work)?;
    let unsigned = p.work.join("unsigned.apk");
    let aligned = p.work.join("aligned.apk");
    for f in [&unsigned, &aligned] {
        let _ = std::fs::remove_file(f);
    }

    let mut cmd = Command::new(&aapt);
    cmd.args(["package", "-f", "-M"])
        .arg(p.manifest)
        .arg("-I")
        .arg(FRAMEWORK_RES)
        .args(["-0", "arsc", "-0", "so"]);
    if p.res.is_dir() {
        cmd.arg("-S").arg(p.res);
    }
    let assets = p.stage.join("assets");
    if assets.is_dir() {
        cmd.arg("-A").arg(&assets);
    }
    if p.debug {
        cmd.arg("--debug-mode");
    }
    // Raw-files directory holding `lib/arm64-v8a/*.so`: added at the APK root, stored
    // (`-0 so`; `aapt add` would ignore `-0` and deflate it).
    cmd.arg("-F").arg(&unsigned).arg(p.stage.join("native"));
    tools::output(&mut cmd)?;

    tools::output(
        Command::new(&zipalign)
            .args(["-f", "16384"])
            .arg(&unsigned)
            .arg(&aligned),
    )?;

    let key = match release_key()? {
        Some(k) if !p.debug => k,
        _ => {
            if !p.debug {
                println!(
                    "apk: WARNING: DERMIS_KEYSTORE not set, the release APK is signed with the debug key"
                );
            }
            debug_key(p.keystore_dir)?
        }
    };
    if let Some(dir) = p.out.parent() {
        tools::mkdir(dir)?;
    }
    tools::output(
        Command::new(&apksigner)
            .args(["sign", "--ks"])
            .arg(&key.keystore)
            .args(["--ks-key-alias", &key.alias])
            .args(["--ks-pass", &key.ks_pass])
            .args(["--key-pass", &key.key_pass])
            .args([
                "--min-sdk-version",
                &p.min_sdk.to_string(),
                "--v1-signing-enabled",
                "false",
                "--v2-signing-enabled",
                "true",
                "--v3-signing-enabled",
                "true",
                "--out",
            ])
            .arg(p.out)
            .arg(&aligned),
    )?;
    let _ = std::fs::remove_file(p.out.with_extension("apk.idsig"));
    Ok(())
}
