//! The WGSL modules, embedded from `shaders/` at compile time.

/// `(name, source)` of every module the composer can import.
pub const MODULES: &[(&str, &str)] = &[
    ("common", include_str!("../../../shaders/common.wgsl")),
    ("skinning", include_str!("../../../shaders/skinning.wgsl")),
    ("real", include_str!("../../../shaders/real.wgsl")),
    ("ward_nd", include_str!("../../../shaders/ward_nd.wgsl")),
    ("dipole_nd", include_str!("../../../shaders/dipole_nd.wgsl")),
    ("oss_nd", include_str!("../../../shaders/oss_nd.wgsl")),
    ("fresnel", include_str!("../../../shaders/fresnel.wgsl")),
    ("ward_lobe", include_str!("../../../shaders/ward_lobe.wgsl")),
    ("ward", include_str!("../../../shaders/ward.wgsl")),
    ("dipole", include_str!("../../../shaders/dipole.wgsl")),
    ("oss", include_str!("../../../shaders/oss.wgsl")),
    (
        "subsurface",
        include_str!("../../../shaders/subsurface.wgsl"),
    ),
    ("burley", include_str!("../../../shaders/burley.wgsl")),
    ("tabulated", include_str!("../../../shaders/tabulated.wgsl")),
    (
        "preintegrated",
        include_str!("../../../shaders/preintegrated.wgsl"),
    ),
    ("sss_pass", include_str!("../../../shaders/sss_pass.wgsl")),
    ("unlit", include_str!("../../../shaders/unlit.wgsl")),
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

/// The source of module `name`, if it exists.
pub fn module_source(name: &str) -> Option<&'static str> {
    MODULES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}
