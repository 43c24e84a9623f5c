// Unidirectional path tracing with next-event estimation and MIS (power heuristic):
// glint_core::integrator::path, one sample per invocation, drawing its numbers from
// the same path sampler in the same order as the CPU.

struct Frame {
    s: vec3<f32>,
    t: vec3<f32>,
    n: vec3<f32>,
}

fn frame_of(n: vec3<f32>) -> Frame {
    let st = orthonormal_pair(n);
    return Frame(st[0], st[1], n);
}

fn to_local(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.s), dot(v, f.t), dot(v, f.n));
}

fn to_world(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return v.x * f.s + v.y * f.t + v.z * f.n;
}

fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    return select(0.0, a2 / (a2 + b2), a2 + b2 > 0.0);
}

fn same_side_story(hit: Hit, wo_world: vec3<f32>, wi_world: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> bool {
    let ng = hit.geometric_normal;
    return (wo.z * wi.z > 0.0) == (dot(ng, wo_world) * dot(ng, wi_world) > 0.0);
}

fn side_normal(hit: Hit, w: vec3<f32>) -> vec3<f32> {
    return select(-hit.geometric_normal, hit.geometric_normal, dot(hit.geometric_normal, w) >= 0.0);
}

struct Bounce {
    valid: bool,
    point: vec3<f32>,
    pdf: f32,
    delta: bool,
}

fn light_probability(index: u32) -> f32 {
    return probability(params.light_cdf_offset, index);
}

fn emitted(hit: Hit, bsdf_index: u32, wo: vec3<f32>, previous: Bounce) -> vec3<f32> {
    let r = bsdfs[bsdf_index];
    var emission = v3(r.emission);
    if !(max3(emission) > 0.0) {
        return vec3<f32>(0.0);
    }
    // A textured emitter is not among the sampled lights (weight 1 below).
    if r.emission_texture != NO_TEXTURE {
        emission *= texture_sample(r.emission_texture, hit.uv * v2(r.uv_repeat));
    }
    let front = dot(hit.geometric_normal, wo) > 0.0;
    if !front && (r.flags & EMITS_BOTH_SIDES) == 0u {
        return vec3<f32>(0.0);
    }
    var weight = 1.0;
    if previous.valid && !previous.delta && params.emitter_count > 0u {
        let index = emitter_of(hit);
        if index != NO_INDEX {
            let light_pdf = light_probability(index) * emitter_pdf(emitters[index], previous.point, hit.point, hit.geometric_normal);
            weight = power_heuristic(previous.pdf, light_pdf);
        }
    }
    return emission * weight;
}

fn environment_light(r: Ray, previous: Bounce) -> vec3<f32> {
    if params.environment_kind == ENV_NONE {
        return params.background.xyz;
    }
    let l = env_radiance(r.dir);
    if previous.valid && !previous.delta && params.emitter_count > 0u {
        let light_pdf = light_probability(params.environment_emitter) * env_pdf(normalize(r.dir));
        return l * power_heuristic(previous.pdf, light_pdf);
    }
    return l;
}

// A shadow ray of next-event estimation, traced later (any hit, up to t_max): `found`
// when one was sampled, and what the path gains (throughput included) if unoccluded.
struct ShadowTest {
    found: bool,
    ray: Ray,
    t_max: f32,
    contribution: vec3<f32>,
}

fn no_shadow_test() -> ShadowTest {
    return ShadowTest(false, Ray(vec3<f32>(0.0), vec3<f32>(0.0), 0.0), 0.0, vec3<f32>(0.0));
}

// Next-event estimation: one light sampled, its MIS-weighted contribution, and the
// shadow ray that decides whether it counts.
fn direct_light(hit: Hit, bsdf: SurfaceBsdf, f: Frame, wo: vec3<f32>, u_select: f32, u: vec2<f32>, time: f32) -> ShadowTest {
    if params.emitter_count == 0u {
        return no_shadow_test();
    }
    let index = sample_discrete(params.light_cdf_offset, params.emitter_count, u_select).index;
    let p_select = light_probability(index);
    let e = emitters[index];
    var sample: LightSample;
    if e.kind == EM_ENVIRONMENT {
        if params.environment_kind == ENV_NONE {
            return no_shadow_test();
        }
        sample = sample_environment(u);
    } else {
        sample = sample_emitter(e, hit.point, u);
    }
    if !sample.found || !(sample.pdf > 0.0) || all(sample.radiance == vec3<f32>(0.0)) {
        return no_shadow_test();
    }
    let wi = to_local(f, sample.wi);
    if !same_side_story(hit, to_world(f, wo), sample.wi, wo, wi) {
        return no_shadow_test();
    }
    let value = bsdf_eval(bsdf, wo, wi) * abs(wi.z);
    if all(value == vec3<f32>(0.0)) {
        return no_shadow_test();
    }
    let origin = offset_ray_origin(hit.point, side_normal(hit, sample.wi));
    var t_max = INF;
    if finite(sample.distance) && sample.distance < INF {
        t_max = sample.distance * (1.0 - 1e-4);
    }
    let light_pdf = p_select * sample.pdf;
    var weight = 1.0;
    if !sample.delta {
        weight = power_heuristic(light_pdf, bsdf_pdf(bsdf, wo, wi));
    }
    return ShadowTest(true, Ray(origin, sample.wi, time), t_max, value * sample.radiance * (weight / light_pdf));
}

// One loop iteration traces one ray: the pending shadow ray of next-event estimation
// if there is one, else the path's next extension ray. Drivers that inline every call
// (Mesa) then compile the scene's intersection code once in this kernel. The numbers
// are drawn, and contributions added, in the CPU's order.
fn path_radiance(camera_ray: Ray, sampler: ptr<function, PathSampler>) -> vec3<f32> {
    if params.max_depth == 0u {
        return vec3<f32>(0.0);
    }
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    var eta = 1.0;
    var r = camera_ray;
    var previous = Bounce(false, vec3<f32>(0.0), 0.0, false);
    var depth = 0u;
    var shadow = no_shadow_test();
    // The path has ended; only its last shadow ray may remain.
    var ended = false;
    loop {
        if ended && !shadow.found {
            break;
        }
        var ray = r;
        var t_max = INF;
        if shadow.found {
            ray = shadow.ray;
            t_max = shadow.t_max;
        }
        let found = trace_scene(ray, t_max, shadow.found);
        if shadow.found {
            if !found.found {
                radiance += shadow.contribution;
            }
            shadow.found = false;
            continue;
        }
        if !found.found {
            radiance += throughput * environment_light(r, previous);
            break;
        }
        let hit = hit_from(r, found);
        let wo_world = -normalize(r.dir);
        var bsdf = surface_bsdf(hit.material, hit.uv);
        bsdf.color *= hit.color;
        if depth == 0u {
            record_first_hit(bsdf_albedo(bsdf), hit.normal, hit.t * length(r.dir));
        }
        radiance += throughput * emitted(hit, hit.material, wo_world, previous);
        blame(hit.instance, radiance);
        if depth + 1u >= params.max_depth {
            break;
        }
        let f = frame_of(hit.normal);
        let wo = to_local(f, wo_world);
        let choices = next_2d(sampler);
        let u_light = next_2d(sampler);
        let u_dir = next_2d(sampler);
        if has_non_delta(bsdf) {
            shadow = direct_light(hit, bsdf, f, wo, choices.x, u_light, r.time);
            shadow.contribution = throughput * shadow.contribution;
            blame(hit.instance, shadow.contribution);
        }
        let s = bsdf_sample(bsdf, wo, choices.y, u_dir);
        if !s.found {
            ended = true;
            continue;
        }
        let wi = to_world(f, s.wi);
        if !same_side_story(hit, wo_world, wi, wo, s.wi) {
            ended = true;
            continue;
        }
        throughput *= s.weight;
        blame(hit.instance, throughput);
        eta *= s.eta;
        r = Ray(offset_ray_origin(hit.point, side_normal(hit, wi)), wi, r.time);
        previous = Bounce(true, hit.point, s.pdf, s.delta);
        depth += 1u;
        let most = max3(throughput);
        if !(most > 0.0) || !finite3(throughput) {
            ended = true;
            continue;
        }
        if depth >= params.rr_depth {
            let survive = min(most * eta * eta, 0.95);
            if next_1d(sampler) >= survive {
                ended = true;
                continue;
            }
            throughput /= survive;
        }
    }
    return radiance;
}

// ---- the camera (glint_core::camera) ----

fn camera_ray(x: f32, y: f32, lens: vec2<f32>) -> Ray {
    let eye = params.eye.xyz;
    let film_point = (params.world_from_canonical * vec4<f32>(x, y, -1.0, 1.0)).xyz;
    let pinhole = Ray(eye, normalize(film_point - eye), 0.0);
    if params.aperture_radius <= 0.0 {
        return pinhole;
    }
    let focus = ray_at(pinhole, params.focal_distance / dot(pinhole.dir, params.forward.xyz));
    let on_lens = params.aperture_radius * concentric_disk(lens);
    let origin = eye + on_lens.x * params.right.xyz + on_lens.y * params.up.xyz;
    return Ray(origin, normalize(focus - origin), 0.0);
}

// One path sample of pixel (px, py), index `index`: the film position it landed on
// (first two numbers of its sampler) and its radiance.
fn path_sample(px: u32, py: u32, index: u32) -> vec3<f32> {
    var sampler = path_sampler(params.sampler == 0u, px, py, index, params.seed);
    let offset = next_2d(&sampler);
    var lens = vec2<f32>(0.5);
    if params.aperture_radius > 0.0 {
        lens = next_2d(&sampler);
    }
    let fx = f32(px) + offset.x;
    let fy = f32(py) + offset.y;
    var r = camera_ray(2.0 * fx / f32(params.width) - 1.0, 1.0 - 2.0 * fy / f32(params.height), lens);
    if params.has_motion != 0u {
        r.time = next_1d(&sampler);
    }
    return path_radiance(r, &sampler);
}

@compute @workgroup_size(8, 8, 1)
fn trace_path(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let index = pass_sample(id);
    if index != NO_INDEX {
        write_sample(id, path_sample(id.x, id.y, index));
    }
}
