//! One definition of every record the GPU reads, shared by Rust and WGSL.
//!
//! Each record is declared once with [`gpu_record!`]: the Rust type it mirrors and its
//! fields in WGSL terms. From that one list come the WGSL `struct` the shaders use
//! (with explicit padding members where the Rust layout has gaps) and compile-time
//! assertions that every field sits at the offset WGSL's storage-layout rules give it
//! and that the fields cover the whole Rust record — so a field added, moved or
//! retyped on one side stops the build instead of corrupting the upload.
//!
//! glam's `Vec3` is 12 bytes aligned to 4, which WGSL's `vec3<f32>` (aligned to 16) is
//! not; it appears in WGSL as `array<f32, 3>`, read through `v3()`.

/// A field's type as WGSL sees it in a storage buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    U32,
    F32,
    /// glam `Vec2`: `array<f32, 2>`.
    Vec2,
    /// glam `Vec3`: `array<f32, 3>`.
    Vec3,
    /// `vec4<f32>`, 16-byte aligned.
    Vec4,
    /// glam `Mat4` (16-byte aligned columns): `mat4x4<f32>`.
    Mat4,
    F32s(usize),
    U32s(usize),
}

impl Ty {
    /// Alignment under WGSL's storage-buffer rules.
    pub const fn align(self) -> usize {
        match self {
            Ty::Vec4 | Ty::Mat4 => 16,
            _ => 4,
        }
    }

    pub const fn size(self) -> usize {
        match self {
            Ty::U32 | Ty::F32 => 4,
            Ty::Vec2 => 8,
            Ty::Vec3 => 12,
            Ty::Vec4 => 16,
            Ty::Mat4 => 64,
            Ty::F32s(n) | Ty::U32s(n) => 4 * n,
        }
    }

    fn wgsl(self) -> String {
        match self {
            Ty::U32 => "u32".into(),
            Ty::F32 => "f32".into(),
            Ty::Vec2 => "array<f32, 2>".into(),
            Ty::Vec3 => "array<f32, 3>".into(),
            Ty::Vec4 => "vec4<f32>".into(),
            Ty::Mat4 => "mat4x4<f32>".into(),
            Ty::F32s(n) => format!("array<f32, {n}>"),
            Ty::U32s(n) => format!("array<u32, {n}>"),
        }
    }

    /// WGSL expressions reading each 32-bit word of `value` as a `u32`, in memory order
    /// (what the layout test's echo shader writes back).
    fn words(self, value: &str) -> Vec<String> {
        let bits = |e: String| format!("bitcast<u32>({e})");
        match self {
            Ty::U32 => vec![value.to_string()],
            Ty::F32 => vec![bits(value.to_string())],
            Ty::Vec2 | Ty::Vec3 | Ty::F32s(_) => (0..self.size() / 4).map(|i| bits(format!("{value}[{i}]"))).collect(),
            Ty::Vec4 => (0..4).map(|i| bits(format!("{value}[{i}]"))).collect(),
            Ty::U32s(n) => (0..n).map(|i| format!("{value}[{i}]")).collect(),
            Ty::Mat4 => (0..16).map(|i| bits(format!("{value}[{}][{}]", i / 4, i % 4))).collect(),
        }
    }
}

/// One field: its WGSL name and type, and its byte offset in the Rust record.
#[derive(Clone, Copy, Debug)]
pub struct Field {
    pub name: &'static str,
    pub ty: Ty,
    pub offset: usize,
}

/// A record shared by Rust and WGSL.
#[derive(Clone, Copy, Debug)]
pub struct Record {
    pub name: &'static str,
    pub fields: &'static [Field],
    /// `size_of` the Rust record: the stride of an array of them on both sides.
    pub size: usize,
}

impl Record {
    /// Whether WGSL, given the padding [`Record::wgsl`] inserts, lays the fields out
    /// exactly as Rust does: every field aligned for WGSL, fields in order without
    /// overlap, and the struct's size (a multiple of its alignment) equal to Rust's.
    /// Fields must also cover the record: padding Rust adds on its own would hide a
    /// field missing from the list.
    pub const fn matches_rust(&self) -> bool {
        let mut end = 0;
        let mut align = 4;
        let mut covered = 0;
        let mut i = 0;
        while i < self.fields.len() {
            let f = self.fields[i];
            if f.offset < end || !f.offset.is_multiple_of(f.ty.align()) {
                return false;
            }
            end = f.offset + f.ty.size();
            covered += f.ty.size();
            if f.ty.align() > align {
                align = f.ty.align();
            }
            i += 1;
        }
        end <= self.size && self.size.is_multiple_of(align) && covered == self.size
    }

    /// The WGSL struct declaration.
    pub fn wgsl(&self) -> String {
        let mut out = format!("struct {} {{\n", self.name);
        let mut end = 0;
        for (k, f) in self.fields.iter().enumerate() {
            if f.offset > end {
                out += &format!("    _pad{k}: array<u32, {}>,\n", (f.offset - end) / 4);
            }
            out += &format!("    {}: {},\n", f.name, f.ty.wgsl());
            end = f.offset + f.ty.size();
        }
        if self.size > end {
            out += &format!("    _pad_end: array<u32, {}>,\n", (self.size - end) / 4);
        }
        out + "}\n"
    }

    /// For the layout test: a WGSL statement list that writes every field of
    /// `value` as words to `out[k..]`, advancing `k`.
    pub fn echo_statements(&self, value: &str) -> String {
        let mut out = String::new();
        for f in self.fields {
            for word in f.ty.words(&format!("{value}.{}", f.name)) {
                out += &format!("    out[k] = {word}; k += 1u;\n");
            }
        }
        out
    }

    /// The words [`Record::echo_statements`] writes for `bytes`, one Rust record.
    pub fn expected_words(&self, bytes: &[u8]) -> Vec<u32> {
        let mut words = Vec::new();
        for f in self.fields {
            for chunk in bytes[f.offset..f.offset + f.ty.size()].chunks_exact(4) {
                words.push(u32::from_le_bytes(chunk.try_into().expect("4 bytes")));
            }
        }
        words
    }

    /// 32-bit words per record that carry data (padding excluded).
    pub fn data_words(&self) -> usize {
        self.fields.iter().map(|f| f.ty.size() / 4).sum()
    }
}

/// Declares a [`Record`] constant for a Rust type and asserts at compile time that its
/// WGSL layout matches (see [`Record::matches_rust`]).
///
/// ```ignore
/// gpu_record!(pub INSTANCE = Instance as "Instance" {
///     world_from_object: Mat4 = transform.world_from_object,
///     kind: U32 = shape.kind,
/// });
/// ```
#[macro_export]
macro_rules! gpu_record {
    ($vis:vis $name:ident = $rust:ty as $wgsl:literal { $($field:ident : $ty:expr => $($path:ident).+),* $(,)? }) => {
        $vis const $name: $crate::layout::Record = {
            #[allow(unused_imports)]
            use $crate::layout::Ty::*;
            $crate::layout::Record {
                name: $wgsl,
                size: ::core::mem::size_of::<$rust>(),
                fields: &[$($crate::layout::Field {
                    name: stringify!($field),
                    ty: $ty,
                    offset: ::core::mem::offset_of!($rust, $($path).+),
                }),*],
            }
        };
        const _: () = assert!($name.matches_rust(), concat!("record ", $wgsl, " does not match its WGSL layout"));
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[repr(C)]
    struct Padded {
        a: u32,
        pad: [u32; 3],
        m: glam::Mat4,
    }

    #[test]
    fn explicit_padding_keeps_the_mat4_aligned() {
        gpu_record!(PADDED = Padded as "Padded" { a: U32 => a, pad: U32s(3) => pad, m: Mat4 => m });
        let text = PADDED.wgsl();
        assert!(text.contains("a: u32,\n    pad: array<u32, 3>,\n    m: mat4x4<f32>,\n}"), "{text}");
        assert_eq!(PADDED.data_words(), 20);
    }

    #[test]
    fn gaps_and_misaligned_fields_are_caught() {
        // Constants, so the field lists are promoted to the `'static` slices records hold.
        const A: Field = Field { name: "a", ty: Ty::U32, offset: 0 };
        let gap = Record { name: "G", size: 80, fields: &[A, Field { name: "m", ty: Ty::Mat4, offset: 16 }] };
        assert!(!gap.matches_rust(), "a field missing from the list must not pass as padding");
        let misaligned = Record { name: "M", size: 80, fields: &[Field { name: "m", ty: Ty::Mat4, offset: 4 }] };
        assert!(!misaligned.matches_rust());
        let exact = Record { name: "E", size: 4, fields: &[A] };
        assert!(exact.matches_rust());
    }
}
