//! The renderer's integration tests, one binary: every shading model, pass and effect drawn
//! through the real renderer on a real driver (lavapipe on CI; `VK_ICD_FILENAMES`), checked by
//! pixels, plus the measurement scenes (the face truth, the conformance suite, stability).
mod adding_a_pass;
mod blob_shadow;
mod character_materials;
mod common;
mod curvature;
mod effects;
#[path = "../shared/external.rs"]
mod external;
mod face;
mod materials_per_region;
mod phone_limits;
mod prepared_frames;
mod prop_culling;
mod render_gl;
mod render_models;
mod shading_conformance;
mod shading_printed_defects;
mod shading_stability;
mod shadow_map;
mod showroom;
mod showroom_head;
mod skin_albedo;
mod subsurface_render;
mod textures;
mod ui_gpu;
mod window_path_governor;
