//! The Android platform symbol table for arm64, derived from the NDK symbol maps.
//!
//! The maps (`../shared/ndk-symbols/*.map.txt`, see its SOURCE.md) name every exported
//! symbol of the platform libraries with its version node and tags. This module applies the
//! rules of the NDK stub generator to them:
//!
//! - blocks named `*_PRIVATE`, `*_PLATFORM`, `*_DEPRECATED` are dropped;
//! - blocks and symbols tagged `apex`, `llndk`, `platform-only`, `systemapi` or `future`
//!   are dropped, as are those with architecture tags that do not include `arm64`;
//! - the API level is the largest of the block's and the symbol's `introduced=` (or
//!   `introduced-arm64=`, which takes precedence), codenames mapped to numbers, and 21 (the
//!   first arm64 release);
//! - `var` marks data; `versioned=N` means the symbol carries no version before API N.
//!
//! The result is the committed table `tools/ndk-table/ndk-symbols.tsv` (symbol, library,
//! version node, API level, kind, versioned-from), from which the stub libraries are
//! generated, so the build does not need `../shared`. `cargo xtask apk --check-table`
//! re-derives it from the maps and fails if it differs.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// The platform libraries rustc links a `cdylib` for Android against.
pub const LIBRARIES: [&str; 5] = ["libc", "libm", "libdl", "liblog", "libandroid"];

/// First API level of the arm64 ABI.
pub const ARM64_FIRST_API: u32 = 21;

const ARCH_TAGS: [&str; 7] = ["arm", "arm64", "x86", "x86_64", "riscv64", "mips", "mips64"];
const DROPPED_TAGS: [&str; 5] = ["apex", "llndk", "platform-only", "systemapi", "future"];
const DROPPED_BLOCK_SUFFIXES: [&str; 3] = ["_PRIVATE", "_PLATFORM", "_DEPRECATED"];

#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Symbol {
    pub name: String,
    pub library: String,
    pub version: String,
    pub api: u32,
    pub is_var: bool,
    /// API level from which the symbol is versioned (`versioned=`); before it, unversioned.
    pub versioned_from: Option<u32>,
}

impl Symbol {
    /// Whether the symbol carries its version node at API level `api`.
    pub fn versioned_at(&self, api: u32) -> bool {
        self.versioned_from.is_none_or(|v| v <= api)
    }
}

fn codename(level: &str) -> Result<u32, String> {
    if let Ok(n) = level.parse::<u32>() {
        return Ok(n);
    }
    Ok(match level {
        "O" => 26,
        "P" => 28,
        "Q" => 29,
        "R" => 30,
        "S" => 31,
        "Sv2" => 32,
        "Tiramisu" | "T" => 33,
        "UpsideDownCake" | "U" => 34,
        "VanillaIceCream" | "V" => 35,
        "Baklava" => 36,
        other => return Err(format!("unknown API codename `{other}`")),
    })
}

/// Parsed tags of one line (the text after `#`).
#[derive(Default)]
struct Tags {
    arches: Vec<String>,
    dropped: bool,
    introduced: Option<u32>,
    introduced_arm64: Option<u32>,
    is_var: bool,
    versioned: Option<u32>,
}

impl Tags {
    fn parse(comment: &str) -> Result<Tags, String> {
        let mut t = Tags::default();
        for word in comment.split(|c: char| c.is_whitespace() || c == '#') {
            if word.is_empty() {
                continue;
            }
            if ARCH_TAGS.contains(&word) {
                t.arches.push(word.to_string());
            } else if DROPPED_TAGS.contains(&word) {
                t.dropped = true;
            } else if word == "var" {
                t.is_var = true;
            } else if let Some(v) = word.strip_prefix("introduced=") {
                t.introduced = Some(codename(v)?);
            } else if let Some(v) = word.strip_prefix("introduced-arm64=") {
                t.introduced_arm64 = Some(codename(v)?);
            } else if let Some(v) = word.strip_prefix("versioned=") {
                t.versioned = Some(codename(v)?);
            }
            // Other words (other architectures' `introduced-*=`, `weak`, prose) do not
            // affect arm64 stubs.
        }
        Ok(t)
    }

    /// Excluded for arm64 NDK stubs.
    fn excluded(&self) -> bool {
        self.dropped || (!self.arches.is_empty() && !self.arches.iter().any(|a| a == "arm64"))
    }

    fn api(&self) -> u32 {
        self.introduced_arm64
            .or(self.introduced)
            .unwrap_or(ARM64_FIRST_API)
    }
}

fn split_comment(line: &str) -> (&str, &str) {
    match line.find('#') {
        Some(i) => (line[..i].trim(), &line[i + 1..]),
        None => (line.trim(), ""),
    }
}

/// Parses one map file into the symbols exported to NDK code on arm64.
pub fn parse_map(library: &str, text: &str) -> Result<Vec<Symbol>, String> {
    let mut out = Vec::new();
    // (name, excluded, api) of the current version block.
    let mut block: Option<(String, bool, u32)> = None;
    let mut local = false;
    let mut in_cxx = false;
    for (n, raw) in text.lines().enumerate() {
        let ctx = |e: String| format!("{library}.map.txt:{}: {e}", n + 1);
        let (code, comment) = split_comment(raw);
        if code.is_empty() {
            continue;
        }
        if in_cxx {
            if code.starts_with('}') {
                in_cxx = false;
            }
            continue;
        }
        if code.starts_with("extern") {
            in_cxx = !code.contains('}');
            continue;
        }
        if let Some(name) = code.strip_suffix('{') {
            let name = name.trim().to_string();
            let tags = Tags::parse(comment).map_err(ctx)?;
            let excluded =
                tags.excluded() || DROPPED_BLOCK_SUFFIXES.iter().any(|s| name.ends_with(s));
            block = Some((name, excluded, tags.api()));
            local = false;
            continue;
        }
        if code.starts_with('}') {
            block = None;
            continue;
        }
        match code {
            "global:" => {
                local = false;
                continue;
            }
            "local:" => {
                local = true;
                continue;
            }
            _ => {}
        }
        let Some((bname, bexcluded, bapi)) = &block else {
            return Err(ctx(format!("symbol outside a version block: `{code}`")));
        };
        if local || *bexcluded {
            continue;
        }
        let name = code.trim_end_matches(';').trim();
        if name.contains('*') || name.is_empty() {
            continue;
        }
        let tags = Tags::parse(comment).map_err(ctx)?;
        if tags.excluded() {
            continue;
        }
        out.push(Symbol {
            name: name.to_string(),
            library: library.to_string(),
            version: bname.clone(),
            api: tags.api().max(*bapi).max(ARM64_FIRST_API),
            is_var: tags.is_var,
            versioned_from: tags.versioned,
        });
    }
    Ok(out)
}

/// Derives the whole table from the map directory.
pub fn table_from_maps(dir: &Path) -> Result<Vec<Symbol>, String> {
    let mut all = Vec::new();
    for lib in LIBRARIES {
        let path = dir.join(format!("{lib}.map.txt"));
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        all.extend(parse_map(lib, &text)?);
    }
    all.sort();
    all.dedup();
    Ok(all)
}

const HEADER: &str = "# Android arm64 platform symbols available to NDK code, derived by `cargo xtask apk --write-table`\n\
# from the NDK symbol maps (../shared/ndk-symbols, AOSP, Apache-2.0); checked by `cargo xtask apk --check-table`.\n\
# symbol\tlibrary\tversion\tapi\tkind\tversioned_from\n";

pub fn to_tsv(table: &[Symbol]) -> String {
    let mut s = String::from(HEADER);
    for sym in table {
        let _ = writeln!(
            s,
            "{}\t{}\t{}\t{}\t{}\t{}",
            sym.name,
            sym.library,
            sym.version,
            sym.api,
            if sym.is_var { "var" } else { "func" },
            sym.versioned_from
                .map_or("-".to_string(), |v| v.to_string())
        );
    }
    s
}

pub fn from_tsv(text: &str) -> Result<Vec<Symbol>, String> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        let bad = || format!("ndk-symbols.tsv:{}: malformed line `{line}`", n + 1);
        if f.len() != 6 {
            return Err(bad());
        }
        out.push(Symbol {
            name: f[0].to_string(),
            library: f[1].to_string(),
            version: f[2].to_string(),
            api: f[3].parse().map_err(|_| bad())?,
            is_var: match f[4] {
                "var" => true,
                "func" => false,
                _ => return Err(bad()),
            },
            versioned_from: match f[5] {
                "-" => None,
                v => Some(v.parse().map_err(|_| bad())?),
            },
        });
    }
    Ok(out)
}

/// Symbols of one library available at `api`.
pub fn available<'a>(table: &'a [Symbol], library: &str, api: u32) -> Vec<&'a Symbol> {
    table
        .iter()
        .filter(|s| s.library == library && s.api <= api)
        .collect()
}

/// An undefined dynamic symbol of a built `.so`.
#[derive(Debug)]
pub struct Import {
    pub name: String,
    pub version: Option<String>,
    pub weak: bool,
}

/// Parses `llvm-readelf --dyn-syms --wide` output into the undefined symbols.
pub fn parse_readelf_imports(text: &str) -> Vec<Import> {
    let mut out = Vec::new();
    for line in text.lines() {
        // Num: Value Size Type Bind Vis Ndx Name
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() < 8 || !f[0].ends_with(':') || f[6] != "UND" {
            continue;
        }
        let full = f[7];
        let (name, version) = match full.find('@') {
            Some(i) => (
                &full[..i],
                Some(full[i..].trim_start_matches('@').to_string()),
            ),
            None => (full, None),
        };
        if name.is_empty() {
            continue;
        }
        out.push(Import {
            name: name.to_string(),
            version,
            weak: f[4] == "WEAK",
        });
    }
    out
}

/// Checks every import against the table at `min_api`. Returns the report lines and the
/// number of failures.
pub fn check_imports(table: &[Symbol], imports: &[Import], min_api: u32) -> (String, usize) {
    let mut by_name: BTreeMap<&str, Vec<&Symbol>> = BTreeMap::new();
    for s in table {
        by_name.entry(s.name.as_str()).or_default().push(s);
    }
    let mut report = String::new();
    let mut failures = 0;
    for imp in imports {
        let Some(cands) = by_name.get(imp.name.as_str()) else {
            failures += 1;
            let _ = writeln!(report, "FAIL {}: not in the platform maps", imp.name);
            continue;
        };
        let matching: Vec<&&Symbol> = cands
            .iter()
            .filter(|s| imp.version.as_ref().is_none_or(|v| *v == s.version))
            .collect();
        if matching.is_empty() {
            failures += 1;
            let _ = writeln!(
                report,
                "FAIL {}@{}: version node not in the maps",
                imp.name,
                imp.version.as_deref().unwrap_or("")
            );
            continue;
        }
        let api = matching.iter().map(|s| s.api).min().unwrap_or(u32::MAX);
        if api > min_api {
            if imp.weak {
                let _ = writeln!(
                    report,
                    "note {}: weak reference to API {api} > minSdk {min_api} (must be checked at run time)",
                    imp.name
                );
            } else {
                failures += 1;
                let _ = writeln!(
                    report,
                    "FAIL {}: needs API {api} > minSdk {min_api}",
                    imp.name
                );
            }
        }
    }
    (report, failures)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MAP: &str = "\
LIBC {
  global:
    a;
    b; # arm x86
    c; # introduced=23
    d; # var
    e; # apex
    f; # introduced-arm=9 introduced-arm64=24 introduced=12
    g; # introduced=Tiramisu
    h; # arm64 x86_64 versioned=28
  local:
    *;
};
LIBC_N { # introduced-arm64=24 introduced-x86=24
  global:
    n;
} LIBC;
LIBC_P { # introduced=28
  global:
    p; # introduced=29
    extern \"C++\" {
        foo*;
    };
} LIBC_N;
LIBC_PRIVATE {
  global:
    priv;
};
";

    #[test]
    fn parses_rules() {
        let syms = parse_map("libc", MAP).unwrap();
        let got: Vec<(&str, &str, u32, bool, Option<u32>)> = syms
            .iter()
            .map(|s| {
                (
                    s.name.as_str(),
                    s.version.as_str(),
                    s.api,
                    s.is_var,
                    s.versioned_from,
                )
            })
            .collect();
        assert_eq!(
            got,
            vec![
                ("a", "LIBC", 21, false, None),
                ("c", "LIBC", 23, false, None),
                ("d", "LIBC", 21, true, None),
                ("f", "LIBC", 24, false, None),
                ("g", "LIBC", 33, false, None),
                ("h", "LIBC", 21, false, Some(28)),
                ("n", "LIBC_N", 24, false, None),
                ("p", "LIBC_P", 29, false, None),
            ]
        );
    }

    #[test]
    fn tsv_round_trip() {
        let mut syms = parse_map("libc", MAP).unwrap();
        syms.sort();
        assert_eq!(from_tsv(&to_tsv(&syms)).unwrap(), syms);
    }

    #[test]
    fn import_check() {
        let syms = parse_map("libc", MAP).unwrap();
        let readelf = "\
Symbol table '.dynsym' contains 4 entries:
   Num:    Value          Size Type    Bind   Vis       Ndx Name
     0: 0000000000000000     0 NOTYPE  LOCAL  DEFAULT   UND
     1: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND a@LIBC
     2: 0000000000000000     0 FUNC    WEAK   DEFAULT   UND g@LIBC
     3: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND p@LIBC_P
     4: 0000000000000000     0 FUNC    GLOBAL DEFAULT   UND zz
     5: 0000000000001000     8 FUNC    GLOBAL DEFAULT    12 ANativeActivity_onCreate
";
        let imports = parse_readelf_imports(readelf);
        assert_eq!(imports.len(), 4);
        let (report, failures) = check_imports(&syms, &imports, 26);
        assert_eq!(failures, 2, "{report}");
        assert!(report.contains("FAIL p"));
        assert!(report.contains("FAIL zz"));
        assert!(report.contains("note g"));
    }
}
