//! Effects only where the scene calls for them: the game builds exactly the pipelines its
//! materials and tiers can reach, and the props' shader carries no subsurface code at all.

use dermis_engine::render::passes::PassId;
use std::path::Path;

use dermis_engine::render::standard_keys;
use dermis_engine::render::{
    Clock, FrameDriver, Gpu, LiveObjects, Offscreen, Output, PipelineSet, OFFSCREEN_FORMAT,
};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shader::{compose, compose_from, modules, ShaderDefs};
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, Session};
use dermis_game::rules::Screen;

/// The modules composed into some model's character shader but not into the props': the
/// skin-shading code (derived from the registry, so a new model's modules are in it).
fn skin_modules() -> Vec<&'static str> {
    let marker = |src: &str, name: &str| src.contains(&format!("// ---- module {name} ----"));
    let prop = compose("prop", &ShaderDefs::new()).unwrap();
    let characters: Vec<String> = ShadingModel::ALL
        .iter()
        .map(|m| compose("character", &m.defs()).unwrap())
        .collect();
    modules()
        .iter()
        .map(|(n, _)| *n)
        .filter(|n| !marker(&prop, n) && characters.iter().any(|c| marker(c, n)))
        .collect()
}

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
    let skin = skin_modules();
    // Every model's own module is among them.
    for m in ShadingModel::ALL {
        assert!(skin.contains(&m.module()), "{m}");
    }
    let without: Vec<(&str, &str)> = modules()
        .iter()
        .copied()
        .filter(|(n, _)| !skin.contains(n))
        .collect();
    assert!(without.len() < modules().len());
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
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT).unwrap();
    // The first model's pipeline now, the others' from the background builder.
    gg.finish_loading(&gpu);
    let after = LiveObjects::read(&gpu.device);
    let needed = PipelineSet::game();
    assert_eq!(gg.renderer.built_pipelines(), needed);
    assert!(!needed.unlit, "the game never draws the unlit baseline");
    // One pipeline per reachable model, one for props, one for the UI, and — because the
    // menu reaches screen-space models — the props' two-target variant and the subsurface
    // pass; and the blob shadows' two (one per target layout: the props cast); the key
    // light's shadow map's depth-only caster (the character casts) and — because the menu
    // reaches a model with the penumbra effect — the penumbra map's two passes; and for each
    // standard material variant of the character (its cloth), one per target layout.
    assert!(needed.needs_subsurface_pass() && gg.renderer.is_on(PassId::subsurface));
    assert!(gg.renderer.has_shadow_map());
    let penumbra = needed.models.iter().any(|m| m.effects().penumbra);
    assert!(penumbra);
    let standard = standard_keys(&assets.character, &assets.roles).len() as isize;
    assert!(
        standard >= 1,
        "the character's cloth is a standard material"
    );
    assert_eq!(
        after.render_pipelines - before.render_pipelines,
        needed.models.len() as isize + 6 + 1 + 2 + 2 * standard
    );
}

#[test]
fn a_model_chosen_before_its_pipeline_arrives_is_drawn_and_play_finds_every_pipeline() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets =
        SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None).unwrap();
    // The first pipeline is the first model's; the menu's first frame shows the last one.
    let (first, shown) = (
        ShadingModel::ALL[0],
        ShadingModel::ALL[ShadingModel::ALL.len() - 1],
    );
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, first).unwrap();
    let target = Offscreen::new(&gpu, 96, 72);
    let mut session = Session::new(&assets.character, 1, None, true);
    session.settings.set_shading_model(shown);
    let mut driver = FrameDriver::new(Clock::Fixed(1.0 / 60.0));
    driver.sync = true;
    let mut frame = |session: &mut Session, gg: &mut GameGpu| {
        let mut f = GameFrame::new(session, gg, &assets.character);
        f.run(&mut driver, &gpu, Output::Offscreen(&target))
            .unwrap();
        f.stats
    };
    let stats = frame(&mut session, &mut gg);
    // The character's triangles were drawn: its pipeline was waited for, not skipped.
    assert_eq!(session.drawn_model(), shown);
    assert!(
        stats.triangles >= gg.renderer.character_triangles(),
        "{stats:?}"
    );
    // The bot starts the run after half a second: by then every pipeline is in.
    while session.game.screen() != Screen::Play {
        frame(&mut session, &mut gg);
    }
    frame(&mut session, &mut gg);
    assert!(!gg.renderer.pipelines_loading());
    let live = LiveObjects::read(&gpu.device);
    gg.finish_loading(&gpu);
    assert_eq!(LiveObjects::read(&gpu.device), live);
}

#[test]
fn each_model_composes_exactly_the_effects_it_declares() {
    for model in ShadingModel::ALL {
        let src = compose("character", &model.defs()).unwrap();
        let has = |m: &str| src.contains(&format!("// ---- module {m} ----"));
        let e = model.effects();
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
            src.contains("-> SplitOut {"),
            e.screen_space,
            "{model}: screen-space split"
        );
        assert_eq!(
            src.contains("textureSampleLevel(lut"),
            e.lut,
            "{model}: LUT"
        );
        assert_eq!(
            src.contains("textureLoad(penumbra_map"),
            e.penumbra,
            "{model}: penumbra map"
        );
    }
}
