//! Every composed shader validates with naga (the compiler wgpu uses) and with Dawn's
//! independent compiler, tint: the project's `tools/wgsl-tint` (npm package `webgpu`, which
//! `.ci/run` installs) or a `tint` executable on the PATH. Without either the tint check says
//! loudly that it did not run, and fails under `CI=true`. And every WGSL declaration is
//! written once: no two modules declare the same item, no file declares a struct the
//! composer generates from Rust, and the penumbra's seed pass refuses a block size other than
//! the Rust side's.

use dermis_engine::shader::uniforms::PENUMBRA_BLOCK;
use dermis_engine::shader::{compose, compose_from, module_source, modules, structs, ShaderDefs};
use dermis_engine::shading::ShadingModel;

/// Every (label, composed source) the renderer can build.
fn all_shaders() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = ShadingModel::ALL
        .iter()
        .map(|m| {
            (
                format!("character/{}", m.name()),
                compose("character", &m.defs()).unwrap(),
            )
        })
        .collect();
    // A mesh with a normal map (the scanned head) gets each model's NORMAL_MAP variant.
    out.extend(ShadingModel::ALL.iter().map(|m| {
        (
            format!("character/{}/normal-map", m.name()),
            compose("character", &m.defs().flag("NORMAL_MAP")).unwrap(),
        )
    }));
    let unlit = ShaderDefs::new().alias("shading_model", "unlit");
    out.push((
        "character/unlit".into(),
        compose("character", &unlit).unwrap(),
    ));
    out.push(("prop".into(), compose("prop", &ShaderDefs::new()).unwrap()));
    let split = ShaderDefs::new().flag("SCREEN_SPACE");
    out.push(("prop/split".into(), compose("prop", &split).unwrap()));
    out.push((
        "sss_pass".into(),
        compose("sss_pass", &ShaderDefs::new()).unwrap(),
    ));
    out.push(("ui".into(), compose("ui", &ShaderDefs::new()).unwrap()));
    out.push((
        "shadow".into(),
        compose("shadow", &ShaderDefs::new()).unwrap(),
    ));
    out.push(("shadow/split".into(), compose("shadow", &split).unwrap()));
    out.push((
        "penumbra".into(),
        compose("penumbra", &ShaderDefs::new()).unwrap(),
    ));
    out.push((
        "shadow_caster".into(),
        compose("shadow_caster", &ShaderDefs::new()).unwrap(),
    ));
    out
}

fn validate(label: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
    let mut validator = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    );
    let info = validator
        .validate(&module)
        .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(source)));
    // Both backends the app ships must accept it: SPIR-V (Vulkan) and GLSL ES 3.00 (GLES).
    naga::back::spv::write_vec(&module, &info, &naga::back::spv::Options::default(), None)
        .unwrap_or_else(|e| panic!("{label}: SPIR-V: {e}"));
    // Every entry point (most shaders: vs_main + fs_main; the penumbra passes have two
    // fragment entries, the shadow caster only vertex ones).
    let entries: Vec<(naga::ShaderStage, String)> = module
        .entry_points
        .iter()
        .map(|e| (e.stage, e.name.clone()))
        .collect();
    for (stage, entry) in entries {
        let entry = entry.as_str();
        let mut glsl = String::new();
        let options = naga::back::glsl::Options {
            version: naga::back::glsl::Version::Embedded {
                version: 300,
                is_webgl: false,
            },
            ..Default::default()
        };
        let pipeline = naga::back::glsl::PipelineOptions {
            shader_stage: stage,
            entry_point: entry.into(),
            multiview: None,
        };
        let mut writer = naga::back::glsl::Writer::new(
            &mut glsl,
            &module,
            &info,
            &options,
            &pipeline,
            naga::proc::BoundsCheckPolicies::default(),
        )
        .unwrap_or_else(|e| panic!("{label}: GLSL {entry}: {e}"));
        writer
            .write()
            .unwrap_or_else(|e| panic!("{label}: GLSL {entry}: {e}"));
    }
    module
}

#[test]
fn every_shader_passes_naga_validation_and_both_backends() {
    for (label, source) in all_shaders() {
        let module = validate(&label, &source);
        let has = |stage| module.entry_points.iter().any(|e| e.stage == stage);
        assert!(has(naga::ShaderStage::Vertex), "{label}");
        // Only the shadow map's casters are depth-only.
        assert_eq!(
            has(naga::ShaderStage::Fragment),
            label != "shadow_caster",
            "{label}"
        );
    }
}

#[test]
fn every_module_file_is_used() {
    let composed: String = all_shaders().into_iter().map(|(_, s)| s).collect();
    for (name, _) in modules() {
        assert!(
            composed.contains(&format!("// ---- module {name} ----")),
            "module {name} is never composed"
        );
    }
}

#[test]
fn props_and_ui_carry_no_subsurface_code() {
    for entry in ["prop", "ui", "shadow"] {
        let src = compose(entry, &ShaderDefs::new()).unwrap();
        for module in [
            "dipole",
            "oss",
            "subsurface",
            "ward",
            "ward_lobe",
            "fresnel",
            "skinning",
        ] {
            assert!(
                !src.contains(&format!("// ---- module {module} ----")),
                "{entry} shader includes {module}"
            );
        }
    }
}

#[test]
fn variants_differ_only_where_flagged() {
    let a = compose("character", &ShadingModel::Ward.defs()).unwrap();
    let b = compose("character", &ShadingModel::WardPrinted.defs()).unwrap();
    assert_ne!(a, b);
    assert!(b.contains("cos2_phi_i") && !a.contains("cos2_phi_i"));
}

/// Dawn's WGSL compiler, as the test can reach it.
enum Tint {
    /// The project's own: `tools/wgsl-tint` (npm package `webgpu`, installed by `.ci/run` with
    /// `npm ci`), run with node.
    Dawn {
        node: std::path::PathBuf,
        script: std::path::PathBuf,
    },
    /// A `tint` executable on the PATH.
    Binary(std::path::PathBuf),
}

fn find_tint() -> Option<Tint> {
    let tool = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/wgsl-tint");
    if tool.join("node_modules/webgpu/package.json").is_file() {
        if let Ok(node) = which("node") {
            return Some(Tint::Dawn {
                node,
                script: tool.join("check.mjs"),
            });
        }
    }
    which("tint").ok().map(Tint::Binary)
}

/// Runs tint on one file (one process per file: dawn.node crashes after a few modules in one
/// process).
fn run_tint(
    tint: &Tint,
    path: &std::path::Path,
    scratch: &std::path::Path,
) -> std::io::Result<std::process::Output> {
    match tint {
        Tint::Dawn { node, script } => std::process::Command::new(node)
            .arg(script)
            .arg(path)
            .output(),
        Tint::Binary(t) => std::process::Command::new(t)
            .arg("--format")
            .arg("wgsl")
            .arg("-o")
            .arg(scratch.join("out.wgsl"))
            .arg(path)
            .output(),
    }
}

/// Says (past libtest's capture, so it is seen) that the check did not run.
fn not_run(why: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipping: tint check NOT RUN: {why}");
}

#[test]
fn tint_accepts_every_shader() {
    if cfg!(target_os = "android") {
        // The core's tests on bionic: the shaders are the same text everywhere; the host's run
        // of this test checks them.
        not_run("not on Android (the host run checks the same shaders)");
        return;
    }
    let Some(tint) = find_tint() else {
        let why = "Dawn's WGSL compiler not found: run `npm ci` in tools/wgsl-tint (needs node), \
                   or put a `tint` executable on the PATH";
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("{why} (CI=true: the independent WGSL check is required)");
        }
        not_run(why);
        return;
    };
    let dir = std::env::temp_dir().join(format!("dermis-tint-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    for (label, source) in all_shaders() {
        let path = dir.join(format!("{}.wgsl", label.replace('/', "_")));
        std::fs::write(&path, &source).unwrap();
        files.push((label, path));
    }
    for (label, path) in &files {
        let out = run_tint(&tint, path, &dir).unwrap();
        assert!(
            out.status.success(),
            "tint rejected {label} ({:?}):\n{}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_tint_check_rejects_a_bad_shader() {
    // The check can fail: a type error it must catch.
    if cfg!(target_os = "android") {
        return;
    }
    let Some(tint) = find_tint() else {
        return; // reported by tint_accepts_every_shader
    };
    let dir = std::env::temp_dir().join(format!("dermis-tint-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.wgsl");
    std::fs::write(&path, "fn f() -> i32 { return 1.0; }\n").unwrap();
    let status = run_tint(&tint, &path, &dir).unwrap().status;
    assert!(!status.success(), "tint accepted a type error");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The top-level declarations of WGSL `src` (comments and preprocessor lines dropped,
/// whitespace collapsed), each up to its `;` or its closing `}`.
fn declarations(src: &str) -> Vec<String> {
    let code: String = src
        .lines()
        .map(|l| l.split("//").next().unwrap_or_default())
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    let (mut out, mut item, mut depth) = (Vec::new(), String::new(), 0i32);
    for c in code.chars() {
        item.push(c);
        match c {
            '{' | '(' => depth += 1,
            '}' | ')' => depth -= 1,
            _ => {}
        }
        if depth == 0 && (c == ';' || c == '}') {
            let text = item.split_whitespace().collect::<Vec<_>>().join(" ");
            if text != ";" && !text.is_empty() {
                out.push(text);
            }
            item.clear();
        }
    }
    out
}

/// `(module, source)` of every WGSL text: the composer's modules (generated ones included)
/// and the files of `shaders/` it does not hold (the conformance kernels).
fn every_wgsl() -> Vec<(String, String)> {
    let mut all: Vec<(String, String)> = modules()
        .iter()
        .map(|(n, s)| (n.to_string(), s.to_string()))
        .collect();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders");
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if !all.iter().any(|(n, _)| *n == name) {
            all.push((name, std::fs::read_to_string(&path).unwrap()));
        }
    }
    all
}

/// Declarations written in more than one module: `(declaration, modules)`.
fn written_twice(all: &[(String, String)]) -> Vec<(String, Vec<String>)> {
    let mut seen: Vec<(String, Vec<String>)> = Vec::new();
    for (module, src) in all {
        for d in declarations(src) {
            match seen.iter_mut().find(|(s, _)| *s == d) {
                Some((_, ms)) if !ms.contains(module) => ms.push(module.clone()),
                Some(_) => {}
                None => seen.push((d, vec![module.clone()])),
            }
        }
    }
    seen.retain(|(_, ms)| ms.len() > 1);
    seen
}

#[test]
fn no_declaration_is_written_in_two_modules() {
    let all = every_wgsl();
    assert!(all.len() > 30, "only {} modules", all.len());
    let twice = written_twice(&all);
    assert!(twice.is_empty(), "declared more than once: {twice:#?}");
    // The check finds a planted copy: a struct written again in another module.
    let mut planted = all.clone();
    let split_out = module_source("split_out").unwrap();
    planted.push(("planted".into(), format!("// a copy\n{split_out}")));
    let twice = written_twice(&planted);
    assert_eq!(twice.len(), 1, "{twice:#?}");
    assert!(twice[0].0.starts_with("struct SplitOut"), "{twice:#?}");
}

#[test]
fn no_shader_file_declares_a_struct_generated_from_rust() {
    let generated: Vec<&str> = structs::table().iter().map(|l| l.name).collect();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders");
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        let src = std::fs::read_to_string(&path).unwrap();
        for d in declarations(&src) {
            for name in &generated {
                assert!(
                    !d.starts_with(&format!("struct {name} {{")),
                    "{} declares {name}, which is generated from its Rust declaration",
                    path.display()
                );
            }
        }
    }
}

#[test]
fn the_penumbra_seed_pass_refuses_a_block_other_than_the_rust_sides() {
    // As composed, with the Rust side's block, the pass validates (the tests above); with the
    // block changed in `consts` and nothing else, the composition is refused.
    let consts = module_source("consts").unwrap();
    let line = format!("const PENUMBRA_BLOCK: u32 = {PENUMBRA_BLOCK}u;");
    assert!(consts.contains(&line), "consts has no `{line}`");
    let other = consts.replace(
        &line,
        &format!("const PENUMBRA_BLOCK: u32 = {}u;", PENUMBRA_BLOCK * 2),
    );
    let set: Vec<(&str, &str)> = modules()
        .iter()
        .map(|&(n, s)| {
            if n == "consts" {
                (n, other.as_str())
            } else {
                (n, s)
            }
        })
        .collect();
    let good = compose("penumbra", &ShaderDefs::new()).unwrap();
    naga::front::wgsl::parse_str(&good).unwrap_or_else(|e| panic!("{e}"));
    let bad = compose_from(&set, "penumbra", &ShaderDefs::new()).unwrap();
    assert!(
        naga::front::wgsl::parse_str(&bad).is_err(),
        "the seed pass accepted a block of {}",
        PENUMBRA_BLOCK * 2
    );
}

fn which(name: &str) -> Result<std::path::PathBuf, ()> {
    let path = std::env::var_os("PATH").ok_or(())?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
        .ok_or(())
}
