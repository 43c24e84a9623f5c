//! Camera rays of neighbouring pixels traced as one packet through the whole scene:
//! the instance BVH and each mesh's BVH are traversed once per packet
//! ([`crate::accel::WideBvh::traverse_packet`]), analytic shapes ray by ray.

use super::{Hit, RenderScene};
use crate::accel::lanes::Portable;
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
        assert!(rays.len() <= PACKET && hits.len() >= rays.len(), "at most {PACKET} rays, one hit slot each");
        if rays.is_empty() {
            return;
        }
        let all = (1u32 << rays.len()) - 1;
        let mut t_max = [f32::INFINITY; PACKET];
        let mut closest: Closest = [None; PACKET];
        self.bvh.traverse_packet::<Portable, _>(&self.instances, rays, all, &mut t_max, |index, in_leaf, t_max| {
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
