// Constructive solid geometry traced directly (glint_core::shape::csg): one pass over
// the tree's nodes in post-order with a stack of span lists — leaves push their spans
// along the ray, operations pop two lists and push their combination — then the first
// crossing. Spans live in one bounded array per invocation; a tree whose lists
// outgrow it loses the farthest spans (CSG_SPANS is far beyond the examples' needs).

const KIND_CSG: u32 = 8u;
const CSG_LEAF: u32 = 0u;
const CSG_UNION: u32 = 1u;
const CSG_INTERSECTION: u32 = 2u;
const CSG_DIFFERENCE: u32 = 3u;
const CSG_FLIP: u32 = 128u;
const CSG_SPANS: u32 = 32u;
const CSG_STACK: u32 = 16u;

struct SpanList {
    count: u32,
    spans: array<Span, 8>,
}

fn span_list() -> SpanList {
    var l: SpanList;
    l.count = 0u;
    return l;
}

fn push_span(l: ptr<function, SpanList>, s: Span) {
    if (*l).count < 8u {
        (*l).spans[(*l).count] = s;
        (*l).count += 1u;
    }
}

// Clips `s` to `clip` (glint_core::shape::cylinder::clip).
fn clip_span(s_in: Span, clip: Span) -> Span {
    var s = s_in;
    if clip.enter > s.enter {
        s.enter = clip.enter;
        s.enter_part = clip.enter_part;
    }
    if clip.exit < s.exit {
        s.exit = clip.exit;
        s.exit_part = clip.exit_part;
    }
    return s;
}

// The slab −1 ≤ y ≤ 1, its ends the top (1) and bottom (2) caps; `found` false when
// a ray parallel to it runs outside.
fn slab_span(r: Ray) -> BoxSpan {
    let o = r.origin.y;
    let d = r.dir.y;
    if d == 0.0 {
        return BoxSpan(abs(o) <= 1.0, span_all());
    }
    let t_top = (1.0 - o) / d;
    let t_bottom = (-1.0 - o) / d;
    if d > 0.0 {
        return BoxSpan(true, Span(t_bottom, 2u, t_top, 1u));
    }
    return BoxSpan(true, Span(t_top, 1u, t_bottom, 2u));
}

// The spans of a solid leaf along its object-space ray (Solid::spans of each kind).
fn leaf_spans(kind: u32, param: f32, r: Ray) -> SpanList {
    var out = span_list();
    switch kind {
        case 0u: {
            let t0 = -dot(r.origin, r.dir) / dot(r.dir, r.dir);
            let near = ray_at(r, t0);
            let h = sqrt((1.0 - dot(near, near)) / dot(r.dir, r.dir));
            if h > 0.0 {
                push_span(&out, Span(t0 - h, 0u, t0 + h, 0u));
            }
        }
        case 1u: {
            let b = box_span(r, vec3<f32>(-1.0), vec3<f32>(1.0));
            if b.found {
                push_span(&out, Span(b.span.enter, b.span.enter_part - BOX_FACE, b.span.exit, b.span.exit_part - BOX_FACE));
            }
        }
        case 2u: {
            let o = r.origin;
            let d = r.dir;
            let a = d.x * d.x + d.z * d.z;
            var t0 = 0.0;
            if a > 0.0 {
                t0 = -(o.x * d.x + o.z * d.z) / a;
            }
            let cx = o.x + t0 * d.x;
            let cz = o.z + t0 * d.z;
            let body = quadratic_spans(a, 0.0, cx * cx + cz * cz - 1.0);
            let slab = slab_span(r);
            if body.count > 0u && slab.found {
                var s = body.spans[0];
                s.enter += t0;
                s.exit += t0;
                s = clip_span(s, slab.span);
                if s.enter < s.exit {
                    push_span(&out, s);
                }
            }
        }
        case 3u: {
            let slab = slab_span(r);
            if !slab.found {
                return out;
            }
            var t0 = -dot(r.origin, r.dir) / dot(r.dir, r.dir);
            if !finite(t0) {
                t0 = 0.0;
            }
            let q = cone_quadratic(r.origin + t0 * r.dir, r.dir);
            let body = quadratic_spans(q.x, q.y, q.z);
            for (var k = 0u; k < body.count; k += 1u) {
                var s = body.spans[k];
                s.enter += t0;
                s.exit += t0;
                s = clip_span(s, slab.span);
                if s.enter < s.exit {
                    // The slab's lower end is the base (2); its upper end only the apex.
                    if s.enter_part != 0u && s.enter_part != 2u {
                        s.enter_part = 0u;
                    }
                    if s.exit_part != 0u && s.exit_part != 2u {
                        s.exit_part = 0u;
                    }
                    push_span(&out, s);
                }
            }
        }
        case 4u: {
            let o = r.origin.y;
            let d = r.dir.y;
            if d == 0.0 {
                if o <= 0.0 {
                    push_span(&out, span_all());
                }
                return out;
            }
            let t = -o / d;
            if d > 0.0 {
                push_span(&out, Span(-INF, 0u, t, 0u));
            } else {
                push_span(&out, Span(t, 0u, INF, 0u));
            }
        }
        case 6u: {
            if TORI {
                out = torus_spans(param, r);
            }
        }
        case 11u: {
            if QUADRICS {
                out = quadric_spans(bitcast<u32>(param), r);
            }
        }
        default: {
            if SOLVED_SHAPES && (kind == KIND_SUPERELLIPSOID || kind == KIND_IMPLICIT || kind == KIND_BLOB) {
                out = solved_spans(kind, bitcast<u32>(param), r);
            }
        }
    }
    return out;
}

fn csg_end(l: ptr<function, array<Span, CSG_SPANS>>, start: u32, k: u32) -> vec2<f32> {
    // (t, part as bits) of end k of the list starting at `start`: even k an entry.
    let s = (*l)[start + k / 2u];
    if (k & 1u) == 0u {
        return vec2<f32>(s.enter, bitcast<f32>(s.enter_part));
    }
    return vec2<f32>(s.exit, bitcast<f32>(s.exit_part));
}

fn csg_apply(op: u32, a: bool, b: bool) -> bool {
    switch op {
        case 1u: { return a || b; }
        case 2u: { return a && b; }
        case 3u: { return a && !b; }
        default: { return a; }
    }
}

fn intersect_csg(root: u32, r: Ray, t_max: f32) -> ShapeHit {
    var spans: array<Span, CSG_SPANS>;
    var result: array<Span, CSG_SPANS>;
    var stack_start: array<u32, CSG_STACK>;
    var stack_len: array<u32, CSG_STACK>;
    var used = 0u;
    var top = 0u;
    let inv = 1.0 / r.dir;
    let first = csg_nodes[root].first;
    for (var index = first; index <= root; index += 1u) {
        let node = csg_nodes[index];
        if node.op == CSG_LEAF {
            let start = used;
            if csg_reaches(node, r, inv, t_max) {
                let local = object_ray(Xform(node.world_from_object, node.object_from_world), r);
                let leaf = leaf_spans(node.kind, node.param, local);
                for (var k = 0u; k < leaf.count; k += 1u) {
                    if used < CSG_SPANS {
                        var s = leaf.spans[k];
                        s.enter_part = (index << 8u) | s.enter_part;
                        s.exit_part = (index << 8u) | s.exit_part;
                        spans[used] = s;
                        used += 1u;
                    }
                }
            }
            if top < CSG_STACK {
                stack_start[top] = start;
                stack_len[top] = used - start;
                top += 1u;
            }
            continue;
        }
        if top < 2u {
            return no_hit();
        }
        let b_start = stack_start[top - 1u];
        let b_len = stack_len[top - 1u];
        let a_start = stack_start[top - 2u];
        let a_len = stack_len[top - 2u];
        top -= 2u;
        // combine(op, a, b) into `result`.
        var n = 0u;
        let na = 2u * a_len;
        let nb = 2u * b_len;
        var ia = 0u;
        var ib = 0u;
        var in_a = false;
        var in_b = false;
        var inside = false;
        var open = vec2<f32>(0.0, 0.0);
        while ia < na || ib < nb {
            var ta = INF;
            if ia < na {
                ta = csg_end(&spans, a_start, ia).x;
            }
            var tb = INF;
            if ib < nb {
                tb = csg_end(&spans, b_start, ib).x;
            }
            let t = min(ta, tb);
            var from_a = false;
            var hit_a = vec2<f32>(0.0);
            var from_b = false;
            var hit_b = vec2<f32>(0.0);
            while ia < na && csg_end(&spans, a_start, ia).x == t {
                in_a = (ia & 1u) == 0u;
                from_a = true;
                hit_a = csg_end(&spans, a_start, ia);
                ia += 1u;
            }
            while ib < nb && csg_end(&spans, b_start, ib).x == t {
                in_b = (ib & 1u) == 0u;
                from_b = true;
                hit_b = csg_end(&spans, b_start, ib);
                ib += 1u;
            }
            if !from_a && !from_b {
                break;
            }
            let now = csg_apply(node.op, in_a, in_b);
            if now == inside {
                continue;
            }
            inside = now;
            var surface = hit_a;
            if !from_a {
                surface = hit_b;
                if node.op == CSG_DIFFERENCE {
                    surface.y = bitcast<f32>(bitcast<u32>(surface.y) ^ CSG_FLIP);
                }
            }
            if now {
                open = surface;
            } else if open.x < surface.x && n < CSG_SPANS {
                result[n] = Span(open.x, bitcast<u32>(open.y), surface.x, bitcast<u32>(surface.y));
                n += 1u;
            }
        }
        // The result replaces both operands, which are adjacent (a before b).
        let room = min(n, CSG_SPANS - a_start);
        for (var k = 0u; k < room; k += 1u) {
            spans[a_start + k] = result[k];
        }
        used = a_start + room;
        stack_start[top] = a_start;
        stack_len[top] = room;
        top += 1u;
    }
    if top == 0u {
        return no_hit();
    }
    let start = stack_start[top - 1u];
    let len = stack_len[top - 1u];
    for (var k = 0u; k < len; k += 1u) {
        let c = span_crossing(spans[start + k]);
        if c.found {
            return nearer_than(c, t_max);
        }
    }
    return no_hit();
}

// Whether a leaf's box (in the CSG object's space) meets the ray within [0, t_max].
fn csg_reaches(node: CsgNode, r: Ray, inv: vec3<f32>, t_max: f32) -> bool {
    let lo = v3(node.min);
    let hi = v3(node.max);
    if !(all(abs(lo) < vec3<f32>(UNBOUNDED)) && all(abs(hi) < vec3<f32>(UNBOUNDED))) {
        return all(lo <= hi);
    }
    let t0 = (lo - r.origin) * inv;
    let t1 = (hi - r.origin) * inv;
    let near = max(max3(min(t0, t1)), 0.0);
    let far = min(min(min(max(t0, t1).x, max(t0, t1).y), max(t0, t1).z), t_max);
    return near <= far;
}

// The leaf a CSG hit came from, whether its normal flips, and its own part.
fn csg_leaf(part: u32) -> vec3<u32> {
    return vec3<u32>(part >> 8u, select(0u, 1u, (part & CSG_FLIP) != 0u), part & (CSG_FLIP - 1u));
}

fn csg_material(part: u32) -> u32 {
    return csg_nodes[csg_leaf(part).x].material;
}

fn csg_surface(r: Ray, hit: ShapeHit) -> SurfacePoint {
    let leaf = csg_leaf(hit.part);
    let node = csg_nodes[leaf.x];
    let x = Xform(node.world_from_object, node.object_from_world);
    let local = object_ray(x, r);
    let leaf_hit = ShapeHit(true, hit.t, leaf.z, vec3<f32>(0.0));
    var s: SurfacePoint;
    if QUADRICS && node.kind == KIND_QUADRIC {
        s = quadric_surface(bitcast<u32>(node.param), local, leaf_hit);
    } else if TORI && node.kind == KIND_TORUS {
        s = torus_surface(node.param, local, leaf_hit);
    } else if SOLVED_SHAPES && node.kind == KIND_SUPERELLIPSOID {
        s = superellipsoid_surface(bitcast<u32>(node.param), local, leaf_hit);
    } else if IMPLICITS && node.kind == KIND_IMPLICIT {
        s = implicit_surface(bitcast<u32>(node.param), local, leaf_hit);
    } else if BLOBS && node.kind == KIND_BLOB {
        s = blob_surface(bitcast<u32>(node.param), local, leaf_hit);
    } else {
        s = analytic_surface(node.kind, local, leaf_hit);
    }
    let n = normal_to_world(x, s.normal);
    return SurfacePoint((node.world_from_object * vec4<f32>(s.point, 1.0)).xyz, select(n, -n, leaf.y == 1u), s.uv);
}
