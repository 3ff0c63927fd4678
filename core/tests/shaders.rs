//! Every composed shader validates with naga (the compiler wgpu uses) and, where the `tint`
//! binary is installed (required in CI), with Dawn's independent compiler too.

use dermis_core::shader::{compose, ShaderDefs, MODULES};
use dermis_core::shading::ShadingModel;

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
    for (name, _) in MODULES {
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
            "burley",
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

#[test]
fn tint_accepts_every_shader() {
    let tint = std::path::Path::new("/usr/local/bin/tint");
    let tint = if tint.exists() {
        tint.to_path_buf()
    } else if let Ok(p) = which("tint") {
        p
    } else {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("tint is required in CI (independent WGSL compiler) but was not found");
        }
        eprintln!("skipping: tint not installed");
        return;
    };
    let dir = std::env::temp_dir().join(format!("dermis-tint-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (label, source) in all_shaders() {
        let path = dir.join(format!("{}.wgsl", label.replace('/', "_")));
        std::fs::write(&path, &source).unwrap();
        let out = std::process::Command::new(&tint)
            .arg("--format")
            .arg("wgsl")
            .arg("-o")
            .arg(dir.join("out.wgsl"))
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "tint rejected {label}:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn which(name: &str) -> Result<std::path::PathBuf, ()> {
    let path = std::env::var_os("PATH").ok_or(())?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
        .ok_or(())
}
