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

/// Named exceptions: where a model is named outside its own files on purpose, `(file, name,
/// why)`.
const EXCEPTIONS: &[(&str, &str, &str)] = &[
    (
        "android_app/src/soak.rs",
        "Oss",
        "the Game Loop scenarios 1 and 3 run the paper's OSS by the published protocol",
    ),
    (
        "engine/src/shading/bake.rs",
        "tabulated",
        "the measured tables' module names the two models that read them (being rewritten \
         with the LUT code)",
    ),
    (
        "engine/src/shading/bake.rs",
        "preintegrated",
        "the measured tables' module names the two models that read them (being rewritten \
         with the LUT code)",
    ),
    (
        "engine/src/shading/sphere_grid.rs",
        "preintegrated",
        "the LUT model's sphere rows for any material, interpolated from the shipped grid",
    ),
    (
        "measure/src/grid.rs",
        "preintegrated",
        "the offline bake of the LUT model's sphere-row grid (not linked into the APK)",
    ),
    (
        "src/cmd/bench_tables.rs",
        "preintegrated",
        "the grid's yardstick compares the LUT model's sphere rows with a direct bake",
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

/// Models whose registry name is also the name of the maths they implement, which the
/// shared modules and the paper's other models use by that name (Ward's lobe in OSS, the
/// dipole's R_d as Ward's diffuse colour, OSS's colour model, Burley's diffusion profile and
/// sampling): for these only the registry's variant and the module path count as naming the
/// model. Every other model's name is its own: any mention counts.
const CONCEPTS: &[&str] = &["ward", "dipole", "oss", "burley"];

/// Whether `word` occurs in `text` as a whole word (not inside an identifier).
fn has_word(text: &str, word: &str) -> bool {
    let part = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(word).any(|(i, _)| {
        !text[..i].chars().next_back().is_some_and(part)
            && !text[i + word.len()..].chars().next().is_some_and(part)
    })
}

/// Every name of `m` that counts as naming it in `code` (the variant, the module path, the
/// registry name, …), as found.
fn names_in(m: ShadingModel, code: &str) -> Vec<String> {
    let d = m.descriptor();
    let variant = format!("{m:?}");
    let mut found = Vec::new();
    let path = format!("ShadingModel::{variant}");
    if code
        .match_indices(&path)
        .any(|(i, _)| !code[i + path.len()..].starts_with(char::is_alphanumeric))
    {
        found.push(variant.clone());
    }
    // The paper's closed-form models share analytic functions (Ward's lobe in OSS, the
    // dipole's R_d as Ward's diffuse, their nondimensional kernels in the conformance suite),
    // and the spatial models the `subsurface` module (their uniform and kernel, the
    // screen-space models' WGSL); every other model's module path names it too.
    let shares_code = ["ward", "dipole", "oss", "subsurface"].contains(&d.module);
    let module = format!("{}::", d.module);
    if !shares_code
        && code
            .match_indices(&module)
            .any(|(i, _)| !code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_'))
    {
        found.push(d.module.to_string());
    }
    if !CONCEPTS.contains(&d.name) {
        // (The composition flag a descriptor declares, e.g. `WARD_PRINTED`, is what it hands
        // the composer: a shared module may read it.)
        let upper = d.name.to_uppercase().replace('-', "_");
        let upper = Some(upper.as_str()).filter(|u| d.variant != Some(*u));
        for word in [Some(d.name), Some(variant.as_str()), upper]
            .into_iter()
            .flatten()
        {
            if has_word(code, word) && !found.iter().any(|f| f == word) {
                found.push(word.to_string());
            }
        }
    }
    found
}

/// The tracked Rust and WGSL sources outside the tests, comments included (an inline unit
/// test, after `#[cfg(test)]`, may name what it tests).
fn sources() -> Vec<(String, String)> {
    let files = Command::new("git")
        .args(["ls-files", "*.rs", "*.wgsl"])
        .current_dir(root())
        .output()
        .expect("git");
    let files = String::from_utf8_lossy(&files.stdout);
    files
        .lines()
        .filter(|f| !f.starts_with("tests/") && !f.contains("/tests/") && !f.ends_with("tests.rs"))
        .map(|f| {
            let text = std::fs::read_to_string(root().join(f)).unwrap_or_default();
            let code = text.split("#[cfg(test)]").next().unwrap_or("").to_string();
            (f.to_string(), code)
        })
        .collect()
}

/// Every mention of a model outside its own files (its Rust file, its module's Rust and WGSL
/// files, the registry's rows) and the named exceptions: `"file names key"`.
fn mentions(sources: &[(String, String)]) -> Vec<String> {
    let mut found = Vec::new();
    for m in ShadingModel::ALL {
        let d = m.descriptor();
        let own = |f: &str| {
            f == format!("engine/src/shading/{}.rs", d.module)
                || f == format!("engine/src/shading/{}.rs", d.name)
                || f == format!("shaders/{}.wgsl", d.module)
                || f == "engine/src/shading/mod.rs"
        };
        for (f, code) in sources {
            if own(f) {
                continue;
            }
            for key in names_in(m, code) {
                let excepted = EXCEPTIONS.iter().any(|(ef, ek, _)| ef == f && *ek == key);
                let line = format!("{f} names {key}");
                if !excepted && !found.contains(&line) {
                    found.push(line);
                }
            }
        }
    }
    found
}

#[test]
fn no_source_outside_a_models_place_names_it() {
    let sources = sources();
    assert!(
        sources.len() > 50,
        "git ls-files found {} sources",
        sources.len()
    );
    let found = mentions(&sources);
    assert!(
        found.is_empty(),
        "models named outside their place: {found:#?}"
    );
    // Every exception is still needed (a stale one would hide nothing, but mislead).
    for (f, key, why) in EXCEPTIONS {
        let code = &sources.iter().find(|(s, _)| s == f).expect(f).1;
        assert!(
            ShadingModel::ALL
                .iter()
                .any(|m| names_in(*m, code).iter().any(|k| k == key)),
            "{f}: exception for {key} ({why}) no longer needed"
        );
    }
}

#[test]
fn a_new_mention_anywhere_is_caught() {
    // In code, in a comment, in a shader, by any of a model's names: each planted mention of
    // the default model (whose name is its own) in a file outside its place is found.
    let d = ShadingModel::DEFAULT.descriptor();
    assert!(!CONCEPTS.contains(&d.name), "{}", d.name);
    let variant = format!("{:?}", ShadingModel::DEFAULT);
    for (file, text) in [
        (
            "engine/src/render/renderer.rs",
            format!("let m = ShadingModel::{variant};"),
        ),
        (
            "engine/src/shader/consts.rs",
            format!("// the LUT of `{}`", d.name),
        ),
        ("shaders/common.wgsl", format!("// as {} needs it", d.name)),
        (
            "src/cmd/pareto.rs",
            format!("row(\"{}\", 0.1, 2.0)", d.name),
        ),
    ] {
        let planted = [(file.to_string(), text.clone())];
        assert_eq!(mentions(&planted).len(), 1, "{file}: {text}");
    }
    // A word that only contains a name is not one.
    assert!(!has_word(&format!("x_{}", d.name), d.name));
    assert!(!has_word(&format!("{}s", d.name), d.name));
    assert!(has_word(&format!("`{}`-style", d.name), d.name));
}
