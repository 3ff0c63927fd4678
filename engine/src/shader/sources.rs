//! The WGSL modules: the ones generated from Rust declarations (`consts.rs`, `structs.rs`),
//! and those embedded from `shaders/` at compile time — the shared ones listed here, and
//! each shading model's own, which its descriptor carries (`shading/<model>.rs`).

use std::sync::OnceLock;

use super::ShaderDefs;
use crate::shading::ShadingModel;

/// `(name, source)` of every shared module (not a shading model's).
pub const SHARED: &[(&str, &str)] = &[
    ("common", include_str!("../../../shaders/common.wgsl")),
    (
        "fullscreen",
        include_str!("../../../shaders/fullscreen.wgsl"),
    ),
    ("split_out", include_str!("../../../shaders/split_out.wgsl")),
    ("skinning", include_str!("../../../shaders/skinning.wgsl")),
    ("real", include_str!("../../../shaders/real.wgsl")),
    ("ward_nd", include_str!("../../../shaders/ward_nd.wgsl")),
    ("dipole_nd", include_str!("../../../shaders/dipole_nd.wgsl")),
    ("oss_nd", include_str!("../../../shaders/oss_nd.wgsl")),
    ("fresnel", include_str!("../../../shaders/fresnel.wgsl")),
    ("ward_lobe", include_str!("../../../shaders/ward_lobe.wgsl")),
    (
        "subsurface",
        include_str!("../../../shaders/subsurface.wgsl"),
    ),
    ("sss_pass", include_str!("../../../shaders/sss_pass.wgsl")),
    ("unlit", include_str!("../../../shaders/unlit.wgsl")),
    ("material", include_str!("../../../shaders/material.wgsl")),
    ("pbr", include_str!("../../../shaders/pbr.wgsl")),
    ("character", include_str!("../../../shaders/character.wgsl")),
    ("prop", include_str!("../../../shaders/prop.wgsl")),
    ("ui", include_str!("../../../shaders/ui.wgsl")),
    ("shadow", include_str!("../../../shaders/shadow.wgsl")),
    ("penumbra", include_str!("../../../shaders/penumbra.wgsl")),
    (
        "shadow_caster",
        include_str!("../../../shaders/shadow_caster.wgsl"),
    ),
];

/// `(name, source)` of every module the composer can import: the generated ones — `consts`
/// (`consts.rs`) and one per shared struct (`structs.rs`), named after it —, [`SHARED`], then
/// each registered model's module (once, for models that share a file).
pub fn modules() -> &'static [(&'static str, &'static str)] {
    static GENERATED: OnceLock<Vec<(&str, String)>> = OnceLock::new();
    static ALL: OnceLock<Vec<(&str, &str)>> = OnceLock::new();
    ALL.get_or_init(|| {
        let generated = GENERATED.get_or_init(|| {
            let structs = super::structs::table();
            let structs = structs.iter().map(|l| (l.name, super::structs::wgsl(l)));
            std::iter::once(("consts", super::consts::wgsl()))
                .chain(structs)
                .collect()
        });
        let mut all: Vec<(&str, &str)> = generated.iter().map(|(n, s)| (*n, s.as_str())).collect();
        all.extend_from_slice(SHARED);
        for m in ShadingModel::ALL {
            let d = m.descriptor();
            if !all.iter().any(|(n, _)| *n == d.module) {
                all.push((d.module, d.wgsl));
            }
        }
        all
    })
}

/// The source of module `name`, if it exists.
pub fn module_source(name: &str) -> Option<&'static str> {
    modules().iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

impl ShadingModel {
    /// Composition flags selecting the model's shader: `shading_model` bound to its module,
    /// its variant flag, else the flags its effects imply.
    pub fn defs(self) -> ShaderDefs {
        let d = self.descriptor();
        let defs = ShaderDefs::new().alias("shading_model", d.module);
        if let Some(flag) = d.variant {
            return defs.flag(flag);
        }
        let e = d.effects;
        let defs = if e.screen_space {
            defs.flag("SCREEN_SPACE")
        } else {
            defs
        };
        if e.subsurface && e.translucency {
            defs.flag("TRANSLUCENCY")
        } else {
            defs
        }
    }
}
