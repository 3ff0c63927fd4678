//! The library's imports against real system libraries, symbol versions included.
//!
//! `cargo xtask apk --check-imports` checks the imports against the NDK's symbol maps; this
//! checks them against the binaries of a real userland: each versioned import `name@V` must be
//! defined as `name@V` (or `name@@V`) by a `NEEDED` library that the version-needs section
//! names for `V`; an unversioned import by any `NEEDED` library. The imports left are those of
//! libraries the userland does not have; only `@LIBANDROID` ones are allowed (weak references,
//! checked at run time by the app, are reported as notes).

use crate::apk::{symbols, tools};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// The version node whose imports may stay unresolved (no libandroid.so in the userland).
pub const ALLOWED_LEFT: &str = "LIBANDROID";

pub struct Report {
    pub text: String,
    pub failures: usize,
    /// Number of undefined dynamic symbols.
    pub imports: usize,
    /// Imports left to the device (`name@LIBANDROID`).
    pub left: Vec<String>,
    /// `NEEDED` libraries found in the userland / missing from it.
    pub found_libraries: Vec<String>,
    pub missing_libraries: Vec<String>,
}

fn readelf(readelf: &Path, args: &[&str], file: &Path) -> Result<String, String> {
    let out = tools::output(Command::new(readelf).args(args).arg(file))?;
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// `NEEDED` entries of `llvm-readelf -d`.
pub fn parse_needed(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| l.contains("(NEEDED)"))
        .filter_map(|l| {
            let start = l.find('[')? + 1;
            let end = l[start..].find(']')? + start;
            Some(l[start..end].to_string())
        })
        .collect()
}

/// Version name → files, from the version-needs section of `llvm-readelf -V`.
pub fn parse_version_needs(text: &str) -> BTreeMap<String, BTreeSet<String>> {
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut in_needs = false;
    let mut file = None;
    for line in text.lines() {
        if line.starts_with("Version needs section") {
            in_needs = true;
            continue;
        }
        if line.starts_with("Version ") {
            in_needs = false;
        }
        if !in_needs {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let after = |key: &str| {
            words
                .iter()
                .position(|w| *w == key)
                .and_then(|i| words.get(i + 1))
                .map(|w| w.to_string())
        };
        if let Some(f) = after("File:") {
            file = Some(f);
        } else if let (Some(name), Some(f)) = (after("Name:"), &file) {
            out.entry(name).or_default().insert(f.clone());
        }
    }
    out
}

/// Defined dynamic symbols of `llvm-readelf --dyn-syms --wide`: name → versions (`None` for
/// an unversioned definition).
pub fn parse_exports(text: &str) -> BTreeMap<String, BTreeSet<Option<String>>> {
    let mut out: BTreeMap<String, BTreeSet<Option<String>>> = BTreeMap::new();
    for line in text.lines() {
        // Num: Value Size Type Bind Vis Ndx Name
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() < 8 || !f[0].ends_with(':') || f[6] == "UND" || f[4] == "LOCAL" {
            continue;
        }
        let (name, version) = match f[7].find('@') {
            Some(i) => (
                &f[7][..i],
                Some(f[7][i..].trim_start_matches('@').to_string()),
            ),
            None => (f[7], None),
        };
        out.entry(name.to_string()).or_default().insert(version);
    }
    out
}

type Exports = BTreeMap<String, BTreeSet<Option<String>>>;

/// Resolves the imports; pure (the tests feed it readelf text).
pub fn resolve(
    imports: &[symbols::Import],
    needed: &[String],
    needs: &BTreeMap<String, BTreeSet<String>>,
    libraries: &BTreeMap<String, Exports>,
) -> Report {
    let mut text = String::new();
    let mut failures = 0;
    let mut left = Vec::new();
    let mut per_library: BTreeMap<&str, usize> = BTreeMap::new();
    for imp in imports {
        // The libraries that may define it: those the version-needs section names for its
        // version, else every NEEDED one.
        let candidates: Vec<&String> = match &imp.version {
            Some(v) => needed
                .iter()
                .filter(|n| needs.get(v).is_some_and(|files| files.contains(*n)))
                .collect(),
            None => needed.iter().collect(),
        };
        let found = candidates.iter().find(|lib| {
            libraries
                .get(lib.as_str())
                .and_then(|e| e.get(&imp.name))
                .is_some_and(|versions| match &imp.version {
                    Some(v) => versions.contains(&Some(v.clone())) || versions.contains(&None),
                    None => true,
                })
        });
        let full = match &imp.version {
            Some(v) => format!("{}@{v}", imp.name),
            None => imp.name.clone(),
        };
        if let Some(lib) = found {
            *per_library.entry(lib.as_str()).or_default() += 1;
        } else if imp.version.as_deref() == Some(ALLOWED_LEFT) {
            left.push(imp.name.clone());
        } else if imp.weak {
            let _ = writeln!(text, "note {full}: weak, unresolved (checked at run time)");
        } else {
            failures += 1;
            let _ = writeln!(
                text,
                "FAIL {full}: not defined by {}",
                if candidates.is_empty() {
                    "any NEEDED library".to_string()
                } else {
                    candidates
                        .iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(" / ")
                }
            );
        }
    }
    for (lib, n) in &per_library {
        let _ = writeln!(text, "  {n:>4} resolved in {lib}");
    }
    let (found_libraries, missing_libraries): (Vec<String>, Vec<String>) = needed
        .iter()
        .cloned()
        .partition(|n| libraries.contains_key(n));
    Report {
        text,
        failures,
        imports: imports.len(),
        left,
        found_libraries,
        missing_libraries,
    }
}

/// Checks `so`'s imports against the libraries in `libdir` (the userland's system/lib64).
pub fn check(readelf_path: &Path, so: &Path, libdir: &Path) -> Result<Report, String> {
    let needed = parse_needed(&readelf(readelf_path, &["-d"], so)?);
    let needs = parse_version_needs(&readelf(readelf_path, &["-V"], so)?);
    let imports =
        symbols::parse_readelf_imports(&readelf(readelf_path, &["--dyn-syms", "--wide"], so)?);
    let mut libraries = BTreeMap::new();
    for n in &needed {
        let path = libdir.join(n);
        if path.is_file() {
            let exports = parse_exports(&readelf(readelf_path, &["--dyn-syms", "--wide"], &path)?);
            libraries.insert(n.clone(), exports);
        }
    }
    Ok(resolve(&imports, &needed, &needs, &libraries))
}

#[cfg(test)]
mod tests {
    use super::*;

    const APP_SYMS: &str = "\
Symbol table '.dynsym' contains 6 entries:
   Num:    Value          Size Type    Bind   Vis       Ndx Name
     0: 0000000000000000     0 NOTYPE  LOCAL  DEFAULT   UND
     1: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND malloc@LIBC
     2: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND dlopen@LIBC
     3: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND ANativeWindow_acquire@LIBANDROID
     4: 0000000000000000     0 FUNC    WEAK   DEFAULT   UND newer@LIBC_Q
     5: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND gone@LIBC
     6: 0000000000001000     8 FUNC    GLOBAL DEFAULT    12 ANativeActivity_onCreate
";
    const NEEDS: &str = "\
Version symbols section '.gnu.version' contains 7 entries:
 Addr: 0000000000000520  Offset: 0x000520  Link: 2 (.dynsym)
  000:   0 (*local*)       2 (LIBC)          3 (LIBC)          4 (LIBANDROID)

Version needs section '.gnu.version_r' contains 3 entries:
 Addr: 0000000000000530  Offset: 0x000530  Link: 6 (.dynstr)
  0x0000: Version: 1  File: libc.so  Cnt: 2
  0x0010:   Name: LIBC  Flags: none  Version: 2
  0x0020:   Name: LIBC_Q  Flags: none  Version: 5
  0x0030: Version: 1  File: libdl.so  Cnt: 1
  0x0040:   Name: LIBC  Flags: none  Version: 3
  0x0050: Version: 1  File: libandroid.so  Cnt: 1
  0x0060:   Name: LIBANDROID  Flags: none  Version: 4
";
    const LIBC: &str = "\
     1: 0000000000010000    40 FUNC    GLOBAL DEFAULT    10 malloc@@LIBC
     2: 0000000000010000    40 FUNC    GLOBAL DEFAULT    10 dlopen@@LIBC
";
    const LIBDL: &str = "\
     1: 0000000000010000    40 FUNC    GLOBAL DEFAULT    10 dlopen@@LIBC
     2: 0000000000010000    40 FUNC    GLOBAL DEFAULT    10 gone@LIBC_OTHER
";

    #[test]
    fn resolves_by_version_and_file() {
        let imports = symbols::parse_readelf_imports(APP_SYMS);
        let needs = parse_version_needs(NEEDS);
        assert_eq!(needs["LIBC"].len(), 2);
        let needed: Vec<String> = ["libc.so", "libdl.so", "libandroid.so"]
            .map(String::from)
            .to_vec();
        let mut libs = BTreeMap::new();
        libs.insert("libc.so".to_string(), parse_exports(LIBC));
        libs.insert("libdl.so".to_string(), parse_exports(LIBDL));
        let r = resolve(&imports, &needed, &needs, &libs);
        assert_eq!(r.failures, 1, "{}", r.text);
        assert!(r.text.contains("FAIL gone@LIBC"), "{}", r.text);
        assert!(r.text.contains("note newer@LIBC_Q"), "{}", r.text);
        assert_eq!(r.left, vec!["ANativeWindow_acquire".to_string()]);
        assert_eq!(r.missing_libraries, vec!["libandroid.so".to_string()]);
        assert_eq!(r.imports, 5);
    }

    #[test]
    fn needed_entries() {
        let d = "  0x0000000000000001 (NEEDED)  Shared library: [libc.so]\n\
                 0x000000000000000e (SONAME)  Library soname: [libx.so]\n";
        assert_eq!(parse_needed(d), vec!["libc.so".to_string()]);
    }
}
