//! What the GPU reads, declared once in Rust: the structs (`gpu_struct!`), the uniform block
//! every model's shader reads at `@group(1) @binding(0)` with each model's layout inside it
//! (`model_uniform!`), and the constants the shaders share ([`SharedConst`]).
//!
//! The WGSL side is generated from these declarations, never written by hand: the composer
//! serves each struct as a module of its name (`#import WardUniform`, text by
//! `shader::structs`) and the constants as module `consts` (`shader::consts`). Each model
//! declares its uniform once, with `model_uniform!` in its own Rust file
//! (`ward::WardUniform`, `dipole::DipoleUniform`, `oss::OssUniform`,
//! `subsurface::SubsurfaceUniform`): `Params::pack` fills it by field name, the f64
//! references read it back by field name ([`ModelParams::uniform`]), and its shader binds the
//! generated struct. `engine/tests/engine/uniform_layout.rs` checks every generated struct as
//! naga lays it out against the Rust layout recorded here.

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

/// The WGSL type of a member of a GPU struct: an element type, or an array of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WgslType {
    /// The element type as WGSL spells it (`f32`, `vec3<f32>`, `mat4x4<f32>`, or the name of
    /// a struct declared with `gpu_struct!`).
    pub name: &'static str,
    /// `Some(n)`: `array<name, n>`.
    pub array: Option<usize>,
    /// The element is a struct declared with `gpu_struct!` (its module is imported first).
    pub declared: bool,
}

impl WgslType {
    const fn plain(name: &'static str) -> Self {
        Self {
            name,
            array: None,
            declared: false,
        }
    }
}

/// A Rust type a GPU struct's member may have, with the WGSL type it is: `f32`, `u32`,
/// `[f32; 3]` (`vec3<f32>`, followed by a scalar that fills its 16 bytes), `[f32; 4]`
/// (`vec4<f32>`), [`glam::Mat4`] (`mat4x4<f32>`), `[[f32; 4]; N]` (`array<vec4<f32>, N>`) and
/// `[S; N]` of a struct `S` declared with `gpu_struct!` (`array<S, N>`).
pub trait GpuType {
    const WGSL: WgslType;
}

impl GpuType for f32 {
    const WGSL: WgslType = WgslType::plain("f32");
}

impl GpuType for u32 {
    const WGSL: WgslType = WgslType::plain("u32");
}

impl GpuType for [f32; 3] {
    const WGSL: WgslType = WgslType::plain("vec3<f32>");
}

impl GpuType for [f32; 4] {
    const WGSL: WgslType = WgslType::plain("vec4<f32>");
}

impl GpuType for glam::Mat4 {
    const WGSL: WgslType = WgslType::plain("mat4x4<f32>");
}

impl<const N: usize> GpuType for [[f32; 4]; N] {
    const WGSL: WgslType = WgslType {
        name: "vec4<f32>",
        array: Some(N),
        declared: false,
    };
}

impl<S: Uniform, const N: usize> GpuType for [S; N] {
    const WGSL: WgslType = WgslType {
        name: S::LAYOUT.name,
        array: Some(N),
        declared: true,
    };
}

/// One member of a GPU struct: its name (the same in Rust and WGSL), byte offset, size, WGSL
/// type and doc comment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub offset: usize,
    pub size: usize,
    pub ty: WgslType,
    /// Its Rust doc comment, one line per `///` line (empty: none).
    pub doc: &'static str,
}

/// A GPU struct as declared in Rust: its name (the WGSL struct's too), the file declaring
/// it, size in bytes and members in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub name: &'static str,
    pub file: &'static str,
    pub size: usize,
    pub fields: &'static [Field],
}

/// A struct the GPU reads, declared with `gpu_struct!` (or `model_uniform!`).
pub trait Uniform: bytemuck::Pod {
    /// Its layout, member by member.
    const LAYOUT: Layout;
}

/// A value a shared constant has in WGSL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Const {
    U32(u32),
    F32(f32),
    /// An abstract float: it takes the type of its use (`f32`, or `f16` in the `*_nd`
    /// modules composed at half precision).
    Float(f64),
}

/// A constant the shaders share with Rust, declared once in Rust: its WGSL name, its value
/// (from the Rust constant) and what it is. The shared ones are listed in `shader::consts`, a
/// model's own in its descriptor (`Descriptor::consts`); all reach the shaders through the
/// generated module `consts`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedConst {
    pub name: &'static str,
    pub value: Const,
    pub doc: &'static str,
}

/// Declares a struct the GPU reads, once: `#[repr(C)]`, `Pod`, with its [`Layout`] recorded
/// (`Uniform::LAYOUT`), from which `shader::structs` writes the WGSL struct of the same name,
/// member docs included (members may carry doc comments only). Members are the [`GpuType`]s;
/// padding is spelled out as members named `_pad*`, and each member must sit where WGSL's
/// layout rules put it (a `vec3<f32>` on 16 bytes: `engine/tests/engine/uniform_layout.rs`
/// checks each generated struct as naga lays it out). The size must be a multiple of 16 bytes
/// (WGSL rounds a struct up to its 16-byte alignment). Exported (`dermis_engine::gpu_struct!`)
/// for the measurement crate's compute kernels.
#[macro_export]
macro_rules! gpu_struct {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( $(#[doc = $doc:literal])* pub $field:ident : $ty:ty ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $( $(#[doc = $doc])* pub $field: $ty ),*
        }

        impl $crate::shading::Uniform for $name {
            const LAYOUT: $crate::shading::Layout = $crate::shading::Layout {
                name: stringify!($name),
                file: file!(),
                size: std::mem::size_of::<$name>(),
                fields: &[$($crate::shading::Field {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($name, $field),
                    size: std::mem::size_of::<$ty>(),
                    ty: <$ty as $crate::shading::GpuType>::WGSL,
                    doc: concat!($($doc, "\n"),*),
                }),*],
            };
        }

        const _: () = assert!(
            std::mem::size_of::<$name>() % 16 == 0,
            concat!(stringify!($name), ": not a multiple of 16 bytes")
        );
    };
}

/// Declares a model's uniform struct ([`gpu_struct!`]) that fits in [`ModelParams`].
macro_rules! model_uniform {
    (
        $(#[$meta:meta])*
        pub struct $name:ident { $($body:tt)* }
    ) => {
        $crate::gpu_struct! {
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
            /// Its first member,
            /// over two lines.
            pub a: [f32; 3],
            pub b: f32,
            pub table: [[f32; 4]; 2],
        }
    }

    #[test]
    fn layout_is_recorded_and_the_block_round_trips() {
        let l = TestUniform::LAYOUT;
        assert_eq!(l.name, "TestUniform");
        assert!(l.file.ends_with("uniform.rs"), "{}", l.file);
        assert_eq!(l.size, 48);
        let got: Vec<_> = l
            .fields
            .iter()
            .map(|f| (f.name, f.offset, f.size))
            .collect();
        assert_eq!(got, [("a", 0, 12), ("b", 12, 4), ("table", 16, 32)]);
        let types: Vec<_> = l.fields.iter().map(|f| (f.ty.name, f.ty.array)).collect();
        assert_eq!(
            types,
            [("vec3<f32>", None), ("f32", None), ("vec4<f32>", Some(2))]
        );
        assert_eq!(l.fields[0].doc, " Its first member,\n over two lines.\n");
        assert_eq!(l.fields[1].doc, "");
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
