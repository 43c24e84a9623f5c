//! The point lights as the eight hits of a wave see them, worked out side by side.
//!
//! Shading hits one after another, each light's direction waits on a square root and a
//! division, and the next hit's cannot start until the long shading code between them
//! has gone through: the chains run one at a time. Worked out for the whole wave first,
//! in lanes, the eight chains run together. (Measured on the Whitted scene of
//! `bench/povray_whitted.sh`: 2.4% more instructions, misses computed too, and 8–13%
//! less time at 1600×1200 on two threads.)

// Lane loops index several arrays by the same lane: written so, they vectorize.
#![allow(clippy::needless_range_loop)]

use glam::Vec3;

use crate::light::{Incidence, Light, LightKind};
use crate::scene::{RayWave, RenderScene, WAVE, WaveHits};

/// How many of the scene's first lights a wave works out in lanes; the rest are
/// sampled hit by hit.
const LANE_LIGHTS: usize = 4;

/// The scene's first point lights (up to [`LANE_LIGHTS`], up to the first light of
/// another kind) as each lane's hit sees them.
pub(super) struct LaneIncidence {
    /// How many of the scene's first lights are here.
    count: usize,
    /// `to_light[light][axis][lane]`: unit direction from the hit to the light.
    to_light: [[[f32; WAVE]; 3]; LANE_LIGHTS],
    distance: [[f32; WAVE]; LANE_LIGHTS],
    /// `f_att` at that distance.
    f_att: [[f32; WAVE]; LANE_LIGHTS],
}

impl LaneIncidence {
    /// The lights as the hits `hits` of the wave `rays` see them, at `o + t·d` (which
    /// differs from the hit record's point in the last bits at most). Lanes that hit
    /// nothing hold values no one reads.
    #[inline(always)]
    pub(super) fn of(scene: &RenderScene, rays: &RayWave, hits: &WaveHits) -> LaneIncidence {
        let mut lit = LaneIncidence {
            count: 0,
            to_light: [[[0.0; WAVE]; 3]; LANE_LIGHTS],
            distance: [[0.0; WAVE]; LANE_LIGHTS],
            f_att: [[0.0; WAVE]; LANE_LIGHTS],
        };
        let mut point = [[0.0f32; WAVE]; 3];
        for lane in 0..WAVE {
            for axis in 0..3 {
                point[axis][lane] = rays.origin[axis][lane] + hits.t[lane] * rays.dir[axis][lane];
            }
        }
        for (k, light) in scene.lights.iter().take(LANE_LIGHTS).enumerate() {
            if light.kind != LightKind::Point {
                break;
            }
            lit.count = k + 1;
            let [c1, c2, c3] = light.attenuation.to_array();
            // As `Light::incidence` computes them, lane by lane.
            for lane in 0..WAVE {
                let offset: [f32; 3] = std::array::from_fn(|axis| light.position[axis] - point[axis][lane]);
                let distance = (offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]).sqrt();
                let reciprocal = 1.0 / distance;
                for axis in 0..3 {
                    lit.to_light[k][axis][lane] = offset[axis] * reciprocal;
                }
                lit.distance[k][lane] = distance;
                lit.f_att[k][lane] = (1.0 / (c1 + c2 * distance + c3 * distance * distance)).min(1.0);
            }
        }
        lit
    }

    /// Light `index` (of the scene's) as lane `lane`'s hit sees it, if it is worked out
    /// here: what [`Light::sample`] gives for a point light, to rounding.
    #[inline(always)]
    pub(super) fn get(&self, index: usize, light: &Light, lane: usize) -> Option<Incidence> {
        if index >= self.count {
            return None;
        }
        let to_light = Vec3::from(std::array::from_fn(|axis| self.to_light[index][axis][lane]));
        Some(Incidence {
            to_light,
            distance: self.distance[index][lane],
            radiance: self.f_att[index][lane] * light.color,
        })
    }
}
