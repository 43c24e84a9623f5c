// The Whitted integrator (glint_core::integrator::whitted): ambient, every light's
// shadow-tested Phong terms, and the reflected and transmitted rays, recursively. The
// recursion is a loop over an explicit stack visited depth first in the CPU's order,
// so the sample's random stream (glint_core::sampling::Rng) is drawn in the same order:
// the lens, then each light's jitter at each hit.

// The LIGHT_*, FEATURE_*, PATTERN_* and INTEGRATOR_* constants and NO_TEXTURE come
// from Rust (crate::shader::constants).

fn feature(bit: u32) -> bool {
    return (params.features & bit) != 0u;
}

fn positive_infinity() -> f32 {
    return bitcast<f32>(0x7f800000u);
}

// ---- glint_core::sampling::rng ----

fn hash4(a: u32, b: u32, c: u32, d: u32) -> u32 {
    return hash_step(hash3(a, b, c), d);
}

// PCG-RXS-M-XS-32: the state of a 32-bit LCG, output through a random xorshift, a
// multiply and a fixed xorshift.
fn rng_new(seed: u32) -> u32 {
    return mix32(seed);
}

fn rng_next_u32(state: ptr<function, u32>) -> u32 {
    *state = *state * 747796405u + 2891336453u;
    let s = *state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (word >> 22u) ^ word;
}

fn rng_next_f32(state: ptr<function, u32>) -> f32 {
    return unit_float(rng_next_u32(state));
}

// ---- glint_core::sampling::pattern ----

// Where sample `index` of pixel (px, py) lies in it: the pixel pattern's point, or the
// centre in an adaptive pilot round (glint_core::render::adaptive_tile).
fn whitted_offset(px: u32, py: u32, index: u32) -> vec2<f32> {
    if params.adaptive_first == ADAPTIVE_PILOT {
        return vec2<f32>(0.5);
    }
    return pixel_offset(px, py, index);
}

// PixelSampler::offset: sample `index` of pixel (px, py) as an offset in [0, 1]² from
// the pixel's top-left corner.
fn pixel_offset(px: u32, py: u32, index: u32) -> vec2<f32> {
    let n = max(params.per_axis, 1u);
    switch params.pattern {
        case PATTERN_GRID: {
            let i = index % (n * n);
            return vec2<f32>(f32(i % n) + 0.5, f32(i / n) + 0.5) / f32(n);
        }
        case PATTERN_CORNERS: {
            let corners = array<vec2<f32>, 5>(
                vec2<f32>(0.5, 0.5),
                vec2<f32>(0.0, 0.0),
                vec2<f32>(1.0, 0.0),
                vec2<f32>(0.0, 1.0),
                vec2<f32>(1.0, 1.0),
            );
            return corners[index % 5u];
        }
        case PATTERN_JITTERED: {
            let i = index % (n * n);
            let h = hash4(px, py, index / (n * n), params.pattern_seed);
            let jitter = vec2<f32>(unit_float(hash3(h, i, 0u)), unit_float(hash3(h, i, 1u)));
            return (vec2<f32>(f32(i % n), f32(i / n)) + jitter) / f32(n);
        }
        default: {
            // PATTERN_SOBOL, Owen-scrambled: owen_scramble(x, s) = reverse(laine_karras(reverse(x), s)),
            // and the reversed dimensions are the index itself and sobol_y_reversed.
            let seed = hash3(px, py, params.pattern_seed);
            let x = reverseBits(laine_karras(index, seed));
            let y = reverseBits(laine_karras(sobol_y_reversed(index), seed ^ 0x9e3779b9u));
            return vec2<f32>(unit_float(x), unit_float(y));
        }
    }
}

// ---- glint_core::light ----

struct Incidence {
    // Unit vector toward the light, the lecture's l.
    to_light: vec3<f32>,
    // INF (the largest float, which no hit reaches) for directional lights.
    distance: f32,
    // f_att · L, with a spot light's cone falloff and an area sample's share.
    radiance: vec3<f32>,
}

// Point, directional and spot lights: one sample, no jitter used.
fn is_single(l: Light) -> bool {
    return l.kind == LIGHT_POINT || l.kind == LIGHT_DIRECTIONAL || l.kind == LIGHT_SPOT;
}

fn light_sample_count(l: Light) -> u32 {
    if is_single(l) {
        return 1u;
    }
    return l.samples_per_axis * l.samples_per_axis;
}

// f_att = min(1, 1/(c1 + c2·d + c3·d²)).
fn f_att(l: Light, d: f32) -> f32 {
    let c = v3(l.attenuation);
    return min(1.0 / (c.x + c.y * d + c.z * d * d), 1.0);
}

// 1 inside the inner cone, 0 outside the outer one, the smooth cubic (or a linear
// fade) across the penumbra.
fn light_spot_falloff(l: Light, from_light: vec3<f32>) -> f32 {
    let angle = acos(clamp(dot(from_light, v3(l.direction)), -1.0, 1.0));
    if angle <= l.inner_angle {
        return 1.0;
    }
    if angle >= l.outer_angle {
        return 0.0;
    }
    let x = (angle - l.inner_angle) / (l.outer_angle - l.inner_angle);
    if l.linear_falloff != 0u {
        return 1.0 - x;
    }
    return 1.0 - x * x * (3.0 - 2.0 * x);
}

// Light::incidence: the point, directional and spot lights.
fn light_incidence(l: Light, p: vec3<f32>) -> Incidence {
    if l.kind == LIGHT_DIRECTIONAL {
        return Incidence(-v3(l.direction), INF, v3(l.color));
    }
    let offset = v3(l.position) - p;
    let distance = length(offset);
    let to_light = offset / distance;
    var cone = 1.0;
    if l.kind == LIGHT_SPOT {
        cone = light_spot_falloff(l, -to_light);
    }
    return Incidence(to_light, distance, f_att(l, distance) * cone * v3(l.color));
}

// light.rs disk_point: the point of the disk of `radius` facing `normal` at u in
// [0, 1)², by Shirley and Chiu's concentric mapping.
fn disk_point(normal: vec3<f32>, radius: f32, u: vec2<f32>) -> vec3<f32> {
    let tb = orthonormal_pair(normalize_or(normal, vec3<f32>(0.0, 1.0, 0.0)));
    let d = 2.0 * u - vec2<f32>(1.0);
    if d.x == 0.0 && d.y == 0.0 {
        return vec3<f32>(0.0);
    }
    var r: f32;
    var theta: f32;
    if abs(d.x) > abs(d.y) {
        r = d.x;
        theta = (PI / 4.0) * (d.y / d.x);
    } else {
        r = d.y;
        theta = PI / 2.0 - (PI / 4.0) * (d.x / d.y);
    }
    return radius * r * (cos(theta) * tb[0] + sin(theta) * tb[1]);
}

// Light::sample: sample `index` of light_sample_count, jittered inside its stratum;
// an area light's intensity is shared equally by its samples.
fn light_sample(l: Light, p: vec3<f32>, index: u32, jitter: vec2<f32>) -> Incidence {
    if is_single(l) {
        return light_incidence(l, p);
    }
    let n = l.samples_per_axis;
    let u = (vec2<f32>(f32(index % n), f32(index / n)) + jitter) / f32(n);
    var point: vec3<f32>;
    if l.kind == LIGHT_RECTANGLE {
        point = v3(l.position) + u.x * v3(l.edge_u) + u.y * v3(l.edge_v);
    } else if l.kind == LIGHT_DISK {
        point = v3(l.position) + disk_point(v3(l.direction), l.radius, u);
    } else {
        // LIGHT_SPHERE: the disk the sphere presents to p.
        point = v3(l.position) + disk_point(p - v3(l.position), l.radius, u);
    }
    let offset = point - p;
    let distance = length(offset);
    let share = 1.0 / f32(light_sample_count(l));
    return Incidence(offset / distance, distance, share * f_att(l, distance) * v3(l.color));
}

// ---- shading ----

// Mirror direction of d about the unit normal n: d − 2(d·n)n.
fn reflect_dir(d: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return d - 2.0 * dot(d, n) * n;
}

struct Refraction {
    found: bool,
    dir: vec3<f32>,
}

// Snell's law for unit d arriving against unit n, eta = η₁/η₂; none past the critical
// angle (total internal reflection).
fn refract_dir(d: vec3<f32>, n: vec3<f32>, eta: f32) -> Refraction {
    let cos_i = -dot(d, n);
    let sin2_t = eta * eta * max(1.0 - cos_i * cos_i, 0.0);
    if sin2_t > 1.0 {
        return Refraction(false, vec3<f32>(0.0));
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return Refraction(true, eta * d + (eta * cos_i - cos_t) * n);
}

// Rust's powf for x ≥ 0: x⁰ = 1 (WGSL's pow leaves 0⁰ undefined) and 0^y = 0 for y > 0.
fn pow_nonnegative(x: f32, y: f32) -> f32 {
    if y == 0.0 {
        return 1.0;
    }
    if x == 0.0 {
        return select(0.0, positive_infinity(), y < 0.0);
    }
    return pow(x, y);
}

// A ray still to shade: its depth in the ray tree and the product of the k·O factors
// that lead to it from the pixel.
struct Pending {
    origin: vec3<f32>,
    dir: vec3<f32>,
    depth: u32,
    weight: vec3<f32>,
}

// One pending ray per level waits while its sibling's subtree is shaded, plus the two
// children just pushed: max_depth (≤ 64) + 1 entries at most.
const WHITTED_STACK: u32 = 66u;

// A hit being shaded (whitted::direct_lighting), kept across the loop iterations that
// trace its shadow rays.
struct Shading {
    // The ray that found the hit.
    entry: Pending,
    hit: Hit,
    m: Material,
    // The unit ray direction; n faces the viewer and ng, the true surface's normal on
    // the same side, carries the ray offsets.
    d: vec3<f32>,
    entering: bool,
    n: vec3<f32>,
    ng: vec3<f32>,
    diffuse: vec3<f32>,
    specular: vec3<f32>,
    shadow_origin: vec3<f32>,
    // Ambient plus the light samples added so far.
    direct: vec3<f32>,
    // The next light sample to draw: the light and its sample index.
    light: u32,
    sample: u32,
    // The sample whose shadow ray is traced: its incidence and the Phong factor
    // k_d (n·l) + k_s (r·v)^shininess it is multiplied by.
    incidence: Incidence,
    phong: vec3<f32>,
}

// The current sample's footprint as a fraction of a pixel (TraceContext::footprint_scale).
var<private> sample_footprint_scale: f32 = 1.0;

// glint_core::scene::Settings::sample_footprint: in adaptive rounds sample k is filtered
// as one of k + 1; a uniform render's scale rides in pixel_dx.w.
fn sample_footprint(index: u32) -> f32 {
    if params.adaptive_min > 0u {
        return max(1.0 / sqrt(f32(index + 1u)), 0.125);
    }
    return params.pixel_dx.w;
}

// glint_core::scene::RenderScene::texture_at_hit: averaged over the pixel's footprint
// when the texture is filtered.
fn texture_at_hit(index: u32, hit: Hit, repeat: vec2<f32>, time: f32) -> vec3<f32> {
    let uv = hit.uv * repeat;
    if !texture_is_filtered(index) {
        return texture_sample(index, uv);
    }
    let footprint = uv_steps(hit, time, sample_footprint_scale);
    return texture_sample_over(index, uv, footprint.steps * vec4<f32>(repeat, repeat), footprint.bounded);
}

fn shading_of(entry: Pending, r: Ray, hit: Hit) -> Shading {
    var s: Shading;
    s.entry = entry;
    s.hit = hit;
    let m = materials[hit.material];
    s.m = m;
    s.d = normalize(r.dir);
    s.entering = dot(hit.geometric_normal, s.d) < 0.0;
    s.n = select(-hit.normal, hit.normal, s.entering);
    s.ng = select(-hit.geometric_normal, hit.geometric_normal, s.entering);
    var diffuse = v3(m.diffuse);
    var ambient = v3(m.ambient);
    if feature(FEATURE_TEXTURES) && m.texture != NO_TEXTURE {
        let texel = texture_at_hit(m.texture, hit, v2(m.texture_repeat), r.time);
        diffuse = (1.0 - m.blend) * diffuse + m.blend * m.kd * texel;
        ambient = (1.0 - m.ambient_blend) * ambient + m.ambient_blend * m.ka * texel;
    }
    s.diffuse = diffuse * hit.color;
    s.specular = v3(m.specular);
    s.direct = params.ambient.xyz * ambient * hit.color;
    // Seen from outside, a smooth mesh's shadow rays start on the surface its normals
    // describe (Hanika 2021).
    let outside = dot(hit.geometric_normal, s.n) >= 0.0;
    let shadow_side = select(-hit.geometric_normal, hit.geometric_normal, outside);
    s.shadow_origin = offset_ray_origin(select(hit.point, hit.shadow_point, outside), shadow_side);
    s.light = 0u;
    s.sample = 0u;
    return s;
}

// Material::highlight: (r·v)^n, or Blinn's (n·h)^n.
fn highlight_of(m: Material, n: vec3<f32>, l: vec3<f32>, v: vec3<f32>) -> f32 {
    var cosine = dot(reflect_dir(-l, n), v);
    if m.highlight == BLINN_HIGHLIGHT {
        let h = l + v;
        let length2 = dot(h, h);
        cosine = select(0.0, dot(h, n) / sqrt(length2), length2 > 0.0);
    }
    return pow_nonnegative(max(cosine, 0.0), m.shininess);
}

// Draws light samples (each its jitter) until one needs a shadow ray: true, with its
// incidence and Phong factor in `s`. Without shadows, samples are added at once.
fn next_light_sample(s: ptr<function, Shading>, rng: ptr<function, u32>) -> bool {
    while (*s).light < params.light_count {
        let l = lights[(*s).light];
        if (*s).sample >= light_sample_count(l) {
            (*s).light += 1u;
            (*s).sample = 0u;
            continue;
        }
        let index = (*s).sample;
        (*s).sample += 1u;
        let jx = rng_next_f32(rng);
        let jy = rng_next_f32(rng);
        let incidence = light_sample(l, (*s).hit.point, index, vec2<f32>(jx, jy));
        let n_dot_l = dot((*s).n, incidence.to_light);
        if n_dot_l <= 0.0 || all(incidence.radiance == vec3<f32>(0.0)) {
            continue;
        }
        var highlight = 0.0;
        if any((*s).specular != vec3<f32>(0.0)) {
            highlight = highlight_of((*s).m, (*s).n, incidence.to_light, -(*s).d);
        }
        (*s).incidence = incidence;
        (*s).phong = (*s).diffuse * n_dot_l + (*s).specular * highlight;
        if !feature(FEATURE_SHADOWS) {
            (*s).direct += vec3<f32>(1.0) * incidence.radiance * (*s).phong;
            continue;
        }
        return true;
    }
    return false;
}

// whitted::radiance of a camera ray. Every hit adds weight × (its direct lighting),
// every miss weight × background: the recursive sum, expanded. One loop iteration
// traces one ray: a camera, reflected or transmitted ray, or a shadow ray of the hit
// being shaded, so that drivers that inline every call (Mesa) compile the scene's
// intersection code once in this kernel. Light samples draw their jitter and add
// their terms in the CPU's order.
fn whitted_radiance(camera: Ray, rng: ptr<function, u32>) -> vec3<f32> {
    var stack: array<Pending, WHITTED_STACK>;
    var top = 0u;
    var color = vec3<f32>(0.0);
    var entry = Pending(camera.origin, camera.dir, 0u, vec3<f32>(1.0));
    var r = camera;
    var t_max = INF;
    var shading: Shading;
    var shading_active = false;
    // Whether r is a shadow ray of `shading`: an any-hit test when every surface is
    // opaque to it, else the surfaces it crosses one at a time
    // (glint_core::scene::RenderScene::transmittance): zero if an opaque surface blocks
    // it, else the product of k_t·O_t of every surface crossed.
    var shadow = false;
    var any_hit = false;
    var shadow_filter = vec3<f32>(1.0);
    var crossing = 0u;
    loop {
        let found = trace_scene(r, t_max, any_hit);
        var hit: Hit;
        if found.found && !any_hit {
            hit = hit_from(r, found);
        }
        if shadow {
            if any_hit {
                if found.found {
                    shadow_filter = vec3<f32>(0.0);
                }
            } else if found.found {
                if !casts_no_shadow(found.instance) {
                    shadow_filter *= v3(materials[hit.material].transmissive);
                }
                crossing += 1u;
                if max3(shadow_filter) <= 0.0 || crossing >= 64u {
                    shadow_filter = vec3<f32>(0.0);
                } else {
                    let ng = hit.geometric_normal;
                    let side = select(-ng, ng, dot(ng, r.dir) > 0.0);
                    let origin = offset_ray_origin(hit.point, side);
                    // Keep the far end fixed; an infinite segment (a directional light) stays so.
                    if t_max < INF {
                        let end = ray_at(r, t_max);
                        t_max = dot(end - origin, r.dir) / dot(r.dir, r.dir);
                    }
                    r.origin = origin;
                    continue;
                }
            }
            if !all(shadow_filter == vec3<f32>(0.0)) {
                shading.direct += shadow_filter * shading.incidence.radiance * shading.phong;
            }
        } else if !found.found {
            var background = params.background.xyz;
            if params.environment_kind != ENV_NONE {
                background = env_radiance(r.dir);
            }
            color += entry.weight * background;
        } else {
            shading = shading_of(entry, r, hit);
            shading_active = true;
            if entry.depth == 0u {
                record_first_hit(shading.diffuse, hit.normal, hit.t * length(r.dir));
            }
        }
        if shading_active && next_light_sample(&shading, rng) {
            r = Ray(shading.shadow_origin, shading.incidence.to_light, camera.time);
            t_max = shading.incidence.distance;
            any_hit = !(feature(FEATURE_TRANSPARENT_SHADOWS) && params.has_transmissive != 0u);
            shadow = true;
            shadow_filter = vec3<f32>(1.0);
            crossing = 0u;
            continue;
        }
        if shading_active {
            shading_active = false;
            let e = shading.entry;
            let m = shading.m;
            color += e.weight * shading.direct;
            blame(shading.hit.instance, color);
            if e.depth < params.max_depth {
                let point = shading.hit.point;
                let d = shading.d;
                let n = shading.n;
                let ng = shading.ng;
                let reflected_dir = reflect_dir(d, n);
                let reflect_weight = e.weight * v3(m.reflective);
                let transmit_weight = e.weight * v3(m.transmissive);
                // Push the transmitted ray first so that the reflected subtree is shaded
                // (and draws its numbers) first, as the CPU recursion does.
                if feature(FEATURE_REFRACTIONS) && max3(transmit_weight) > params.min_contribution && top < WHITTED_STACK {
                    var eta = m.ior;
                    if shading.entering {
                        eta = 1.0 / m.ior;
                    }
                    var t = Refraction(true, d);
                    if m.ior != 1.0 {
                        t = refract_dir(d, n, eta);
                    }
                    if t.found {
                        stack[top] = Pending(offset_ray_origin(point, -ng), t.dir, e.depth + 1u, transmit_weight);
                    } else {
                        // Total internal reflection: the transmitted share is reflected instead.
                        stack[top] = Pending(offset_ray_origin(point, ng), reflected_dir, e.depth + 1u, transmit_weight);
                    }
                    top += 1u;
                }
                if feature(FEATURE_REFLECTIONS) && max3(reflect_weight) > params.min_contribution && top < WHITTED_STACK {
                    stack[top] = Pending(offset_ray_origin(point, ng), reflected_dir, e.depth + 1u, reflect_weight);
                    top += 1u;
                }
            }
        }
        if top == 0u {
            break;
        }
        top -= 1u;
        entry = stack[top];
        r = Ray(entry.origin, entry.dir, camera.time);
        t_max = INF;
        any_hit = false;
        shadow = false;
    }
    return color;
}

// One Whitted sample of pixel (px, py), index `index` (render.rs camera_sample): the
// film position from the pixel pattern, then a stream seeded by hash(px, py, index,
// seed) whose first two numbers place the ray on the lens.
fn whitted_sample(px: u32, py: u32, index: u32) -> vec3<f32> {
    sample_footprint_scale = sample_footprint(index);
    let offset = whitted_offset(px, py, index);
    var rng = rng_new(hash4(px, py, index, params.seed));
    let lx = rng_next_f32(&rng);
    let ly = rng_next_f32(&rng);
    let fx = f32(px) + offset.x;
    let fy = f32(py) + offset.y;
    var r = camera_ray(2.0 * fx / f32(params.width) - 1.0, 1.0 - 2.0 * fy / f32(params.height), vec2<f32>(lx, ly));
    if params.has_motion != 0u {
        // A moment in the shutter interval, drawn after the lens as the CPU draws it.
        r.time = rng_next_f32(&rng);
    }
    return whitted_radiance(r, &rng);
}

@compute @workgroup_size(8, 8, 1)
fn trace_whitted(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let index = pass_sample(id);
    if index != NO_INDEX {
        write_sample(id, whitted_sample(id.x, id.y, index));
    }
}
