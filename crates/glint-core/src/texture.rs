//! Colour patterns over uv: image textures (bilinear or nearest; repeating, clamped or
//! mirrored beyond the image) and a procedural checker, which can be averaged exactly over
//! a pixel's footprint.

use bytemuck::NoUninit;
use glam::{Vec2, Vec3};

use crate::desc::{ImageSampling, TextureDesc, TextureWrap};

/// [`Texture::flags`]: two bits of [`TextureWrap`] for u, two for v, then nearest.
const WRAP_V_SHIFT: u32 = 2;
const WRAP_MASK: u32 = 3;
const NEAREST: u32 = 16;
/// A checker averaged over each pixel's footprint ([`Texture::sample_over`]).
pub const FILTERED: u32 = 32;

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
    /// How images wrap and filter (see [`ImageSampling`]), packed in bits.
    pub flags: u32,
}

fn flags_of(sampling: &ImageSampling) -> u32 {
    let [u, v] = sampling.wrap.map(|w| w as u32);
    u | v << WRAP_V_SHIFT | if sampling.nearest { NEAREST } else { 0 }
}

/// Texel index `i` of `n` along one axis, wrapped as `mode` (a [`TextureWrap`] as u32) says.
#[inline]
fn wrap_index(i: i64, n: i64, mode: u32) -> i64 {
    const CLAMP: u32 = TextureWrap::Clamp as u32;
    const MIRROR: u32 = TextureWrap::Mirror as u32;
    match mode {
        CLAMP => i.clamp(0, n - 1),
        MIRROR => {
            let m = i.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
        _ => i.rem_euclid(n),
    }
}

impl Texture {
    /// Appends an image's texels to `texels` and returns its record.
    pub fn compile(desc: &TextureDesc, texels: &mut Vec<Vec3>) -> Self {
        match desc {
            TextureDesc::Image { width, height, texels: pixels, sampling, .. } => {
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
                    flags: flags_of(sampling),
                }
            }
            TextureDesc::Checker { even, odd, cells, filtered, .. } => Self {
                kind: TextureKind::Checker,
                width: 0,
                height: 0,
                offset: 0,
                even: *even,
                odd: *odd,
                cells: *cells,
                flags: if *filtered { FILTERED } else { 0 },
            },
        }
    }

    /// The colour at `uv`; both patterns repeat with period 1. Always inlined, so a
    /// checker's floors compile into the AVX2 Whitted tile as one instruction each (in a
    /// function of its own, built for any x86-64, each was a library call); an image is
    /// a call.
    #[inline(always)]
    pub fn sample(&self, uv: Vec2, texels: &[Vec3]) -> Vec3 {
        match self.kind {
            TextureKind::Checker => {
                let cell = (uv * self.cells).floor();
                if modulo_two(cell.x + cell.y) == 0.0 { self.even } else { self.odd }
            }
            TextureKind::Image => self.image(uv, texels),
        }
    }

    /// Whether the colour depends on the footprint ([`Texture::sample_over`]), so a
    /// caller must work the footprint out.
    #[inline]
    pub fn is_filtered(&self) -> bool {
        self.flags & FILTERED != 0
    }

    /// The colour averaged over the pixel footprint at `uv`, whose steps to the
    /// neighbouring pixels are `steps` (in the same units as `uv`; `None`: unbounded, the
    /// pattern's mean). Unfiltered textures ignore the footprint.
    #[inline(always)]
    pub fn sample_over(&self, uv: Vec2, steps: Option<[Vec2; 2]>, texels: &[Vec3]) -> Vec3 {
        if !self.is_filtered() || self.kind != TextureKind::Checker {
            return self.sample(uv, texels);
        }
        // The footprint is the parallelogram the two steps span (half a step either way
        // of the point). Along each axis its spread is the sum of the two steps' spreads,
        // each uniform: the sum of two boxes, a trapezoid. Exact across any single edge,
        // however the footprint is turned; where an edge of each axis falls inside,
        // the product of the two axes' means stands for the mean of their product.
        let Some([dx, dy]) = steps else {
            return self.even * 0.5 + self.odd * 0.5;
        };
        let (across, down) = (dx.abs() * self.cells, dy.abs() * self.cells);
        let cell = uv * self.cells;
        let sign = trapezoid_filtered_square_wave(cell.x, across.x, down.x)
            * trapezoid_filtered_square_wave(cell.y, across.y, down.y);
        // sign = +1 on an even cell, −1 on an odd one.
        self.even * (0.5 + 0.5 * sign) + self.odd * (0.5 - 0.5 * sign)
    }

    /// Bilinear (or nearest) filtering, wrapped as the flags say; v = 1 is the image's
    /// top row.
    #[inline(never)]
    fn image(&self, uv: Vec2, texels: &[Vec3]) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let (wrap_u, wrap_v) = (self.flags & WRAP_MASK, self.flags >> WRAP_V_SHIFT & WRAP_MASK);
        // Each axis is reduced first, so huge uvs keep precision and never overflow the
        // texel index: repeat to [0, 1), mirror to [0, 2), clamp to [−1, 2].
        let reduce = |t: f32, mode: u32| match mode {
            m if m == TextureWrap::Clamp as u32 => t.clamp(-1.0, 2.0),
            m if m == TextureWrap::Mirror as u32 => modulo_two(t),
            _ => modulo_one(t),
        };
        let x = reduce(uv.x, wrap_u) * w as f32;
        let y = (1.0 - reduce(uv.y, wrap_v)) * h as f32;
        let texel = |i: i64, j: i64| {
            let (i, j) = (wrap_index(i, w, wrap_u), wrap_index(j, h, wrap_v));
            texels[self.offset as usize + (j * w + i) as usize]
        };
        if self.flags & NEAREST != 0 {
            return texel(x.floor() as i64, y.floor() as i64);
        }
        let (x, y) = (x - 0.5, y - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = texel(i, j).lerp(texel(i + 1, j), fx);
        let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// `x.rem_euclid(2.0)`, the same value (but `+0` for `−0`), without `fmodf`: Rust's
/// `%` on `f32` calls a bit-by-bit software `fmodf`, which took 7% of a Whitted render
/// with a filtered checker. `x − 2⌊x/2⌋` rounds once, as `rem_euclid` does: its exact
/// value lies in [0, 2), and `x/2`, the floor and the doubling are exact.
#[inline]
fn modulo_two(x: f32) -> f32 {
    x - 2.0 * (0.5 * x).floor()
}

/// `x.rem_euclid(1.0)` without `fmodf`, as [`modulo_two`].
#[inline]
fn modulo_one(x: f32) -> f32 {
    x - x.floor()
}

/// The mean of the square wave that is +1 on even cells `[2k, 2k + 1)` and −1 on odd
/// ones, at `x + a + b` with `a` and `b` uniform over widths `wa` and `wb` about zero
/// (a trapezoid of support `wa + wb`). A footprint within one cell is that cell's value;
/// one across a single edge weighs the two cells by the trapezoid's distribution, which
/// is well conditioned however narrow it is; a wider one is the difference of the
/// wave's second integral across the footprint, taken within one period so that it
/// keeps its precision far from the origin.
#[inline(always)]
fn trapezoid_filtered_square_wave(x: f32, wa: f32, wb: f32) -> f32 {
    let half = 0.5 * (wa + wb);
    if half.is_nan() {
        return square_wave_on(x.floor());
    }
    if half >= 1e4 {
        return 0.0;
    }
    let (lo, hi) = ((x - half).floor(), (x + half).floor());
    if lo == hi {
        return square_wave_on(lo);
    }
    if half < 0.5 {
        // One edge, at `hi`: the cell below it with the chance of landing below it.
        let below = trapezoid_cdf(hi - x, wa, wb);
        return square_wave_on(hi) * (1.0 - 2.0 * below);
    }
    let (long, short) = (wa.max(wb), wa.min(wb));
    if short < 1e-2 * long {
        // A trapezoid this steep is its long box to within a fraction of `short / long`.
        return box_filtered_square_wave(x, long);
    }
    // The wave's second integral less its mean slope (x/2): periodic over two cells.
    let periodic = |t: f32| {
        let y = modulo_two(t);
        if y <= 1.0 { 0.5 * y * (y - 1.0) } else { -0.5 * y * y + 1.5 * y - 1.0 }
    };
    let (outer, inner) = (half, 0.5 * (long - short));
    let x = modulo_two(x);
    let second_difference = periodic(x + outer) - periodic(x + inner) - periodic(x - inner) + periodic(x - outer);
    (second_difference / (wa * wb)).clamp(-1.0, 1.0)
}

/// The square wave on cell `cell` (an integer): +1 on even cells, −1 on odd ones.
#[inline]
fn square_wave_on(cell: f32) -> f32 {
    if modulo_two(cell) == 0.0 { 1.0 } else { -1.0 }
}

/// The chance that `a + b` (uniform over widths `wa` and `wb` about zero) is below `t`.
#[inline]
fn trapezoid_cdf(t: f32, wa: f32, wb: f32) -> f32 {
    let (long, short) = (wa.max(wb), wa.min(wb));
    let (outer, inner) = (0.5 * (long + short), 0.5 * (long - short));
    let below = if t <= -outer {
        0.0
    } else if t <= -inner {
        // The rising ramp; empty when `short` is zero.
        let rise = t + outer;
        0.5 * rise * rise / (long * short)
    } else if t <= inner {
        0.5 * short / long + (t + inner) / long
    } else if t < outer {
        let fall = outer - t;
        1.0 - 0.5 * fall * fall / (long * short)
    } else {
        1.0
    };
    below.clamp(0.0, 1.0)
}

/// The mean over `[x − w/2, x + w/2]` of the square wave that is +1 on even cells
/// `[2k, 2k + 1)` and −1 on odd ones: the difference of its integral, a triangle wave,
/// across the box. Point-sampled when the box is too narrow for `f32` to tell the ends
/// apart, zero when it spans so many cells that the mean is lost in rounding.
#[inline]
fn box_filtered_square_wave(x: f32, w: f32) -> f32 {
    let point = square_wave_on(x.floor());
    if w.is_nan() || w <= 1e-4 * x.abs().max(1.0) {
        return point;
    }
    if w >= 1e4 {
        return 0.0;
    }
    // ∫₀ˣ wave = 1 − |1 − (x mod 2)|.
    let integral = |x: f32| 1.0 - (1.0 - modulo_two(x)).abs();
    ((integral(x + 0.5 * w) - integral(x - 0.5 * w)) / w).clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modulo_two_and_one_are_rem_euclid() {
        let mut rng = crate::sampling::Rng::new(3);
        let edges = [0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 1e-10, -1e-10, 1.999_999_9, -1.999_999_9, 3e7, -3e7, 1e38];
        let random = (0..100_000).map(|i| (rng.next_f32() - 0.5) * [1e-3, 1.0, 1e3, 1e6][i % 4]);
        for x in edges.into_iter().chain(random) {
            let (got, want) = (modulo_two(x), x.rem_euclid(2.0));
            assert!(got == want, "{x}: {got} against {want}");
            let (got, want) = (modulo_one(x), x.rem_euclid(1.0));
            assert!(got == want, "{x}: {got} against {want} (mod 1)");
        }
        assert!(modulo_two(f32::INFINITY).is_nan() && modulo_two(f32::NAN).is_nan());
        assert!(modulo_one(f32::INFINITY).is_nan() && modulo_one(f32::NAN).is_nan());
    }

    #[test]
    fn checker_alternates_and_repeats() {
        let t = checker(false);
        assert_eq!(t.sample(Vec2::new(0.1, 0.1), &[]), Vec3::ONE);
        assert_eq!(t.sample(Vec2::new(0.6, 0.1), &[]), Vec3::ZERO);
        assert_eq!(t.sample(Vec2::new(0.6, 0.6), &[]), Vec3::ONE);
        assert_eq!(t.sample(Vec2::new(-0.4, 0.1), &[]), Vec3::ZERO);
    }

    /// White even and black odd cells, two along each axis of the unit square.
    fn checker(filtered: bool) -> Texture {
        let desc = TextureDesc::Checker {
            name: "c".into(),
            even: Vec3::ONE,
            odd: Vec3::ZERO,
            cells: Vec2::splat(2.0),
            filtered,
        };
        Texture::compile(&desc, &mut Vec::new())
    }

    /// Steps of `du` across and `dv` down: a box `du` × `dv` in uv.
    fn steps(du: f32, dv: f32) -> Option<[Vec2; 2]> {
        Some([Vec2::new(du, 0.0), Vec2::new(0.0, dv)])
    }

    #[test]
    fn a_filtered_checker_averages_exactly_over_whole_and_split_cells() {
        let t = checker(true);
        // A tiny footprint inside a cell is that cell.
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-4;
        assert!(close(t.sample_over(Vec2::new(0.1, 0.1), steps(1e-3, 1e-3), &[]), Vec3::ONE));
        assert!(close(t.sample_over(Vec2::new(0.6, 0.1), steps(1e-3, 1e-3), &[]), Vec3::ZERO));
        // Two whole cells along u (one period): half white, whatever the position.
        for u in [0.0, 0.13, 0.5, 0.77] {
            let c = t.sample_over(Vec2::new(u, 0.2), steps(1.0, 0.01), &[]);
            assert!((c - Vec3::splat(0.5)).length() < 1e-5, "u {u}: {c}");
        }
        // Centred on the edge at u = 0.5 and a quarter cell wide: half and half.
        let c = t.sample_over(Vec2::new(0.5, 0.2), steps(0.125, 0.01), &[]);
        assert!((c - Vec3::splat(0.5)).length() < 1e-5, "{c}");
        // Three quarters in the white cell: 0.75.
        let c = t.sample_over(Vec2::new(0.4375, 0.2), steps(0.25, 0.01), &[]);
        assert!((c - Vec3::splat(0.75)).length() < 1e-5, "{c}");
        // An unbounded footprint is the mean; an unfiltered checker ignores the footprint.
        assert_eq!(t.sample_over(Vec2::new(0.1, 0.1), None, &[]), Vec3::splat(0.5));
        assert_eq!(checker(false).sample_over(Vec2::new(0.1, 0.1), None, &[]), Vec3::ONE);
    }

    #[test]
    fn a_filtered_checker_is_the_mean_of_point_samples_over_its_box() {
        let t = checker(true);
        let mut rng = crate::sampling::Rng::new(7);
        for _ in 0..40 {
            let uv = Vec2::new(rng.next_f32() * 8.0 - 4.0, rng.next_f32() * 8.0 - 4.0);
            let (du, dv) = (rng.next_f32() * 1.5, rng.next_f32() * 0.7);
            let n = 200;
            let mut sum = Vec3::ZERO;
            for i in 0..n {
                for j in 0..n {
                    let offset =
                        Vec2::new(du * ((i as f32 + 0.5) / n as f32 - 0.5), dv * ((j as f32 + 0.5) / n as f32 - 0.5));
                    sum += t.sample(uv + offset, &[]);
                }
            }
            let numeric = sum / (n * n) as f32;
            let exact = t.sample_over(uv, steps(du, dv), &[]);
            assert!((numeric - exact).abs().max_element() < 0.015, "uv {uv} box {du}×{dv}: {exact} vs {numeric}");
        }
    }

    #[test]
    fn a_filtered_checker_is_the_exact_mean_over_a_turned_footprint_across_one_edge() {
        // Sheared parallelograms, as a floor in perspective gives off the image's centre:
        // across a single edge (of either axis) the trapezoid is exact, where the box
        // around the parallelogram blurred the edge by the shear.
        let t = checker(true);
        let mut rng = crate::sampling::Rng::new(11);
        let mut tested = 0;
        while tested < 60 {
            let uv = Vec2::new(rng.next_f32() * 6.0 - 3.0, rng.next_f32() * 6.0 - 3.0);
            let mut random_step = || Vec2::new(rng.next_f32() - 0.5, rng.next_f32() - 0.5) * 0.4;
            let (a, b) = (random_step(), random_step());
            // In cells (two to a unit): the footprint's extent along each axis.
            let extent = (a.abs() + b.abs()) * 2.0;
            let edges =
                |centre: f32, extent: f32| ((centre + 0.5 * extent).floor() - (centre - 0.5 * extent).floor()) as i32;
            let (edges_u, edges_v) = (edges(uv.x * 2.0, extent.x), edges(uv.y * 2.0, extent.y));
            if edges_u + edges_v != 1 {
                continue;
            }
            tested += 1;
            let n = 400;
            let mut sum = Vec3::ZERO;
            for i in 0..n {
                for j in 0..n {
                    let (alpha, beta) = ((i as f32 + 0.5) / n as f32 - 0.5, (j as f32 + 0.5) / n as f32 - 0.5);
                    sum += t.sample(uv + alpha * a + beta * b, &[]);
                }
            }
            let numeric = sum / (n * n) as f32;
            let exact = t.sample_over(uv, Some([a, b]), &[]);
            assert!((numeric - exact).abs().max_element() < 4e-3, "uv {uv} steps {a} {b}: {exact} vs {numeric}");
        }
    }

    #[test]
    fn the_trapezoid_filter_is_its_distribution_and_keeps_its_precision_far_out() {
        // Its distribution function is the two boxes' convolution, numerically.
        let mut rng = crate::sampling::Rng::new(5);
        for _ in 0..200 {
            let (wa, wb, t) = (rng.next_f32() * 2.0, rng.next_f32() * 2.0, rng.next_f32() * 4.0 - 2.0);
            let n = 300;
            let below = (0..n * n)
                .filter(|k| {
                    let (i, j) = (k / n, k % n);
                    let a = wa * ((i as f32 + 0.5) / n as f32 - 0.5);
                    let b = wb * ((j as f32 + 0.5) / n as f32 - 0.5);
                    a + b < t
                })
                .count() as f32
                / (n * n) as f32;
            let cdf = trapezoid_cdf(t, wa, wb);
            assert!((cdf - below).abs() < 1e-2, "wa {wa} wb {wb} t {t}: {cdf} vs {below}");
        }
        // Wide footprints: the same mean at the origin and a million cells out (one
        // period is 2 cells), and the mean over any box of one whole period is zero.
        // (Positions in sixteenths, which f32 still holds a million cells out.)
        for (x, wa, wb) in [(0.3125, 1.3, 0.7), (1.6875, 2.0, 0.9), (0.125, 0.6, 0.55)] {
            let near = trapezoid_filtered_square_wave(x, wa, wb);
            let far = trapezoid_filtered_square_wave(x + 1_000_000.0, wa, wb);
            assert!((near - far).abs() < 2e-3, "{x}: {near} vs {far}");
        }
        assert!(trapezoid_filtered_square_wave(0.37, 2.0, 0.0).abs() < 1e-5);
        assert!(trapezoid_filtered_square_wave(0.37, 2.0, 0.5).abs() < 1e-5);
    }

    #[test]
    fn image_texel_centres_are_exact_and_top_row_is_v1() {
        let texels = vec![Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE]; // 2×2: red green / blue white
        let desc = TextureDesc::Image {
            name: "i".into(),
            path: String::new(),
            width: 2,
            height: 2,
            texels,
            sampling: ImageSampling::default(),
        };
        let mut all = vec![Vec3::splat(9.0)]; // an earlier texture's texels
        let t = Texture::compile(&desc, &mut all);
        assert!((t.sample(Vec2::new(0.25, 0.75), &all) - Vec3::X).length() < 1e-6);
        assert!((t.sample(Vec2::new(0.75, 0.25), &all) - Vec3::ONE).length() < 1e-6);
        // Halfway between red and green.
        let mid = t.sample(Vec2::new(0.5, 0.75), &all);
        assert!((mid - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
    }

    /// A 2×1 image, red then blue, sampled with `sampling`.
    fn red_blue(sampling: ImageSampling) -> (Texture, Vec<Vec3>) {
        let texels = vec![Vec3::X, Vec3::Z];
        let desc = TextureDesc::Image { name: "rb".into(), path: String::new(), width: 2, height: 1, texels, sampling };
        let mut all = Vec::new();
        (Texture::compile(&desc, &mut all), all)
    }

    #[test]
    fn wrap_modes_repeat_clamp_and_mirror_beyond_the_image() {
        let at = |wrap: TextureWrap, u: f32| {
            let (t, texels) = red_blue(ImageSampling { wrap: [wrap, TextureWrap::Repeat], nearest: true });
            t.sample(Vec2::new(u, 0.5), &texels)
        };
        // u in [1, 1.5) is the first texel again, clamped the last, mirrored the last.
        assert_eq!(at(TextureWrap::Repeat, 1.25), Vec3::X);
        assert_eq!(at(TextureWrap::Clamp, 1.25), Vec3::Z);
        assert_eq!(at(TextureWrap::Clamp, -3.0), Vec3::X);
        assert_eq!(at(TextureWrap::Mirror, 1.25), Vec3::Z);
        assert_eq!(at(TextureWrap::Mirror, 1.75), Vec3::X);
        assert_eq!(at(TextureWrap::Mirror, -0.25), Vec3::X);
        // Bilinear at the right edge: repeating blends blue into red, clamping stays blue.
        let edge = |wrap| {
            let (t, texels) = red_blue(ImageSampling { wrap: [wrap, TextureWrap::Repeat], nearest: false });
            t.sample(Vec2::new(0.999, 0.5), &texels)
        };
        assert!(edge(TextureWrap::Repeat).x > 0.4);
        assert_eq!(edge(TextureWrap::Clamp), Vec3::Z);
    }

    #[test]
    fn huge_and_odd_uvs_wrap_without_overflow() {
        for wrap in [TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror] {
            for nearest in [false, true] {
                let (t, texels) = red_blue(ImageSampling { wrap: [wrap; 2], nearest });
                for u in [1e30, -1e30, f32::MAX, f32::MIN, 3.0e9] {
                    let c = t.sample(Vec2::new(u, 0.5), &texels);
                    assert!(c.is_finite() && c.max_element() <= 1.0, "{wrap:?} at {u}: {c}");
                }
                // A NaN uv gives a NaN colour (reported as a non-finite sample), not a panic.
                t.sample(Vec2::splat(f32::NAN), &texels);
            }
        }
        // Far out, a clamped axis shows its edge texel.
        let (t, texels) = red_blue(ImageSampling { wrap: [TextureWrap::Clamp; 2], nearest: false });
        assert_eq!(t.sample(Vec2::new(1e30, 0.5), &texels), Vec3::Z);
        assert_eq!(t.sample(Vec2::new(-1e30, 0.5), &texels), Vec3::X);
    }

    #[test]
    fn nearest_filtering_shows_whole_texels() {
        let (t, texels) = red_blue(ImageSampling { nearest: true, ..Default::default() });
        assert_eq!(t.sample(Vec2::new(0.49, 0.5), &texels), Vec3::X);
        assert_eq!(t.sample(Vec2::new(0.51, 0.5), &texels), Vec3::Z);
        let (t, texels) = red_blue(ImageSampling::default());
        let mid = t.sample(Vec2::new(0.5, 0.5), &texels);
        assert!((mid - Vec3::new(0.5, 0.0, 0.5)).length() < 1e-6, "{mid}");
    }
}
