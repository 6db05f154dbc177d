//! The host↔shader interface, declared once: each struct the shader reads is
//! declared here (or in its primitive's module) with `gpu_struct!`, which
//! makes the Rust `Pod` structs of both precisions and the GLSL declaration
//! from the same field list. The shader's block declarations, binding
//! numbers, workgroup size and primitive scans are generated from those and
//! from the table of primitive kinds (`crate::prim`), per variant; nothing
//! is kept in a hand-written second copy (docs/shaders.md, Interface).

use std::sync::Arc;

use bytemuck::Pod;

use super::Precision;

/// One struct of the interface: its values on the host (f64 reals) and its
/// layouts in f32 and f64 (std140 and std430 agree on them: every member is
/// 16 bytes, or a vec3 and a uint that share 16, and f64 structs with a
/// dvec4 are padded to its 32-byte alignment).
pub trait GpuStruct: Copy {
    type F32: Pod;
    type F64: Pod;
    /// The struct's name in GLSL.
    const NAME: &'static str;
    /// Its members in GLSL, one declaration a line.
    const MEMBERS: &'static str;
    /// Its members' names and types, in order.
    const FIELDS: &'static [(&'static str, Member)];
    fn f32(&self) -> Self::F32;
    fn f64(&self) -> Self::F64;
}

/// A member's type (`gpu_struct!`'s field types).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Member {
    /// `vec4r`: four reals, 16 bytes in f32 and 32 in f64.
    Real4,
    /// `uvec4`: 16 bytes.
    Uvec4,
    /// `vec4`: four f32 in both precisions, 16 bytes.
    Float4,
    /// `vec3`: three f32 in both precisions, sharing 16 bytes with the
    /// `Uint` that follows it.
    Float3,
    /// `uint`: after a `Float3`, in the same 16 bytes.
    Uint,
}

/// `struct Name { members };` in GLSL.
pub fn declaration<S: GpuStruct>() -> String {
    format!("struct {} {{\n{}}};\n", S::NAME, S::MEMBERS)
}

/// 16-byte words a struct of these members takes in `precision`'s layout
/// (the size of `gpu_struct!`'s F32 or F64 over 16): its stride in an
/// array, and in texels of a texel buffer.
pub fn words(fields: &[(&str, Member)], precision: Precision) -> usize {
    let n = span(fields, precision);
    let dvec4 = fields.iter().any(|(_, m)| *m == Member::Real4);
    match precision {
        Precision::F64 if dvec4 => n.next_multiple_of(2),
        _ => n,
    }
}

/// 16-byte words these members take in `precision`'s layout, before the
/// struct's padding: where the member after them starts.
pub fn span(fields: &[(&str, Member)], precision: Precision) -> usize {
    fields
        .iter()
        .map(|(_, m)| match (m, precision) {
            (Member::Real4, Precision::F64) => 2,
            (Member::Uint, _) => 0,
            _ => 1,
        })
        .sum()
}

/// One array of the scene as bytes of `precision`, with its element count
/// (at least 1: Vulkan has no empty buffers, GLSL no empty arrays; the
/// counts never reach the zeroed slot of an absent kind).
pub fn array<S: GpuStruct>(items: impl Iterator<Item = S>, precision: Precision) -> Array<'static> {
    // Straight into bytes: a vector of the structs first, then a copy of
    // its bytes, would hold a large texture's texels twice.
    fn held<T: Pod>(items: impl Iterator<Item = T>) -> Array<'static> {
        let size = std::mem::size_of::<T>();
        let mut bytes = Vec::with_capacity(items.size_hint().0.max(1) * size);
        for item in items {
            bytes.extend_from_slice(bytemuck::bytes_of(&item));
        }
        if bytes.is_empty() {
            bytes.resize(size, 0);
        }
        Array {
            len: bytes.len() / size,
            byte_len: bytes.len(),
            data: Data::Held(bytes),
        }
    }
    match precision {
        Precision::F32 => held(items.map(|s| s.f32())),
        Precision::F64 => held(items.map(|s| s.f64())),
    }
}

/// As [`array`], for `len` items that `each` hands, in order, to the
/// function it is given, afresh each time it is called: the bytes are not
/// held, but written where they are wanted (into the mapped buffer that
/// takes them), so that a million triangles are laid out once, not once in
/// a vector and again in the buffer.
pub fn written<'a, S: GpuStruct>(
    len: usize,
    each: impl Fn(&mut dyn FnMut(S)) + Send + Sync + 'a,
    precision: Precision,
) -> Array<'a> {
    let size = match precision {
        Precision::F32 => std::mem::size_of::<S::F32>(),
        Precision::F64 => std::mem::size_of::<S::F64>(),
    };
    let write = move |dst: &mut [u8]| {
        dst.fill(0);
        let mut slots = dst.chunks_exact_mut(size);
        each(&mut |s: S| {
            let slot = slots.next().expect("no more items than the array's length");
            match precision {
                Precision::F32 => slot.copy_from_slice(bytemuck::bytes_of(&s.f32())),
                Precision::F64 => slot.copy_from_slice(bytemuck::bytes_of(&s.f64())),
            }
        });
    };
    Array {
        len: len.max(1),
        byte_len: len.max(1) * size,
        data: Data::Written(Arc::new(write)),
    }
}

/// One scene array: its element count (at least 1) and its bytes, held, or
/// written on demand ([`written`]).
#[derive(Clone)]
pub struct Array<'a> {
    pub len: usize,
    byte_len: usize,
    data: Data<'a>,
}

/// What writes an array's bytes into a slice of its size.
type Writer<'a> = Arc<dyn Fn(&mut [u8]) + Send + Sync + 'a>;

#[derive(Clone)]
enum Data<'a> {
    Held(Vec<u8>),
    Written(Writer<'a>),
}

impl Array<'_> {
    /// Its size in bytes.
    pub fn byte_len(&self) -> usize {
        self.byte_len
    }

    /// Writes its bytes into `dst`, which is `byte_len` long.
    pub fn write(&self, dst: &mut [u8]) {
        assert_eq!(
            dst.len(),
            self.byte_len,
            "an array written into a slice of another size"
        );
        match &self.data {
            Data::Held(bytes) => dst.copy_from_slice(bytes),
            Data::Written(write) => write(dst),
        }
    }

    /// Its bytes, in a vector of their own.
    #[cfg(test)]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut v = vec![0; self.byte_len];
        self.write(&mut v);
        v
    }
}

impl std::fmt::Debug for Array<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Array")
            .field("len", &self.len)
            .field("byte_len", &self.byte_len)
            .finish()
    }
}

/// Declares one interface struct: `gpu_struct!(pub mod m: "Name" { field:
/// type, .. })` makes `m::Values` (the host's values, f64 reals), `m::F32`
/// and `m::F64` (the layouts) and implements [`GpuStruct`] for `Values`.
/// Field types: `real4` (vec4r: vec4 or dvec4), `uvec4`, `float4` (a vec4,
/// f32 in both precisions), and `float3` followed by `uint` (a vec3 and a
/// uint in one 16-byte slot, f32 in both precisions). `real4` fields come first, so that each sits at a multiple
/// of 32 bytes in f64.
macro_rules! gpu_struct {
    (@host real4) => { [f64; 4] };
    (@host uvec4) => { [u32; 4] };
    (@host float3) => { [f32; 3] };
    (@host float4) => { [f32; 4] };
    (@host uint) => { u32 };
    (@f32 real4) => { [f32; 4] };
    (@f32 uvec4) => { [u32; 4] };
    (@f32 float3) => { [f32; 3] };
    (@f32 float4) => { [f32; 4] };
    (@f32 uint) => { u32 };
    (@f64 real4) => { [f64; 4] };
    (@f64 uvec4) => { [u32; 4] };
    (@f64 float3) => { [f32; 3] };
    (@f64 float4) => { [f32; 4] };
    (@f64 uint) => { u32 };
    (@to32 real4, $v:expr) => { $v.map(|x| x as f32) };
    (@to32 $t:ident, $v:expr) => { $v };
    (@glsl real4) => { "vec4r" };
    (@glsl uvec4) => { "uvec4" };
    (@glsl float3) => { "vec3" };
    (@glsl float4) => { "vec4" };
    (@glsl uint) => { "uint" };
    (@member real4) => { $crate::base::interface::Member::Real4 };
    (@member uvec4) => { $crate::base::interface::Member::Uvec4 };
    (@member float3) => { $crate::base::interface::Member::Float3 };
    (@member float4) => { $crate::base::interface::Member::Float4 };
    (@member uint) => { $crate::base::interface::Member::Uint };
    (@real4 real4) => { true };
    (@real4 $t:ident) => { false };
    (@bytes64 real4) => { 32 };
    (@bytes64 uvec4) => { 16 };
    (@bytes64 float3) => { 12 };
    (@bytes64 float4) => { 16 };
    (@bytes64 uint) => { 4 };
    (
        $(#[$doc:meta])*
        $vis:vis mod $m:ident : $name:literal {
            $( $(#[$fdoc:meta])* $field:ident : $ty:ident ),* $(,)?
        }
    ) => {
        $(#[$doc])*
        $vis mod $m {
            use bytemuck::{Pod, Zeroable};

            /// The values as the host computes them.
            #[derive(Debug, Clone, Copy, PartialEq, Default)]
            pub struct Values {
                $( $(#[$fdoc])* pub $field: $crate::base::interface::gpu_struct!(@host $ty), )*
            }

            const BYTES_64: usize = 0 $( + $crate::base::interface::gpu_struct!(@bytes64 $ty) )*;
            /// A struct with a dvec4 is aligned to 32 bytes in f64.
            const ALIGN_64: usize = if false $( || $crate::base::interface::gpu_struct!(@real4 $ty) )* { 32 } else { 16 };

            /// The f32 layout.
            #[repr(C)]
            #[derive(Debug, Clone, Copy, Pod, Zeroable)]
            pub struct F32 {
                $( pub $field: $crate::base::interface::gpu_struct!(@f32 $ty), )*
            }

            /// The f64 layout, padded to a multiple of 32 bytes where it
            /// holds a `real4`.
            #[repr(C)]
            #[derive(Debug, Clone, Copy, Pod, Zeroable)]
            pub struct F64 {
                $( pub $field: $crate::base::interface::gpu_struct!(@f64 $ty), )*
                pub pad: [u32; (ALIGN_64 - BYTES_64 % ALIGN_64) % ALIGN_64 / 4],
            }

            impl $crate::base::interface::GpuStruct for Values {
                type F32 = F32;
                type F64 = F64;
                const NAME: &'static str = $name;
                const MEMBERS: &'static str = concat!(
                    $( "    ", $crate::base::interface::gpu_struct!(@glsl $ty), " ", stringify!($field), ";\n", )*
                );
                const FIELDS: &'static [(&'static str, $crate::base::interface::Member)] = &[
                    $( (stringify!($field), $crate::base::interface::gpu_struct!(@member $ty)), )*
                ];
                fn f32(&self) -> F32 {
                    F32 { $( $field: $crate::base::interface::gpu_struct!(@to32 $ty, self.$field), )* }
                }
                fn f64(&self) -> F64 {
                    F64 { $( $field: self.$field, )* pad: Zeroable::zeroed() }
                }
            }
        }
    };
}
pub(crate) use gpu_struct;

#[cfg(test)]
mod tests {
    use super::*;

    crate::base::interface::gpu_struct!(
        pub mod probe: "Probe" {
            a: real4,
            b: uvec4,
        }
    );

    #[test]
    fn one_field_list_gives_both_layouts_and_the_glsl() {
        use std::mem::size_of;
        assert_eq!(size_of::<probe::F32>(), 32);
        assert_eq!(size_of::<probe::F64>(), 64);
        assert_eq!(
            words(<probe::Values as GpuStruct>::FIELDS, Precision::F32),
            2
        );
        assert_eq!(
            words(<probe::Values as GpuStruct>::FIELDS, Precision::F64),
            4
        );
        assert_eq!(
            declaration::<probe::Values>(),
            "struct Probe {\n    vec4r a;\n    uvec4 b;\n};\n"
        );
        let v = probe::Values {
            a: [1.0, 2.0, 3.0, 0.1],
            b: [7, 0, 0, 0],
        };
        let bytes = array([v].into_iter(), Precision::F32).to_bytes();
        assert_eq!(&bytes[..16], bytemuck::bytes_of(&[1.0f32, 2.0, 3.0, 0.1]));
        assert_eq!(
            array(std::iter::empty::<probe::Values>(), Precision::F64).len,
            1
        );
    }
}
