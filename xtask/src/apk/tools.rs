//! Finding and running the external tools.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Searches `PATH` for an executable.
pub fn which(name: &str) -> Option<PathBuf> {
    if name.contains('/') {
        let p = PathBuf::from(name);
        return p.is_file().then_some(p);
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

/// The first of `names` found on `PATH`.
pub fn first_of(names: &[String]) -> Option<PathBuf> {
    names.iter().find_map(|n| which(n))
}

pub fn require(name: &str, hint: &str) -> Result<PathBuf, String> {
    which(name).ok_or_else(|| format!("`{name}` not found on PATH ({hint})"))
}

fn describe(cmd: &Command) -> String {
    let mut s = cmd.get_program().to_string_lossy().into_owned();
    for a in cmd.get_args() {
        s.push(' ');
        s.push_str(&a.to_string_lossy());
    }
    s
}

/// Runs a command with inherited stdout/stderr; fails on a non-zero exit.
pub fn run(cmd: &mut Command) -> Result<(), String> {
    if std::env::var_os("DERMIS_APK_VERBOSE").is_some() {
        eprintln!("+ {}", describe(cmd));
    }
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run `{}`: {e}", describe(cmd)))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{}` failed ({status})", describe(cmd)))
    }
}

/// Runs a command capturing its output; fails on a non-zero exit (printing stderr).
pub fn output(cmd: &mut Command) -> Result<Output, String> {
    if std::env::var_os("DERMIS_APK_VERBOSE").is_some() {
        eprintln!("+ {}", describe(cmd));
    }
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run `{}`: {e}", describe(cmd)))?;
    if out.status.success() {
        Ok(out)
    } else {
        Err(format!(
            "`{}` failed ({}):\n{}{}",
            describe(cmd),
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

pub fn write(path: &Path, data: impl AsRef<[u8]>) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        mkdir(dir)?;
    }
    std::fs::write(path, data).map_err(|e| format!("{}: {e}", path.display()))
}

pub fn mkdir(path: &Path) -> Result<(), String> {
    std::fs::create_dir_all(path).map_err(|e| format!("{}: {e}", path.display()))
}

pub fn copy(from: &Path, to: &Path) -> Result<(), String> {
    if let Some(dir) = to.parent() {
        mkdir(dir)?;
    }
    std::fs::copy(from, to)
        .map(|_| ())
        .map_err(|e| format!("copy {} -> {}: {e}", from.display(), to.display()))
}
