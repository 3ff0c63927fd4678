//! Spatial model `tabulated` (WGSL: `shaders/subsurface.wgsl`, shared by the screen-space
//! models): the material's diffusion profile as measured by the project's Monte Carlo for a
//! normally incident pencil beam
//! ([`bake`]), spread over the screen by the subsurface pass with rings of exact mass; the
//! oblique-incidence factor q(μ) and the translucency of thin parts from measured tables.
//!
//! It is the accuracy reference among the real-time models: everything it assumes is the
//! ring quadrature, the screen-space mapping and that an obliquely lit surface scatters with
//! the normal-incidence kernel scaled by q(μ).

use super::bake::{self, Bake};
use super::subsurface::{self, Kernel, Params};
use super::{Descriptor, Effects, Material};

pub fn params(m: &Material) -> Params {
    params_from(&bake::for_material(m), m)
}

/// The uniform for `m` from the tables `b`.
pub fn params_from(b: &Bake, m: &Material) -> Params {
    Params {
        albedo: b.reflectance(),
        eta: m.eta,
        oblique: b.oblique,
        shift: b.shift,
        slab: Some(b.slab),
        lift: [0.0; 3],
        entry_reach_mm: 0.0,
    }
}

pub fn kernel(m: &Material) -> Kernel {
    let b = bake::for_material(m);
    Kernel::from_rings(&b.edges, &b.mass)
}

/// `tabulated`.
pub const TABULATED: Descriptor = Descriptor {
    name: "tabulated",
    label: "Measured profile",
    variant: None,
    effects: Effects {
        subsurface: true,
        translucency: true,
        screen_space: true,
        ..Effects::NONE
    },
    params: |m| params(m).pack(),
    params_from: Some(|b, m| params_from(b, m).pack()),
    kernel: Some(kernel),
    lut: None,
    total_reflectance: |m, _| super::prediction::measured(m),
    ..subsurface::SPATIAL
};
