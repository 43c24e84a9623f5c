//! What the window shows, as 0x00RRGGBB pixels: the image in sRGB, the explained ray
//! tree drawn over it, and the HUD and error text in an 8×8 bitmap font (font8x8's
//! public-domain Basic Latin glyphs: no font files, no text shaping).

use font8x8::legacy::BASIC_LEGACY;
use glam::{Vec2, Vec3};
use glint_core::camera::Camera;
use glint_core::film::{Image, Transfer};
use glint_core::integrator::observe::RayKind;

use crate::viewer::{Explained, ViewMode, Viewer};

/// Glyph cell size in pixels.
const GLYPH: i32 = 8;
/// How far a ray that meets nothing is drawn, in multiples of the camera's distance.
const MISS_LENGTH: f32 = 4.0;

/// A canvas of 0x00RRGGBB pixels, the layout an X11 window of depth 24 takes.
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u32>,
}

impl Canvas {
    /// The image encoded as `transfer` says (sRGB for linear light).
    pub fn from_image(image: &Image, transfer: Transfer) -> Self {
        let bytes = image.encode8(transfer);
        let pixels = bytes.chunks_exact(3).map(|c| rgb(c[0], c[1], c[2])).collect();
        Self { width: image.width, height: image.height, pixels }
    }

    fn put(&mut self, x: i32, y: i32, colour: u32) {
        if x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height {
            self.pixels[(y as u32 * self.width + x as u32) as usize] = colour;
        }
    }

    /// Darkens a rectangle so text over a bright image stays readable.
    fn shade(&mut self, x: i32, y: i32, width: i32, height: i32) {
        for py in y.max(0)..(y + height).min(self.height as i32) {
            for px in x.max(0)..(x + width).min(self.width as i32) {
                let p = &mut self.pixels[(py as u32 * self.width + px as u32) as usize];
                *p = (*p >> 2) & 0x003f_3f3f;
            }
        }
    }

    /// Writes `text` with its top-left corner at (x, y) on a darkened band.
    pub fn text(&mut self, x: i32, y: i32, text: &str, colour: u32) {
        self.shade(x - 2, y - 2, text.chars().count() as i32 * GLYPH + 4, GLYPH + 4);
        for (i, c) in text.chars().enumerate() {
            let glyph = BASIC_LEGACY.get(c as usize).copied().unwrap_or(BASIC_LEGACY[b'?' as usize]);
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..GLYPH {
                    if bits >> col & 1 == 1 {
                        self.put(x + i as i32 * GLYPH + col, y + row as i32, colour);
                    }
                }
            }
        }
    }

    /// A straight line (Bresenham's), clipped pixel by pixel.
    pub fn line(&mut self, from: Vec2, to: Vec2, colour: u32) {
        let (mut x, mut y) = (from.x as i32, from.y as i32);
        let (x1, y1) = (to.x as i32, to.y as i32);
        let (dx, dy) = ((x1 - x).abs(), -(y1 - y).abs());
        let (sx, sy) = ((x1 - x).signum(), (y1 - y).signum());
        let mut error = dx + dy;
        for _ in 0..=(dx - dy).min(1 << 14) {
            self.put(x, y, colour);
            if x == x1 && y == y1 {
                break;
            }
            let e2 = 2 * error;
            if e2 >= dy {
                error += dy;
                x += sx;
            }
            if e2 <= dx {
                error += dx;
                y += sy;
            }
        }
    }
}

/// 0x00RRGGBB from bytes.
pub fn rgb(r: u8, g: u8, b: u8) -> u32 {
    (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b)
}

const WHITE: u32 = 0x00ff_ffff;
const RED: u32 = 0x00ff_5050;

/// The viewer's picture with the explained rays, the HUD and any error drawn on it.
pub fn compose(viewer: &Viewer) -> Canvas {
    let transfer = match viewer.view() {
        ViewMode::Beauty => viewer.desc().settings.output_transfer,
        // Debug views are display values already.
        ViewMode::Debug(_) => Transfer::Identity,
    };
    let mut canvas = Canvas::from_image(viewer.image(), transfer);
    if let Some(explained) = viewer.explained() {
        draw_rays(&mut canvas, explained, viewer.camera().distance());
    }
    if viewer.toggles().hud {
        for (row, line) in hud_lines(viewer).iter().enumerate() {
            canvas.text(4, 4 + row as i32 * (GLYPH + 4), line, WHITE);
        }
    }
    if let Some(error) = viewer.error() {
        let bottom = canvas.height as i32 - 4 - GLYPH;
        let lines: Vec<&str> = error.lines().collect();
        for (row, line) in lines.iter().rev().enumerate() {
            canvas.text(4, bottom - row as i32 * (GLYPH + 4), line, RED);
        }
    }
    canvas
}

/// The HUD: samples, timing, speed, switches, view, and the latest status note.
pub fn hud_lines(viewer: &Viewer) -> Vec<String> {
    let timing = viewer.timing();
    let t = viewer.toggles();
    let on = |b: bool| if b { "on" } else { "off" };
    let view = match viewer.view() {
        ViewMode::Beauty => "beauty".to_string(),
        ViewMode::Debug(d) => format!("{d:?}").to_lowercase(),
    };
    let (width, height) = viewer.size();
    let mut lines = vec![
        format!(
            "{} spp  {:.1} ms/pass  {}  {width}x{height}",
            viewer.passes(),
            timing.last_pass.as_secs_f64() * 1e3,
            if timing.on_gpu { "GPU".to_string() } else { format!("{:.2} Mrays/s", timing.rays_per_second / 1e6) }
        ),
        format!(
            "{} | shadows {} refl {} refr {} aa {} | depth {} | {view}",
            if t.path { "path" } else { "whitted" },
            on(t.shadows),
            on(t.reflections),
            on(t.refractions),
            on(t.anti_aliasing),
            t.max_depth
        ),
    ];
    lines.extend(viewer.status().map(str::to_string));
    lines
}

/// Each ray of the explained tree from its origin to its hit (or a stretch into the
/// distance when it misses), and each shadow ray, projected with the camera that
/// traced them.
fn draw_rays(canvas: &mut Canvas, explained: &Explained, reach: f32) {
    let size = Vec2::new(canvas.width as f32, canvas.height as f32);
    let project = |p: Vec3| project(&explained.camera, p, size);
    for ray in &explained.tree.rays {
        let end = ray.hit.map_or(ray.origin + ray.dir * reach * MISS_LENGTH, |h| h.point);
        let colour = match ray.kind {
            RayKind::Camera => WHITE,
            RayKind::Reflected => 0x0040_e0ff,
            RayKind::Refracted | RayKind::TotalInternalReflection => 0x00ff_60ff,
        };
        segment(canvas, project, ray.origin, end, colour);
        for shadow in &ray.shadow_rays {
            let lit = shadow.filter != Vec3::ZERO;
            let end = shadow.origin + shadow.dir * shadow.distance.min(reach * MISS_LENGTH);
            segment(canvas, project, shadow.origin, end, if lit { 0x00ff_e040 } else { 0x0070_7070 });
        }
    }
    let (x, y) = (explained.x as i32, explained.y as i32);
    for d in -3..=3 {
        canvas.put(x + d, y, RED);
        canvas.put(x, y + d, RED);
    }
}

/// Draws the part of segment a→b in front of the eye.
fn segment(canvas: &mut Canvas, project: impl Fn(Vec3) -> Option<Vec2>, a: Vec3, b: Vec3, colour: u32) {
    // The camera ray starts at the eye itself, which projects nowhere: start a hair along.
    let a = a.lerp(b, 1e-3);
    if let (Some(pa), Some(pb)) = (project(a), project(b)) {
        canvas.line(pa, pb, colour);
    }
}

/// Where world point `p` lands on a film of `size` pixels (y down), if it is in front
/// of the camera: the inverse of the camera's `world_from_canonical`, then the
/// perspective divide onto the plane z = −1.
pub fn project(camera: &Camera, p: Vec3, size: Vec2) -> Option<Vec2> {
    let q = camera.world_from_canonical.inverse().transform_point3(p);
    if q.z >= -1e-6 {
        return None;
    }
    let film = Vec2::new(q.x, q.y) / -q.z;
    let pixel = Vec2::new((film.x + 1.0) * 0.5 * size.x, (1.0 - film.y) * 0.5 * size.y);
    // Far off-screen points would make the line loop long; clamp them to a margin.
    Some(pixel.clamp(-size * 4.0, size * 5.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glint_core::desc::CameraDesc;

    #[test]
    fn a_point_on_the_centre_ray_projects_to_the_centre_of_the_film() {
        let camera = Camera::new(&CameraDesc::default(), 2.0).unwrap();
        let ray = camera.ray(0.5, -0.25, Vec2::splat(0.5));
        let p = project(&camera, ray.at(7.0), Vec2::new(200.0, 100.0)).unwrap();
        assert!(p.distance(Vec2::new(150.0, 62.5)) < 1e-2, "{p}");
        assert!(project(&camera, camera.eye - camera.forward, Vec2::ONE).is_none());
    }

    #[test]
    fn text_sets_pixels_inside_its_cells_only() {
        let mut canvas = Canvas { width: 40, height: 12, pixels: vec![0x00ff_ffff; 480] };
        canvas.text(2, 2, "A", 0x0000_ff00);
        let mut green = canvas.pixels.iter().enumerate().filter(|&(_, &p)| p == 0x0000_ff00);
        assert!(green.clone().count() > 10);
        assert!(green.all(|(i, _)| (2..10).contains(&(i % 40)) && (2..10).contains(&(i / 40))));
    }
}
