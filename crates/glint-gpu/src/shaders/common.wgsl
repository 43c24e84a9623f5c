// Shared helpers: constants, packed-vector reads, 32-bit hashing and the path sampler.
// Every function here mirrors one in glint-core (named in its comment) operation for
// operation, so both backends draw the same numbers.

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;
const INF: f32 = 3.40282347e38;
const NO_INDEX: u32 = 0xffffffffu;

fn v3(a: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(a[0], a[1], a[2]);
}

fn v2(a: array<f32, 2>) -> vec2<f32> {
    return vec2<f32>(a[0], a[1]);
}

fn float3(i: u32) -> vec3<f32> {
    return vec3<f32>(floats[i], floats[i + 1u], floats[i + 2u]);
}

fn max3(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

fn sum3(v: vec3<f32>) -> f32 {
    return v.x + v.y + v.z;
}

// A finite number: exponent bits not all ones (no NaN, no infinity). WGSL has no isnan.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn finite3(v: vec3<f32>) -> bool {
    return finite(v.x) && finite(v.y) && finite(v.z);
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// glam's `signum`: +1 for +0.0, −1 for −0.0.
fn signum(x: f32) -> f32 {
    return select(1.0, -1.0, (bitcast<u32>(x) & 0x80000000u) != 0u);
}

// glam's `Vec3::any_orthonormal_pair` (Duff et al. 2017).
fn orthonormal_pair(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let sign = signum(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// glam's `normalize_or(fallback)`.
fn normalize_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    let r = 1.0 / sqrt(len2);
    if finite(r) && r > 0.0 {
        return v * r;
    }
    return fallback;
}

// glint_core::math::offset_ray_origin: a few ulps off the surface, on the side of n.
fn offset_ray_origin(p: vec3<f32>, n_in: vec3<f32>) -> vec3<f32> {
    let n = normalize_or(n_in, vec3<f32>(0.0));
    return vec3<f32>(offset_axis(p.x, n.x), offset_axis(p.y, n.y), offset_axis(p.z, n.z));
}

fn offset_axis(p: f32, n: f32) -> f32 {
    if abs(p) < 1.0 / 32.0 {
        return p + n / 65536.0;
    }
    var ulps = i32(256.0 * n);
    if p < 0.0 {
        ulps = -ulps;
    }
    return bitcast<f32>(bitcast<i32>(p) + ulps);
}

// ---- glint_core::sampling::sequence ----

fn mix32(x_in: u32) -> u32 {
    var x = x_in;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

fn hash_step(h: u32, w: u32) -> u32 {
    return mix32(h ^ mix32(w + 0x9e3779b9u));
}

fn hash3(a: u32, b: u32, c: u32) -> u32 {
    return hash_step(hash_step(hash_step(0x6a09e667u, a), b), c);
}

fn unit_float(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

fn laine_karras(v_in: u32, seed: u32) -> u32 {
    var v = v_in + seed;
    v ^= v * 0x6c50b47cu;
    v ^= v * 0xb82f1e52u;
    v ^= v * 0xc7afe638u;
    v ^= v * 0x8d22f6e6u;
    return v;
}

// The second Sobol dimension of `index`, bit-reversed: the XOR of the direction
// numbers of its set bits (glint_core's byte tables, computed bit by bit).
fn sobol_y_reversed(index: u32) -> u32 {
    var y = 0u;
    var v = 0x80000000u;
    var bits = index;
    for (var j = 0u; j < 32u && bits != 0u; j += 1u) {
        if (bits & 1u) != 0u {
            y ^= v;
        }
        v ^= v >> 1u;
        bits >>= 1u;
    }
    return reverseBits(y);
}

const SOBOL_DIMENSIONS: u32 = 8u;

struct PathSampler {
    sobol: bool,
    pixel_seed: u32,
    index_reversed: u32,
    sample_seed: u32,
    dimension: u32,
}

fn path_sampler(sobol: bool, px: u32, py: u32, index: u32, seed: u32) -> PathSampler {
    let pixel_seed = hash3(px, py, seed);
    return PathSampler(sobol, pixel_seed, reverseBits(index), mix32(pixel_seed ^ mix32(index)), 0u);
}

fn next_salt(s: ptr<function, PathSampler>) -> u32 {
    let salt = (*s).dimension * 0x9e3779b9u + 0x7f4a7c15u;
    (*s).dimension += 1u;
    return salt;
}

fn next_1d(s: ptr<function, PathSampler>) -> f32 {
    let sobol = (*s).sobol && (*s).dimension < SOBOL_DIMENSIONS;
    let salt = next_salt(s);
    if !sobol {
        return unit_float(mix32((*s).sample_seed ^ salt));
    }
    let seed = mix32((*s).pixel_seed ^ salt);
    let shuffled = reverseBits(laine_karras((*s).index_reversed, seed));
    return unit_float(reverseBits(laine_karras(shuffled, seed ^ 0x68bc21ebu)));
}

fn next_2d(s: ptr<function, PathSampler>) -> vec2<f32> {
    let sobol = (*s).sobol && (*s).dimension < SOBOL_DIMENSIONS;
    let salt = next_salt(s);
    if !sobol {
        let h = mix32((*s).sample_seed ^ salt);
        return vec2<f32>(unit_float(h), unit_float(mix32(h ^ 0x5bd1e995u)));
    }
    let seed = mix32((*s).pixel_seed ^ salt);
    let shuffled = reverseBits(laine_karras((*s).index_reversed, seed));
    let x = reverseBits(laine_karras(shuffled, seed ^ 0x68bc21ebu));
    let y = reverseBits(laine_karras(sobol_y_reversed(shuffled), seed ^ 0x02e5be93u));
    return vec2<f32>(unit_float(x), unit_float(y));
}

// ---- glint_core::sampling::distribution, over cdf tables in `floats` ----

struct Discrete {
    index: u32,
    within: f32,
}

// Distribution1D::sample_discrete over the `n + 1` cdf entries at `cdf`: the bin and
// the position within it.
fn sample_discrete(cdf: u32, n: u32, u: f32) -> Discrete {
    // partition_point(c <= u): the first entry greater than u.
    var lo = 0u;
    var hi = n + 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if floats[cdf + mid] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = min(max(lo, 1u) - 1u, n - 1u);
    let width = floats[cdf + i + 1u] - floats[cdf + i];
    var within = 0.5;
    if width > 0.0 {
        within = clamp((u - floats[cdf + i]) / width, 0.0, 0.99999994);
    }
    return Discrete(i, within);
}

fn probability(cdf: u32, i: u32) -> f32 {
    return floats[cdf + i + 1u] - floats[cdf + i];
}

fn density(cdf: u32, n: u32, x: f32) -> f32 {
    let i = min(u32(x * f32(n)), n - 1u);
    return probability(cdf, i) * f32(n);
}

// ---- glint_core::bsdf::lobes ----

fn concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let d = 2.0 * u - vec2<f32>(1.0);
    if d.x == 0.0 && d.y == 0.0 {
        return vec2<f32>(0.0);
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
    return r * vec2<f32>(cos(theta), sin(theta));
}

fn cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let d = concentric_disk(u);
    return vec3<f32>(d.x, d.y, sqrt(max(1.0 - dot(d, d), 0.0)));
}

fn cosine_hemisphere_pdf(w: vec3<f32>) -> f32 {
    return max(w.z, 0.0) * INV_PI;
}

fn mirror(w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(-w.x, -w.y, w.z);
}

fn reflect_about(w: vec3<f32>, m: vec3<f32>) -> vec3<f32> {
    return 2.0 * dot(w, m) * m - w;
}

fn refract_about(w: vec3<f32>, m: vec3<f32>, cos_t: f32, eta_ti: f32) -> vec3<f32> {
    return m * (dot(w, m) * eta_ti + cos_t) - w * eta_ti;
}

fn phong_lobe(axis: vec3<f32>, exponent: f32, u: vec2<f32>) -> vec3<f32> {
    let cos_a = pow(u.x, 1.0 / (exponent + 1.0));
    let sin_a = sqrt(max(1.0 - cos_a * cos_a, 0.0));
    let phi = 2.0 * PI * u.y;
    let tb = orthonormal_pair(axis);
    return (sin_a * cos(phi)) * tb[0] + (sin_a * sin(phi)) * tb[1] + cos_a * axis;
}

fn phong_lobe_pdf(axis: vec3<f32>, exponent: f32, w: vec3<f32>) -> f32 {
    let c = dot(axis, w);
    if c <= 0.0 {
        return 0.0;
    }
    return (exponent + 1.0) / (2.0 * PI) * pow(c, exponent);
}
