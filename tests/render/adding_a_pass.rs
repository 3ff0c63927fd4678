//! The README's "Adding a pass": a pass is its module `engine/src/render/passes/<name>.rs` (its
//! pipelines, its bind groups, `build`, `prepare` and one `encode` or `draw`) and its row in
//! `passes!` (`engine/src/render/passes/mod.rs`).
//!
//! For every row: its module exists and declares the row's type; the renderer builds it where
//! the scene needs what it draws for and not otherwise; in a frame that needs it, it runs and
//! records (its own count in the frame's statistics), in a frame that does not, it records
//! nothing; and no source outside its module and the registry names its type, so the frame's
//! walk reaches it through the row alone. The table is the only place that lists the passes
//! (no other render file imports a pass's module; no pass imports another's), and the
//! frame's order, derived from what each pass declares it creates, reads and writes, is a
//! valid one.

use dermis_engine::render::passes::PassId;
use std::path::Path;

use dermis_engine::camera::look_at;
use dermis_engine::render::graph::{self, Stage, Target};
use dermis_engine::render::passes::{frame_order, stage, ACCESS, NAMES, PASS_COUNT};
use dermis_engine::render::{Gpu, Offscreen, PipelineSet, RenderStats, Renderer, OFFSCREEN_FORMAT};
use dermis_engine::scene::{
    key_light, showroom, DrawSet, FramePacket, FrameView, SceneAssets, SubjectPose, EXPOSURE,
};
use dermis_engine::shading::ShadingModel;
use glam::{Mat4, Vec3};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Each row's (name, type), read from the registry's source.
fn rows() -> Vec<(String, String)> {
    let src = std::fs::read_to_string(root().join("engine/src/render/passes/mod.rs")).unwrap();
    let body = &src[src.rfind("passes! {").expect("the registry")..];
    let body = &body[..body.find("\n}").unwrap()];
    body.lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("//") && l.contains(':') && l.ends_with(','))
        .map(|l| {
            let (name, ty) = l.trim_end_matches(',').split_once(':').unwrap();
            (name.trim().to_string(), ty.trim().to_string())
        })
        .collect()
}

#[test]
fn every_row_has_its_module_and_only_its_module_names_it() {
    let rows = rows();
    let names: Vec<&str> = rows.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, NAMES, "the registry's rows, in frame order");
    let passes = root().join("engine/src/render/passes");
    let mut sources = Vec::new();
    let mut stack = vec![
        root().join("engine/src"),
        root().join("game/src"),
        root().join("src"),
    ];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                sources.push((p.clone(), std::fs::read_to_string(&p).unwrap()));
            }
        }
    }
    for (name, ty) in &rows {
        let module = passes.join(format!("{name}.rs"));
        let text = std::fs::read_to_string(&module).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            text.contains(&format!("pub struct {ty}"))
                && text.contains(&format!("impl Pass for {ty}")),
            "{name}.rs declares {ty} and implements Pass for it"
        );
        for (path, text) in &sources {
            let own = *path == module || path.ends_with("render/passes/mod.rs");
            if !own {
                assert!(
                    !text.contains(ty.as_str()),
                    "{} names the pass type {ty}: the frame reaches passes through their rows",
                    path.display()
                );
            }
        }
    }
}

#[test]
fn the_table_alone_lists_the_passes_and_their_declarations_order_the_frame() {
    // No render file outside the table imports a pass's module (the renderer's public
    // shader-source re-exports in render/mod.rs aside), and no pass imports another's.
    let render = root().join("engine/src/render");
    let mut files = Vec::new();
    for dir in [render.clone(), render.join("passes")] {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "rs") {
                files.push(p);
            }
        }
    }
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap();
        let file = path.file_stem().unwrap().to_str().unwrap();
        let in_passes = path.parent().unwrap().ends_with("passes");
        if file == "mod" {
            continue;
        }
        for name in NAMES {
            if in_passes && file == name {
                continue;
            }
            for import in [format!("passes::{name}"), format!("super::{name}::")] {
                assert!(
                    !(text.contains(&import) && (in_passes || import.starts_with("passes"))),
                    "{} imports the {name} pass's module: passes are reached through the table",
                    path.display()
                );
            }
        }
    }
    // The order derived from the declarations is valid, and puts the light's maps first, the
    // scene next and the output last.
    let order = frame_order();
    graph::check(&ACCESS, order).unwrap_or_else(|e| panic!("{e}"));
    let stages: Vec<Stage> = order.iter().map(|&s| stage(s)).collect();
    assert!(stages.windows(2).all(|w| w[0] <= w[1]), "{stages:?}");
    let at = |name: &str| {
        let slot = NAMES.iter().position(|n| *n == name).unwrap();
        order.iter().position(|&s| s == slot).unwrap()
    };
    for (name, target) in [
        ("shadow_map", Target::ShadowMap),
        ("penumbra", Target::PenumbraMap),
    ] {
        for (reader, access) in NAMES.iter().zip(ACCESS) {
            if access.reads.contains(&target) && *reader != name {
                assert!(at(name) < at(reader), "{name} before {reader}");
            }
        }
    }
    // Every pass writes something, and every transient target has a creator.
    for (name, access) in NAMES.iter().zip(ACCESS) {
        assert!(!access.writes.is_empty(), "{name} writes nothing");
    }
    let creates_split = ACCESS.iter().filter(|a| a.creates.contains(&Target::Split));
    assert_eq!(
        creates_split.count(),
        1,
        "one pass creates the split targets"
    );
}

/// A renderer with the whole scene (the character, the props, blob shadows, the UI) for
/// `set`, and one frame of `model` prepared and drawn at 160×120.
struct Scene {
    gpu: Gpu,
    assets: SceneAssets,
    target: Offscreen,
}

impl Scene {
    fn new() -> Self {
        let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
        let assets = SceneAssets::load(&root().join("assets"), None).unwrap();
        let target = Offscreen::new(&gpu, 160, 120);
        Self {
            gpu,
            assets,
            target,
        }
    }

    fn renderer(&self, set: &PipelineSet) -> Renderer {
        let gpu = &self.gpu;
        let mut r = Renderer::with_pipelines(gpu, OFFSCREEN_FORMAT, set);
        let assets = &self.assets;
        r.load_scene(gpu, (&assets.character, &assets.roles), &assets.props)
            .unwrap();
        r.enable(gpu, PassId::blobs);
        r.enable(gpu, PassId::ui);
        r.resize(gpu, (160, 120));
        r
    }

    /// One frame drawing `draw` (a UI of one quad when `draw.ui`), the whole character in
    /// view; its statistics and what each pass decided.
    fn frame(&self, r: &mut Renderer, draw: DrawSet) -> (RenderStats, [bool; PASS_COUNT]) {
        self.frame_from(r, draw, Vec3::new(1.2, 1.5, 3.5), Vec3::new(0.0, 0.9, 0.0))
    }

    /// The same from `eye`, looking at `at`.
    fn frame_from(
        &self,
        r: &mut Renderer,
        draw: DrawSet,
        eye: Vec3,
        at: Vec3,
    ) -> (RenderStats, [bool; PASS_COUNT]) {
        let model = &self.assets.character;
        let mut pose = dermis_engine::anim::Pose::new(model);
        pose.update_world(model);
        let view = FrameView {
            view_proj: look_at(eye, at, 0.8, 160.0 / 120.0),
            camera_pos: eye,
            light: key_light(Vec3::ZERO),
            exposure: EXPOSURE,
        };
        let mut ui = dermis_engine::ui::Ui::with_embedded_atlas();
        ui.begin(160.0, 120.0, 1.0, dermis_engine::ui::Insets::ZERO);
        ui.fill(dermis_engine::ui::Rect::new(4.0, 4.0, 20.0, 10.0), [1.0; 4]);
        ui.end();
        let props = showroom();
        let packet = FramePacket {
            subject: Some(SubjectPose {
                model,
                pose: &pose,
                world: Mat4::IDENTITY,
            }),
            props: &props,
            ui: ui.vertices(),
            ..FramePacket::new((160, 120), view, draw)
        };
        let frame = r.prepare(&self.gpu, &packet);
        let stats = r
            .draw_offscreen(&self.gpu, &self.target, &frame)
            .unwrap_or_else(|e| panic!("{e}"));
        (stats, frame.passes.map(|p| p.runs))
    }
}

fn everything(shading: ShadingModel) -> DrawSet {
    DrawSet {
        shading: Some(shading),
        character: true,
        props: true,
        ui: true,
    }
}

#[test]
fn every_pass_is_built_where_needed_and_records_when_it_runs() {
    let scene = Scene::new();
    // Every model, so every effect is reachable: every pass is built.
    let mut all = scene.renderer(&PipelineSet::everything());
    assert_eq!(all.passes_built(), [true; PASS_COUNT], "{NAMES:?}");
    // The penumbra tier close up (the face, 0.4 m away: 3 mm pixels, finer than skin's
    // diffusion length) and a screen-space tier between them run every pass; a pass that
    // runs records, one that does not records nothing.
    let penumbra = ShadingModel::ALL
        .into_iter()
        .find(|m| m.effects().penumbra)
        .unwrap();
    let split = ShadingModel::ALL
        .into_iter()
        .find(|m| m.effects().screen_space)
        .unwrap();
    let mut ran = [false; PASS_COUNT];
    let slot_of = |name: &str| NAMES.iter().position(|n| *n == name).unwrap();
    // The whole character in 120 pixels (~3 cm each): the penumbra would change nothing seen.
    let (_, far) = scene.frame(&mut all, everything(penumbra));
    assert!(!far[slot_of("penumbra")], "no penumbra map for 3 cm pixels");
    let face = (Vec3::new(0.1, 1.5, 0.4), Vec3::new(0.0, 1.45, 0.0));
    for model in [penumbra, split] {
        let (stats, runs) = if model == penumbra {
            scene.frame_from(&mut all, everything(model), face.0, face.1)
        } else {
            scene.frame(&mut all, everything(model))
        };
        if model == penumbra {
            assert!(runs[slot_of("penumbra")], "the penumbra map close up");
        }
        for slot in 0..PASS_COUNT {
            assert_eq!(
                runs[slot],
                stats.passes[slot] > 0,
                "{model}: {} runs {} with {} draw calls",
                NAMES[slot],
                runs[slot],
                stats.passes[slot]
            );
            ran[slot] |= runs[slot];
        }
        assert_eq!(stats.passes.iter().sum::<u32>(), stats.draw_calls);
    }
    assert_eq!(
        ran, [true; PASS_COUNT],
        "every pass ran in one of the two frames: {NAMES:?}"
    );
    // A plain frame — a one-pass model without the penumbra, no props, no UI — runs only the
    // shadow map and the character.
    let plain = ShadingModel::BASELINE;
    assert!(!plain.effects().penumbra && !plain.effects().screen_space);
    let draw = DrawSet {
        props: false,
        ui: false,
        ..everything(plain)
    };
    let (stats, runs) = scene.frame(&mut all, draw);
    for slot in 0..PASS_COUNT {
        let expected = matches!(NAMES[slot], "shadow_map" | "character");
        assert_eq!(runs[slot], expected, "{} in a plain frame", NAMES[slot]);
        assert_eq!(
            stats.passes[slot] > 0,
            expected,
            "{}: {stats:?}",
            NAMES[slot]
        );
    }
    // A scene that cannot reach an effect has no pass for it.
    let one_pass = PipelineSet {
        models: vec![plain],
        unlit: false,
    };
    let built = scene.renderer(&one_pass).passes_built();
    for slot in 0..PASS_COUNT {
        let effect_pass = matches!(NAMES[slot], "penumbra" | "subsurface");
        assert_eq!(
            built[slot], !effect_pass,
            "{} with {one_pass:?}",
            NAMES[slot]
        );
    }
}
