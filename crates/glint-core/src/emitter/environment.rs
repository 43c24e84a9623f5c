//! Light from infinitely far away: a constant radiance or an equirectangular map,
//! importance-sampled by a piecewise-constant distribution over its texels.

use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

use super::luminance;
use crate::sampling::Distribution2D;

/// The scene's environment light.
///
/// Directions map to the map as Mitsuba's `envmap` does, in the map's own frame
/// (`env_from_world`): `u = atan2(x, −z)/2π` (mod 1), `v = acos(y)/π`. Texels are the
/// values at lattice points — column `i` at `u = (i + ½)/W` (wrapping), row `j` at
/// `v = j/(H−1)` — interpolated bilinearly between them, exactly as Mitsuba 3.9 does.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// Radiance scale (the whole radiance when there is no map).
    pub scale: Vec3,
    /// Map texels in linear RGB, row 0 the top (+y); empty for a constant environment.
    pub texels: Vec<Vec3>,
    pub width: usize,
    pub height: usize,
    pub env_from_world: Mat3,
    pub world_from_env: Mat3,
    /// Over the lattice cells `[(i+½)/W, (i+1½)/W] × [j/(H−1), (j+1)/(H−1)]`, weighted
    /// by the brightest of each cell's corners times sin θ.
    distribution: Option<Distribution2D>,
    /// Mean luminance over the sphere, for choosing this light among the others.
    mean_luminance: f32,
}

impl Environment {
    /// A constant environment of radiance `scale` (`texels` empty) or a map. `rotation`
    /// takes the map's frame to the world.
    pub fn new(scale: Vec3, texels: Vec<Vec3>, width: usize, height: usize, rotation: Mat3) -> Self {
        let mut env = Self {
            scale,
            texels,
            width,
            height,
            env_from_world: rotation.transpose(),
            world_from_env: rotation,
            distribution: None,
            mean_luminance: luminance(scale),
        };
        if env.has_map() {
            env.build_distribution();
        }
        env
    }

    fn has_map(&self) -> bool {
        self.width >= 1 && self.height >= 2 && self.texels.len() == self.width * self.height
    }

    fn texel(&self, i: usize, j: usize) -> Vec3 {
        self.texels[j * self.width + i % self.width]
    }

    fn build_distribution(&mut self) {
        let (w, rows) = (self.width, self.height - 1);
        let mut weights = Vec::with_capacity(w * rows);
        let mut total = 0.0f64;
        for j in 0..rows {
            let sin_theta = (PI * (j as f32 + 0.5) / rows as f32).sin();
            for i in 0..w {
                let corners = [self.texel(i, j), self.texel(i + 1, j), self.texel(i, j + 1), self.texel(i + 1, j + 1)];
                let brightest = corners.iter().map(|c| luminance(*c).max(0.0)).fold(0.0, f32::max);
                let mean = corners.iter().map(|c| luminance(*c).max(0.0)).sum::<f32>() / 4.0;
                total += (mean * sin_theta) as f64;
                // A floor keeps every direction samplable (no bias where a texel is 0).
                weights.push((brightest + 1e-3) * sin_theta);
            }
        }
        let solid_angle_weight: f64 =
            (0..rows).map(|j| (PI * (j as f32 + 0.5) / rows as f32).sin() as f64).sum::<f64>() * w as f64;
        self.mean_luminance = luminance(self.scale) * (total / solid_angle_weight) as f32;
        self.distribution = Distribution2D::new(&weights, w, rows);
    }

    /// Mean radiance (luminance) over all directions.
    /// The texel distribution importance sampling draws from (`None` for a constant
    /// environment), for backends that sample it themselves.
    pub fn distribution(&self) -> Option<&Distribution2D> {
        self.distribution.as_ref()
    }

    pub fn power(&self) -> f32 {
        self.mean_luminance * 4.0 * PI
    }

    /// The map coordinates of world direction `d`.
    pub(crate) fn uv(&self, d: Vec3) -> Vec2 {
        let v = self.env_from_world * d.normalize();
        let u = v.x.atan2(-v.z) / (2.0 * PI);
        Vec2::new(u - u.floor(), v.y.clamp(-1.0, 1.0).acos() / PI)
    }

    /// The world direction of map coordinates `uv`.
    pub(crate) fn direction(&self, uv: Vec2) -> Vec3 {
        let (phi, theta) = (2.0 * PI * uv.x, PI * uv.y);
        let (s, c) = theta.sin_cos();
        // Inverse of uv(): x = sin θ sin φ, y = cos θ, z = −sin θ cos φ.
        self.world_from_env * Vec3::new(s * phi.sin(), c, -s * phi.cos())
    }

    /// Radiance arriving from world direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        if !self.has_map() {
            return self.scale;
        }
        let uv = self.uv(d);
        let x = (uv.x * self.width as f32 - 0.5).rem_euclid(self.width as f32);
        let y = uv.y * (self.height - 1) as f32;
        let (i, j) = (x.floor().min((self.width - 1) as f32), y.floor().min((self.height - 2) as f32));
        let (fx, fy) = (x - i, y - j);
        let (i, j) = (i as usize, j as usize);
        let top = self.texel(i, j).lerp(self.texel(i + 1, j), fx);
        let bottom = self.texel(i, j + 1).lerp(self.texel(i + 1, j + 1), fx);
        self.scale * top.lerp(bottom, fy)
    }

    /// A direction toward the environment, its radiance and solid-angle density.
    pub fn sample(&self, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
        let Some(dist) = &self.distribution else {
            // Uniform over the sphere.
            let z = 1.0 - 2.0 * u.x;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            let d = Vec3::new(s * phi.cos(), s * phi.sin(), z);
            return Some((d, self.scale, 1.0 / (4.0 * PI)));
        };
        let (cell, _) = dist.sample(u);
        let d = self.direction(Vec2::new(cell.x + self.half_texel(), cell.y));
        // The density of the direction as `pdf` computes it, so that both strategies of
        // MIS agree exactly (the pole loses precision in the round trip).
        let pdf = self.pdf(d);
        (pdf > 0.0).then(|| (d, self.radiance(d), pdf))
    }

    /// The solid-angle density of [`Environment::sample`] choosing `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let Some(dist) = &self.distribution else { return 1.0 / (4.0 * PI) };
        let uv = self.uv(d);
        let sin_theta = (PI * uv.y).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let cell = Vec2::new((uv.x - self.half_texel()).rem_euclid(1.0), uv.y);
        dist.density(cell) / (2.0 * PI * PI * sin_theta)
    }

    /// Texel centres sit half a texel right of the cell lattice's origin.
    fn half_texel(&self) -> f32 {
        0.5 / self.width as f32
    }
}
