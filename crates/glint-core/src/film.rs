//! The film: accumulated pixel values and their conversion to output encodings.

use glam::Vec3;

mod srgb8;

pub use crate::desc::Transfer;
use crate::sampling::{Filter, FilterKind};

/// Weighted sample sums over a rectangle of pixels: a tile plus the halo its filter
/// reaches into, or the whole image. A pixel is `Σ w·L / Σ w` over the samples whose
/// filter footprint covers it (the lecture's "filter to get a weighted average").
#[derive(Clone, Debug, PartialEq)]
pub struct FilmTile {
    pub x0: u32,
    pub y0: u32,
    pub width: u32,
    pub height: u32,
    sums: Vec<Vec3>,
    weights: Vec<f32>,
    /// Weighted sums of the auxiliary outputs, when kept: albedo, normal, depth.
    aov_sums: Vec<[Vec3; 3]>,
}

/// What the first surface a camera sample meets looks like: the auxiliary outputs
/// (AOVs) a denoiser or a debugging eye wants beside the colour.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aov {
    /// The surface's main reflectance (textured), black where the ray left the scene.
    pub albedo: Vec3,
    /// Unit world-space shading normal, zero where the ray left the scene.
    pub normal: Vec3,
    /// Distance from the camera to the hit, 0 where the ray left the scene.
    pub depth: f32,
}

/// The AOV images of a render, filtered like the colour.
#[derive(Clone, Debug, PartialEq)]
pub struct AovImages {
    pub albedo: Image,
    pub normal: Image,
    /// Distance in all three channels.
    pub depth: Image,
}

impl FilmTile {
    pub fn new(x0: u32, y0: u32, width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self { x0, y0, width, height, sums: bytemuck::zeroed_vec(n), weights: vec![0.0; n], aov_sums: Vec::new() }
    }

    /// A film that also accumulates [`Aov`]s.
    pub fn with_aovs(mut self) -> Self {
        self.aov_sums = vec![[Vec3::ZERO; 3]; self.sums.len()];
        self
    }

    /// Adds a sample at continuous film position (`fx`, `fy`) (pixels, y down) to every
    /// pixel of this rectangle within the filter's radius.
    pub fn splat(&mut self, filter: &Filter, fx: f32, fy: f32, value: Vec3) {
        self.splat_with(filter, fx, fy, value, None);
    }

    /// [`FilmTile::splat`] with the sample's AOVs (kept only by a film made
    /// [`FilmTile::with_aovs`]). Inlined: a Whitted tile at one sample per pixel splats
    /// as often as it traces a camera ray, and the pixel box's single pixel is a few
    /// instructions where the call and its checks were ninety.
    #[inline(always)]
    pub fn splat_with(&mut self, filter: &Filter, fx: f32, fy: f32, value: Vec3, aov: Option<&Aov>) {
        let Some(i) = self.only_pixel(filter, fx, fy) else {
            self.splat_spread(filter, (fx, fy), value, aov);
            return;
        };
        let aov = aov.filter(|_| !self.aov_sums.is_empty()).map(aov_layers);
        self.add(i, filter.box_weight(), value, &aov);
    }

    /// [`FilmTile::splat_with`] where the sample may reach more than one pixel.
    #[inline(never)]
    fn splat_spread(&mut self, filter: &Filter, (fx, fy): (f32, f32), value: Vec3, aov: Option<&Aov>) {
        let aov = aov.filter(|_| !self.aov_sums.is_empty()).map(aov_layers);
        let r = filter.radius;
        let x_lo = ((fx - 0.5 - r).ceil() as i64).max(self.x0 as i64);
        let x_hi = ((fx - 0.5 + r).floor() as i64).min(self.x0 as i64 + self.width as i64 - 1);
        let y_lo = ((fy - 0.5 - r).ceil() as i64).max(self.y0 as i64);
        let y_hi = ((fy - 0.5 + r).floor() as i64).min(self.y0 as i64 + self.height as i64 - 1);
        for py in y_lo..=y_hi {
            for px in x_lo..=x_hi {
                let w = filter.eval(px as f32 + 0.5 - fx, py as f32 + 0.5 - fy);
                if w != 0.0 {
                    let i = ((py - self.y0 as i64) * self.width as i64 + (px - self.x0 as i64)) as usize;
                    self.add(i, w, value, &aov);
                }
            }
        }
    }

    /// The index of the one pixel the pixel-sized box filter gives a sample strictly
    /// inside it to (the common case, and the cost of a whole splat saved); `None` for
    /// other filters, samples on a pixel border (which reach both sides) and pixels
    /// outside this rectangle. Branch-free tests, and 32-bit conversions, whose
    /// saturation costs less than 64-bit ones'.
    #[inline(always)]
    fn only_pixel(&self, filter: &Filter, fx: f32, fy: f32) -> Option<usize> {
        // Truncation is the floor for the non-negative positions kept; one past `i32`
        // saturates, and then is no pixel of this rectangle.
        let (x, y) = (fx as i32, fy as i32);
        let box_filter = (filter.kind == FilterKind::Box) & (filter.radius == 0.5);
        let inside = box_filter & (fx >= 0.0) & (fy >= 0.0) & (fx > x as f32) & (fy > y as f32);
        // Left of or above the rectangle wraps past its width or height.
        let (px, py) = (x.wrapping_sub(self.x0 as i32) as u32, y.wrapping_sub(self.y0 as i32) as u32);
        let here = (px < self.width) & (py < self.height);
        (inside & here).then(|| py as usize * self.width as usize + px as usize)
    }

    /// Adds a sample of weight `w` to pixel `i`.
    #[inline(always)]
    fn add(&mut self, i: usize, w: f32, value: Vec3, aov: &Option<[Vec3; 3]>) {
        self.sums[i] += w * value;
        self.weights[i] += w;
        if let Some(layers) = aov {
            for (sum, layer) in self.aov_sums[i].iter_mut().zip(layers) {
                *sum += w * *layer;
            }
        }
    }

    /// The weighted sums as they are, to save the film bit for bit: colour sums,
    /// weights, and AOV sums (empty unless kept), row by row.
    pub fn raw(&self) -> (&[Vec3], &[f32], &[[Vec3; 3]]) {
        (&self.sums, &self.weights, &self.aov_sums)
    }

    /// The film [`FilmTile::raw`] saved, or `None` when the arrays do not fit the
    /// rectangle.
    pub fn from_raw(
        (x0, y0, width, height): (u32, u32, u32, u32),
        sums: Vec<Vec3>,
        weights: Vec<f32>,
        aov_sums: Vec<[Vec3; 3]>,
    ) -> Option<Self> {
        let n = width as usize * height as usize;
        let fits = sums.len() == n && weights.len() == n && (aov_sums.is_empty() || aov_sums.len() == n);
        fits.then_some(Self { x0, y0, width, height, sums, weights, aov_sums })
    }

    /// Adds another rectangle's sums into this one (the parts that overlap).
    pub fn merge(&mut self, other: &FilmTile) {
        let (x_lo, x_hi) = (other.x0.max(self.x0), (other.x0 + other.width).min(self.x0 + self.width));
        let (y_lo, y_hi) = (other.y0.max(self.y0), (other.y0 + other.height).min(self.y0 + self.height));
        if x_lo >= x_hi {
            return;
        }
        let n = (x_hi - x_lo) as usize;
        let aovs = !self.aov_sums.is_empty() && !other.aov_sums.is_empty();
        // Row by row, slice against slice: the loops compile to vector adds.
        for y in y_lo..y_hi {
            let i = ((y - self.y0) * self.width + (x_lo - self.x0)) as usize;
            let j = ((y - other.y0) * other.width + (x_lo - other.x0)) as usize;
            add_all(floats_mut(&mut self.sums[i..i + n]), floats(&other.sums[j..j + n]));
            add_all(&mut self.weights[i..i + n], &other.weights[j..j + n]);
            if aovs {
                add_all(floats_mut(&mut self.aov_sums[i..i + n]), floats(&other.aov_sums[j..j + n]));
            }
        }
    }

    /// This film, emptied and reshaped to the rectangle (`x0`, `y0`, `width`, `height`),
    /// keeping [`Aov`]s where `aovs`, its memory kept: a merge that fills one band after
    /// another reuses one film.
    pub fn reset(&mut self, (x0, y0, width, height): (u32, u32, u32, u32), aovs: bool) {
        let n = width as usize * height as usize;
        (self.x0, self.y0, self.width, self.height) = (x0, y0, width, height);
        self.sums.clear();
        self.sums.resize(n, Vec3::ZERO);
        self.weights.clear();
        self.weights.resize(n, 0.0);
        self.aov_sums.clear();
        if aovs {
            self.aov_sums.resize(n, [Vec3::ZERO; 3]);
        }
    }

    /// The weighted averages; a pixel no sample reached is black.
    pub fn resolve(&self) -> Image {
        let mut image = Image::new(self.width, self.height);
        self.resolve_into(&mut image.pixels);
        image
    }

    /// [`FilmTile::resolve`] into `pixels`, this rectangle's pixels row by row (a band
    /// of a larger image).
    pub fn resolve_into(&self, pixels: &mut [Vec3]) {
        for ((pixel, s), &w) in pixels.iter_mut().zip(&self.sums).zip(&self.weights) {
            *pixel = if w.abs() > 1e-12 { *s / w } else { Vec3::ZERO };
        }
    }

    /// The AOVs' weighted averages, when this film kept them.
    pub fn resolve_aovs(&self) -> Option<AovImages> {
        if self.aov_sums.is_empty() {
            return None;
        }
        let layer = |k: usize| Image {
            width: self.width,
            height: self.height,
            pixels: self
                .aov_sums
                .iter()
                .zip(&self.weights)
                .map(|(s, &w)| if w.abs() > 1e-12 { s[k] / w } else { Vec3::ZERO })
                .collect(),
        };
        Some(AovImages { albedo: layer(0), normal: layer(1), depth: layer(2) })
    }
}

impl AovImages {
    /// The AOVs of bands of rows, top to bottom, as the whole image's; `None` when the
    /// bands kept none.
    pub fn stacked(bands: Vec<Option<AovImages>>) -> Option<AovImages> {
        let bands: Vec<AovImages> = bands.into_iter().collect::<Option<_>>().filter(|b: &Vec<_>| !b.is_empty())?;
        let stack = |layer: fn(&AovImages) -> &Image| {
            let width = bands.first().map_or(0, |b| layer(b).width);
            let pixels: Vec<Vec3> = bands.iter().flat_map(|b| layer(b).pixels.iter().copied()).collect();
            Image { width, height: (pixels.len() / width.max(1) as usize) as u32, pixels }
        };
        Some(AovImages { albedo: stack(|b| &b.albedo), normal: stack(|b| &b.normal), depth: stack(|b| &b.depth) })
    }
}

/// A linear-RGB image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

impl Image {
    pub fn new(width: u32, height: u32) -> Self {
        // Zeroed by the allocator: a big image comes as fresh zero pages, not written
        // through first (`vec![Vec3::ZERO; n]` stores each pixel).
        Self { width, height, pixels: bytemuck::zeroed_vec(width as usize * height as usize) }
    }

    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// 8-bit values, RGB interleaved, encoded by `transfer`: in bands on the current
    /// rayon pool, as it is the last step between a render and its file.
    pub fn encode8(&self, transfer: Transfer) -> Vec<u8> {
        match transfer {
            // By table: the same bytes as through `linear_to_srgb`, several times faster.
            Transfer::Srgb => self.encode8_with(srgb8::encoder()),
            Transfer::Identity => self.encode8_with(|c| (clamp_unit(c) * 255.0 + 0.5) as u8),
        }
    }

    /// Each channel through `encode`, into a buffer sized once (collecting the
    /// channels' iterator grew it as it went).
    fn encode8_with(&self, encode: impl Fn(f32) -> u8 + Sync) -> Vec<u8> {
        use rayon::prelude::*;
        const BAND: usize = 16 * 1024;
        let mut bytes = vec![0; 3 * self.pixels.len()];
        bytes.par_chunks_mut(3 * BAND).zip(self.pixels.par_chunks(BAND)).for_each(|(out, pixels)| {
            for (rgb, p) in out.chunks_exact_mut(3).zip(pixels) {
                rgb.copy_from_slice(&[encode(p.x), encode(p.y), encode(p.z)]);
            }
        });
        bytes
    }

    /// 16-bit values, RGB interleaved, encoded by `transfer`.
    pub fn encode16(&self, transfer: Transfer) -> Vec<u16> {
        self.encoded(transfer).map(|c| (c * 65535.0 + 0.5) as u16).collect()
    }

    fn encoded(&self, transfer: Transfer) -> impl Iterator<Item = f32> + '_ {
        let encode = match transfer {
            Transfer::Srgb => linear_to_srgb,
            Transfer::Identity => clamp_unit,
        };
        self.pixels.iter().flat_map(|p| p.to_array()).map(encode)
    }

    /// Mean absolute difference per channel: the distance used by image comparisons.
    pub fn mean_abs_diff(&self, other: &Image) -> f32 {
        assert_eq!((self.width, self.height), (other.width, other.height));
        let sum: f32 = self.pixels.iter().zip(&other.pixels).map(|(a, b)| (*a - *b).abs().element_sum()).sum();
        sum / (3 * self.pixels.len()) as f32
    }
}

/// An [`Aov`] as the three layers a film sums: albedo, normal, and depth in all three
/// channels.
fn aov_layers(aov: &Aov) -> [Vec3; 3] {
    [aov.albedo, aov.normal, Vec3::splat(aov.depth)]
}

/// Adds `adds` into `sums`, element by element: over plain floats, so the loop is
/// vector adds (over `Vec3`s, three scalar adds each).
fn add_all(sums: &mut [f32], adds: &[f32]) {
    for (sum, &add) in sums.iter_mut().zip(adds) {
        *sum += add;
    }
}

/// Vectors as the floats they hold, in order.
fn floats<T: bytemuck::Pod>(vectors: &[T]) -> &[f32] {
    bytemuck::cast_slice(vectors)
}

/// [`floats`], to write.
fn floats_mut<T: bytemuck::Pod>(vectors: &mut [T]) -> &mut [f32] {
    bytemuck::cast_slice_mut(vectors)
}

/// Clamps to [0, 1]; NaN maps to 0.
pub fn clamp_unit(c: f32) -> f32 {
    if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) }
}

/// The sRGB transfer function (IEC 61966-2-1), clamped to [0, 1]; NaN maps to 0.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = clamp_unit(c);
    if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// The sRGB electro-optical transfer function, the inverse of [`linear_to_srgb`]: an
/// encoded value in [0, 1] → linear light (for reading 8-bit textures and images).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_merge_adds_only_the_overlap_and_a_reset_film_merges_as_a_fresh_one() {
        let filter = Filter::new(FilterKind::Box, 0.5).unwrap();
        let mut a = FilmTile::new(2, 1, 3, 2);
        a.splat(&filter, 2.5, 1.5, Vec3::ONE);
        a.splat(&filter, 4.5, 2.5, Vec3::splat(2.0));
        let mut b = FilmTile::new(3, 2, 4, 3);
        b.splat(&filter, 4.5, 2.5, Vec3::splat(4.0));
        b.splat(&filter, 6.5, 4.5, Vec3::splat(8.0));
        let merged = |film: &mut FilmTile| {
            film.merge(&a);
            film.merge(&b);
            film.resolve()
        };
        let fresh = merged(&mut FilmTile::new(0, 0, 6, 4));
        // Pixel (4, 2) has a sample from each; (6, 4) lies outside the film; (2, 1) has
        // only a's.
        assert_eq!(fresh.get(4, 2), Vec3::splat(3.0));
        assert_eq!(fresh.get(2, 1), Vec3::ONE);
        assert_eq!(fresh.pixels.iter().filter(|p| **p != Vec3::ZERO).count(), 2);
        let mut reused = FilmTile::new(1, 1, 9, 9);
        reused.splat(&filter, 4.5, 2.5, Vec3::splat(100.0));
        reused.reset((0, 0, 6, 4), false);
        assert_eq!(merged(&mut reused), fresh);
        // A film made empty (as a merge's workers start) keeps the AOVs it is reset to.
        let mut empty = FilmTile::new(0, 0, 0, 0);
        empty.reset((0, 0, 6, 4), true);
        let aov = Aov { albedo: Vec3::X, normal: Vec3::Y, depth: 2.0 };
        empty.splat_with(&filter, 4.5, 2.5, Vec3::ONE, Some(&aov));
        assert_eq!(empty.resolve_aovs().expect("AOVs kept").depth.get(4, 2), Vec3::splat(2.0));
        empty.reset((0, 0, 6, 4), false);
        assert!(empty.resolve_aovs().is_none());
    }

    #[test]
    fn srgb_round_trips_and_clamps() {
        for i in 0..=255 {
            let c = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5);
        }
        assert!((linear_to_srgb(2.0) - 1.0).abs() < 1e-6);
        assert_eq!(linear_to_srgb(-1.0), 0.0);
        assert_eq!(linear_to_srgb(f32::NAN), 0.0);
    }

    #[test]
    fn a_pixel_box_gives_each_sample_to_the_pixel_it_falls_in() {
        let filter = Filter::new(FilterKind::Box, 0.5).unwrap();
        // A tile with a halo: pixels 2..6 across, 3..6 down.
        let mut film = FilmTile::new(2, 3, 4, 3);
        let inside = [(2.25, 3.5, 1.0), (5.999, 5.001, 2.0), (4.5, 4.5, 4.0)];
        for (fx, fy, v) in inside {
            film.splat(&filter, fx, fy, Vec3::splat(v));
        }
        // On the border between two pixels the sample reaches both; outside, neither.
        film.splat(&filter, 3.0, 3.5, Vec3::splat(8.0));
        film.splat(&filter, 7.5, 3.5, Vec3::splat(16.0));
        film.splat(&filter, 1.5, 4.5, Vec3::splat(32.0));
        // Far outside, where the pixel's coordinates would not fit an `i32`, or left of
        // the image: neither.
        for (fx, fy) in [(-0.5, 4.5), (4.5, -0.25), (3e9, 4.5), (4.5, f32::MAX)] {
            film.splat(&filter, fx, fy, Vec3::splat(64.0));
        }
        let at = |x: u32, y: u32| {
            let i = ((y - 3) * 4 + (x - 2)) as usize;
            (film.sums[i].x, film.weights[i])
        };
        assert_eq!(at(2, 3), (9.0, 2.0));
        assert_eq!(at(3, 3), (8.0, 1.0));
        assert_eq!(at(5, 5), (2.0, 1.0));
        assert_eq!(at(4, 4), (4.0, 1.0));
        let total: f32 = film.weights.iter().sum();
        assert_eq!(total, 5.0, "only the samples inside the tile count, the border one twice");
    }
}
