//! Each model's uniform is declared once in Rust (`model_uniform!` in its file in
//! `engine/src/shading/`, recorded as its registry row's `uniform`) and once in WGSL (the struct
//! its shader binds at `@group(1) @binding(0)`): for every row of the registry, the WGSL struct
//! naga parses from the model's composed shader has the Rust struct's name, size and members —
//! the same names, in the same order, at the same offsets, of the same sizes. Renaming,
//! reordering, retyping or dropping a member on either side fails here. The same rule holds
//! for the other structs the GPU reads: the frame uniform every pass binds at `@group(0)
//! @binding(0)` and the subsurface pass's kernel (`gpu_struct!`).

use dermis_engine::render::FrameUniform;
use dermis_engine::shader::{compose, ShaderDefs};
use dermis_engine::shading::subsurface::{KernelUniform, MAX_RINGS};
use dermis_engine::shading::{Layout, ShadingModel, Uniform};

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

/// The model uniform (`@group(1) @binding(0)`) in `source`, as naga lays it out.
fn wgsl_struct(label: &str, source: &str) -> Struct {
    wgsl_struct_at(label, source, 1)
}

/// The struct bound at `@group(group) @binding(0)` in `source`, as naga lays it out.
fn wgsl_struct_at(label: &str, source: &str, group: u32) -> Struct {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
    let binding = naga::ResourceBinding { group, binding: 0 };
    let (_, var) = module
        .global_variables
        .iter()
        .find(|(_, v)| v.binding == Some(binding))
        .unwrap_or_else(|| panic!("{label}: nothing bound at @group({group}) @binding(0)"));
    assert_eq!(var.space, naga::AddressSpace::Uniform, "{label}");
    let ty = &module.types[var.ty];
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{label}: the uniform at @group(1) @binding(0) is not a struct");
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

/// The shader the renderer composes for `model`.
fn source(model: ShadingModel) -> String {
    compose("character", &model.defs()).unwrap_or_else(|e| panic!("{model}: {e}"))
}

#[test]
fn every_model_declares_the_same_uniform_in_rust_and_wgsl() {
    let mut bad = Vec::new();
    for model in ShadingModel::ALL {
        let d = model.descriptor();
        let rust = rust_struct(&d.uniform);
        let wgsl = wgsl_struct(d.name, &source(model));
        assert!(!rust.members.is_empty(), "{}: an empty uniform", d.name);
        for m in mismatches(&rust, &wgsl) {
            bad.push(format!("{} ({}): {m}", d.name, rust.name));
        }
    }
    assert!(
        bad.is_empty(),
        "Rust and WGSL uniforms differ:\n{}",
        bad.join("\n")
    );
}

#[test]
fn a_renamed_or_reordered_member_on_either_side_is_caught() {
    let d = ShadingModel::Ward.descriptor();
    let rust = rust_struct(&d.uniform);
    let src = source(ShadingModel::Ward);
    assert!(mismatches(&rust, &wgsl_struct("ward", &src)).is_empty());
    // WGSL side: two members of the same type swapped (same offsets and sizes, other names).
    let swapped = src.replacen(
        "    alpha_x: f32,\n    alpha_y: f32,",
        "    alpha_y: f32,\n    alpha_x: f32,",
        1,
    );
    assert_ne!(
        swapped, src,
        "ward.wgsl no longer declares alpha_x, alpha_y"
    );
    assert!(!mismatches(&rust, &wgsl_struct("swapped", &swapped)).is_empty());
    // WGSL side: a member renamed (its reads renamed too, so the shader still parses).
    let renamed = src.replace("rho_s", "rho_spec");
    assert!(!mismatches(&rust, &wgsl_struct("renamed", &renamed)).is_empty());
    // Rust side: a member renamed, or two members reordered.
    let mut r = rust_struct(&d.uniform);
    r.members[1].0 = "tex".into();
    assert!(!mismatches(&r, &wgsl_struct("ward", &src)).is_empty());
    let mut r = rust_struct(&d.uniform);
    r.members.swap(2, 3);
    assert!(!mismatches(&r, &wgsl_struct("ward", &src)).is_empty());
}

#[test]
fn the_frame_uniform_and_the_subsurface_kernel_are_declared_the_same_in_rust_and_wgsl() {
    // Every pass that binds the frame: the character (each model), the props, the
    // subsurface pass, the blob shadows.
    let mut frames: Vec<(String, String)> = ShadingModel::ALL
        .iter()
        .map(|m| (format!("character/{m}"), source(*m)))
        .collect();
    for entry in ["prop", "sss_pass", "shadow"] {
        frames.push((entry.into(), compose(entry, &ShaderDefs::new()).unwrap()));
    }
    let frame = rust_struct(&FrameUniform::LAYOUT);
    for (label, src) in &frames {
        let bad = mismatches(&frame, &wgsl_struct_at(label, src, 0));
        assert!(bad.is_empty(), "{label}: FrameUniform differs: {bad:?}");
    }
    // The kernel, whose ring array's length is `MAX_RINGS` on both sides.
    let sss = compose("sss_pass", &ShaderDefs::new()).unwrap();
    let kernel = rust_struct(&KernelUniform::LAYOUT);
    let bad = mismatches(&kernel, &wgsl_struct("sss_pass", &sss));
    assert!(bad.is_empty(), "KernelUniform differs: {bad:?}");
    // …and a different ring count on the WGSL side is caught.
    let (n, m) = (MAX_RINGS, MAX_RINGS - 1);
    let fewer = sss.replacen(
        &format!("const MAX_RINGS: u32 = {n}u;"),
        &format!("const MAX_RINGS: u32 = {m}u;"),
        1,
    );
    assert_ne!(fewer, sss, "sss_pass.wgsl does not declare MAX_RINGS = {n}");
    assert!(!mismatches(&kernel, &wgsl_struct("fewer", &fewer)).is_empty());
}
