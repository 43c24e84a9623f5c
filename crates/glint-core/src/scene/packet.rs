//! Camera rays of neighbouring pixels traced as one packet through the whole scene:
//! the instance BVH and each mesh's BVH are traversed once per packet
//! ([`crate::accel::WideBvh::traverse_packet`], on AVX2 where the CPU has it), analytic
//! shapes ray by ray.

use super::{Hit, RenderScene};
use crate::accel::lanes::{Lanes, Portable};
use crate::accel::{PACKET, bits};
use crate::math::Ray;
use crate::shape::{ShapeHit, ShapeKind};

/// Per ray: the instance and hit closest so far.
type Closest = [Option<(u32, ShapeHit)>; PACKET];

impl RenderScene {
    /// [`RenderScene::intersect`] for up to [`PACKET`] rays at once (`hits[i]` for
    /// `rays[i]`, closest hits with `0 < t`): the same hits, with less traversal work
    /// when the rays are coherent. Which of two surfaces at exactly the same distance
    /// is reported may differ, as it may between any two traversal orders.
    pub fn intersect_packet(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.intersect_packet_avx2(avx, rays, hits),
            self.intersect_packet_on(Portable, rays, hits)
        )
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn intersect_packet_avx2(&self, avx: crate::accel::lanes::Avx2, rays: &[Ray], hits: &mut [Option<Hit>]) {
        self.intersect_packet_on(avx, rays, hits);
    }

    /// [`RenderScene::intersect_packet`] with the instance BVH traversed on the lanes `L`.
    #[inline(always)]
    fn intersect_packet_on<L: Lanes>(&self, lanes: L, rays: &[Ray], hits: &mut [Option<Hit>]) {
        assert!(rays.len() <= PACKET && hits.len() >= rays.len(), "at most {PACKET} rays, one hit slot each");
        if rays.is_empty() {
            return;
        }
        let all = (1u32 << rays.len()) - 1;
        let mut t_max = [f32::INFINITY; PACKET];
        let mut closest: Closest = [None; PACKET];
        self.bvh.traverse_packet(lanes, &self.instances, rays, all, &mut t_max, |index, in_leaf, t_max| {
            self.intersect_instance(index, rays, in_leaf, t_max, &mut closest);
            0
        });
        for index in self.bounded_count..self.instances.len() {
            self.intersect_instance(index as u32, rays, all, &mut t_max, &mut closest);
        }
        for (r, ray) in rays.iter().enumerate() {
            hits[r] = closest[r].map(|(index, hit)| self.hit_from(ray, index, hit));
        }
    }

    /// Tests the rays of mask `active` against instance `index`, recording closer hits.
    fn intersect_instance(
        &self,
        index: u32,
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        closest: &mut Closest,
    ) {
        let inst = &self.instances[index as usize];
        let local = |ray: &Ray| self.transform_at(inst, ray.time).ray_to_object(ray);
        if inst.shape.kind == ShapeKind::Mesh {
            let mut local_rays = [rays[0]; PACKET];
            for r in bits(active) {
                local_rays[r] = local(&rays[r]);
            }
            let mut found = [None; PACKET];
            let mesh = &self.meshes[inst.shape.mesh_index() as usize];
            mesh.intersect_packet(&local_rays[..rays.len()], active, t_max, &mut found);
            for r in bits(active) {
                if let Some(hit) = found[r] {
                    closest[r] = Some((index, hit));
                }
            }
            return;
        }
        for r in bits(active) {
            if let Some(hit) = self.intersect_shape(inst, &local(&rays[r]), t_max[r]) {
                t_max[r] = hit.t;
                closest[r] = Some((index, hit));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::desc::{MaterialDesc, MeshDesc, NodeDesc, NodeKind, SceneDesc, ShapeDesc, TransformOp};

    /// The portable lanes and the dispatched ones (AVX2 where the CPU has it) find the
    /// same hits and occlusion, single rays and packets, over a grid of spheres, cubes
    /// and mesh instances.
    #[test]
    fn portable_and_dispatched_paths_agree() {
        let tetrahedron = MeshDesc {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
            ..Default::default()
        };
        let shapes = [ShapeDesc::Sphere, ShapeDesc::Cube, ShapeDesc::Mesh { index: 0 }];
        let objects = (0..300)
            .map(|i| NodeDesc {
                transform: vec![
                    TransformOp::Scale(Vec3::splat(0.3)),
                    TransformOp::Translate(Vec3::new((i % 10) as f32, (i / 10 % 10) as f32, -((i / 100) as f32))),
                ],
                kind: NodeKind::Shape { shape: shapes[i % 3], material: 0 },
                origin: String::new(),
            })
            .collect();
        let desc = SceneDesc {
            meshes: vec![tetrahedron],
            materials: vec![MaterialDesc::default()],
            objects,
            ..Default::default()
        };
        let scene = crate::scene::compile(&desc).expect("valid scene");
        // Without AVX2 the dispatched path is the portable one: comparing them would
        // compare a path with itself.
        let avx2 = crate::accel::lanes::avx2_or_skip("scene::packet::portable_and_dispatched_paths_agree");
        let key = |h: Option<Hit>| h.map(|h| (h.t, h.point, h.material));
        let mut hit = 0;
        for row in 0..40 {
            let rays: Vec<Ray> = (0..8)
                .map(|k| {
                    let target = Vec3::new(row as f32 * 0.25 - 0.5, k as f32 * 1.3 - 0.5, -1.0);
                    Ray::new(Vec3::new(4.5, 4.5, 8.0), target - Vec3::new(4.5, 4.5, 8.0))
                })
                .collect();
            let mut dispatched = [None; PACKET];
            let mut portable = [None; PACKET];
            scene.intersect_packet(&rays, &mut dispatched);
            scene.intersect_packet_on(Portable, &rays, &mut portable);
            for (r, ray) in rays.iter().enumerate() {
                let single = scene.intersect(ray, f32::INFINITY);
                // Packets against single rays, on each path.
                assert_eq!(key(single), key(dispatched[r]));
                assert_eq!(key(scene.intersect_on(Portable, ray, f32::INFINITY)), key(portable[r]));
                if avx2 {
                    assert_eq!(key(single), key(scene.intersect_on(Portable, ray, f32::INFINITY)));
                    assert_eq!(scene.occluded(ray, 100.0), scene.occluded_on(Portable, ray, 100.0));
                }
                assert_eq!(single.is_some_and(|h| h.t < 100.0), scene.occluded(ray, 100.0));
                hit += usize::from(single.is_some());
            }
        }
        assert!((60..300).contains(&hit), "{hit} of 320 rays hit: the test should see hits and misses");
    }
}
