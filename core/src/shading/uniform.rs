//! The uniform block every model's shader reads at `@group(1) @binding(0)`.

/// 32 vec4s, laid out by each model's own `Params::pack` (see `ward.rs`, `dipole.rs`,
/// `oss.rs`, `subsurface.rs`).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ModelParams(pub [[f32; 4]; MODEL_PARAM_ROWS]);

/// Rows (vec4) of [`ModelParams`].
pub const MODEL_PARAM_ROWS: usize = 32;

impl ModelParams {
    pub const SIZE: u64 = std::mem::size_of::<Self>() as u64;

    /// Packs a model's vec4 rows, zero-filling the rest.
    pub fn from_rows(rows: &[[f32; 4]]) -> Self {
        let mut p = [[0.0; 4]; MODEL_PARAM_ROWS];
        p[..rows.len()].copy_from_slice(rows);
        Self(p)
    }
}
