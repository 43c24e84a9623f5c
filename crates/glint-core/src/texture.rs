//! Colour patterns over uv: image textures (bilinear, repeating) and a procedural checker.

use bytemuck::NoUninit;
use glam::{Vec2, Vec3};

use crate::desc::TextureDesc;

/// What a [`Texture`] record is.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, NoUninit)]
pub enum TextureKind {
    Image = 0,
    Checker = 1,
}

/// A texture as flat data; image texels live in the scene's shared texel array.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Texture {
    pub kind: TextureKind,
    pub width: u32,
    pub height: u32,
    /// First texel of this image in the scene's texel array.
    pub offset: u32,
    pub even: Vec3,
    pub odd: Vec3,
    pub cells: Vec2,
}

impl Texture {
    /// Appends an image's texels to `texels` and returns its record.
    pub fn compile(desc: &TextureDesc, texels: &mut Vec<Vec3>) -> Self {
        match desc {
            TextureDesc::Image { width, height, texels: pixels, .. } => {
                let offset = texels.len() as u32;
                texels.extend_from_slice(pixels);
                Self {
                    kind: TextureKind::Image,
                    width: *width,
                    height: *height,
                    offset,
                    even: Vec3::ZERO,
                    odd: Vec3::ZERO,
                    cells: Vec2::ZERO,
                }
            }
            TextureDesc::Checker { even, odd, cells, .. } => Self {
                kind: TextureKind::Checker,
                width: 0,
                height: 0,
                offset: 0,
                even: *even,
                odd: *odd,
                cells: *cells,
            },
        }
    }

    /// The colour at `uv`; both patterns repeat with period 1.
    pub fn sample(&self, uv: Vec2, texels: &[Vec3]) -> Vec3 {
        match self.kind {
            TextureKind::Checker => {
                let cell = (uv * self.cells).floor();
                if (cell.x + cell.y).rem_euclid(2.0) == 0.0 { self.even } else { self.odd }
            }
            TextureKind::Image => self.bilinear(uv, texels),
        }
    }

    /// Bilinear filtering with wrap-around; v = 1 is the image's top row.
    fn bilinear(&self, uv: Vec2, texels: &[Vec3]) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let x = uv.x.rem_euclid(1.0) * w as f32 - 0.5;
        let y = (1.0 - uv.y.rem_euclid(1.0)) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |i: i64, j: i64| {
            let (i, j) = (i.rem_euclid(w), j.rem_euclid(h));
            texels[self.offset as usize + (j * w + i) as usize]
        };
        let (i, j) = (x0 as i64, y0 as i64);
        let top = texel(i, j).lerp(texel(i + 1, j), fx);
        let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_and_repeats() {
        let desc = TextureDesc::Checker { name: "c".into(), even: Vec3::ONE, odd: Vec3::ZERO, cells: Vec2::splat(2.0) };
        let t = Texture::compile(&desc, &mut Vec::new());
        assert_eq!(t.sample(Vec2::new(0.1, 0.1), &[]), Vec3::ONE);
        assert_eq!(t.sample(Vec2::new(0.6, 0.1), &[]), Vec3::ZERO);
        assert_eq!(t.sample(Vec2::new(0.6, 0.6), &[]), Vec3::ONE);
        assert_eq!(t.sample(Vec2::new(-0.4, 0.1), &[]), Vec3::ZERO);
    }

    #[test]
    fn image_texel_centres_are_exact_and_top_row_is_v1() {
        let texels = vec![Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE]; // 2×2: red green / blue white
        let desc = TextureDesc::Image { name: "i".into(), path: String::new(), width: 2, height: 2, texels };
        let mut all = vec![Vec3::splat(9.0)]; // an earlier texture's texels
        let t = Texture::compile(&desc, &mut all);
        assert!((t.sample(Vec2::new(0.25, 0.75), &all) - Vec3::X).length() < 1e-6);
        assert!((t.sample(Vec2::new(0.75, 0.25), &all) - Vec3::ONE).length() < 1e-6);
        // Halfway between red and green.
        let mid = t.sample(Vec2::new(0.5, 0.75), &all);
        assert!((mid - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
    }
}
