// Light sources for next-event estimation (glint_core::emitter) and the environment
// (glint_core::emitter::environment).

const EM_TRIANGLE: u32 = 0u;
const EM_PARALLELOGRAM: u32 = 1u;
const EM_DISK: u32 = 2u;
const EM_SPHERE: u32 = 3u;
const EM_POINT: u32 = 4u;
const EM_SPOT: u32 = 5u;
const EM_DIRECTIONAL: u32 = 6u;
const EM_ENVIRONMENT: u32 = 7u;

struct LightSample {
    found: bool,
    wi: vec3<f32>,
    distance: f32,
    radiance: vec3<f32>,
    pdf: f32,
    delta: bool,
}

fn no_light() -> LightSample {
    return LightSample(false, vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0, false);
}

fn emitting_cos(e: Emitter, normal: vec3<f32>, wi: vec3<f32>) -> f32 {
    let c = -dot(normal, wi);
    return select(c, abs(c), e.two_sided != 0u);
}

fn attenuate(e: Emitter, d: f32) -> f32 {
    let a = v3(e.attenuation);
    return 1.0 / (a.x + a.y * d + a.z * d * d);
}

fn spot_falloff(e: Emitter, from_light: vec3<f32>) -> f32 {
    let c = dot(from_light, v3(e.e1));
    if c >= e.cos_inner {
        return 1.0;
    }
    if c <= e.cos_outer {
        return 0.0;
    }
    let inner = acos(clamp(e.cos_inner, -1.0, 1.0));
    let outer = acos(clamp(e.cos_outer, -1.0, 1.0));
    let x = (acos(clamp(c, -1.0, 1.0)) - inner) / (outer - inner);
    if e.linear_falloff != 0u {
        return 1.0 - x;
    }
    return 1.0 - x * x * (3.0 - 2.0 * x);
}

fn sample_emitter(e: Emitter, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    switch e.kind {
        case 4u, 5u: {
            let offset = v3(e.p) - p;
            let distance = length(offset);
            let wi = offset / distance;
            var falloff = 1.0;
            if e.kind == EM_SPOT {
                falloff = spot_falloff(e, -wi);
            }
            return LightSample(true, wi, distance, v3(e.radiance) * (falloff * attenuate(e, distance)), 1.0, true);
        }
        case 6u: {
            return LightSample(true, -v3(e.e1), INF, v3(e.radiance), 1.0, true);
        }
        case 3u: { return sample_sphere_emitter(e, p, u); }
        case 7u: { return no_light(); }
        default: {
            var q: vec3<f32>;
            if e.kind == EM_TRIANGLE {
                let s = sqrt(u.x);
                q = v3(e.p) + (1.0 - s) * v3(e.e1) + (s * u.y) * v3(e.e2);
            } else if e.kind == EM_PARALLELOGRAM {
                q = v3(e.p) + u.x * v3(e.e1) + u.y * v3(e.e2);
            } else {
                let d = concentric_disk(u);
                q = v3(e.p) + d.x * v3(e.e1) + d.y * v3(e.e2);
            }
            let pdf_area = 1.0 / e.size;
            let offset = q - p;
            let distance2 = dot(offset, offset);
            let distance = sqrt(distance2);
            let wi = offset / distance;
            let cos_light = emitting_cos(e, v3(e.normal), wi);
            if cos_light <= 0.0 || distance == 0.0 {
                return no_light();
            }
            return LightSample(true, wi, distance, v3(e.radiance), pdf_area * distance2 / cos_light, false);
        }
    }
}

fn sample_sphere_emitter(e: Emitter, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let c = v3(e.p);
    let r = e.size;
    let to_centre = c - p;
    let d2 = dot(to_centre, to_centre);
    if d2 <= r * r {
        let z = 1.0 - 2.0 * u.x;
        let s = sqrt(max(1.0 - z * z, 0.0));
        let phi = 2.0 * PI * u.y;
        let n = vec3<f32>(s * cos(phi), s * sin(phi), z);
        let q = c + r * n;
        let offset = q - p;
        let distance2 = dot(offset, offset);
        let distance = sqrt(distance2);
        let wi = offset / distance;
        let cos_light = emitting_cos(e, n, wi);
        if cos_light <= 0.0 {
            return no_light();
        }
        return LightSample(true, wi, distance, v3(e.radiance), distance2 / (cos_light * 4.0 * PI * r * r), false);
    }
    let d = sqrt(d2);
    let sin2_max = r * r / d2;
    let one_minus_cos_max = sin2_max / (1.0 + sqrt(max(1.0 - sin2_max, 0.0)));
    let one_minus_cos = u.x * one_minus_cos_max;
    let cos_a = 1.0 - one_minus_cos;
    let sin_a = sqrt(max(one_minus_cos * (2.0 - one_minus_cos), 0.0));
    let phi = 2.0 * PI * u.y;
    let axis = to_centre / d;
    let tb = orthonormal_pair(axis);
    let wi = (sin_a * cos(phi)) * tb[0] + (sin_a * sin(phi)) * tb[1] + cos_a * axis;
    let along = dot(wi, to_centre);
    let distance = along - sqrt(max(r * r - (d2 - along * along), 0.0));
    return LightSample(true, wi, distance, v3(e.radiance), 1.0 / (2.0 * PI * one_minus_cos_max), false);
}

// Solid-angle density of light sampling toward q (normal n) from p.
fn emitter_pdf(e: Emitter, p: vec3<f32>, q: vec3<f32>, n: vec3<f32>) -> f32 {
    switch e.kind {
        case 0u, 1u, 2u: {
            let offset = q - p;
            let distance2 = dot(offset, offset);
            let cos_light = abs(dot(n, offset)) / sqrt(distance2);
            if cos_light <= 0.0 {
                return 0.0;
            }
            return distance2 / (cos_light * e.size);
        }
        case 3u: {
            let c = v3(e.p);
            let r = e.size;
            let d2 = dot(c - p, c - p);
            if d2 <= r * r {
                let offset = q - p;
                let distance2 = dot(offset, offset);
                let cos_light = abs(dot(n, offset)) / sqrt(distance2);
                if cos_light <= 0.0 {
                    return 0.0;
                }
                return distance2 / (cos_light * 4.0 * PI * r * r);
            }
            let sin2_max = r * r / d2;
            let one_minus_cos_max = sin2_max / (1.0 + sqrt(max(1.0 - sin2_max, 0.0)));
            return 1.0 / (2.0 * PI * one_minus_cos_max);
        }
        default: { return 0.0; }
    }
}

// The emitter record of the surface a hit landed on, or NO_INDEX.
fn emitter_of(hit: Hit) -> u32 {
    let first = words[params.instance_emitter_offset + hit.instance];
    if first == NO_INDEX {
        return NO_INDEX;
    }
    let kind = instances[hit.instance].kind;
    if kind == KIND_MESH || kind == KIND_CUBE {
        return first + hit.part;
    }
    return first;
}

// ---- the environment ----

const ENV_NONE: u32 = 0u;
const ENV_CONSTANT: u32 = 1u;
const ENV_MAP: u32 = 2u;

fn env_uv(d: vec3<f32>) -> vec2<f32> {
    let v = (params.env_from_world * vec4<f32>(normalize(d), 0.0)).xyz;
    let u = atan2(v.x, -v.z) / (2.0 * PI);
    return vec2<f32>(u - floor(u), acos(clamp(v.y, -1.0, 1.0)) / PI);
}

fn env_direction(uv: vec2<f32>) -> vec3<f32> {
    let phi = 2.0 * PI * uv.x;
    let theta = PI * uv.y;
    let s = sin(theta);
    let c = cos(theta);
    return (params.world_from_env * vec4<f32>(s * sin(phi), c, -s * cos(phi), 0.0)).xyz;
}

fn env_texel(i: u32, j: u32) -> vec3<f32> {
    let w = params.env_width;
    return float3(params.env_texel_offset + 3u * (j * w + i % w));
}

fn env_radiance(d: vec3<f32>) -> vec3<f32> {
    if params.environment_kind != ENV_MAP {
        return params.env_scale.xyz;
    }
    let uv = env_uv(d);
    let w = f32(params.env_width);
    let xr = uv.x * w - 0.5;
    let x = xr - w * floor(xr / w);
    let y = uv.y * f32(params.env_height - 1u);
    let i = min(floor(x), w - 1.0);
    let j = min(floor(y), f32(params.env_height - 2u));
    let fx = x - i;
    let fy = y - j;
    let ii = u32(i);
    let jj = u32(j);
    let top = mix(env_texel(ii, jj), env_texel(ii + 1u, jj), fx);
    let bottom = mix(env_texel(ii, jj + 1u), env_texel(ii + 1u, jj + 1u), fx);
    return params.env_scale.xyz * mix(top, bottom, fy);
}

fn env_rows() -> u32 {
    return params.env_height - 1u;
}

fn env_row_cdf(row: u32) -> u32 {
    return params.env_cdf_offset + env_rows() + 1u + row * (params.env_width + 1u);
}

fn env_pdf(d: vec3<f32>) -> f32 {
    if params.environment_kind != ENV_MAP {
        return 1.0 / (4.0 * PI);
    }
    let uv = env_uv(d);
    let sin_theta = sin(PI * uv.y);
    if sin_theta <= 0.0 {
        return 0.0;
    }
    let half_texel = 0.5 / f32(params.env_width);
    let xs = uv.x - half_texel;
    let cell = vec2<f32>(xs - floor(xs), uv.y);
    let rows = env_rows();
    let row = min(u32(cell.y * f32(rows)), rows - 1u);
    let dens = density(params.env_cdf_offset, rows, cell.y) * density(env_row_cdf(row), params.env_width, cell.x);
    return dens / (2.0 * PI * PI * sin_theta);
}

fn sample_environment(u: vec2<f32>) -> LightSample {
    if params.environment_kind != ENV_MAP {
        let z = 1.0 - 2.0 * u.x;
        let s = sqrt(max(1.0 - z * z, 0.0));
        let phi = 2.0 * PI * u.y;
        let d = vec3<f32>(s * cos(phi), s * sin(phi), z);
        return LightSample(true, d, INF, params.env_scale.xyz, 1.0 / (4.0 * PI), false);
    }
    let rows = env_rows();
    let w = params.env_width;
    // Distribution2D::sample: the row from the marginal, then the column in that row.
    let ry = sample_discrete(params.env_cdf_offset, rows, u.y);
    let y = min((f32(ry.index) + ry.within) / f32(rows), 0.99999994);
    let rx = sample_discrete(env_row_cdf(ry.index), w, u.x);
    let x = min((f32(rx.index) + rx.within) / f32(w), 0.99999994);
    let d = env_direction(vec2<f32>(x + 0.5 / f32(w), y));
    let pdf = env_pdf(d);
    if !(pdf > 0.0) {
        return no_light();
    }
    return LightSample(true, d, INF, env_radiance(d), pdf, false);
}
