//! The constants the shaders and the Rust side share, written once — in Rust — and handed to
//! the shaders as the generated module `consts` (`#import consts`): the shared ones listed
//! here, then each registered model's own (`Descriptor::consts`, declared in its file). No
//! shader spells one of these numbers itself.

use std::fmt::Write;

use super::uniforms::PENUMBRA_BLOCK;
use crate::asset::MAX_JOINTS;
use crate::shading::{bake, edge_spread, subsurface, units, ward};
use crate::shading::{Const, ShadingModel, SharedConst};

/// A shared constant.
const fn shared(name: &'static str, value: Const, doc: &'static str) -> SharedConst {
    SharedConst { name, value, doc }
}

/// The constants every shader may read (not a model's own).
const SHARED: &[SharedConst] = &[
    shared(
        "PI",
        Const::Float(std::f64::consts::PI),
        "π (abstract: f32, or f16 in the half-precision `*_nd` compositions)",
    ),
    shared("INV_PI", Const::Float(std::f64::consts::FRAC_1_PI), "1/π"),
    shared(
        "MM_PER_M",
        Const::F32(units::MM_PER_M as f32),
        "millimetres per metre (shading::units::MM_PER_M)",
    ),
    shared(
        "MAX_JOINTS",
        Const::U32(MAX_JOINTS as u32),
        "joints of one skin's palette (asset::MAX_JOINTS)",
    ),
    shared(
        "MAX_RINGS",
        Const::U32(subsurface::MAX_RINGS as u32),
        "rings a subsurface kernel holds (shading::subsurface::MAX_RINGS)",
    ),
    shared(
        "OBLIQUE_NODES",
        Const::U32(bake::OBLIQUE_NODES as u32),
        "nodes of the oblique-incidence tables (shading::bake::OBLIQUE_NODES)",
    ),
    shared(
        "SLAB_NODES",
        Const::U32(bake::SLAB_NODES as u32),
        "nodes of the slab transmittance table (shading::bake::SLAB_NODES)",
    ),
    shared(
        "SLAB_FIRST_MM",
        Const::F32(bake::SLAB_FIRST_MM as f32),
        "the thinnest slab of the table, mm (shading::bake::SLAB_FIRST_MM)",
    ),
    shared(
        "EXIT_COSINE_MIN",
        Const::Float(subsurface::EXIT_COSINE_MIN),
        "the smallest view cosine of the exit factor (shading::subsurface::EXIT_COSINE_MIN)",
    ),
    shared(
        "PENUMBRA_SPAN_MM",
        Const::F32(edge_spread::SPAN_MM as f32),
        "the edge-spread row's reach either side of an edge, mm (edge_spread::SPAN_MM)",
    ),
    shared(
        "PENUMBRA_BLOCK",
        Const::U32(PENUMBRA_BLOCK),
        "shadow-map texels per penumbra grid texel, per side (shader::uniforms::PENUMBRA_BLOCK)",
    ),
    shared(
        "SHADOW_RAMP_TEXELS",
        Const::F32(edge_spread::SHADOW_RAMP_TEXELS),
        "the shadow test's linear ramp across an edge, map texels (shading::edge_spread::SHADOW_RAMP_TEXELS)",
    ),
    shared(
        "LIGHT_D_MIN_M",
        Const::F32(units::LIGHT_D_MIN_M as f32),
        "the smallest light distance any model sees, m (shading::units::LIGHT_D_MIN_M)",
    ),
    shared(
        "FLAT_RADIUS_M",
        Const::F32(units::FLAT_RADIUS_M as f32),
        "the radius of curvature of a flat or unknown surface, m (units::FLAT_RADIUS_M)",
    ),
    shared(
        "WARD_ALPHA_MIN",
        Const::Float(ward::ALPHA_MIN),
        "the smallest roughness Ward's lobe is evaluated with (shading::ward::ALPHA_MIN)",
    ),
    shared(
        "WARD_COS_PRODUCT_MIN",
        Const::Float(ward::COS_PRODUCT_MIN),
        "the floor of n·l n·v under the lobe's square root (shading::ward::COS_PRODUCT_MIN)",
    ),
];

/// Every shared constant: [`SHARED`], then each registered model's own (once, for models
/// that share a descriptor's list).
pub fn table() -> Vec<SharedConst> {
    let mut all = SHARED.to_vec();
    for m in ShadingModel::ALL {
        for c in m.descriptor().consts {
            if !all.iter().any(|a| a.name == c.name) {
                all.push(*c);
            }
        }
    }
    all
}

/// The WGSL text of `value` and its type annotation (none for an abstract float).
fn literal(value: Const) -> (String, &'static str) {
    match value {
        Const::U32(v) => (format!("{v}u"), ": u32"),
        Const::F32(v) => (format!("{v:?}"), ": f32"),
        Const::Float(v) => (format!("{v:?}"), ""),
    }
}

/// The generated WGSL of module `consts`.
pub fn wgsl() -> String {
    let mut out = String::from(
        "// Generated from the Rust constants (engine/src/shader/consts.rs and the models' \
         descriptors): do not edit.\n",
    );
    for c in table() {
        let (value, ty) = literal(c.value);
        let _ = writeln!(out, "// {}\nconst {}{ty} = {value};", c.doc, c.name);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_block_declares_every_constant_once_with_its_value() {
        let src = wgsl();
        for c in table() {
            let decl = format!("const {}", c.name);
            let lines: Vec<&str> = src
                .lines()
                .filter(|l| {
                    l.starts_with(&format!("{decl}:")) || l.starts_with(&format!("{decl} ="))
                })
                .collect();
            assert_eq!(lines.len(), 1, "{}", c.name);
            let (value, _) = literal(c.value);
            assert!(lines[0].ends_with(&format!("= {value};")), "{}", lines[0]);
        }
        naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{e}"));
        // A model's constant is the table's: no two declarations of a name differ.
        for m in ShadingModel::ALL {
            for c in m.descriptor().consts {
                assert!(
                    table().contains(c),
                    "{m}: {} differs from the table's",
                    c.name
                );
            }
        }
    }
}
