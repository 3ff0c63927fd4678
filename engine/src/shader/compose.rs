use std::collections::BTreeMap;
use std::fmt;

/// What a composition is parameterised by: flags for `#ifdef` and aliases for `#import`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ShaderDefs {
    flags: Vec<&'static str>,
    aliases: BTreeMap<&'static str, &'static str>,
}

impl ShaderDefs {
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets `flag` for `#ifdef`.
    pub fn flag(mut self, flag: &'static str) -> Self {
        if !self.flags.contains(&flag) {
            self.flags.push(flag);
        }
        self
    }

    /// Makes `#import alias` import `module`.
    pub fn alias(mut self, alias: &'static str, module: &'static str) -> Self {
        self.aliases.insert(alias, module);
        self
    }

    fn has(&self, flag: &str) -> bool {
        self.flags.contains(&flag)
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ComposeError {
    UnknownModule {
        module: String,
        imported_from: String,
    },
    ImportCycle(Vec<String>),
    Unbalanced {
        module: String,
        line: usize,
        what: &'static str,
    },
}

impl fmt::Display for ComposeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownModule {
                module,
                imported_from,
            } => {
                write!(
                    f,
                    "unknown shader module `{module}` imported from `{imported_from}`"
                )
            }
            Self::ImportCycle(chain) => write!(f, "shader import cycle: {}", chain.join(" -> ")),
            Self::Unbalanced { module, line, what } => {
                write!(f, "{module}.wgsl:{line}: {what}")
            }
        }
    }
}

impl std::error::Error for ComposeError {}

/// Composes module `entry` with its imports into one WGSL source.
pub fn compose(entry: &str, defs: &ShaderDefs) -> Result<String, ComposeError> {
    compose_from(super::modules(), entry, defs)
}

/// Composes from an explicit module set (e.g. to prove a shader builds without some modules).
pub fn compose_from(
    modules: &[(&str, &str)],
    entry: &str,
    defs: &ShaderDefs,
) -> Result<String, ComposeError> {
    let mut state = State {
        modules,
        defs,
        out: String::new(),
        done: Vec::new(),
        stack: Vec::new(),
    };
    state.module(entry, "<root>")?;
    Ok(state.out)
}

struct State<'a> {
    modules: &'a [(&'a str, &'a str)],
    defs: &'a ShaderDefs,
    out: String,
    done: Vec<String>,
    stack: Vec<String>,
}

impl State<'_> {
    fn module(&mut self, name: &str, from: &str) -> Result<(), ComposeError> {
        let resolved = self.defs.aliases.get(name).copied().unwrap_or(name);
        if self.done.iter().any(|d| d == resolved) {
            return Ok(());
        }
        if self.stack.iter().any(|s| s == resolved) {
            let mut chain = self.stack.clone();
            chain.push(resolved.to_string());
            return Err(ComposeError::ImportCycle(chain));
        }
        let source = self
            .modules
            .iter()
            .find(|(n, _)| *n == resolved)
            .map(|(_, s)| *s);
        let source = source.ok_or_else(|| ComposeError::UnknownModule {
            module: resolved.to_string(),
            imported_from: from.to_string(),
        })?;
        self.stack.push(resolved.to_string());
        self.out
            .push_str(&format!("// ---- module {resolved} ----\n"));
        // Each entry: (this branch active, some enclosing branch inactive).
        let mut conds: Vec<(bool, bool)> = Vec::new();
        for (i, line) in source.lines().enumerate() {
            let trimmed = line.trim_start();
            let active = conds.iter().all(|c| c.0);
            let unbalanced = |what| ComposeError::Unbalanced {
                module: resolved.to_string(),
                line: i + 1,
                what,
            };
            if let Some(flag) = directive(trimmed, "#ifdef") {
                conds.push((self.defs.has(flag), !active));
            } else if let Some(flag) = directive(trimmed, "#ifndef") {
                conds.push((!self.defs.has(flag), !active));
            } else if trimmed.starts_with("#else") {
                let top = conds
                    .last_mut()
                    .ok_or_else(|| unbalanced("#else without #ifdef"))?;
                top.0 = !top.0;
            } else if trimmed.starts_with("#endif") {
                conds
                    .pop()
                    .ok_or_else(|| unbalanced("#endif without #ifdef"))?;
            } else if let Some(import) = directive(trimmed, "#import") {
                if active {
                    self.module(import, resolved)?;
                }
            } else if active {
                self.out.push_str(line);
                self.out.push('\n');
            }
        }
        if !conds.is_empty() {
            return Err(unbalanced_end(resolved));
        }
        self.stack.pop();
        self.done.push(resolved.to_string());
        Ok(())
    }
}

fn unbalanced_end(module: &str) -> ComposeError {
    ComposeError::Unbalanced {
        module: module.to_string(),
        line: 0,
        what: "missing #endif",
    }
}

fn directive<'l>(line: &'l str, name: &str) -> Option<&'l str> {
    let rest = line.strip_prefix(name)?;
    if !rest.starts_with(char::is_whitespace) {
        return None;
    }
    Some(rest.trim())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imports_once_and_resolves_aliases() {
        let defs = ShaderDefs::new().alias("shading_model", "ward");
        let src = compose("character", &defs).unwrap();
        assert_eq!(src.matches("// ---- module common ----").count(), 1);
        assert!(src.contains("// ---- module ward ----"));
        assert!(!src.contains("#import"));
    }

    #[test]
    fn unknown_module_is_an_error() {
        let defs = ShaderDefs::new().alias("shading_model", "nope");
        let err = compose("character", &defs).unwrap_err();
        assert!(err.to_string().contains("nope"), "{err}");
    }
}
