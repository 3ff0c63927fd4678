//! The structs the shaders and the Rust side share, written once — in Rust, with
//! `gpu_struct!` / `model_uniform!` — and handed to the shaders as generated modules, one per
//! struct, named after it: a shader that reads a `FrameUniform` says `#import FrameUniform`.
//! No shader declares one of these structs itself.

use std::fmt::Write;

use crate::shading::subsurface::{KernelUniform, Ring};
use crate::shading::{Layout, ShadingModel, Uniform};

/// Every shared struct: the shared modules' and the passes' ([`super::uniforms::DECLARED`]),
/// the subsurface pass's kernel and its rings, then each registered model's uniform (once,
/// for models that share one).
pub fn table() -> Vec<Layout> {
    let mut all = super::uniforms::DECLARED.to_vec();
    all.extend([KernelUniform::LAYOUT, Ring::LAYOUT]);
    for m in ShadingModel::ALL {
        let uniform = m.descriptor().uniform;
        if !all.iter().any(|l| l.name == uniform.name) {
            all.push(uniform);
        }
    }
    all
}

/// The generated WGSL of the module declaring `layout`: the imports of the structs it holds,
/// then the struct, member by member, with the Rust doc comments.
pub fn wgsl(layout: &Layout) -> String {
    let mut out = format!(
        "// `{}`, generated from its Rust declaration ({}): do not edit.\n",
        layout.name, layout.file
    );
    for f in layout.fields.iter().filter(|f| f.ty.declared) {
        let _ = writeln!(out, "#import {}", f.ty.name);
    }
    let _ = writeln!(out, "struct {} {{", layout.name);
    for f in layout.fields {
        for line in f.doc.lines() {
            // Rustdoc links read as plain code spans here.
            let line = line.trim().replace("[`", "`").replace("`]", "`");
            let _ = writeln!(out, "    // {line}");
        }
        let ty = match f.ty.array {
            Some(n) => format!("array<{}, {n}>", f.ty.name),
            None => f.ty.name.to_string(),
        };
        let _ = writeln!(out, "    {}: {ty},", f.name);
    }
    out.push_str("};\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_struct_is_declared_once_with_its_members_in_order() {
        let table = table();
        for (i, l) in table.iter().enumerate() {
            assert!(
                table[..i].iter().all(|o| o.name != l.name),
                "{} twice",
                l.name
            );
            let src = wgsl(l);
            assert_eq!(src.matches("struct ").count(), 1, "{src}");
            let members: Vec<&str> = src
                .lines()
                .map(str::trim)
                .filter(|t| !t.starts_with("//") && !t.starts_with('#') && t.ends_with(','))
                .map(|t| t.split(':').next().unwrap_or_default())
                .collect();
            let names: Vec<&str> = l.fields.iter().map(|f| f.name).collect();
            assert_eq!(members, names, "{src}");
        }
        // A struct of structs imports them.
        let kernel = wgsl(&KernelUniform::LAYOUT);
        assert!(kernel.contains("#import Ring\n"), "{kernel}");
        assert!(kernel.contains("rings: array<Ring, "), "{kernel}");
    }
}
