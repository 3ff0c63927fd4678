//! How a model's materials are drawn: as skin — by the shading model chosen, with the medium's
//! optics and, for a skin material of a file, its albedo map as the pigment — or as a standard
//! glTF material (metallic-roughness PBR, the props' lighting). Plain data the renderer reads
//! when it uploads a model; which materials are skin comes from [`asset::skin::classify`]
//! (the user's choice, the file's declaration, the name rule).

use crate::asset::skin::Classification;
use crate::asset::Model;
use crate::shading::material::{Material as Optics, DEFAULT_SKIN};

/// How one material is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Skin, shaded by the subject's shading model. `pigmented`: its albedo (texture ×
    /// factor, [`crate::asset::Material::skin_albedo`]) is the skin's albedo per texel;
    /// otherwise the surface shows the medium's own (a measured medium).
    Skin { pigmented: bool },
    /// A standard glTF material: metallic-roughness PBR.
    Standard,
}

/// Every material's [`Role`], and the role of primitives without a material.
#[derive(Clone, Debug, PartialEq)]
pub struct Roles {
    pub materials: Vec<Role>,
    pub unassigned: Role,
    /// The optics the skin is shaded with (the first skin material's; skin1's when none).
    pub optics: Optics,
}

impl Roles {
    /// Every part is the measured medium itself (the measurement scenes, the homogeneous
    /// head): skin without a pigment, whatever the model's materials say.
    pub fn medium(optics: &Optics) -> Self {
        Self {
            materials: Vec::new(),
            unassigned: Role::Skin { pigmented: false },
            optics: optics.clone(),
        }
    }

    /// The roles `class` gives `model`'s materials: its skin materials pigmented skin, the
    /// rest (and primitives without a material) standard.
    pub fn classified(model: &Model, class: &Classification) -> Self {
        let materials = (0..model.materials.len())
            .map(|i| match class.is_skin(i) {
                true => Role::Skin { pigmented: true },
                false => Role::Standard,
            })
            .collect();
        let optics = class
            .materials
            .iter()
            .find_map(|c| c.skin.clone())
            .unwrap_or_else(|| DEFAULT_SKIN.clone());
        Self {
            materials,
            unassigned: Role::Standard,
            optics,
        }
    }

    /// The roles of `model` by the skin rules alone (no user choice), logged.
    pub fn of(model: &Model) -> Self {
        match crate::asset::skin::classify(model, None) {
            Ok(class) => {
                log::info!("{}", class.summary);
                Self::classified(model, &class)
            }
            // Without a user's choice classification cannot fail; keep every part standard.
            Err(e) => {
                log::warn!("{e}");
                Self {
                    materials: vec![Role::Standard; model.materials.len()],
                    unassigned: Role::Standard,
                    optics: DEFAULT_SKIN.clone(),
                }
            }
        }
    }

    /// The role of a primitive with material `material`.
    pub fn role(&self, material: Option<usize>) -> Role {
        material
            .and_then(|m| self.materials.get(m).copied())
            .unwrap_or(self.unassigned)
    }

    /// Whether any part is skin.
    pub fn has_skin(&self) -> bool {
        self.unassigned != Role::Standard || self.materials.iter().any(|r| *r != Role::Standard)
    }
}
