//! The constants the shaders and the Rust side share, written once — here, from the Rust
//! values — and handed to the shaders as the generated module `consts` (`#import consts`).
//! No shader spells one of these numbers itself.

use std::fmt::Write;

use crate::asset::MAX_JOINTS;
use crate::shading::{bake, edge_spread, preintegrated, subsurface, units};

/// A shared constant's WGSL type and value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Const {
    U32(u32),
    F32(f32),
}

/// `(name, value, what it is)` of every shared constant.
pub fn table() -> [(&'static str, Const, &'static str); 14] {
    use preintegrated::{LUT_U, LUT_V, PENUMBRA_ROW, SLAB_SPAN, TEXTURE_ROWS};
    [
        (
            "MAX_JOINTS",
            Const::U32(MAX_JOINTS as u32),
            "joints of one skin's palette (asset::MAX_JOINTS)",
        ),
        (
            "MAX_RINGS",
            Const::U32(subsurface::MAX_RINGS as u32),
            "rings a subsurface kernel holds (shading::subsurface::MAX_RINGS)",
        ),
        (
            "LUT_U",
            Const::F32(LUT_U as f32),
            "texels per row of the pre-integrated LUT (shading::preintegrated::LUT_U)",
        ),
        (
            "LUT_CURVATURE_ROWS",
            Const::F32(LUT_V as f32),
            "the LUT's sphere rows over curvature (LUT_V)",
        ),
        (
            "LUT_TEXTURE_ROWS",
            Const::F32(TEXTURE_ROWS as f32),
            "rows of the LUT texture (TEXTURE_ROWS)",
        ),
        (
            "LUT_PENUMBRA_ROW",
            Const::F32(PENUMBRA_ROW as f32),
            "the LUT's edge-spread row (PENUMBRA_ROW)",
        ),
        (
            "OBLIQUE_NODES",
            Const::U32(bake::OBLIQUE_NODES as u32),
            "nodes of the oblique-incidence tables (shading::bake::OBLIQUE_NODES)",
        ),
        (
            "SLAB_NODES",
            Const::U32(bake::SLAB_NODES as u32),
            "nodes of the slab transmittance table (shading::bake::SLAB_NODES)",
        ),
        (
            "SLAB_FIRST_MM",
            Const::F32(bake::SLAB_FIRST_MM as f32),
            "the thinnest tabulated slab, mm (shading::bake::SLAB_FIRST_MM)",
        ),
        (
            "LUT_SLAB_SPAN",
            Const::F32(SLAB_SPAN as f32),
            "doublings of thickness the LUT's slab row spans (SLAB_SPAN)",
        ),
        (
            "PENUMBRA_SPAN_MM",
            Const::F32(edge_spread::SPAN_MM as f32),
            "the edge-spread row's reach either side of an edge, mm (edge_spread::SPAN_MM)",
        ),
        (
            "SHADOW_RAMP_TEXELS",
            Const::F32(edge_spread::SHADOW_RAMP_TEXELS),
            "the shadow test's linear ramp across an edge, map texels (shading::edge_spread::SHADOW_RAMP_TEXELS)",
        ),
        (
            "LIGHT_D_MIN_M",
            Const::F32(units::LIGHT_D_MIN_M as f32),
            "the smallest light distance any model sees, m (shading::units::LIGHT_D_MIN_M)",
        ),
        (
            "FLAT_RADIUS_M",
            Const::F32(units::FLAT_RADIUS_M as f32),
            "the radius of curvature of a flat or unknown surface, m (units::FLAT_RADIUS_M)",
        ),
    ]
}

/// The generated WGSL of module `consts`.
pub fn wgsl() -> String {
    let mut out = String::from(
        "// Generated from the Rust constants (engine/src/shader/consts.rs): do not edit.\n",
    );
    for (name, value, what) in table() {
        let value = match value {
            Const::U32(v) => format!("{v}u"),
            Const::F32(v) => format!("{v:?}"),
        };
        let ty = if value.ends_with('u') { "u32" } else { "f32" };
        let _ = writeln!(out, "// {what}\nconst {name}: {ty} = {value};");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_block_declares_every_constant_once_with_its_value() {
        let src = wgsl();
        for (name, value, _) in table() {
            assert_eq!(src.matches(&format!("const {name}:")).count(), 1, "{name}");
            let line = src.lines().find(|l| l.contains(&format!("const {name}:")));
            let text = line.unwrap_or_default();
            match value {
                Const::U32(v) => assert!(text.ends_with(&format!("= {v}u;")), "{text}"),
                Const::F32(v) => assert!(text.contains(&format!("{v:?}")), "{text}"),
            }
        }
        naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{e}"));
    }
}
