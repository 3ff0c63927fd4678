//! dermis-engine's integration tests, one binary: assets (fixtures, the hostile corpus's
//! neighbours, materials, third-party models, KTX2), animation, the composed shaders and the
//! uniforms' layouts. They need no GPU or window, and also run on Android bionic under qemu
//! (`cargo xtask android-test`).
mod anim_clips_fit;
mod anim_golden;
mod anim_sampling;
mod asset_external;
mod asset_fixtures;
mod asset_materials;
#[path = "../../../tests/shared/external.rs"]
mod external;
mod ktx2_files;
mod platform_runtime;
mod shaders;
mod uniform_layout;
