//! Triangle meshes: flat vertex and index arrays with their own bottom-level BVH.
//!
//! A mesh is stored once in [`crate::scene::RenderScene::meshes`] and placed any number
//! of times by instances whose [`crate::shape::Shape`] names its index (two-level
//! instancing: the top-level BVH is over instances, each mesh has its own BVH over
//! triangles in object space). Everything is plain arrays so a GPU backend can upload
//! them as they are: `WideNode` and `Triangle4` are `Pod`, indices are `[u32; 3]`,
//! vertices `Vec3`.

pub mod triangle;
pub mod triangle4;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::accel::lanes::{Lanes, Portable};
use crate::accel::{Bvh, Order, PACKET, WIDTH, WideBvh, bits, one_octant};
use crate::desc::MeshDesc;
use crate::math::{Aabb, Ray};
use crate::shape::{ShapeHit, SurfacePoint};
pub use triangle::{TriangleHit, WatertightRay};
pub use triangle4::{Triangle4, WatertightRay4};

/// A compiled mesh. `triangles` are in the order the BVH leaves expect.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals, or empty (flat shading with the geometric normal).
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates, or empty (the barycentric `(b1, b2)` are used).
    pub uvs: Vec<Vec2>,
    /// Per-vertex colours in linear RGB, or empty (white): they tint the material.
    pub colors: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Built with the binary SAH builder (a leaf costs one test per four triangles), then
    /// collapsed to eight children per node. Its leaves index [`Mesh::packets`]: a
    /// leaf's `child` is its first packet and `count` the number of packets.
    pub bvh: WideBvh,
    /// Triangles dropped at compile time because they have no area.
    pub degenerate: usize,
    /// The corners of each leaf's triangles again, four to a packet, so the traversal
    /// tests four at once without going through the index (Embree's `Triangle4`).
    pub packets: Vec<Triangle4>,
}

/// Surface data at a mesh hit, in object space, none of it normalized.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshSurface {
    /// The point, the shading normal (interpolated, pointing outside) and uv.
    pub surface: SurfacePoint,
    /// The interpolated vertex colour (white without vertex colours).
    pub color: Vec3,
    /// The triangle's plane normal, on the side of the shading normal.
    pub geometric: Vec3,
    /// Where shadow rays toward lights outside should start (see [`terminator_point`]).
    pub shadow_point: Vec3,
}

/// The hit point lifted onto the curved surface the vertex normals describe, for
/// shadow rays: Hanika, "Hacking the Shadow Terminator" (Ray Tracing Gems II, ch. 4).
///
/// Each vertex's tangent plane is a guess of the true surface; where `P` lies below
/// one, it is moved up onto it, and the moves are blended with the barycentrics:
/// `P' = P + Σ bᵢ·max(0, −(P − vᵢ)·nᵢ)·nᵢ`. A flat-shaded coarse mesh then no longer
/// shadows itself in jagged triangles near the terminator.
fn terminator_point(p: Vec3, bary: Vec3, v: [Vec3; 3], n: [Vec3; 3]) -> Vec3 {
    let mut out = p;
    for (k, (v, n)) in v.into_iter().zip(n).enumerate() {
        let n = n.normalize_or_zero();
        out += bary[k] * (-(p - v).dot(n)).max(0.0) * n;
    }
    out
}

/// Whether the corners are not collinear: the edges' cross product, in f64, is not
/// zero (exactly so: the edges and products of f32 corners are exact in f64, so only
/// equal products cancel). In f32 the product underflows, and its squared length much
/// sooner, for triangles that rays still hit: edges under about 1e-11.
fn has_area(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let [a, b, c] = [a, b, c].map(|p| p.as_dvec3());
    (b - a).cross(c - a) != glam::DVec3::ZERO
}

/// Why a [`MeshDesc`] cannot be compiled.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MeshError {
    #[error("index count {0} is not a multiple of 3")]
    Ragged(usize),
    #[error("triangle {triangle} uses vertex {index}, but there are only {count} vertices")]
    IndexOutOfRange { triangle: usize, index: u32, count: usize },
    #[error("vertex {0} has a coordinate that is not a finite number")]
    NonFinite(usize),
    #[error("{what} has {found} entries, but there are {count} vertices (it must be empty or match)")]
    AttributeCount { what: &'static str, found: usize, count: usize },
    #[error("more than 2^32 - 1 vertices")]
    TooLarge,
}

impl Mesh {
    /// Validates `desc` and builds the BVH; zero-area triangles are dropped (counted in
    /// [`Mesh::degenerate`]) since no ray can hit them.
    pub fn compile(desc: &MeshDesc) -> Result<Mesh, MeshError> {
        let count = desc.positions.len();
        if count >= u32::MAX as usize {
            return Err(MeshError::TooLarge);
        }
        if !desc.indices.len().is_multiple_of(3) {
            return Err(MeshError::Ragged(desc.indices.len()));
        }
        if !all_finite(&desc.positions)
            && let Some(i) = desc.positions.par_iter().position_first(|p| !p.is_finite())
        {
            return Err(MeshError::NonFinite(i));
        }
        let attributes = [
            ("the normal list", desc.normals.len()),
            ("the uv list", desc.uvs.len()),
            ("the colour list", desc.colors.len()),
        ];
        for (what, found) in attributes {
            if found != 0 && found != count {
                return Err(MeshError::AttributeCount { what, found, count });
            }
        }
        let out_of_range = || {
            desc.indices.par_chunks_exact(3).enumerate().find_map_first(|(triangle, tri)| {
                tri.iter().find(|&&i| i as usize >= count).map(|&index| (triangle, index))
            })
        };
        if largest_index(&desc.indices).is_some_and(|i| i as usize >= count)
            && let Some((triangle, index)) = out_of_range()
        {
            return Err(MeshError::IndexOutOfRange { triangle, index, count });
        }
        // Kept in their order: the parallel filter collects as the serial one would.
        let triangles: Vec<[u32; 3]> = desc
            .indices
            .par_chunks_exact(3)
            .map(|tri| [tri[0], tri[1], tri[2]])
            .filter(|tri| {
                let [a, b, c] = tri.map(|i| desc.positions[i as usize]);
                has_area(a, b, c)
            })
            .collect();
        let degenerate = desc.indices.len() / 3 - triangles.len();
        // Non-finite or zero normals would poison shading; fall back to flat shading.
        let keep_normals = desc.normals.par_iter().all(|n| n.is_finite() && n.length_squared() > 0.0);
        let keep_uvs = desc.uvs.par_iter().all(|uv| uv.is_finite());
        // Negative or non-finite colours are no colours at all: the material shows plain.
        let keep_colors = desc.colors.par_iter().all(|c| c.is_finite() && c.min_element() >= 0.0);
        // The vertex arrays are filled from `desc` once, in their final order, by
        // `renumber_vertices`.
        let mut mesh = Mesh {
            positions: Vec::new(),
            normals: Vec::new(),
            uvs: Vec::new(),
            colors: Vec::new(),
            triangles,
            bvh: WideBvh::default(),
            degenerate,
            packets: vec![],
        };
        let bounds =
            |i: usize| mesh.triangles[i].map(|v| desc.positions[v as usize]).into_iter().fold(Aabb::EMPTY, Aabb::grow);
        let (bvh, order) = Bvh::build_blocks_with(mesh.triangles.len(), 4, bounds);
        // The collapse needs only the tree; the triangles' and vertices' new order only
        // the leaf order. One runs beside the other (renumbering is serial).
        let (wide, ()) = rayon::join(
            || WideBvh::from_binary(&bvh),
            || {
                mesh.triangles = order.par_iter().map(|&i| mesh.triangles[i as usize]).collect();
                mesh.renumber_vertices(desc, [keep_normals, keep_uvs, keep_colors]);
            },
        );
        mesh.bvh = wide;
        mesh.pack_leaves();
        Ok(mesh)
    }

    /// Packs each leaf's triangles four at a time into [`Mesh::packets`] and points the
    /// leaf at its packets instead of its triangles.
    fn pack_leaves(&mut self) {
        // Each packet's first triangle and how many it holds, in leaf order.
        let mut packs: Vec<(u32, u32)> = Vec::with_capacity(self.triangles.len() / 2);
        for node in &mut self.bvh.nodes {
            for lane in 0..WIDTH {
                let count = node.count[lane];
                if count == 0 || count == crate::accel::EMPTY {
                    continue;
                }
                let first = node.child[lane];
                node.child[lane] = packs.len() as u32;
                packs.extend((first..first + count).step_by(4).map(|start| (start, (first + count - start).min(4))));
                node.count[lane] = packs.len() as u32 - node.child[lane];
            }
        }
        // Filled in place, in parallel: the vector has its room on huge pages already.
        let mut packets = crate::accel::with_capacity_on_huge_pages(packs.len());
        packets.par_extend(packs.par_iter().map(|&(first, n)| {
            let corners: [[Vec3; 3]; 4] =
                std::array::from_fn(|k| self.vertices((first + (k as u32).min(n - 1)) as usize));
            Triangle4::new(&corners[..n as usize], first)
        }));
        self.packets = packets;
    }

    /// Stores the vertices of `source` in the order the (BVH-ordered) triangles first use
    /// them, so that triangles near each other in space read vertices near each other in
    /// memory; vertices no triangle uses are dropped. `keep` says which of the normals,
    /// uvs and colours of `source` passed validation.
    fn renumber_vertices(&mut self, source: &MeshDesc, [normals, uvs, colors]: [bool; 3]) {
        let mut new_index = vec![u32::MAX; source.positions.len()];
        let mut old_of_new = Vec::with_capacity(source.positions.len());
        for tri in &mut self.triangles {
            for i in tri.iter_mut() {
                let slot = &mut new_index[*i as usize];
                if *slot == u32::MAX {
                    *slot = old_of_new.len() as u32;
                    old_of_new.push(*i);
                }
                *i = *slot;
            }
        }
        fn gather<T: Copy + Send + Sync>(order: &[u32], values: &[T], keep: bool) -> Vec<T> {
            if !keep || values.is_empty() {
                return Vec::new();
            }
            order.par_iter().map(|&i| values[i as usize]).collect()
        }
        self.positions = gather(&old_of_new, &source.positions, true);
        self.normals = gather(&old_of_new, &source.normals, normals);
        self.uvs = gather(&old_of_new, &source.uvs, uvs);
        self.colors = gather(&old_of_new, &source.colors, colors);
    }

    #[inline]
    fn vertices(&self, triangle: usize) -> [Vec3; 3] {
        self.triangles[triangle].map(|i| self.positions[i as usize])
    }

    /// Object-space bounds of every triangle.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The closest hit in `(0, t_max)`; `part` is the triangle index.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.intersect_avx2(avx, ray, t_max),
            self.intersect_on(Portable, ray, t_max)
        )
    }

    /// How many packets of four triangles the closest-hit query for `ray` tests: the
    /// work it takes, for a traversal-cost view (portable lanes, not timed).
    pub fn packets_tested(&self, ray: &Ray, t_max: f32) -> u32 {
        let Some(wray) = WatertightRay::new(ray).map(WatertightRay4::new) else { return 0 };
        let mut tested = 0;
        self.bvh.traverse(ray, &mut { t_max }, |packet, t_max| {
            tested += 1;
            if let Some((t, _)) = triangle4::intersect(&wray, &self.packets[packet as usize], *t_max) {
                *t_max = t;
            }
            false
        });
        tested
    }

    /// Whether any triangle is hit in `(0, t_max)`; stops at the first.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.occluded_avx2(avx, ray, t_max),
            self.occluded_on(Portable, ray, t_max)
        )
    }

    /// [`Mesh::intersect`] for up to [`PACKET`] coherent rays (neighbouring camera
    /// rays) at once, the rays of mask `active`: where `rays[i]` hits closer than
    /// `t_max[i]`, `t_max[i]` becomes the hit's distance and `hits[i]` the hit — the
    /// closest one, as the single-ray query finds it (of triangles hit at exactly the
    /// same distance, possibly another), with less traversal work per ray.
    /// Other entries are left as they are, so a caller can carry them across meshes.
    pub fn intersect_packet(
        &self,
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        hits: &mut [Option<ShapeHit>; PACKET],
    ) {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.intersect_packet_avx2(avx, rays, active, t_max, hits),
            self.intersect_packet_on(Portable, rays, active, t_max, hits)
        )
    }

    /// [`Mesh::occluded`] for up to [`PACKET`] coherent rays: bit `i` of the result is
    /// set where `rays[i]` is blocked.
    pub fn occluded_packet(&self, rays: &[Ray], t_max: f32) -> u32 {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.occluded_packet_avx2(avx, rays, t_max),
            self.occluded_packet_on(Portable, rays, t_max)
        )
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn intersect_packet_avx2(
        &self,
        avx: crate::accel::lanes::Avx2,
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        hits: &mut [Option<ShapeHit>; PACKET],
    ) {
        self.intersect_packet_on(avx, rays, active, t_max, hits);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn occluded_packet_avx2(&self, avx: crate::accel::lanes::Avx2, rays: &[Ray], t_max: f32) -> u32 {
        self.occluded_packet_on(avx, rays, t_max)
    }

    /// The watertight rays of the packet's rays in `active`, and the mask of those that
    /// have one (the others are left out: a mesh instance gets only the rays that
    /// entered its box, transformed into its space).
    ///
    /// Written into `prepared`, not returned: returned, the 2 KiB array was copied once
    /// per packet (`memcpy`, about a tenth of a random packet's own work).
    #[inline(always)]
    fn packet_rays(rays: &[Ray], active: u32, prepared: &mut [Option<WatertightRay4>; PACKET]) -> u32 {
        let mut valid = 0;
        for r in bits(active & ((1u32 << rays.len().min(PACKET)) - 1)) {
            prepared[r] = WatertightRay::new(&rays[r]).map(WatertightRay4::new);
            valid |= u32::from(prepared[r].is_some()) << r;
        }
        valid
    }

    #[inline(always)]
    fn intersect_packet_on<L: Lanes>(
        &self,
        lanes: L,
        rays: &[Ray],
        active: u32,
        t_max: &mut [f32; PACKET],
        hits: &mut [Option<ShapeHit>; PACKET],
    ) {
        assert!(rays.len() <= PACKET, "at most {PACKET} rays");
        let active = active & ((1u32 << rays.len()) - 1);
        if !one_octant(rays, active) {
            // Rays into different octants part ways at the root and go on alone: as
            // single rays, without the packet's set-up (random rays in packets ran 8%
            // more instructions than alone).
            for r in bits(active) {
                if let Some(hit) = self.intersect_on(lanes, &rays[r], t_max[r]) {
                    (t_max[r], hits[r]) = (hit.t, Some(hit));
                }
            }
            return;
        }
        let mut wrays = [None; PACKET];
        let valid = Self::packet_rays(rays, active, &mut wrays);
        // Both closures write `hits`, one at a time: a cell lends it to each.
        let hits = std::cell::RefCell::new(hits);
        self.bvh.traverse_hybrid(
            lanes,
            Order::NearestFirst,
            &self.packets,
            rays,
            active & valid,
            t_max,
            |packet, in_leaf, t| {
                let packet = &self.packets[packet as usize];
                for r in bits(in_leaf) {
                    if let Some(w) = &wrays[r]
                        && let Some((t_hit, tri)) = triangle4::intersect(w, packet, t[r])
                    {
                        t[r] = t_hit;
                        hits.borrow_mut()[r] = Some(ShapeHit { t: t_hit, part: tri });
                    }
                }
                0
            },
            // The leaf test of `intersect_on`, written again rather than shared: a shared
            // function's closure has two callers and is then called, not inlined, and
            // runs without AVX2 (measured: the packets' instructions moved into it).
            |r, node, t_max| {
                // Only rays with a watertight form are active.
                let Some(w) = &wrays[r] else { return false };
                let (ray, hit) = (&rays[r], &mut hits.borrow_mut()[r]);
                self.bvh.traverse_from(lanes, Order::NearestFirst, &self.packets, ray, node, t_max, |packet, t_max| {
                    if let Some((t, tri)) = triangle4::intersect(w, &self.packets[packet as usize], *t_max) {
                        *t_max = t;
                        *hit = Some(ShapeHit { t, part: tri });
                    }
                    false
                });
                false
            },
        );
    }

    #[inline(always)]
    fn occluded_packet_on<L: Lanes>(&self, lanes: L, rays: &[Ray], t_max: f32) -> u32 {
        assert!(rays.len() <= PACKET, "at most {PACKET} rays");
        let all = (1u32 << rays.len()) - 1;
        if !one_octant(rays, all) {
            // As in `intersect_packet_on`: scattered rays go alone, as single rays.
            return bits(all).fold(0, |m, r| m | u32::from(self.occluded_on(lanes, &rays[r], t_max)) << r);
        }
        let mut wrays = [None; PACKET];
        let active = Self::packet_rays(rays, u32::MAX, &mut wrays);
        let blocked = std::cell::Cell::new(0);
        self.bvh.traverse_hybrid(
            lanes,
            Order::Any,
            &self.packets,
            rays,
            active,
            &mut [t_max; PACKET],
            |packet, in_leaf, t| {
                let packet = &self.packets[packet as usize];
                let now = bits(in_leaf)
                    .filter(|&r| wrays[r].as_ref().is_some_and(|w| triangle4::occluded(w, packet, t[r])))
                    .fold(0, |m, r| m | 1 << r);
                blocked.set(blocked.get() | now);
                now
            },
            // `occluded_on`'s leaf test, written again for the reason given above.
            |r, node, t_max| {
                let Some(w) = &wrays[r] else { return false };
                let mut hit = false;
                self.bvh.traverse_from(lanes, Order::Any, &self.packets, &rays[r], node, t_max, |packet, t_max| {
                    hit = triangle4::occluded(w, &self.packets[packet as usize], *t_max);
                    hit
                });
                blocked.set(blocked.get() | u32::from(hit) << r);
                hit
            },
        );
        blocked.get()
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn intersect_avx2(&self, avx: crate::accel::lanes::Avx2, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        self.intersect_on(avx, ray, t_max)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn occluded_avx2(&self, avx: crate::accel::lanes::Avx2, ray: &Ray, t_max: f32) -> bool {
        self.occluded_on(avx, ray, t_max)
    }

    #[inline(always)]
    fn intersect_on<L: Lanes>(&self, lanes: L, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let wray = WatertightRay4::new(WatertightRay::new(ray)?);
        let mut best = None;
        let mut t_max = t_max;
        // The leaf tests inlined: called, they made every vector register the walk keeps
        // (the ray's slab terms) a spill around the call, reloaded at every node.
        self.bvh.traverse_with(
            lanes,
            Order::NearestFirst,
            &self.packets,
            ray,
            &mut t_max,
            #[inline(always)]
            |packet, t_max| {
                if let Some((t, tri)) = triangle4::intersect(&wray, &self.packets[packet as usize], *t_max) {
                    *t_max = t;
                    best = Some(ShapeHit { t, part: tri });
                }
                false
            },
        );
        best
    }

    #[inline(always)]
    fn occluded_on<L: Lanes>(&self, lanes: L, ray: &Ray, t_max: f32) -> bool {
        let Some(wray) = WatertightRay::new(ray).map(WatertightRay4::new) else { return false };
        let mut blocked = false;
        self.bvh.traverse_with(
            lanes,
            Order::Any,
            &self.packets,
            ray,
            &mut { t_max },
            #[inline(always)]
            |packet, t_max| {
                blocked = triangle4::occluded(&wray, &self.packets[packet as usize], *t_max);
                blocked
            },
        );
        blocked
    }

    /// Surface data at `hit`, in object space: the point from barycentrics, the
    /// interpolated shading normal (or the geometric one), uv, the geometric normal
    /// `(p1 − p0) × (p2 − p0)` and the origin for shadow rays.
    pub fn surface(&self, ray: &Ray, hit: ShapeHit) -> MeshSurface {
        let tri = hit.part as usize;
        let [a, b, c] = self.vertices(tri);
        let geometric = (b - a).cross(c - a);
        let bary = WatertightRay::new(ray)
            .and_then(|w| triangle::intersect(&w, a, b, c, f32::INFINITY))
            .map_or(Vec3::splat(1.0 / 3.0), |h| h.barycentric);
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let point = bary.x * a + bary.y * b + bary.z * c;
        let (mut normal, mut geometric, mut shadow_point) = (geometric, geometric, point);
        if !self.normals.is_empty() {
            let [n0, n1, n2] = [i0, i1, i2].map(|i| self.normals[i]);
            let n = bary.x * n0 + bary.y * n1 + bary.z * n2;
            if n.length_squared() > 0.0 {
                // The file's normals say which side is outside, whatever the winding.
                normal = n;
                if n.dot(geometric) < 0.0 {
                    geometric = -geometric;
                }
                shadow_point = terminator_point(point, bary, [a, b, c], [n0, n1, n2]);
            }
        }
        let uv = if self.uvs.is_empty() {
            Vec2::new(bary.y, bary.z)
        } else {
            bary.x * self.uvs[i0] + bary.y * self.uvs[i1] + bary.z * self.uvs[i2]
        };
        let color = if self.colors.is_empty() {
            Vec3::ONE
        } else {
            bary.x * self.colors[i0] + bary.y * self.colors[i1] + bary.z * self.colors[i2]
        };
        MeshSurface { surface: SurfacePoint { point, normal, uv }, color, geometric, shadow_point }
    }

    /// `(∂p/∂u, ∂p/∂v)` of triangle `tri` in object space, from its corners and uvs;
    /// `None` without uvs or where the uvs give the triangle no area.
    pub fn uv_frame(&self, tri: usize) -> Option<(Vec3, Vec3)> {
        if self.uvs.is_empty() {
            return None;
        }
        let [a, b, c] = self.vertices(tri);
        let [i0, i1, i2] = self.triangles[tri].map(|i| i as usize);
        let (du1, du2) = (self.uvs[i1] - self.uvs[i0], self.uvs[i2] - self.uvs[i0]);
        let det = du1.x * du2.y - du1.y * du2.x;
        if det.abs() < 1e-12 || !det.is_finite() {
            return None;
        }
        let (e1, e2) = (b - a, c - a);
        let dpdu = (e1 * du2.y - e2 * du1.y) / det;
        let dpdv = (e2 * du1.x - e1 * du2.x) / det;
        Some((dpdu, dpdv))
    }

    /// Heap bytes of the compiled mesh: each array's length times its element size
    /// (vertices, attributes, indices, triangle packets, BVH nodes), unused capacity not
    /// counted. What `bench/embree_compare.sh` compares with Embree's memory per triangle.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.positions.len() * size_of::<Vec3>()
            + self.normals.len() * size_of::<Vec3>()
            + self.uvs.len() * size_of::<Vec2>()
            + self.colors.len() * size_of::<Vec3>()
            + self.triangles.len() * size_of::<[u32; 3]>()
            + self.packets.len() * size_of::<Triangle4>()
            + self.bvh.nodes.len() * size_of::<crate::accel::WideNode>()
    }
}

/// Elements checked at a time by the validation's fast passes.
const VALIDATION_CHUNK: usize = 1 << 14;

/// Whether every coordinate is finite: the fast pass of validation, a loop that does
/// not stop at the first bad value and so compiles to vector compares (the search for
/// the first non-finite vertex, run only when this fails, went vertex by vertex: 2.7 ms
/// for a million-triangle mesh on two threads).
fn all_finite(positions: &[Vec3]) -> bool {
    let coordinates: &[f32] = bytemuck::cast_slice(positions);
    coordinates.par_chunks(VALIDATION_CHUNK).all(|chunk| chunk.iter().fold(true, |ok, x| ok & x.is_finite()))
}

/// The largest vertex index, if there is any: the fast pass of the range check, a
/// vector maximum (the search for the first triangle out of range, run only when this
/// is out of range, went triangle by triangle: 5.4 ms for a million triangles).
fn largest_index(indices: &[u32]) -> Option<u32> {
    indices.par_chunks(VALIDATION_CHUNK).filter_map(|chunk| chunk.iter().copied().max()).max()
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod extreme_tests;

/// What a [`crate::shape::Shape`] of kind `Mesh` can say on its own: nothing, since the
/// triangles live in [`crate::scene::RenderScene::meshes`]. The scene routes mesh
/// instances to [`Mesh`] before the shape dispatch; this keeps that dispatch total.
pub struct MeshRef;

impl crate::shape::Primitive for MeshRef {
    fn intersect(&self, _ray: &Ray, _t_max: f32) -> Option<ShapeHit> {
        None
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        SurfacePoint { point: ray.at(hit.t), normal: -ray.dir, uv: Vec2::ZERO }
    }

    fn bounds(&self) -> Aabb {
        Aabb::EMPTY
    }
}
