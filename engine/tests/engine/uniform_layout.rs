//! Every struct the GPU reads is declared once, in Rust (`gpu_struct!` / `model_uniform!`),
//! and its WGSL is generated from that declaration (`shader::structs`, one composer module per
//! struct). Two things could still diverge, and both are checked with naga, the compiler wgpu
//! uses:
//!
//! * the layout: each generated struct, bound as a uniform, must have the Rust struct's name,
//!   size and members — the same names, in the same order, at the same offsets, of the same
//!   sizes (a Rust member WGSL would place elsewhere, a `[f32; 3]` off its 16 bytes, fails
//!   here);
//! * the binding: each shader must bind the struct its Rust side writes — every model's
//!   character shader its descriptor's uniform at `@group(1) @binding(0)`, every pass the
//!   frame uniform at `@group(0) @binding(0)`, each pass its own.
//!
//! Planted mismatches (a member renamed, reordered or misplaced on either side, an array of
//! another length) fail.

use dermis_engine::render::{caster_shader_source, ui_shader_source, FrameUniform};
use dermis_engine::shader::structs::{table, wgsl};
use dermis_engine::shader::uniforms::{CasterUniform, MaterialUniform, PenumbraUniform, UiUniform};
use dermis_engine::shader::{compose, compose_from, modules, ShaderDefs};
use dermis_engine::shading::subsurface::{KernelUniform, MAX_RINGS};
use dermis_engine::shading::{Field, Layout, ShadingModel, Uniform, WgslType};

/// A uniform struct: name, size in bytes, members (name, offset, size) in order.
#[derive(Debug, PartialEq)]
struct Struct {
    name: String,
    size: usize,
    members: Vec<(String, usize, usize)>,
}

/// A Rust declaration (`gpu_struct!`/`model_uniform!`'s recorded layout).
fn rust_struct(layout: &Layout) -> Struct {
    Struct {
        name: layout.name.to_string(),
        size: layout.size,
        members: layout
            .fields
            .iter()
            .map(|f| (f.name.to_string(), f.offset, f.size))
            .collect(),
    }
}

/// The struct bound at `@group(group) @binding(binding)` in `source`, as naga lays it out
/// (the module validated first: a uniform's layout rules included).
fn wgsl_struct_at(label: &str, source: &str, group: u32, binding: u32) -> Struct {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
    let at = naga::ResourceBinding { group, binding };
    let (_, var) = module
        .global_variables
        .iter()
        .find(|(_, v)| v.binding == Some(at))
        .unwrap_or_else(|| panic!("{label}: nothing bound at @group({group}) @binding({binding})"));
    assert_eq!(var.space, naga::AddressSpace::Uniform, "{label}");
    let ty = &module.types[var.ty];
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{label}: the uniform at @group({group}) @binding({binding}) is not a struct");
    };
    Struct {
        name: ty.name.clone().unwrap_or_default(),
        size: *span as usize,
        members: members
            .iter()
            .map(|m| {
                (
                    m.name.clone().unwrap_or_default(),
                    m.offset as usize,
                    module.types[m.ty].inner.size(module.to_ctx()) as usize,
                )
            })
            .collect(),
    }
}

/// Every difference between the two declarations, described.
fn mismatches(rust: &Struct, wgsl: &Struct) -> Vec<String> {
    let mut out = Vec::new();
    if rust.name != wgsl.name {
        out.push(format!(
            "struct `{}` in Rust, `{}` in WGSL",
            rust.name, wgsl.name
        ));
    }
    if rust.size != wgsl.size {
        out.push(format!(
            "{} bytes in Rust, {} in WGSL",
            rust.size, wgsl.size
        ));
    }
    let n = rust.members.len().max(wgsl.members.len());
    for i in 0..n {
        let (r, w) = (rust.members.get(i), wgsl.members.get(i));
        if r != w {
            out.push(format!(
                "member {i}: Rust {r:?}, WGSL {w:?} (name, offset, size)"
            ));
        }
    }
    out
}

/// A shader binding generated struct `name` (its module's text `text`) as a uniform: what
/// the struct's module composes to, plus the binding.
fn bound(name: &str, text: &str) -> String {
    let mut set: Vec<(&str, &str)> = modules()
        .iter()
        .copied()
        .filter(|(n, _)| *n != name)
        .collect();
    let probe = format!("#import {name}\n@group(0) @binding(0) var<uniform> probe: {name};\n");
    set.push((name, text));
    set.push(("probe", &probe));
    compose_from(&set, "probe", &ShaderDefs::new()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The layout naga gives the struct `layout`'s generated module `text` declares.
fn laid_out(layout: &Layout, text: &str) -> Struct {
    wgsl_struct_at(layout.name, &bound(layout.name, text), 0, 0)
}

#[test]
fn every_generated_struct_is_laid_out_by_naga_as_declared_in_rust() {
    let table = table();
    assert!(table.len() >= 10, "only {} structs", table.len());
    let mut bad = Vec::new();
    for layout in &table {
        let text = modules()
            .iter()
            .find(|(n, _)| n == &layout.name)
            .unwrap_or_else(|| panic!("no generated module {}", layout.name))
            .1;
        assert_eq!(text, wgsl(layout));
        let rust = rust_struct(layout);
        assert!(!rust.members.is_empty(), "{}: an empty struct", rust.name);
        for m in mismatches(&rust, &laid_out(layout, text)) {
            bad.push(format!("{} ({}): {m}", rust.name, layout.file));
        }
    }
    assert!(
        bad.is_empty(),
        "Rust and generated WGSL layouts differ:\n{}",
        bad.join("\n")
    );
}

/// The shader the renderer composes for `model`.
fn source(model: ShadingModel) -> String {
    compose("character", &model.defs()).unwrap_or_else(|e| panic!("{model}: {e}"))
}

#[test]
fn every_shader_binds_the_struct_its_rust_side_writes() {
    let plain = ShaderDefs::new();
    // (label, composed source, group, binding, what the Rust side writes there)
    let mut cases: Vec<(String, String, u32, u32, Layout)> = Vec::new();
    for m in ShadingModel::ALL {
        let src = source(m);
        cases.push((format!("{m}"), src.clone(), 1, 0, m.descriptor().uniform));
        cases.push((format!("{m}"), src.clone(), 0, 0, FrameUniform::LAYOUT));
        cases.push((format!("{m}"), src, 3, 0, MaterialUniform::LAYOUT));
    }
    let split = plain.clone().flag("SCREEN_SPACE");
    // Props as the renderer composes them: instanced, their material at group 1.
    let props = plain.clone().flag("INSTANCED");
    let props_split = props.clone().flag("SCREEN_SPACE");
    for (label, defs) in [("prop", &props), ("prop/split", &props_split)] {
        let src = compose("prop", defs).unwrap();
        cases.push((label.into(), src.clone(), 0, 0, FrameUniform::LAYOUT));
        cases.push((label.into(), src, 1, 0, MaterialUniform::LAYOUT));
    }
    for (label, defs) in [("shadow", &plain), ("shadow/split", &split)] {
        let src = compose("shadow", defs).unwrap();
        cases.push((label.into(), src, 0, 0, FrameUniform::LAYOUT));
    }
    let sss = compose("sss_pass", &plain).unwrap();
    cases.push(("sss_pass".into(), sss.clone(), 0, 0, FrameUniform::LAYOUT));
    cases.push(("sss_pass".into(), sss, 1, 0, KernelUniform::LAYOUT));
    let penumbra = compose("penumbra", &plain).unwrap();
    cases.push(("penumbra".into(), penumbra, 0, 0, PenumbraUniform::LAYOUT));
    cases.push((
        "shadow_caster".into(),
        caster_shader_source(),
        0,
        0,
        CasterUniform::LAYOUT,
    ));
    cases.push(("ui".into(), ui_shader_source(), 0, 0, UiUniform::LAYOUT));
    let mut bad = Vec::new();
    for (label, src, group, binding, layout) in &cases {
        let wgsl = wgsl_struct_at(label, src, *group, *binding);
        for m in mismatches(&rust_struct(layout), &wgsl) {
            bad.push(format!("{label} @group({group}) @binding({binding}): {m}"));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn a_layout_diverging_on_either_side_is_caught() {
    let layout = ShadingModel::Ward.descriptor().uniform;
    let rust = rust_struct(&layout);
    let text = wgsl(&layout);
    assert!(mismatches(&rust, &laid_out(&layout, &text)).is_empty());
    // WGSL side: two members of the same type swapped (same offsets and sizes, other names).
    let swapped = text.replacen(
        "    alpha_x: f32,\n    alpha_y: f32,",
        "    alpha_y: f32,\n    alpha_x: f32,",
        1,
    );
    assert_ne!(swapped, text, "WardUniform no longer has alpha_x, alpha_y");
    assert!(!mismatches(&rust, &laid_out(&layout, &swapped)).is_empty());
    // WGSL side: a member renamed.
    let renamed = text.replace("rho_s:", "rho_spec:");
    assert!(!mismatches(&rust, &laid_out(&layout, &renamed)).is_empty());
    // Rust side: a member renamed, or two members reordered.
    let mut r = rust_struct(&layout);
    r.members[1].0 = "tex".into();
    assert!(!mismatches(&r, &laid_out(&layout, &text)).is_empty());
    let mut r = rust_struct(&layout);
    r.members.swap(2, 3);
    assert!(!mismatches(&r, &laid_out(&layout, &text)).is_empty());

    // A ring array of another length (the kernel's `rings`, MAX_RINGS on the Rust side).
    let kernel = KernelUniform::LAYOUT;
    let text = wgsl(&kernel);
    let (n, m) = (MAX_RINGS, MAX_RINGS - 1);
    let fewer = text.replacen(
        &format!("array<Ring, {n}>"),
        &format!("array<Ring, {m}>"),
        1,
    );
    assert_ne!(fewer, text, "KernelUniform has no array<Ring, {n}>");
    assert!(!mismatches(&rust_struct(&kernel), &laid_out(&kernel, &fewer)).is_empty());

    // A Rust declaration WGSL cannot follow: a vec3 right after a scalar (WGSL puts it on the
    // next 16 bytes), generated as it is.
    let scalar = WgslType {
        name: "f32",
        array: None,
        declared: false,
    };
    let vec3 = WgslType {
        name: "vec3<f32>",
        ..scalar
    };
    let field = |name, offset, size, ty| Field {
        name,
        offset,
        size,
        ty,
        doc: "",
    };
    let planted = Layout {
        name: "Planted",
        file: file!(),
        size: 16,
        fields: &[],
    };
    let fields = [field("a", 0, 4, scalar), field("b", 4, 12, vec3)];
    let planted = Layout {
        fields: Box::leak(Box::new(fields)),
        ..planted
    };
    let text = wgsl(&planted);
    assert!(!mismatches(&rust_struct(&planted), &laid_out(&planted, &text)).is_empty());
}
