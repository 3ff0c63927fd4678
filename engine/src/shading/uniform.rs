//! The uniform block every model's shader reads at `@group(1) @binding(0)`, and the one
//! declaration of each model's layout inside it.
//!
//! Each model declares its uniform once, with `model_uniform!` in its own
//! Rust file (`ward::WardUniform`, `dipole::DipoleUniform`, `oss::OssUniform`,
//! `subsurface::SubsurfaceUniform`): `Params::pack` fills it by field name, the f64 references
//! read it back by field name ([`ModelParams::uniform`]), and the WGSL struct of the same name
//! declares the same members in the same order. The macro records the Rust layout
//! ([`Uniform::LAYOUT`], also each registry row's `uniform`); `engine/tests/engine/uniform_layout.rs`
//! checks it against the WGSL struct naga parses from the model's composed shader.

use glam::DVec3;

/// 32 vec4s: the fixed-size block every model's uniform struct is copied into
/// ([`ModelParams::from_uniform`]), zero-filled past the model's struct.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ModelParams(pub [[f32; 4]; MODEL_PARAM_ROWS]);

/// Rows (vec4) of [`ModelParams`].
pub const MODEL_PARAM_ROWS: usize = 32;

impl ModelParams {
    pub const SIZE: u64 = std::mem::size_of::<Self>() as u64;

    /// The block holding a model's uniform struct `u` (its bytes, then zeros).
    pub fn from_uniform<U: Uniform>(u: &U) -> Self {
        const { assert!(std::mem::size_of::<U>() <= std::mem::size_of::<ModelParams>()) };
        let mut p: Self = bytemuck::Zeroable::zeroed();
        let bytes = bytemuck::bytes_of(u);
        bytemuck::bytes_of_mut(&mut p)[..bytes.len()].copy_from_slice(bytes);
        p
    }

    /// The block read as a model's uniform struct (what its shader sees).
    pub fn uniform<U: Uniform>(&self) -> &U {
        const { assert!(std::mem::size_of::<U>() <= std::mem::size_of::<ModelParams>()) };
        bytemuck::from_bytes(&bytemuck::bytes_of(self)[..std::mem::size_of::<U>()])
    }
}

/// One member of a model's uniform struct: its name (the same in Rust and WGSL), byte offset
/// and size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub offset: usize,
    pub size: usize,
}

/// A model's uniform struct as declared in Rust: its name (the WGSL struct's too), size in
/// bytes and members in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub name: &'static str,
    pub size: usize,
    pub fields: &'static [Field],
}

/// A model's uniform struct, declared with `model_uniform!`.
pub trait Uniform: bytemuck::Pod {
    /// Its layout, member by member.
    const LAYOUT: Layout;
}

/// Declares a struct the GPU reads, once: `#[repr(C)]`, `Pod`, with its [`Layout`] recorded
/// (`Uniform::LAYOUT`), so a test compares it with the WGSL struct of the same name as naga
/// lays it out (`engine/tests/engine/uniform_layout.rs`: the models' uniforms, the frame uniform, the
/// subsurface pass's kernel). Members are f32 scalars, `[f32; 3]` (a WGSL `vec3<f32>`,
/// followed by a scalar that fills its 16 bytes), `[f32; 4]`, `[[f32; 4]; 4]` (`mat4x4<f32>`)
/// and `[[f32; 4]; N]` (`array<vec4<f32>, N>`); padding is spelled out as members named
/// `_pad*`, declared on the WGSL side too. The size must be a multiple of 16 bytes (WGSL
/// rounds a struct up to its 16-byte alignment).
macro_rules! gpu_struct {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( $(#[$fmeta:meta])* pub $field:ident : $ty:ty ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $( $(#[$fmeta])* pub $field: $ty ),*
        }

        impl $crate::shading::uniform::Uniform for $name {
            const LAYOUT: $crate::shading::uniform::Layout = $crate::shading::uniform::Layout {
                name: stringify!($name),
                size: std::mem::size_of::<$name>(),
                fields: &[$($crate::shading::uniform::Field {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($name, $field),
                    size: std::mem::size_of::<$ty>(),
                }),*],
            };
        }

        const _: () = assert!(
            std::mem::size_of::<$name>() % 16 == 0,
            concat!(stringify!($name), ": not a multiple of 16 bytes")
        );
    };
}
pub(crate) use gpu_struct;

/// Declares a model's uniform struct ([`gpu_struct!`]) that fits in [`ModelParams`].
macro_rules! model_uniform {
    (
        $(#[$meta:meta])*
        pub struct $name:ident { $($body:tt)* }
    ) => {
        $crate::shading::uniform::gpu_struct! {
            $(#[$meta])*
            pub struct $name { $($body)* }
        }

        const _: () = assert!(
            std::mem::size_of::<$name>()
                <= std::mem::size_of::<$crate::shading::uniform::ModelParams>(),
            concat!(stringify!($name), ": larger than ModelParams")
        );
    };
}
pub(crate) use model_uniform;

/// An rgb member as f64.
pub fn rgb(v: [f32; 3]) -> DVec3 {
    DVec3::from_array(v.map(f64::from))
}

/// `[f64; 3]` as an rgb member.
pub fn f32x3(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    model_uniform! {
        /// A test layout.
        pub struct TestUniform {
            pub a: [f32; 3],
            pub b: f32,
            pub table: [[f32; 4]; 2],
        }
    }

    #[test]
    fn layout_is_recorded_and_the_block_round_trips() {
        let l = TestUniform::LAYOUT;
        assert_eq!(l.name, "TestUniform");
        assert_eq!(l.size, 48);
        let got: Vec<_> = l
            .fields
            .iter()
            .map(|f| (f.name, f.offset, f.size))
            .collect();
        assert_eq!(got, [("a", 0, 12), ("b", 12, 4), ("table", 16, 32)]);
        let u = TestUniform {
            a: [1.0, 2.0, 3.0],
            b: 4.0,
            table: [[5.0, 6.0, 7.0, 8.0], [9.0, 10.0, 11.0, 12.0]],
        };
        let p = ModelParams::from_uniform(&u);
        assert_eq!(p.0[0], [1.0, 2.0, 3.0, 4.0]);
        assert_eq!(p.0[2], [9.0, 10.0, 11.0, 12.0]);
        assert!(p.0[3..].iter().flatten().all(|v| *v == 0.0));
        assert_eq!(p.uniform::<TestUniform>(), &u);
    }
}
