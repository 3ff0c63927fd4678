//! The README's "Adding a model": a model is its `engine/src/shading/<module>.rs` (declaring its
//! `Descriptor`), its `shaders/<module>.wgsl` and its row in `engine/src/shading/mod.rs`.
//!
//! Two halves prove it. Every registered model reaches every consumer through the registry
//! alone — the composer, naga, the conformance harness, the renderer, the CLI, the menu — and
//! no source outside a model's own files and its row names it, so no list elsewhere can
//! silently miss a new one.

use std::path::Path;
use std::process::Command;

use dermis_engine::render::Gpu;
use dermis_engine::scene::SceneAssets;
use dermis_engine::shader::{compose, modules};
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};
use dermis_game::app::{Key, Session};
use dermis_measure::conformance::harness::shade_source;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn marker(module: &str) -> String {
    format!("// ---- module {module} ----")
}

fn valid(label: &str, src: &str) {
    let module = naga::front::wgsl::parse_str(src)
        .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(src)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(src)));
}

#[test]
fn every_registered_model_is_composed_validated_and_conformance_compiled() {
    for m in ShadingModel::ALL {
        let d = m.descriptor();
        // The composer finds the model's module through its descriptor, with its file's text.
        let file = std::fs::read_to_string(root().join(format!("shaders/{}.wgsl", d.module)))
            .unwrap_or_else(|e| panic!("{m}: {e}"));
        assert_eq!(
            d.wgsl, file,
            "{m}: the descriptor embeds shaders/{}.wgsl",
            d.module
        );
        assert!(modules()
            .iter()
            .any(|(n, s)| *n == d.module && *s == d.wgsl));
        let character = compose("character", &m.defs()).unwrap();
        assert!(character.contains(&marker(d.module)), "{m}");
        valid(&format!("character/{m}"), &character);
        // The conformance harness's kernel: the model's shade plus its WGSL probe.
        let harness = shade_source(m);
        assert!(harness.contains(d.probe_wgsl), "{m}");
        valid(&format!("conformance/{m}"), &harness);
    }
}

#[test]
fn every_registered_model_renders_and_is_listed_by_the_cli_and_the_menu() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets = SceneAssets::load(&root().join("assets"), None).unwrap();
    let mut still = StillRenderer::new(&gpu, &assets, 96, 72).unwrap();
    let empty = still
        .render(
            &gpu,
            &assets,
            &Shot {
                shading: None,
                ..Shot::new(ShadingModel::DEFAULT, SKIN1)
            },
        )
        .unwrap();
    for m in ShadingModel::ALL {
        let image = still.render(&gpu, &assets, &Shot::new(m, SKIN1)).unwrap();
        let changed = image
            .pixels
            .chunks_exact(4)
            .zip(empty.pixels.chunks_exact(4))
            .filter(|(a, b)| a[..3] != b[..3])
            .count();
        assert!(
            changed > 200,
            "{m}: only {changed} pixels differ from the unlit frame"
        );
    }

    // The CLI's help and its parser.
    let help = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&help.stdout);
    for m in ShadingModel::ALL {
        assert!(help.contains(m.name()), "`dermis --help` does not list {m}");
        assert_eq!(m.name().parse::<ShadingModel>(), Ok(m));
    }

    // The menu's skin switch visits every model once and comes back.
    let mut session = Session::new(&assets.character, 1, None, false);
    let start = session.shading();
    let mut seen = vec![start];
    for _ in 1..ShadingModel::ALL.len() {
        session.key(Key::NextModel);
        seen.push(session.shading());
    }
    session.key(Key::NextModel);
    assert_eq!(session.shading(), start);
    seen.sort();
    assert_eq!(seen, ShadingModel::ALL.to_vec());
}

/// Named exceptions: where a model is named outside its own files on purpose.
const EXCEPTIONS: &[(&str, &str, &str)] = &[
    (
        "android_app/src/soak.rs",
        "Oss",
        "the Game Loop scenarios 1 and 3 run the paper's OSS by the published protocol",
    ),
    (
        "engine/src/shader/consts.rs",
        "preintegrated",
        "the shaders' copy of the LUT's layout (rows, width, slab span), written once in its file",
    ),
    (
        "measure/src/lut.rs",
        "preintegrated",
        "the LUT model's offline bake (Monte Carlo spheres; not linked into the APK)",
    ),
    (
        "measure/src/bake.rs",
        "preintegrated",
        "installs that bake for materials no shipped LUT covers (measurement commands)",
    ),
    (
        "src/cmd/lut.rs",
        "preintegrated",
        "`dermis lut` writes the shipped LUT files",
    ),
];

#[test]
fn no_source_outside_a_models_place_names_it() {
    let files = Command::new("git")
        .args(["ls-files", "*.rs"])
        .current_dir(root())
        .output()
        .expect("git");
    let files = String::from_utf8_lossy(&files.stdout);
    let sources: Vec<(&str, String)> = files
        .lines()
        .filter(|f| !f.starts_with("tests/") && !f.contains("/tests/") && !f.ends_with("tests.rs"))
        .map(|f| {
            let text = std::fs::read_to_string(root().join(f)).unwrap_or_default();
            // Inline unit tests may name what they test.
            let code = text.split("#[cfg(test)]").next().unwrap_or("").to_string();
            (f, code)
        })
        .collect();
    assert!(
        sources.len() > 50,
        "git ls-files found {} sources",
        sources.len()
    );
    let mut found = Vec::new();
    for m in ShadingModel::ALL {
        let d = m.descriptor();
        let own = |f: &str| {
            f == format!("engine/src/shading/{}.rs", d.module)
                || f == format!("engine/src/shading/{}.rs", d.name)
                || f == "engine/src/shading/mod.rs"
        };
        let variant = format!("ShadingModel::{m:?}");
        // The paper's closed-form models share analytic functions (Ward's lobe in OSS, the
        // dipole's R_d as Ward's diffuse, their nondimensional kernels in the conformance
        // suite), and the spatial models the `subsurface` module (their uniform and kernel,
        // the screen-space models' WGSL); every other model's module path names it too.
        let shares_code = ["ward", "dipole", "oss", "subsurface"].contains(&d.module);
        let path = format!("{}::", d.module);
        for (f, code) in &sources {
            if own(f) {
                continue;
            }
            let names_variant = code
                .match_indices(&variant)
                .any(|(i, _)| !code[i + variant.len()..].starts_with(char::is_alphanumeric));
            let names_module = !shares_code
                && code
                    .match_indices(&path)
                    .any(|(i, _)| !code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_'));
            if names_variant || names_module {
                let key = if names_variant {
                    format!("{m:?}")
                } else {
                    d.module.to_string()
                };
                if !EXCEPTIONS.iter().any(|(ef, ek, _)| ef == f && *ek == key) {
                    found.push(format!("{f} names {key}"));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "models named outside their place: {found:#?}"
    );
    // Every exception is still needed (a stale one would hide nothing, but mislead).
    for (f, key, why) in EXCEPTIONS {
        let code = &sources.iter().find(|(s, _)| s == f).expect(f).1;
        assert!(
            code.contains(&format!("ShadingModel::{key}")) || code.contains(&format!("{key}::")),
            "{f}: exception for {key} ({why}) no longer needed"
        );
    }
}
