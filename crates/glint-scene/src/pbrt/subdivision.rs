//! Loop subdivision (Loop 1987) for pbrt's `loopsubdiv` shape: each level splits every
//! triangle into four and smooths the vertices with Loop's weights, boundaries with the
//! cubic B-spline rule. Unlike pbrt, the vertices are not pushed to the limit surface
//! after the last level; smooth normals come from the faces around each vertex.

use std::collections::HashMap;

use glam::Vec3;
use glint_core::desc::MeshDesc;

/// The most triangles subdivision may make (each level multiplies the count by four).
pub(super) const MAX_TRIANGLES: usize = 1 << 24;

/// The most levels, up to `levels`, that keep `triangles` under [`MAX_TRIANGLES`].
pub(super) fn affordable_levels(triangles: usize, levels: u32) -> u32 {
    let mut n = 0;
    while n < levels && triangles.saturating_mul(4usize.saturating_pow(n + 1)) <= MAX_TRIANGLES {
        n += 1;
    }
    n
}

/// Subdivides `mesh` (positions and indices) `levels` times and gives it smooth normals.
pub(super) fn loop_subdivide(mesh: &mut MeshDesc, levels: u32) {
    mesh.uvs.clear();
    mesh.normals.clear();
    for _ in 0..levels {
        let (positions, indices) = one_level(&mesh.positions, &mesh.indices);
        mesh.positions = positions;
        mesh.indices = indices;
    }
    if levels > 0 {
        mesh.normals = vertex_normals(&mesh.positions, &mesh.indices);
    }
}

/// An undirected edge, smaller index first.
fn edge(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// One level: new edge points, smoothed old points, four triangles per triangle.
fn one_level(p: &[Vec3], indices: &[u32]) -> (Vec<Vec3>, Vec<u32>) {
    // The vertices opposite each edge (one on a boundary, two inside).
    let mut opposite: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for t in indices.chunks_exact(3) {
        for k in 0..3 {
            opposite.entry(edge(t[k], t[(k + 1) % 3])).or_default().push(t[(k + 2) % 3]);
        }
    }
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); p.len()];
    let mut boundary_neighbours: Vec<Vec<u32>> = vec![Vec::new(); p.len()];
    for (&(a, b), opp) in &opposite {
        neighbours[a as usize].push(b);
        neighbours[b as usize].push(a);
        if opp.len() == 1 {
            boundary_neighbours[a as usize].push(b);
            boundary_neighbours[b as usize].push(a);
        }
    }
    let mut out: Vec<Vec3> = p
        .iter()
        .enumerate()
        .map(|(i, &v)| match (boundary_neighbours[i].as_slice(), neighbours[i].len()) {
            ([b0, b1], _) => 0.75 * v + 0.125 * (p[*b0 as usize] + p[*b1 as usize]),
            ([], n) if n >= 3 => {
                let beta = if n == 3 { 3.0 / 16.0 } else { 3.0 / (8.0 * n as f32) };
                let sum: Vec3 = neighbours[i].iter().map(|&j| p[j as usize]).sum();
                (1.0 - n as f32 * beta) * v + beta * sum
            }
            _ => v,
        })
        .collect();
    let mut edge_point: HashMap<(u32, u32), u32> = HashMap::with_capacity(opposite.len());
    let mut keys: Vec<_> = opposite.keys().copied().collect();
    keys.sort_unstable();
    for e in keys {
        let (a, b) = (p[e.0 as usize], p[e.1 as usize]);
        let point = match opposite[&e].as_slice() {
            [c, d] => 0.375 * (a + b) + 0.125 * (p[*c as usize] + p[*d as usize]),
            _ => 0.5 * (a + b),
        };
        edge_point.insert(e, out.len() as u32);
        out.push(point);
    }
    let mut tris = Vec::with_capacity(indices.len() * 4);
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]];
        let [ab, bc, ca] = [edge(a, b), edge(b, c), edge(c, a)].map(|e| edge_point[&e]);
        tris.extend([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    (out, tris)
}

/// Area-weighted averages of the face normals around each vertex.
fn vertex_normals(p: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; p.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let face = (p[b] - p[a]).cross(p[c] - p[a]);
        for i in [a, b, c] {
            n[i] += face;
        }
    }
    n.into_iter().map(|v| v.normalize_or(Vec3::Z)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tetrahedron_shrinks_towards_a_sphere() {
        let positions = vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ];
        let indices = vec![0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2];
        let mut mesh = MeshDesc { positions, indices, ..MeshDesc::default() };
        loop_subdivide(&mut mesh, 2);
        assert_eq!(mesh.indices.len(), 12 * 16);
        assert_eq!(mesh.positions.len(), 4 + 6 + 24);
        let r: Vec<f32> = mesh.positions.iter().map(|v| v.length()).collect();
        let (lo, hi) = r.iter().fold((f32::MAX, 0f32), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        assert!(hi < 3f32.sqrt() && hi / lo < 1.6, "{lo} {hi}");
        // Normals point outwards.
        assert!(mesh.positions.iter().zip(&mesh.normals).all(|(p, n)| p.dot(*n) > 0.0));
    }

    #[test]
    fn levels_stop_before_the_triangle_budget() {
        assert_eq!(affordable_levels(4, 3), 3);
        assert_eq!(affordable_levels(MAX_TRIANGLES / 4, 9), 1);
        assert_eq!(affordable_levels(MAX_TRIANGLES, 2), 0);
    }
}
