//! The UI shader composes and validates with naga (and both shipped backends).

use dermis_core::shader::{compose, ShaderDefs};

#[test]
fn ui_shader_validates() {
    let source = compose("ui", &ShaderDefs::new()).unwrap();
    assert!(
        !source.contains("// ---- module common ----"),
        "the UI needs no common module"
    );
    let module = naga::front::wgsl::parse_str(&source)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    let mut validator = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    );
    let info = validator
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    naga::back::spv::write_vec(&module, &info, &naga::back::spv::Options::default(), None)
        .unwrap_or_else(|e| panic!("SPIR-V: {e}"));
    for (stage, entry) in [
        (naga::ShaderStage::Vertex, "vs_main"),
        (naga::ShaderStage::Fragment, "fs_main"),
    ] {
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
        .unwrap_or_else(|e| panic!("GLSL {entry}: {e}"));
        writer
            .write()
            .unwrap_or_else(|e| panic!("GLSL {entry}: {e}"));
    }
    // The vertex layout the pipeline uses matches the shader's inputs.
    let vs = module
        .entry_points
        .iter()
        .find(|e| e.name == "vs_main")
        .unwrap();
    assert_eq!(vs.function.arguments.len(), 1);
    let layout = dermis_core::render::ui_vertex_layout();
    assert_eq!(layout.attributes.len(), 3);
    assert_eq!(layout.array_stride, 20);
    assert_eq!(dermis_core::render::ui_shader_source(), source);
}
