//! `dermis shaders --spirv DIR`: every composed shader the renderer can build, as SPIR-V, one
//! module per stage (`NAME.vert.spv`, `NAME.frag.spv`): the character shader of each shading
//! model, the unlit baseline (`unlit`) and the screen-space subsurface pass (`sss_pass`),
//! plus `NAME_x2…` variants with one loop's body written twice ([`DOUBLED`]), from which
//! `bench shading` weights Mesa's static counts by the loops' iteration counts.
//! `tools/mali/cycles.sh DIR` reads them (Mali-G52/G57 cycle estimates; the JSON for the
//! current shaders is `docs/results/mali-cycles.json`).
//!
//! The SPIR-V is written with the options wgpu's Vulkan backend uses on a device without
//! robustness2 (index, buffer and image loads bounds-checked by `Restrict`, loops bounded, no
//! coordinate-space adjustment), so it is what a phone's driver would be given.

use std::path::{Path, PathBuf};

use dermis_engine::render::build_shader_source;
use dermis_engine::shader::{compose, ShaderDefs};
use dermis_engine::shading::ShadingModel;
use serde_json::{Map, Value};

#[derive(clap::Args, Debug)]
pub struct ShadersArgs {
    /// Directory to write NAME.vert.spv and NAME.frag.spv into (created if missing).
    #[arg(long)]
    pub spirv: PathBuf,
    /// Also write each composed shader's WGSL (NAME.wgsl), as the renderer builds it: what
    /// the SPIR-V was made from, for reading or for trying a change through `naga` and
    /// `tools/mali/cycles.sh` without a rebuild.
    #[arg(long)]
    pub wgsl: bool,
}

/// Every shader as (name, composed WGSL): the models in registry order, `unlit`, `sss_pass`,
/// then the loop-doubled variants ([`DOUBLED`]).
pub fn sources() -> Result<Vec<(String, String)>, String> {
    let mut out: Vec<(String, String)> = ShadingModel::ALL
        .iter()
        .map(|m| (m.name().to_string(), build_shader_source(*m)))
        .collect();
    let unlit = compose(
        "character",
        &ShaderDefs::new().alias("shading_model", "unlit"),
    )
    .map_err(|e| format!("unlit: {e}"))?;
    out.push(("unlit".into(), unlit));
    let sss = compose("sss_pass", &ShaderDefs::new()).map_err(|e| format!("sss_pass: {e}"))?;
    out.push(("sss_pass".into(), sss));
    let mut doubled = Vec::new();
    for (name, src) in &out {
        for (suffix, header, shift) in DOUBLED {
            if src.contains(header) {
                let twice = double_loop_body(src, header, shift)?;
                doubled.push((format!("{name}_{suffix}"), twice));
            }
        }
    }
    out.extend(doubled);
    Ok(out)
}

/// Loops whose body Mali's static cycle counts see once, however often it runs: (variant
/// suffix, loop header, a different value of the loop variable). For each shader holding such
/// a loop, `NAME_SUFFIX` is written too, with the loop's body written twice, the second copy
/// at the other value (so the compiler cannot merge the copies); the difference from `NAME`
/// is the cost of one more iteration, which `bench shading` scales by the iteration count:
/// the subsurface models' per-channel light loop (3), and the subsurface pass's samples
/// (rings × angles) and rings.
pub const DOUBLED: [(&str, &str, &str); 3] = [
    (
        "x2channel",
        "for (var c = 0u; c < 3u; c = c + 1u) {",
        "let c = 2u - c;",
    ),
    (
        "x2sample",
        "for (var j = 0u; j < angles; j = j + 1u) {",
        "let j = j + angles;",
    ),
    (
        "x2ring",
        "for (var k = 0u; k < rings; k = k + 1u) {",
        "let k = k + 1u;",
    ),
];

/// `src` with the body of the loop opened by `header` written twice, each copy in its own
/// block, the second starting with `shift`.
fn double_loop_body(src: &str, header: &str, shift: &str) -> Result<String, String> {
    let missing = || format!("no loop `{header}` to double");
    let at = src.find(header).ok_or_else(missing)?;
    let open = at + header.len();
    let mut depth = 1usize;
    let mut close = None;
    for (i, ch) in src[open..].char_indices() {
        match ch {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    close = Some(open + i);
                    break;
                }
            }
            _ => {}
        }
    }
    let close = close.ok_or_else(missing)?;
    let body = &src[open..close];
    Ok(format!(
        "{}{{{body}}}\n{{ {shift}{body}}}\n{}",
        &src[..open],
        &src[close..]
    ))
}

/// The SPIR-V writer options (see the module docs).
fn options() -> naga::back::spv::Options<'static> {
    use naga::back::spv::{Options, WriterFlags};
    use naga::proc::{BoundsCheckPolicies, BoundsCheckPolicy};
    Options {
        flags: WriterFlags::LABEL_VARYINGS | WriterFlags::FORCE_POINT_SIZE,
        // (group, binding) become (set, binding), as wgpu's pipeline layout maps them.
        fake_missing_bindings: true,
        bounds_check_policies: BoundsCheckPolicies {
            index: BoundsCheckPolicy::Restrict,
            buffer: BoundsCheckPolicy::Restrict,
            image_load: BoundsCheckPolicy::Restrict,
            binding_array: BoundsCheckPolicy::Unchecked,
        },
        ..Options::default()
    }
}

/// Full-screen passes with a fragment entry point of their own: (name written, composer
/// module, fragment entry). The penumbra map's seed and jump passes run over its grid, not
/// the screen; `bench shading` spreads their cycles over the screen's pixels.
pub const GRID_PASSES: [(&str, &str, &str); 2] = [
    ("penumbra_seed", "penumbra", "fs_seed"),
    ("penumbra_jump", "penumbra", "fs_jump"),
];

/// `src` (WGSL) → (vertex SPIR-V words, fragment SPIR-V words) of `vs_main` / `fs`.
pub fn to_spirv(name: &str, src: &str, fs: &str) -> Result<(Vec<u32>, Vec<u32>), String> {
    let module = naga::front::wgsl::parse_str(src)
        .map_err(|e| format!("{name}: {}", first_line(&e.emit_to_string(src))))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| format!("{name}: {}", first_line(&e.emit_to_string(src))))?;
    let stage = |shader_stage, entry: &str| {
        let pipeline = naga::back::spv::PipelineOptions {
            shader_stage,
            entry_point: entry.into(),
        };
        naga::back::spv::write_vec(&module, &info, &options(), Some(&pipeline))
            .map_err(|e| format!("{name} {entry}: {e}"))
    };
    Ok((
        stage(naga::ShaderStage::Vertex, "vs_main")?,
        stage(naga::ShaderStage::Fragment, fs)?,
    ))
}

fn first_line(s: &str) -> String {
    s.lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .to_string()
}

/// Writes every shader's two stages into `dir` (and its composed WGSL, with `wgsl`); returns
/// the names written.
pub fn write_spirv(dir: &Path, wgsl: bool) -> Result<Vec<String>, String> {
    crate::cmd::args::check_out_dir(dir)?;
    let mut names = Vec::new();
    let mut all: Vec<(String, String, &str)> = sources()?
        .into_iter()
        .map(|(n, s)| (n, s, "fs_main"))
        .collect();
    for (name, module, fs) in GRID_PASSES {
        let src = compose(module, &ShaderDefs::new()).map_err(|e| format!("{name}: {e}"))?;
        all.push((name.to_string(), src, fs));
    }
    for (name, src, fs) in all {
        let (vert, frag) = to_spirv(&name, &src, fs)?;
        let write = |path: std::path::PathBuf, bytes: &[u8]| {
            std::fs::write(&path, bytes)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))
        };
        for (stage, words) in [("vert", vert), ("frag", frag)] {
            let path = dir.join(format!("{name}.{stage}.spv"));
            write(path, bytemuck::cast_slice::<u32, u8>(&words))?;
        }
        if wgsl {
            write(dir.join(format!("{name}.wgsl")), src.as_bytes())?;
        }
        names.push(name);
    }
    Ok(names)
}

/// Reads `tools/mali/cycles.sh` JSON.
pub fn read_cycles(path: &Path) -> Result<Value, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let v: Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: not JSON: {e}", path.display()))?;
    if !v["shaders"].is_object() {
        return Err(format!(
            "{}: no \"shaders\" (expected tools/mali/cycles.sh output)",
            path.display()
        ));
    }
    Ok(v)
}

/// Columns of `shader`'s fragment cycles on `gpu`, with its spill + fill count.
fn frag_cycles(mali: &Value, shader: &str, gpu: &str) -> Option<(Map<String, Value>, f64)> {
    let f = &mali["shaders"][shader][gpu]["frag"];
    let cols = f["cycles"].as_object()?.clone();
    let spills = f["spills"].as_f64().unwrap_or(0.0) + f["fills"].as_f64().unwrap_or(0.0);
    Some((cols, spills))
}

/// base + Σ n_i (variant_i − base) per column (differences ≥ 0); a variant that spills more
/// than the base contributes no load/store difference (its extra spills are the doubled
/// code's register pressure, not the loop's).
fn extrapolate(mali: &Value, base: &str, gpu: &str, steps: &[(&str, f64)]) -> Option<f64> {
    let (cols, spills) = frag_cycles(mali, base, gpu)?;
    let mut out: Vec<f64> = Vec::new();
    for (col, v) in &cols {
        let mut x = v.as_f64()?;
        for (variant, n) in steps {
            if let Some((vc, vs)) = frag_cycles(mali, variant, gpu) {
                let spill_artefact = vs > spills && (col == "ls" || col == "ldst");
                let d = vc.get(col).and_then(Value::as_f64).unwrap_or(x) - v.as_f64()?;
                if !spill_artefact {
                    x += n * d.max(0.0);
                }
            }
        }
        out.push(x);
    }
    out.into_iter().reduce(f64::max)
}

/// One frame's penumbra passes: the texels the seed pass shades and those the jump passes
/// shade, all together.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PenumbraRun {
    pub seed_texels: f64,
    pub jump_texels: f64,
}

impl PenumbraRun {
    /// The passes over the whole of the game's grid for the game's key light and character
    /// (the frustum the renderer fits, so the same number of jumps) and a material whose
    /// edge spread reaches `reach_mm`
    /// ([`dermis_engine::shading::edge_spread::reach_mm`]): an upper bound (a frame keeps
    /// them to the texels its receivers read).
    pub fn runner(reach_mm: f64) -> Self {
        use dermis_engine::render::{jump_steps, ShadowView, PENUMBRA_BLOCK};
        use dermis_engine::scene::{key_light, CHARACTER};
        let size = dermis_engine::render::SHADOW_MAP_SIZE;
        let (centre, radius) = CHARACTER.sphere_at(glam::Vec3::ZERO);
        let view = ShadowView::fit(key_light(glam::Vec3::ZERO).position, centre, radius, size);
        let grid = size / PENUMBRA_BLOCK;
        let width = view.texel_m * size as f32;
        let texels = (grid * grid) as f64;
        Self {
            seed_texels: texels,
            jump_texels: texels * jump_steps(grid, width, reach_mm as f32).count() as f64,
        }
    }
}

/// Fragment cycles on `gpu` of one frame's penumbra passes: (seed pass, jump passes).
pub fn penumbra_cycles(mali: &Value, gpu: &str, run: PenumbraRun) -> Option<(f64, f64)> {
    let bound = |s: &str| mali["shaders"][s][gpu]["frag"]["bound"].as_f64();
    Some((
        run.seed_texels * bound("penumbra_seed")?,
        run.jump_texels * bound("penumbra_jump")?,
    ))
}

/// Mali fragment cycles per pixel of `model` (`None`: unlit) on `gpu`: Mesa's static figure
/// (each instruction counted once) and the loop-weighted one: the per-channel light loop × 3,
/// and for screen-space models the subsurface pass with `rings.0` ring iterations of which
/// `rings.1` take `angles` samples (the rest are under half a pixel and skip theirs); for
/// models with the penumbra effect, the frame's penumbra passes (`penumbra`) spread over
/// the frame's `pixels` of skin.
pub fn mali_cost(
    mali: &Value,
    model: Option<ShadingModel>,
    gpu: &str,
    rings: (usize, usize),
    angles: usize,
    pixels: f64,
    penumbra: PenumbraRun,
) -> Option<(f64, f64)> {
    let name = model.map_or("unlit", |m| m.name());
    let bound = |s: &str| mali["shaders"][s][gpu]["frag"]["bound"].as_f64();
    let mut stat = bound(name)?;
    let channel = format!("{name}_x2channel");
    let mut weighted = extrapolate(mali, name, gpu, &[(&channel, 2.0)])?;
    if model.is_some_and(|m| m.effects().screen_space) {
        stat += bound("sss_pass")?;
        // x2ring − base: one ring's overhead and one sample; x2sample − base: one sample.
        let (all, sampled) = (rings.0.max(1) as f64, rings.1 as f64);
        let samples = (sampled * angles as f64 - all).max(0.0);
        weighted += extrapolate(
            mali,
            "sss_pass",
            gpu,
            &[
                ("sss_pass_x2ring", all - 1.0),
                ("sss_pass_x2sample", samples),
            ],
        )?;
    }
    if model.is_some_and(|m| m.effects().penumbra) {
        let (seed, jumps) = penumbra_cycles(mali, gpu, penumbra)?;
        let grid = (seed + jumps) / pixels.max(1.0);
        stat += grid;
        weighted += grid;
    }
    Some((stat, weighted))
}

pub fn run(args: ShadersArgs) -> Result<(), String> {
    let names = write_spirv(&args.spirv, args.wgsl)?;
    println!(
        "{}: {} shaders × 2 stages ({})",
        args.spirv.display(),
        names.len(),
        names.join(", ")
    );
    Ok(())
}
