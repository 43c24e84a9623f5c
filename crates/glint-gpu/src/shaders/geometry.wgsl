// Rays against the scene: the analytic shapes in object space (glint_core::shape), the
// watertight triangle test (glint_core::mesh::triangle), and the two-level traversal
// of the 8-wide BVHs (glint_core::accel::wide): instances at the top, each mesh's
// triangles below.

struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,
    time: f32,
}

fn ray_at(r: Ray, t: f32) -> vec3<f32> {
    return r.origin + t * r.dir;
}

struct ShapeHit {
    found: bool,
    t: f32,
    part: u32,
    // Barycentrics of a triangle hit (unused by analytic shapes).
    bary: vec3<f32>,
}

fn no_hit() -> ShapeHit {
    return ShapeHit(false, 0.0, 0u, vec3<f32>(0.0));
}

fn shape_hit(t: f32, part: u32) -> ShapeHit {
    return ShapeHit(true, t, part, vec3<f32>(0.0));
}

const KIND_SPHERE: u32 = 0u;
const KIND_CUBE: u32 = 1u;
const KIND_CYLINDER: u32 = 2u;
const KIND_CONE: u32 = 3u;
const KIND_PLANE: u32 = 4u;
const KIND_DISK: u32 = 5u;
const KIND_MESH: u32 = 7u;
const KIND_RECTANGLE: u32 = 13u;

// ---- analytic shapes (object space, direction not normalized) ----

fn nearest_of(t0: f32, t1: f32, t_max: f32) -> f32 {
    if t0 > 0.0 && t0 < t_max {
        return t0;
    }
    if t1 > 0.0 && t1 < t_max {
        return t1;
    }
    return -1.0;
}

fn intersect_sphere(r: Ray, t_max: f32) -> ShapeHit {
    let t0 = -dot(r.origin, r.dir) / dot(r.dir, r.dir);
    let near = ray_at(r, t0);
    let discriminant = 1.0 - dot(near, near);
    if discriminant < 0.0 {
        return no_hit();
    }
    let half_chord = sqrt(discriminant / dot(r.dir, r.dir));
    let t = nearest_of(t0 - half_chord, t0 + half_chord, t_max);
    if t < 0.0 {
        return no_hit();
    }
    return shape_hit(t, 0u);
}

fn intersect_cube(r: Ray, t_max: f32) -> ShapeHit {
    var near = -INF;
    var near_part = 0u;
    var far = INF;
    var far_part = 0u;
    for (var axis = 0u; axis < 3u; axis += 1u) {
        let o = r.origin[axis];
        let inv = 1.0 / r.dir[axis];
        if !finite(inv) {
            if abs(o) > 1.0 {
                return no_hit();
            }
            continue;
        }
        let t_minus = (-1.0 - o) * inv;
        let t_plus = (1.0 - o) * inv;
        var t_in = t_plus;
        var in_part = 2u * axis + 1u;
        var t_out = t_minus;
        var out_part = 2u * axis;
        if t_minus < t_plus {
            t_in = t_minus;
            in_part = 2u * axis;
            t_out = t_plus;
            out_part = 2u * axis + 1u;
        }
        if t_in > near {
            near = t_in;
            near_part = in_part;
        }
        if t_out < far {
            far = t_out;
            far_part = out_part;
        }
    }
    if near > far {
        return no_hit();
    }
    if near > 0.0 && near < t_max {
        return shape_hit(near, near_part);
    }
    if far > 0.0 && far < t_max {
        return shape_hit(far, far_part);
    }
    return no_hit();
}

fn intersect_cylinder(r: Ray, t_max: f32) -> ShapeHit {
    var best = no_hit();
    var limit = t_max;
    let o = r.origin;
    let d = r.dir;
    let a = d.x * d.x + d.z * d.z;
    if a > 0.0 {
        let t0 = -(o.x * d.x + o.z * d.z) / a;
        let cx = o.x + t0 * d.x;
        let cz = o.z + t0 * d.z;
        let discriminant = 1.0 - (cx * cx + cz * cz);
        if discriminant >= 0.0 {
            let h = sqrt(discriminant / a);
            for (var k = 0u; k < 2u; k += 1u) {
                let t = select(t0 + h, t0 - h, k == 0u);
                if t > 0.0 && t < limit && abs(o.y + t * d.y) <= 1.0 {
                    best = shape_hit(t, 0u);
                    limit = t;
                    break;
                }
            }
        }
    }
    if d.y != 0.0 {
        for (var k = 0u; k < 2u; k += 1u) {
            let y = select(-1.0, 1.0, k == 0u);
            let t = (y - o.y) / d.y;
            let x = o.x + t * d.x;
            let z = o.z + t * d.z;
            if x * x + z * z <= 1.0 && t > 0.0 && t < limit {
                best = shape_hit(t, k + 1u);
                limit = t;
            }
        }
    }
    return best;
}

// glint_core::math::roots::solve_quadratic, with an f32 discriminant (fused).
fn solve_quadratic(a: f32, b: f32, c: f32) -> vec3<f32> {
    if a == 0.0 {
        if b == 0.0 {
            return vec3<f32>(0.0, 0.0, -1.0);
        }
        let t = -c / b;
        return vec3<f32>(t, t, 1.0);
    }
    let discriminant = fma(b, b, -4.0 * a * c);
    if discriminant < 0.0 {
        return vec3<f32>(0.0, 0.0, -1.0);
    }
    let root = sqrt(discriminant);
    let q = -0.5 * (b + select(root, -root, b < 0.0));
    if q == 0.0 {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let t0 = q / a;
    let t1 = c / q;
    return vec3<f32>(min(t0, t1), max(t0, t1), 1.0);
}

// The cone x² + z² = ((1 − y)/2)² along o + s·d: the coefficients (a, b, c) of its
// quadratic in s.
fn cone_quadratic(o: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    let oy = 1.0 - o.y;
    let dy = -d.y;
    return vec3<f32>(
        d.x * d.x + d.z * d.z - 0.25 * dy * dy,
        2.0 * (o.x * d.x + o.z * d.z - 0.25 * oy * dy),
        o.x * o.x + o.z * o.z - 0.25 * oy * oy,
    );
}

fn intersect_cone(r: Ray, t_max: f32) -> ShapeHit {
    var best = no_hit();
    var limit = t_max;
    let t0 = -dot(r.origin, r.dir) / dot(r.dir, r.dir);
    let q = cone_quadratic(ray_at(r, t0), r.dir);
    let roots = solve_quadratic(q.x, q.y, q.z);
    if roots.z > 0.0 {
        for (var k = 0u; k < 2u; k += 1u) {
            let t = t0 + roots[k];
            let y = ray_at(r, t).y;
            if t > 0.0 && t < limit && y >= -1.0 && y <= 1.0 {
                best = shape_hit(t, 0u);
                limit = t;
                break;
            }
        }
    }
    if r.dir.y != 0.0 {
        let t = (-1.0 - r.origin.y) / r.dir.y;
        let p = ray_at(r, t);
        if t > 0.0 && t < limit && p.x * p.x + p.z * p.z <= 1.0 {
            best = shape_hit(t, 2u);
        }
    }
    return best;
}

fn intersect_flat(kind: u32, r: Ray, t_max: f32) -> ShapeHit {
    let t = -r.origin.y / r.dir.y;
    if !(t > 0.0 && t < t_max) {
        return no_hit();
    }
    let p = ray_at(r, t);
    if kind == KIND_DISK && !(p.x * p.x + p.z * p.z <= 1.0) {
        return no_hit();
    }
    if kind == KIND_RECTANGLE && !(abs(p.x) <= 1.0 && abs(p.z) <= 1.0) {
        return no_hit();
    }
    return shape_hit(t, 0u);
}

fn intersect_analytic(kind: u32, r: Ray, t_max: f32) -> ShapeHit {
    switch kind {
        case 0u: { return intersect_sphere(r, t_max); }
        case 1u: { return intersect_cube(r, t_max); }
        case 2u: { return intersect_cylinder(r, t_max); }
        case 3u: { return intersect_cone(r, t_max); }
        case 4u, 5u, 13u: { return intersect_flat(kind, r, t_max); }
        default: { return no_hit(); }
    }
}

struct SurfacePoint {
    point: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
}

fn azimuth_u(p: vec3<f32>) -> f32 {
    let u = -atan2(p.z, p.x) / (2.0 * PI);
    return select(u, u + 1.0, u < 0.0);
}

fn disk_uv(p: vec3<f32>, facing_up: bool) -> vec2<f32> {
    let v = select(0.5 + 0.5 * p.z, 0.5 - 0.5 * p.z, facing_up);
    return vec2<f32>(0.5 + 0.5 * p.x, v);
}

fn cap_surface(p: vec3<f32>, top: bool) -> SurfacePoint {
    let y = select(-1.0, 1.0, top);
    let point = vec3<f32>(p.x, y, p.z);
    return SurfacePoint(point, vec3<f32>(0.0, y, 0.0), disk_uv(point, top));
}

fn normalize2_or_x(v: vec2<f32>) -> vec2<f32> {
    let len2 = dot(v, v);
    let r = 1.0 / sqrt(len2);
    if finite(r) && r > 0.0 {
        return v * r;
    }
    return vec2<f32>(1.0, 0.0);
}

fn analytic_surface(kind: u32, r: Ray, hit: ShapeHit) -> SurfacePoint {
    let p = ray_at(r, hit.t);
    switch kind {
        case 0u: {
            let point = normalize_or(p, vec3<f32>(0.0, 1.0, 0.0));
            let v = 0.5 + asin(clamp(point.y, -1.0, 1.0)) / PI;
            return SurfacePoint(point, point, vec2<f32>(azimuth_u(point), v));
        }
        case 1u: {
            let axis = hit.part / 2u;
            let sign = select(-1.0, 1.0, hit.part % 2u == 1u);
            var point = clamp(p, vec3<f32>(-1.0), vec3<f32>(1.0));
            point[axis] = sign;
            var normal = vec3<f32>(0.0);
            normal[axis] = sign;
            var uv: vec2<f32>;
            if axis == 0u {
                uv = vec2<f32>(-sign * point.z, point.y);
            } else if axis == 1u {
                uv = vec2<f32>(point.x, -sign * point.z);
            } else {
                uv = vec2<f32>(sign * point.x, point.y);
            }
            return SurfacePoint(point, normal, vec2<f32>(0.5) + 0.5 * uv);
        }
        case 2u: {
            if hit.part == 0u {
                let radial = normalize2_or_x(vec2<f32>(p.x, p.z));
                let point = vec3<f32>(radial.x, clamp(p.y, -1.0, 1.0), radial.y);
                let uv = vec2<f32>(azimuth_u(point), 0.5 + 0.5 * point.y);
                return SurfacePoint(point, vec3<f32>(point.x, 0.0, point.z), uv);
            }
            return cap_surface(p, hit.part == 1u);
        }
        case 3u: {
            if hit.part == 2u {
                return cap_surface(p, false);
            }
            let y = clamp(p.y, -1.0, 1.0);
            let radial = normalize2_or_x(vec2<f32>(p.x, p.z)) * (0.5 * (1.0 - y));
            let point = vec3<f32>(radial.x, y, radial.y);
            var normal = vec3<f32>(point.x, 0.25 * (1.0 - y), point.z);
            if dot(normal, normal) <= 0.0 {
                normal = vec3<f32>(0.0, 1.0, 0.0);
            }
            return SurfacePoint(point, normal, vec2<f32>(azimuth_u(point), 0.5 + 0.5 * y));
        }
        case 4u: {
            let point = vec3<f32>(p.x, 0.0, p.z);
            return SurfacePoint(point, vec3<f32>(0.0, 1.0, 0.0), vec2<f32>(p.x, -p.z));
        }
        case 5u: {
            let cap = cap_surface(p, true);
            return SurfacePoint(cap.point * vec3<f32>(1.0, 0.0, 1.0), cap.normal, cap.uv);
        }
        default: {
            let q = p * vec3<f32>(1.0, 0.0, 1.0);
            return SurfacePoint(q, vec3<f32>(0.0, 1.0, 0.0), vec2<f32>(0.5 + 0.5 * q.x, 0.5 - 0.5 * q.z));
        }
    }
}

// ---- watertight triangles ----

struct WatertightRay {
    valid: bool,
    origin: vec3<f32>,
    kx: u32,
    ky: u32,
    kz: u32,
    shear: vec3<f32>,
}

fn watertight(r: Ray) -> WatertightRay {
    let d = r.dir;
    let a = abs(d);
    var kz = 2u;
    if a.x > a.y {
        if a.x > a.z {
            kz = 0u;
        }
    } else if a.y > a.z {
        kz = 1u;
    }
    var w: WatertightRay;
    w.valid = a[kz] > 0.0 && finite(a[kz]);
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if d[kz] < 0.0 {
        let k = kx;
        kx = ky;
        ky = k;
    }
    w.origin = r.origin;
    w.kx = kx;
    w.ky = ky;
    w.kz = kz;
    w.shear = vec3<f32>(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
    return w;
}

fn ray_space(w: WatertightRay, p: vec3<f32>) -> vec3<f32> {
    let a = p - w.origin;
    return vec3<f32>(a[w.kx] - w.shear.x * a[w.kz], a[w.ky] - w.shear.y * a[w.kz], a[w.kz]);
}

fn owns_edge(start: vec3<f32>, end: vec3<f32>) -> bool {
    let dx = end.x - start.x;
    let dy = end.y - start.y;
    return dy > 0.0 || (dy == 0.0 && dx < 0.0);
}

// glint_core::mesh::triangle::intersect (without its f64 re-evaluation of exact zeros).
fn intersect_triangle(w: WatertightRay, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, t_max: f32) -> ShapeHit {
    let a = ray_space(w, p0);
    let b = ray_space(w, p1);
    let c = ray_space(w, p2);
    let u = c.x * b.y - c.y * b.x;
    let v = a.x * c.y - a.y * c.x;
    let e = b.x * a.y - b.y * a.x;
    if (u < 0.0 || v < 0.0 || e < 0.0) && (u > 0.0 || v > 0.0 || e > 0.0) {
        return no_hit();
    }
    let det = u + v + e;
    if det == 0.0 {
        return no_hit();
    }
    if (u == 0.0 && !owns_edge(b, c)) || (v == 0.0 && !owns_edge(c, a)) || (e == 0.0 && !owns_edge(a, b)) {
        return no_hit();
    }
    let sz = w.shear.z;
    let t_scaled = u * (sz * a.z) + v * (sz * b.z) + e * (sz * c.z);
    // In front where T and det share a sign; t_max bounds the divided t alone.
    let in_front = (det > 0.0 && t_scaled > 0.0) || (det < 0.0 && t_scaled < 0.0);
    if !in_front {
        return no_hit();
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t > 0.0 && t < t_max) {
        return no_hit();
    }
    return ShapeHit(true, t, 0u, vec3<f32>(u, v, e) * inv_det);
}

fn packet_corner(packet: u32, corner: u32, lane: u32) -> vec3<f32> {
    let base = corner * 12u + lane;
    return vec3<f32>(packets[packet].p[base], packets[packet].p[base + 4u], packets[packet].p[base + 8u]);
}

// ---- wide BVH traversal ----

const STACK: u32 = 96u;
const ROBUST_FAR: f32 = 1.0000003576;

struct SlabRay {
    inv: vec3<f32>,
    origin: vec3<f32>,
    near_plane: vec3<u32>,
    // Axes the ray runs parallel to (a zero or vanishing component): the slab of such
    // an axis holds the whole ray or none of it (the CPU gets this from 1/0 = ∞, which
    // WGSL does not promise).
    parallel: vec3<bool>,
}

fn slab_ray(r: Ray) -> SlabRay {
    let parallel = abs(r.dir) < vec3<f32>(1e-30);
    let d = select(r.dir, vec3<f32>(1.0), parallel);
    let inv = 1.0 / d;
    let near_plane = vec3<u32>(0u, 2u, 4u) + select(vec3<u32>(0u), vec3<u32>(1u), inv < vec3<f32>(0.0));
    return SlabRay(inv, r.origin, near_plane, parallel);
}

// Entry and exit distances of one lane's slab on `axis`.
fn slab(s: SlabRay, node: u32, lane: u32, axis: u32) -> vec2<f32> {
    let lo = nodes[node].bounds[(2u * axis) * 8u + lane];
    let hi = nodes[node].bounds[(2u * axis + 1u) * 8u + lane];
    if s.parallel[axis] {
        let inside = s.origin[axis] >= lo && s.origin[axis] <= hi;
        return select(vec2<f32>(INF, -INF), vec2<f32>(-INF, INF), inside);
    }
    let near = (nodes[node].bounds[s.near_plane[axis] * 8u + lane] - s.origin[axis]) * s.inv[axis];
    let far = (nodes[node].bounds[(s.near_plane[axis] ^ 1u) * 8u + lane] - s.origin[axis]) * s.inv[axis];
    return vec2<f32>(near, far);
}

struct NodeHits {
    count: u32,
    // Children hit, nearest first: node or leaf index, leaf count (0 = inner), entry t.
    child: array<u32, 8>,
    leaves: array<u32, 8>,
    near: array<f32, 8>,
}

// The children of `node` the ray enters before `t_max`, sorted nearest first.
fn test_node(s: SlabRay, node: u32, t_max: f32) -> NodeHits {
    var hits: NodeHits;
    hits.count = 0u;
    for (var lane = 0u; lane < 8u; lane += 1u) {
        let x = slab(s, node, lane, 0u);
        let y = slab(s, node, lane, 1u);
        let z = slab(s, node, lane, 2u);
        let near = max(max(x.x, y.x), max(z.x, 0.0));
        let far = min(min(x.y, y.y), z.y) * ROBUST_FAR;
        if near <= min(far, t_max) {
            // Insertion, nearest first.
            var j = hits.count;
            while j > 0u && hits.near[j - 1u] > near {
                hits.child[j] = hits.child[j - 1u];
                hits.leaves[j] = hits.leaves[j - 1u];
                hits.near[j] = hits.near[j - 1u];
                j -= 1u;
            }
            hits.child[j] = nodes[node].child[lane];
            hits.leaves[j] = nodes[node].count[lane];
            hits.near[j] = near;
            hits.count += 1u;
        }
    }
    return hits;
}

// The closest triangle of `mesh` hit in (0, t_max), or any one when `any_hit`.
fn trace_mesh(mesh: GpuMesh, r: Ray, t_max_in: f32, any_hit: bool) -> ShapeHit {
    var best = no_hit();
    if mesh.node_count == 0u {
        return best;
    }
    let w = watertight(r);
    if !w.valid {
        return best;
    }
    let s = slab_ray(r);
    var t_max = t_max_in;
    var stack_index: array<u32, STACK>;
    var stack_count: array<u32, STACK>;
    var stack_near: array<f32, STACK>;
    var top = 1u;
    stack_index[0] = 0u;
    stack_count[0] = 0u;
    stack_near[0] = 0.0;
    while top > 0u {
        top -= 1u;
        if stack_near[top] > t_max {
            continue;
        }
        let index = stack_index[top];
        let count = stack_count[top];
        if count > 0u {
            for (var k = 0u; k < count; k += 1u) {
                let packet = mesh.packet_offset + index + k;
                for (var lane = 0u; lane < 4u; lane += 1u) {
                    let h = intersect_triangle(
                        w,
                        packet_corner(packet, 0u, lane),
                        packet_corner(packet, 1u, lane),
                        packet_corner(packet, 2u, lane),
                        t_max,
                    );
                    // Lanes past the mesh's last triangle repeat it: the same t, not closer.
                    if h.found {
                        best = h;
                        best.part = packets[packet].triangle[lane];
                        t_max = h.t;
                        if any_hit {
                            return best;
                        }
                    }
                }
            }
            continue;
        }
        let hits = test_node(s, mesh.node_offset + index, t_max);
        // Push farthest first, so the nearest is popped next.
        for (var k = hits.count; k > 0u; k -= 1u) {
            if top < STACK {
                stack_index[top] = hits.child[k - 1u];
                stack_count[top] = hits.leaves[k - 1u];
                stack_near[top] = hits.near[k - 1u];
                top += 1u;
            }
        }
    }
    return best;
}

struct SceneHit {
    found: bool,
    instance: u32,
    shape: ShapeHit,
}

// ---- placement and motion (glint_core::scene::motion) ----

struct Xform {
    world_from_object: mat4x4<f32>,
    object_from_world: mat4x4<f32>,
}

// glam's Quat::slerp (its acos and sin are approximations; WGSL's are the driver's).
fn quat_slerp(a: vec4<f32>, b_in: vec4<f32>, s: f32) -> vec4<f32> {
    var b = b_in;
    var d = dot(a, b);
    if d < 0.0 {
        b = -b;
        d = -d;
    }
    if d > 1.0 - 1.1920929e-7 {
        return normalize(mix(a, b, s));
    }
    let theta = acos(d);
    return (a * sin((1.0 - s) * theta) + b * sin(s * theta)) / sin(theta);
}

fn quat_matrix(q: vec4<f32>) -> mat4x4<f32> {
    let x2 = q.x + q.x;
    let y2 = q.y + q.y;
    let z2 = q.z + q.z;
    let xx = q.x * x2;
    let xy = q.x * y2;
    let xz = q.x * z2;
    let yy = q.y * y2;
    let yz = q.y * z2;
    let zz = q.z * z2;
    let wx = q.w * x2;
    let wy = q.w * y2;
    let wz = q.w * z2;
    return mat4x4<f32>(
        vec4<f32>(1.0 - (yy + zz), xy + wz, xz - wy, 0.0),
        vec4<f32>(xy - wz, 1.0 - (xx + zz), yz + wx, 0.0),
        vec4<f32>(xz + wy, yz - wx, 1.0 - (xx + yy), 0.0),
        vec4<f32>(0.0, 0.0, 0.0, 1.0),
    );
}

fn translation(t: vec3<f32>) -> mat4x4<f32> {
    return mat4x4<f32>(vec4<f32>(1.0, 0.0, 0.0, 0.0), vec4<f32>(0.0, 1.0, 0.0, 0.0), vec4<f32>(0.0, 0.0, 1.0, 0.0), vec4<f32>(t, 1.0));
}

fn scaling(s: vec3<f32>) -> mat4x4<f32> {
    return mat4x4<f32>(vec4<f32>(s.x, 0.0, 0.0, 0.0), vec4<f32>(0.0, s.y, 0.0, 0.0), vec4<f32>(0.0, 0.0, s.z, 0.0), vec4<f32>(0.0, 0.0, 0.0, 1.0));
}

// Motion::at: the open and close poses interpolated at `time`, between the inner and
// outer transforms.
fn motion_at(m: Motion, time: f32) -> Xform {
    let s = mix(v3(m.open_scale), v3(m.close_scale), time);
    let q = quat_slerp(m.open_rotation, m.close_rotation, time);
    let t = mix(v3(m.open_translation), v3(m.close_translation), time);
    let rotation = quat_matrix(q);
    let pose_w = translation(t) * rotation * scaling(s);
    let pose_o = scaling(1.0 / s) * transpose(rotation) * translation(-t);
    return Xform(
        m.outer_world_from_object * pose_w * m.inner_world_from_object,
        m.inner_object_from_world * pose_o * m.outer_object_from_world,
    );
}

fn instance_xform(inst: Instance, time: f32) -> Xform {
    if inst.motion == NO_INDEX {
        return Xform(inst.world_from_object, inst.object_from_world);
    }
    return motion_at(motions[inst.motion], time);
}

fn object_ray(x: Xform, r: Ray) -> Ray {
    let m = x.object_from_world;
    return Ray((m * vec4<f32>(r.origin, 1.0)).xyz, (m * vec4<f32>(r.dir, 0.0)).xyz, r.time);
}

fn intersect_instance(index: u32, r: Ray, t_max: f32, any_hit: bool) -> ShapeHit {
    let inst = instances[index];
    let local = object_ray(instance_xform(inst, r.time), r);
    // Each guard is a pipeline constant: a scene without the shape leaves its code out.
    if MESHES && inst.kind == KIND_MESH {
        return trace_mesh(meshes[bitcast<u32>(inst.param)], local, t_max, any_hit);
    }
    if QUADRICS && inst.kind == KIND_QUADRIC {
        return intersect_quadric(bitcast<u32>(inst.param), local, t_max);
    }
    if TORI && inst.kind == KIND_TORUS {
        return intersect_torus(inst.param, local, t_max);
    }
    if CSG_SHAPES && inst.kind == KIND_CSG {
        return intersect_csg(bitcast<u32>(inst.param), local, t_max);
    }
    if SOLVED_SHAPES && (inst.kind == KIND_SUPERELLIPSOID || inst.kind == KIND_IMPLICIT || inst.kind == KIND_BLOB) {
        return intersect_solved(inst.kind, bitcast<u32>(inst.param), local, t_max);
    }
    return intersect_analytic(inst.kind, local, t_max);
}

// glint_core::scene::RenderScene::casts_no_shadow: shadow rays pass instance i.
fn casts_no_shadow(i: u32) -> bool {
    return (bsdfs[instances[i].material].flags & CASTS_NO_SHADOW) != 0u;
}

// The closest hit in (0, t_max) over every instance, or any hit (for shadow rays, past
// instances that cast no shadow) when `any_hit`. Every candidate range of instances (a
// BVH leaf as it is popped, then the unbounded instances past params.bounded_count)
// goes through one call of intersect_instance: drivers that inline every call (Mesa)
// then compile the shapes once per call of trace_scene.
fn trace_scene(r: Ray, t_max_in: f32, any_hit: bool) -> SceneHit {
    var result = SceneHit(false, 0u, no_hit());
    var t_max = t_max_in;
    let s = slab_ray(r);
    var stack_index: array<u32, 64>;
    var stack_count: array<u32, 64>;
    var stack_near: array<f32, 64>;
    var top = select(0u, 1u, params.node_count > 0u);
    stack_index[0] = 0u;
    stack_count[0] = 0u;
    stack_near[0] = 0.0;
    var unbounded_done = false;
    loop {
        var first: u32;
        var count: u32;
        if top > 0u {
            top -= 1u;
            if stack_near[top] > t_max {
                continue;
            }
            first = stack_index[top];
            count = stack_count[top];
            if count == 0u {
                let hits = test_node(s, first, t_max);
                for (var k = hits.count; k > 0u; k -= 1u) {
                    if top < 64u {
                        stack_index[top] = hits.child[k - 1u];
                        stack_count[top] = hits.leaves[k - 1u];
                        stack_near[top] = hits.near[k - 1u];
                        top += 1u;
                    }
                }
                continue;
            }
        } else if !unbounded_done {
            unbounded_done = true;
            first = params.bounded_count;
            count = params.instance_count - params.bounded_count;
        } else {
            break;
        }
        for (var i = first; i < first + count; i += 1u) {
            if any_hit && casts_no_shadow(i) {
                continue;
            }
            let h = intersect_instance(i, r, t_max, any_hit);
            if h.found {
                result = SceneHit(true, i, h);
                t_max = h.t;
                if any_hit {
                    return result;
                }
            }
        }
    }
    return result;
}

// World-space surface data at a hit (glint_core::scene::Hit).
struct Hit {
    t: f32,
    point: vec3<f32>,
    normal: vec3<f32>,
    geometric_normal: vec3<f32>,
    // Where shadow rays leaving the outside start: `point`, lifted on smooth meshes.
    shadow_point: vec3<f32>,
    uv: vec2<f32>,
    // The vertex colour (white without one): it tints the diffuse or base colour.
    color: vec3<f32>,
    material: u32,
    instance: u32,
    part: u32,
}

fn normal_to_world(x: Xform, n: vec3<f32>) -> vec3<f32> {
    let m = x.object_from_world;
    // (M⁻¹)ᵀ n, with M⁻¹'s upper 3×3 stored column by column.
    return vec3<f32>(dot(m[0].xyz, n), dot(m[1].xyz, n), dot(m[2].xyz, n));
}

// glint_core::normal_map::bent_normal: the normal a tangent-space texel encodes in the
// frame (∂p/∂u, ∂p/∂v, n), its tangential part times `scale`; n where degenerate.
fn bent_normal(dpdu: vec3<f32>, dpdv: vec3<f32>, n: vec3<f32>, texel: vec3<f32>, scale: f32) -> vec3<f32> {
    let t_raw = dpdu - n * dot(n, dpdu);
    let t_len = length(t_raw);
    if !(t_len > 0.0) || t_len > 3.0e38 {
        return n;
    }
    let t = t_raw / t_len;
    let b0 = cross(n, t);
    let b = select(b0, -b0, dot(b0, dpdv) < 0.0);
    let local = (2.0 * texel - vec3<f32>(1.0)) * vec3<f32>(scale, scale, 1.0);
    let bent = t * local.x + b * local.y + n * max(local.z, 0.0);
    let len = length(bent);
    if !(len > 0.0) || len > 3.0e38 {
        return n;
    }
    return bent / len;
}

fn mesh_vertex(mesh: GpuMesh, i: u32) -> vec3<f32> {
    return float3(mesh.position_offset + 3u * i);
}

// glint_core::mesh::terminator_point (Hanika 2021): p lifted onto each vertex's
// tangent plane it lies below, the lifts blended by the barycentrics.
fn terminator_point(
    p: vec3<f32>,
    bary: vec3<f32>,
    a: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    n0: vec3<f32>,
    n1: vec3<f32>,
    n2: vec3<f32>,
) -> vec3<f32> {
    let v = array<vec3<f32>, 3>(a, b, c);
    let normals = array<vec3<f32>, 3>(n0, n1, n2);
    var out = p;
    for (var k = 0u; k < 3u; k += 1u) {
        let n = normalize_or(normals[k], vec3<f32>(0.0));
        out += bary[k] * max(-dot(p - v[k], n), 0.0) * n;
    }
    return out;
}

// The surface of a shape other than a mesh at `h`, in object space
// (glint_core::shape::Shape::surface_with).
fn instance_surface(inst: Instance, local: Ray, h: ShapeHit) -> SurfacePoint {
    if QUADRICS && inst.kind == KIND_QUADRIC {
        return quadric_surface(bitcast<u32>(inst.param), local, h);
    } else if TORI && inst.kind == KIND_TORUS {
        return torus_surface(inst.param, local, h);
    } else if CSG_SHAPES && inst.kind == KIND_CSG {
        return csg_surface(local, h);
    } else if SOLVED_SHAPES && inst.kind == KIND_SUPERELLIPSOID {
        return superellipsoid_surface(bitcast<u32>(inst.param), local, h);
    } else if IMPLICITS && inst.kind == KIND_IMPLICIT {
        return implicit_surface(bitcast<u32>(inst.param), local, h);
    } else if BLOBS && inst.kind == KIND_BLOB {
        return blob_surface(bitcast<u32>(inst.param), local, h);
    }
    return analytic_surface(inst.kind, local, h);
}

// (∂p/∂u, ∂p/∂v) of a triangle from its corners and uvs (glint_core::mesh::Mesh::uv_frame);
// `ok` false where the uvs give it no area.
struct UvFrame {
    dpdu: vec3<f32>,
    dpdv: vec3<f32>,
    ok: bool,
}

fn mesh_uv(mesh: GpuMesh, i: u32) -> vec2<f32> {
    return vec2<f32>(floats[mesh.uv_offset + 2u * i], floats[mesh.uv_offset + 2u * i + 1u]);
}

fn uv_frame(corners: array<vec3<f32>, 3>, uvs: array<vec2<f32>, 3>) -> UvFrame {
    let du1 = uvs[1] - uvs[0];
    let du2 = uvs[2] - uvs[0];
    let det = du1.x * du2.y - du1.y * du2.x;
    if abs(det) < 1e-12 {
        return UvFrame(vec3<f32>(0.0), vec3<f32>(0.0), false);
    }
    let e1 = corners[1] - corners[0];
    let e2 = corners[2] - corners[0];
    return UvFrame((e1 * du2.y - e2 * du1.y) / det, (e2 * du1.x - e1 * du2.x) / det, true);
}

// glint_core::footprint::PixelSpacing::surface_steps, one neighbour: where the ray through
// the pixel `offset` away meets the plane through `eye + d` of normal `n`, less that
// point; .w is 0 where it never meets the plane ahead.
fn neighbour_step(d: vec3<f32>, n: vec3<f32>, offset: vec3<f32>) -> vec4<f32> {
    let dir = d + dot(d, params.forward.xyz) * offset;
    let t = dot(d, n) / dot(dir, n);
    let step = t * dir - d;
    let ok = t > 0.0 && all(abs(step) < vec3<f32>(3.0e38));
    return vec4<f32>(step, select(0.0, 1.0, ok));
}

// glint_core::scene::RenderScene::uv_steps: the steps in uv from `hit` to where the
// neighbouring pixels, `footprint_scale` of a pixel apart, see its surface, .xy across
// and .zw down; `bounded` false where the footprint is unbounded.
struct UvSteps {
    steps: vec4<f32>,
    bounded: bool,
}

fn uv_steps(hit: Hit, time: f32, footprint_scale: f32) -> UvSteps {
    let none = UvSteps(vec4<f32>(0.0), false);
    let d = hit.point - params.eye.xyz;
    if !(dot(d, params.forward.xyz) > 0.0) {
        return none;
    }
    let n = hit.geometric_normal;
    let sx = neighbour_step(d, n, params.pixel_dx.xyz * footprint_scale);
    let sy = neighbour_step(d, n, params.pixel_dy.xyz * footprint_scale);
    if sx.w == 0.0 || sy.w == 0.0 {
        return none;
    }
    let inst = instances[hit.instance];
    let xform = instance_xform(inst, time);
    if inst.kind == KIND_MESH {
        let mesh = meshes[bitcast<u32>(inst.param)];
        if mesh.uv_offset == NO_INDEX {
            return UvSteps(vec4<f32>(0.0), true);
        }
        let tri = mesh.index_offset + 3u * hit.part;
        let i = vec3<u32>(words[tri], words[tri + 1u], words[tri + 2u]);
        let corners = array<vec3<f32>, 3>(mesh_vertex(mesh, i.x), mesh_vertex(mesh, i.y), mesh_vertex(mesh, i.z));
        let frame = uv_frame(corners, array<vec2<f32>, 3>(mesh_uv(mesh, i.x), mesh_uv(mesh, i.y), mesh_uv(mesh, i.z)));
        if !frame.ok {
            return UvSteps(vec4<f32>(0.0), true);
        }
        // step = a·∂p/∂u + b·∂p/∂v, solved for (a, b) by least squares.
        let u = (xform.world_from_object * vec4<f32>(frame.dpdu, 0.0)).xyz;
        let v = (xform.world_from_object * vec4<f32>(frame.dpdv, 0.0)).xyz;
        let uu = dot(u, u);
        let uv = dot(u, v);
        let vv = dot(v, v);
        let det = uu * vv - uv * uv;
        let ax = vec2<f32>(vv * dot(u, sx.xyz) - uv * dot(v, sx.xyz), uu * dot(v, sx.xyz) - uv * dot(u, sx.xyz)) / det;
        let ay = vec2<f32>(vv * dot(u, sy.xyz) - uv * dot(v, sy.xyz), uu * dot(v, sy.xyz) - uv * dot(u, sy.xyz)) / det;
        let steps = vec4<f32>(ax, ay);
        return UvSteps(steps, all(abs(steps) < vec4<f32>(3.0e38)));
    }
    // Analytic shapes give uv from the point: the uv at each neighbour's point on the
    // tangent plane is the shape's own answer. Bounded shapes' uvs wrap at a seam, so
    // the step across it is the short way round; the plane's run on unbounded.
    let h = shape_hit(0.0, hit.part);
    let ux = instance_surface(inst, object_ray(xform, Ray(hit.point + sx.xyz, -hit.normal, time)), h).uv - hit.uv;
    let uy = instance_surface(inst, object_ray(xform, Ray(hit.point + sy.xyz, -hit.normal, time)), h).uv - hit.uv;
    var steps = vec4<f32>(ux, uy);
    if inst.kind != KIND_PLANE {
        steps -= round(steps);
    }
    return UvSteps(steps, all(abs(steps) < vec4<f32>(3.0e38)));
}

fn hit_from(r: Ray, found: SceneHit) -> Hit {
    let inst = instances[found.instance];
    let xform = instance_xform(inst, r.time);
    let local = object_ray(xform, r);
    let h = found.shape;
    var hit: Hit;
    hit.t = h.t;
    hit.material = inst.material;
    hit.instance = found.instance;
    hit.part = h.part;
    let to_world = xform.world_from_object;
    if inst.kind != KIND_MESH {
        let s = instance_surface(inst, local, h);
        if CSG_SHAPES && inst.kind == KIND_CSG {
            hit.material = csg_material(h.part);
        }
        let n = normalize_or(normal_to_world(xform, s.normal), vec3<f32>(0.0, 1.0, 0.0));
        hit.point = (to_world * vec4<f32>(s.point, 1.0)).xyz;
        hit.normal = n;
        hit.geometric_normal = n;
        hit.shadow_point = hit.point;
        hit.uv = s.uv;
        hit.color = vec3<f32>(1.0);
        return hit;
    }
    let mesh = meshes[bitcast<u32>(inst.param)];
    let tri = mesh.index_offset + 3u * h.part;
    let i0 = words[tri];
    let i1 = words[tri + 1u];
    let i2 = words[tri + 2u];
    let a = mesh_vertex(mesh, i0);
    let b = mesh_vertex(mesh, i1);
    let c = mesh_vertex(mesh, i2);
    let bary = h.bary;
    var geometric = cross(b - a, c - a);
    let point = bary.x * a + bary.y * b + bary.z * c;
    var normal = geometric;
    var shadow_point = point;
    if mesh.normal_offset != NO_INDEX {
        let n0 = float3(mesh.normal_offset + 3u * i0);
        let n1 = float3(mesh.normal_offset + 3u * i1);
        let n2 = float3(mesh.normal_offset + 3u * i2);
        let n = bary.x * n0 + bary.y * n1 + bary.z * n2;
        if dot(n, n) > 0.0 {
            normal = n;
            if dot(n, geometric) < 0.0 {
                geometric = -geometric;
            }
            shadow_point = terminator_point(point, bary, a, b, c, n0, n1, n2);
        }
    }
    var uv = vec2<f32>(bary.y, bary.z);
    // ∂p/∂u and ∂p/∂v of the triangle, for a normal map.
    var frame = UvFrame(vec3<f32>(0.0), vec3<f32>(0.0), false);
    if mesh.uv_offset != NO_INDEX {
        let uvs = array<vec2<f32>, 3>(mesh_uv(mesh, i0), mesh_uv(mesh, i1), mesh_uv(mesh, i2));
        uv = bary.x * uvs[0] + bary.y * uvs[1] + bary.z * uvs[2];
        // The frame costs a division: only a normal-mapped material needs it.
        if materials[hit.material].normal_texture != NO_TEXTURE {
            frame = uv_frame(array<vec3<f32>, 3>(a, b, c), uvs);
        }
    }
    let dpdu = frame.dpdu;
    let dpdv = frame.dpdv;
    let has_uv_frame = frame.ok;
    var n = normalize_or(normal_to_world(xform, normal), vec3<f32>(0.0, 1.0, 0.0));
    let shading = materials[hit.material];
    if shading.normal_texture != NO_TEXTURE && has_uv_frame {
        let texel = texture_sample(shading.normal_texture, uv * v2(shading.texture_repeat));
        let frame_u = (to_world * vec4<f32>(dpdu, 0.0)).xyz;
        let frame_v = (to_world * vec4<f32>(dpdv, 0.0)).xyz;
        n = bent_normal(frame_u, frame_v, n, texel, shading.normal_scale);
    }
    hit.color = vec3<f32>(1.0);
    if mesh.color_offset != NO_INDEX {
        let c0 = float3(mesh.color_offset + 3u * i0);
        let c1 = float3(mesh.color_offset + 3u * i1);
        let c2 = float3(mesh.color_offset + 3u * i2);
        hit.color = bary.x * c0 + bary.y * c1 + bary.z * c2;
    }
    hit.point = (to_world * vec4<f32>(point, 1.0)).xyz;
    hit.normal = n;
    hit.geometric_normal = normalize_or(normal_to_world(xform, geometric), n);
    hit.shadow_point = (to_world * vec4<f32>(shadow_point, 1.0)).xyz;
    hit.uv = uv;
    return hit;
}
