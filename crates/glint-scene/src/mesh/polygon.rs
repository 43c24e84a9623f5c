//! Polygons to triangles: a fan when the polygon is convex, ear clipping otherwise, both in
//! the polygon's best-fit plane (its Newell normal), so concave faces keep their shape.
//!
//! Ear clipping after Eberly, "Triangulation by Ear Clipping" (Geometric Tools, 2002):
//! repeatedly cut off a convex corner whose triangle holds no other corner. Every step
//! removes a corner, so the loop ends even for self-intersecting or non-planar input;
//! when no clean ear is left the first convex (or any) corner is cut.

use glam::{Vec2, Vec3};

/// Past this many corners a polygon is fanned: polygons this large are fans or caps in
/// practice.
const MAX_EAR_CLIPPED: usize = 1024;

/// Ear tests allowed per polygon, times its corners squared: a clean polygon needs about
/// one pass per ear, while a tangled one (fuzzed input) could need cubic time. Past the
/// budget every convex corner counts as an ear, so the work stays quadratic.
const EAR_TEST_BUDGET: usize = 2;

/// The triangles of the polygon with corners `points`, in order, as indices into
/// `points`, wound as the polygon is. Fewer than 3 corners give none.
pub fn triangulate(points: &[Vec3]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    let fan = || (1..n - 1).map(|k| [0, k, k + 1]).collect();
    if n == 3 || n > MAX_EAR_CLIPPED {
        return fan();
    }
    let Some(flat) = project(points) else { return fan() };
    if is_convex(&flat) {
        return fan();
    }
    ear_clip(&flat)
}

/// The corners in 2-D coordinates of the plane across the Newell normal, wound
/// counter-clockwise; `None` when the polygon has no area.
fn project(points: &[Vec3]) -> Option<Vec<Vec2>> {
    // Newell's normal: twice the polygon's vector area, robust for non-planar polygons
    // (taken about the first corner, to keep far-off coordinates precise).
    let o = points[0];
    let mut normal = Vec3::ZERO;
    for (k, &p) in points.iter().enumerate() {
        normal += (p - o).cross(points[(k + 1) % points.len()] - o);
    }
    let normal = normal.try_normalize()?;
    let t = normal.any_orthonormal_vector();
    let b = normal.cross(t);
    Some(points.iter().map(|p| Vec2::new(p.dot(t), p.dot(b))).collect())
}

/// Twice the signed area of triangle `a b c` (positive when counter-clockwise).
fn cross(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    (b - a).perp_dot(c - a)
}

/// Whether every corner turns left (none reflex): then a fan is exact.
fn is_convex(flat: &[Vec2]) -> bool {
    let n = flat.len();
    (0..n).all(|k| cross(flat[(k + n - 1) % n], flat[k], flat[(k + 1) % n]) >= 0.0)
}

/// Ear clipping of a counter-clockwise polygon.
fn ear_clip(flat: &[Vec2]) -> Vec<[usize; 3]> {
    let mut ring: Vec<usize> = (0..flat.len()).collect();
    let mut triangles = Vec::with_capacity(flat.len() - 2);
    // Corners in a straight line (to rounding) are not ears: they would give slivers
    // without area, perhaps wound backwards.
    let (min, max) = flat.iter().fold((flat[0], flat[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let tiny = 1e-6 * (max - min).length_squared();
    let mut budget = EAR_TEST_BUDGET * flat.len() * flat.len();
    while ring.len() > 3 {
        let m = ring.len();
        let corner = |k: usize| [ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]];
        let convex = |k: usize| {
            let [a, b, c] = corner(k);
            cross(flat[a], flat[b], flat[c]) > tiny
        };
        let mut is_clean_ear = |k: usize| {
            budget = budget.saturating_sub(m);
            budget == 0 || is_ear(flat, &ring, corner(k), tiny)
        };
        let ear = (0..m).find(|&k| convex(k) && is_clean_ear(k)).or_else(|| (0..m).find(|&k| convex(k))).unwrap_or(0);
        triangles.push(corner(ear));
        ring.remove(ear);
    }
    triangles.push([ring[0], ring[1], ring[2]]);
    triangles
}

/// Whether no other corner of `ring` lies in triangle `abc`, or on it to within `tiny`
/// (rounding must not let an ear cut through a corner on its long side).
fn is_ear(flat: &[Vec2], ring: &[usize], [a, b, c]: [usize; 3], tiny: f32) -> bool {
    let [pa, pb, pc] = [flat[a], flat[b], flat[c]];
    ring.iter().filter(|&&i| i != a && i != b && i != c).all(|&i| {
        let p = flat[i];
        // Corners at the ear's own positions (a polygon touching itself) do not block it.
        if p == pa || p == pb || p == pc {
            return true;
        }
        !(cross(pa, pb, p) >= -tiny && cross(pb, pc, p) >= -tiny && cross(pc, pa, p) >= -tiny)
    })
}
