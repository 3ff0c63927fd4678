//! Effects only where the scene calls for them: the game builds exactly the pipelines its
//! materials and tiers can reach, and the props' shader carries no subsurface code at all.

use std::path::Path;

use dermis_core::game::GameGpu;
use dermis_core::render::{Gpu, LiveObjects, PipelineSet, OFFSCREEN_FORMAT};
use dermis_core::scene::SceneAssets;
use dermis_core::shader::{compose, compose_from, ShaderDefs, MODULES};
use dermis_core::shading::ShadingModel;

/// The subsurface / skin-shading modules.
const SKIN_MODULES: [&str; 12] = [
    "ward",
    "ward_lobe",
    "ward_nd",
    "dipole",
    "dipole_nd",
    "oss",
    "oss_nd",
    "burley",
    "subsurface",
    "tabulated",
    "preintegrated",
    "fresnel",
];

fn spirv_instructions(src: &str) -> usize {
    let module = naga::front::wgsl::parse_str(src).unwrap();
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap();
    let words =
        naga::back::spv::write_vec(&module, &info, &naga::back::spv::Options::default(), None)
            .unwrap();
    let (mut i, mut n) = (5, 0);
    while i < words.len() {
        i += (words[i] >> 16).max(1) as usize;
        n += 1;
    }
    n
}

#[test]
fn the_prop_shader_is_identical_without_the_skin_modules() {
    let without: Vec<(&str, &str)> = MODULES
        .iter()
        .copied()
        .filter(|(n, _)| !SKIN_MODULES.contains(n))
        .collect();
    assert!(without.len() < MODULES.len());
    let full = compose("prop", &ShaderDefs::new()).unwrap();
    let bare = compose_from(&without, "prop", &ShaderDefs::new()).unwrap();
    assert_eq!(full, bare);
    assert_eq!(spirv_instructions(&full), spirv_instructions(&bare));
    // …and the removal is real: the character cannot be built without them.
    assert!(compose_from(&without, "character", &ShadingModel::Oss.defs()).is_err());
}

#[test]
fn the_game_builds_exactly_the_pipelines_it_can_reach() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets =
        SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None).unwrap();
    let before = LiveObjects::read(&gpu.device);
    let gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets).unwrap();
    let after = LiveObjects::read(&gpu.device);
    let needed = PipelineSet::game();
    assert_eq!(gg.renderer.built_pipelines(), needed);
    assert!(!needed.unlit, "the game never draws the unlit baseline");
    // One pipeline per reachable model, one for props, one for the UI, and — because the
    // menu reaches screen-space models — the props' two-target variant and the subsurface
    // pass; and the blob shadows' two (one per target layout: the props cast); the key
    // light's shadow map's depth-only caster (the character casts) and — because the menu
    // reaches a model with the penumbra effect — the penumbra map's two passes.
    assert!(needed.needs_subsurface_pass() && gg.renderer.has_subsurface_pass());
    assert!(gg.renderer.has_shadow_map());
    let penumbra = needed.models.iter().any(|m| m.effects().penumbra);
    assert!(penumbra);
    assert_eq!(
        after.render_pipelines - before.render_pipelines,
        needed.models.len() as isize + 6 + 1 + 2
    );
}

#[test]
fn each_model_composes_exactly_the_effects_it_declares() {
    for model in ShadingModel::ALL {
        let src = compose("character", &model.defs()).unwrap();
        let has = |m: &str| src.contains(&format!("// ---- module {m} ----"));
        let e = model.effects();
        assert_eq!(has("ward_lobe"), e.specular, "{model}: specular lobe");
        assert_eq!(
            has("dipole_nd") || has("oss_nd") || has("subsurface"),
            e.subsurface,
            "{model}: subsurface"
        );
        assert_eq!(
            src.contains("let translucency") || src.contains("sss_slab("),
            e.translucency,
            "{model}: translucency"
        );
        assert_eq!(
            src.contains("fn fs_main(in: VertexOut) -> SplitOut"),
            e.screen_space,
            "{model}: screen-space split"
        );
        assert_eq!(
            src.contains("textureSampleLevel(lut"),
            e.lut,
            "{model}: LUT"
        );
        // Texture: the model reads the surface's albedo (the sampled texture) in `shade`.
        let shade = &src[src.find("fn shade(").unwrap()..];
        assert_eq!(shade.contains("s.albedo"), e.texture, "{model}: texture");
    }
}
