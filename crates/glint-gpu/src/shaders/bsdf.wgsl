// BSDFs in the local shading frame (z = normal): glint_core::bsdf, with its Fresnel
// terms, microfacet distributions, coat tables and the Phong mapping. `wo` points to
// the viewer, `wi` to the light; sampled weights are f·|cos θi|/pdf.

const BSDF_DIFFUSE: u32 = 0u;
const BSDF_CONDUCTOR: u32 = 1u;
const BSDF_DIELECTRIC: u32 = 2u;
const BSDF_THIN: u32 = 3u;
const BSDF_PLASTIC: u32 = 4u;
const BSDF_PHONG: u32 = 5u;
const BSDF_METALLIC_ROUGHNESS: u32 = 6u;

const TWO_SIDED: u32 = 1u;
const NONLINEAR: u32 = 2u;
const BECKMANN: u32 = 4u;
const EMITS_BOTH_SIDES: u32 = 8u;
const CASTS_NO_SHADOW: u32 = 16u;
const MIN_ALPHA: f32 = 1e-4;
// The largest f32 below 1: keeps a rescaled lobe choice inside [0, 1).
const ONE_MINUS_EPSILON: f32 = 0.99999994;

// ---- textures (glint_core::texture) ----

// glint_core::texture's flags: the wrap mode of u and of v, then nearest filtering.
const WRAP_REPEAT: u32 = 0u;
const WRAP_CLAMP: u32 = 1u;
const WRAP_MIRROR: u32 = 2u;
const TEXTURE_NEAREST: u32 = 16u;
const TEXTURE_FILTERED: u32 = 32u;

// glint_core::texture::wrap_index: texel i of n along one axis, wrapped by `mode`.
fn wrap_index(i: i32, n: i32, mode: u32) -> i32 {
    if mode == WRAP_CLAMP {
        return clamp(i, 0, n - 1);
    }
    if mode == WRAP_MIRROR {
        let m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return select(2 * n - 1 - m, m, m < n);
    }
    return ((i % n) + n) % n;
}

fn texel(t: Texture, i: i32, j: i32) -> vec3<f32> {
    let w = i32(t.width);
    let h = i32(t.height);
    let ii = wrap_index(i, w, t.flags & 3u);
    let jj = wrap_index(j, h, (t.flags >> 2u) & 3u);
    return float3(params.texel_offset + 3u * (t.offset + u32(jj * w + ii)));
}

fn rem1(x: f32) -> f32 {
    return x - floor(x);
}

// Each axis is reduced first, as on the CPU: repeat to [0, 1), mirror to [0, 2),
// clamp to [−1, 2], so huge uvs keep precision and never overflow the texel index.
fn reduce_uv(x: f32, mode: u32) -> f32 {
    if mode == WRAP_CLAMP {
        return clamp(x, -1.0, 2.0);
    }
    if mode == WRAP_MIRROR {
        return x - 2.0 * floor(x / 2.0);
    }
    return rem1(x);
}

fn texture_sample(index: u32, uv: vec2<f32>) -> vec3<f32> {
    let t = textures[index];
    if t.kind == 1u {
        let cell = floor(uv * v2(t.cells));
        let parity = cell.x + cell.y;
        if parity - 2.0 * floor(parity / 2.0) == 0.0 {
            return v3(t.even);
        }
        return v3(t.odd);
    }
    let xs = reduce_uv(uv.x, t.flags & 3u) * f32(t.width);
    let ys = (1.0 - reduce_uv(uv.y, (t.flags >> 2u) & 3u)) * f32(t.height);
    if (t.flags & TEXTURE_NEAREST) != 0u {
        return texel(t, i32(floor(xs)), i32(floor(ys)));
    }
    let x = xs - 0.5;
    let y = ys - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let i = i32(x0);
    let j = i32(y0);
    let top = mix(texel(t, i, j), texel(t, i + 1, j), fx);
    let bottom = mix(texel(t, i, j + 1), texel(t, i + 1, j + 1), fx);
    return mix(top, bottom, fy);
}

fn texture_is_filtered(index: u32) -> bool {
    return (textures[index].flags & TEXTURE_FILTERED) != 0u;
}

// glint_core::texture::box_filtered_square_wave: the mean over [x − w/2, x + w/2] of the
// wave that is +1 on even cells and −1 on odd ones.
fn box_filtered_square_wave(x: f32, w: f32) -> f32 {
    let point = square_wave_cell(floor(x));
    if w <= 1e-4 * max(abs(x), 1.0) {
        return point;
    }
    if w >= 1e4 {
        return 0.0;
    }
    let hi = x + 0.5 * w;
    let lo = x - 0.5 * w;
    let integral_hi = 1.0 - abs(1.0 - (hi - 2.0 * floor(hi / 2.0)));
    let integral_lo = 1.0 - abs(1.0 - (lo - 2.0 * floor(lo / 2.0)));
    return clamp((integral_hi - integral_lo) / w, -1.0, 1.0);
}

// glint_core::texture::trapezoid_cdf: the chance that a + b (uniform over widths wa and
// wb about zero) is below t.
fn trapezoid_cdf(t: f32, wa: f32, wb: f32) -> f32 {
    let long = max(wa, wb);
    let short = min(wa, wb);
    let outer = 0.5 * (long + short);
    let inner = 0.5 * (long - short);
    var below = 1.0;
    if t <= -outer {
        below = 0.0;
    } else if t <= -inner {
        let rise = t + outer;
        below = 0.5 * rise * rise / (long * short);
    } else if t <= inner {
        below = 0.5 * short / long + (t + inner) / long;
    } else if t < outer {
        let fall = outer - t;
        below = 1.0 - 0.5 * fall * fall / (long * short);
    }
    return clamp(below, 0.0, 1.0);
}

fn modulo_two(x: f32) -> f32 {
    return x - 2.0 * floor(0.5 * x);
}

fn square_wave_cell(cell: f32) -> f32 {
    return select(-1.0, 1.0, modulo_two(cell) == 0.0);
}

// The periodic part of the square wave's second integral (less its mean slope x/2).
fn square_wave_second_integral(t: f32) -> f32 {
    let y = modulo_two(t);
    if y <= 1.0 {
        return 0.5 * y * (y - 1.0);
    }
    return -0.5 * y * y + 1.5 * y - 1.0;
}

// glint_core::texture::trapezoid_filtered_square_wave: the mean of the wave at x + a + b,
// a and b uniform over widths wa and wb about zero.
fn trapezoid_filtered_square_wave(x: f32, wa: f32, wb: f32) -> f32 {
    let half = 0.5 * (wa + wb);
    if half >= 1e4 {
        return 0.0;
    }
    let lo = floor(x - half);
    let hi = floor(x + half);
    if lo == hi {
        return square_wave_cell(lo);
    }
    if half < 0.5 {
        return square_wave_cell(hi) * (1.0 - 2.0 * trapezoid_cdf(hi - x, wa, wb));
    }
    let long = max(wa, wb);
    let short = min(wa, wb);
    if short < 1e-2 * long {
        return box_filtered_square_wave(x, long);
    }
    let inner = 0.5 * (long - short);
    let y = modulo_two(x);
    let second_difference = square_wave_second_integral(y + half) - square_wave_second_integral(y + inner)
        - square_wave_second_integral(y - inner) + square_wave_second_integral(y - half);
    return clamp(second_difference / (wa * wb), -1.0, 1.0);
}

// glint_core::texture::Texture::sample_over: the texture averaged over the footprint whose
// uv steps to the neighbouring pixels are `steps` (.xy across, .zw down); `bounded` false
// for an unbounded footprint (the pattern's mean).
fn texture_sample_over(index: u32, uv: vec2<f32>, steps: vec4<f32>, bounded: bool) -> vec3<f32> {
    let t = textures[index];
    if t.kind != 1u || (t.flags & TEXTURE_FILTERED) == 0u {
        return texture_sample(index, uv);
    }
    var sign = 0.0;
    if bounded {
        let across = abs(steps.xy) * v2(t.cells);
        let down = abs(steps.zw) * v2(t.cells);
        let cell = uv * v2(t.cells);
        sign = trapezoid_filtered_square_wave(cell.x, across.x, down.x)
            * trapezoid_filtered_square_wave(cell.y, across.y, down.y);
    }
    return v3(t.even) * (0.5 + 0.5 * sign) + v3(t.odd) * (0.5 - 0.5 * sign);
}

// ---- Fresnel (glint_core::bsdf::fresnel) ----

struct DielectricFresnel {
    r: f32,
    cos_t: f32,
    eta_it: f32,
    eta_ti: f32,
}

fn fresnel_dielectric(cos_i: f32, eta: f32) -> DielectricFresnel {
    let outside = cos_i >= 0.0;
    let eta_it = select(1.0 / eta, eta, outside);
    let eta_ti = 1.0 / eta_it;
    let c = abs(cos_i);
    let cos2_t = 1.0 - eta_ti * eta_ti * max(1.0 - c * c, 0.0);
    if cos2_t <= 0.0 || eta == 1.0 {
        if eta == 1.0 {
            return DielectricFresnel(0.0, -cos_i, 1.0, 1.0);
        }
        return DielectricFresnel(1.0, 0.0, eta_it, eta_ti);
    }
    let ct = sqrt(cos2_t);
    let a_s = (eta_it * ct - c) / (eta_it * ct + c);
    let a_p = (eta_it * c - ct) / (eta_it * c + ct);
    return DielectricFresnel(0.5 * (a_s * a_s + a_p * a_p), select(ct, -ct, outside), eta_it, eta_ti);
}

fn fresnel_conductor(cos_i: f32, eta: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    let c = clamp(cos_i, 0.0, 1.0);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let eta2 = eta * eta;
    let k2 = k * k;
    let t0 = eta2 - k2 - vec3<f32>(s2);
    let a2b2 = sqrt(max(t0 * t0 + 4.0 * eta2 * k2, vec3<f32>(0.0)));
    let a = sqrt(max(0.5 * (a2b2 + t0), vec3<f32>(0.0)));
    let t1 = a2b2 + vec3<f32>(c2);
    let t2 = 2.0 * c * a;
    let r_s = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2b2 + vec3<f32>(s2 * s2);
    let t4 = t2 * s2;
    let ratio = select(vec3<f32>(1.0), (t3 - t4) / (t3 + t4), (t3 + t4) > vec3<f32>(0.0));
    return clamp(0.5 * (r_s + r_s * ratio), vec3<f32>(0.0), vec3<f32>(1.0));
}

// ---- microfacets (glint_core::bsdf::microfacet) ----

struct Microfacet {
    alpha: f32,
    beckmann: bool,
}

fn ggx_d(alpha: f32, m: vec3<f32>) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = (m.x * m.x + m.y * m.y) / a2 + m.z * m.z;
    return 1.0 / (PI * a2 * t * t);
}

fn ggx_g1(alpha: f32, w: vec3<f32>, m: vec3<f32>) -> f32 {
    if dot(w, m) * w.z <= 0.0 {
        return 0.0;
    }
    let cos2 = w.z * w.z;
    if cos2 <= 0.0 {
        return 0.0;
    }
    let tan2 = max(1.0 - cos2, 0.0) / cos2;
    return 1.0 / (1.0 + 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0));
}

fn mf_d(mf: Microfacet, m: vec3<f32>) -> f32 {
    if !mf.beckmann {
        return ggx_d(mf.alpha, m);
    }
    if m.z <= 0.0 {
        return 0.0;
    }
    let cos2 = m.z * m.z;
    let tan2 = max(1.0 - cos2, 0.0) / cos2;
    let a2 = mf.alpha * mf.alpha;
    return exp(-tan2 / a2) / (PI * a2 * cos2 * cos2);
}

fn mf_g1(mf: Microfacet, w: vec3<f32>, m: vec3<f32>) -> f32 {
    if !mf.beckmann {
        return ggx_g1(mf.alpha, w, m);
    }
    if dot(w, m) * w.z <= 0.0 {
        return 0.0;
    }
    let cos2 = w.z * w.z;
    let tan = sqrt(max(1.0 - cos2, 0.0) / cos2);
    if tan == 0.0 {
        return 1.0;
    }
    let a = 1.0 / (mf.alpha * tan);
    if a >= 1.6 {
        return 1.0;
    }
    return (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}

fn mf_g(mf: Microfacet, wo: vec3<f32>, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    return mf_g1(mf, wo, m) * mf_g1(mf, wi, m);
}

fn ggx_sample_visible(alpha: f32, w: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let wh = normalize(vec3<f32>(alpha * w.x, alpha * w.y, w.z));
    let len2 = wh.x * wh.x + wh.y * wh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if len2 > 0.0 {
        t1 = vec3<f32>(-wh.y, wh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(wh, t1);
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + wh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * wh;
    return normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 1e-6)));
}

fn mf_sample_normal(mf: Microfacet, w: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    if !mf.beckmann {
        return ggx_sample_visible(mf.alpha, w, u);
    }
    let tan2 = -mf.alpha * mf.alpha * log(max(1.0 - u.x, 1e-12));
    let c = 1.0 / sqrt(1.0 + tan2);
    let s = sqrt(max(1.0 - c * c, 0.0));
    let phi = 2.0 * PI * u.y;
    return vec3<f32>(s * cos(phi), s * sin(phi), c);
}

fn mf_normal_pdf(mf: Microfacet, w: vec3<f32>, m: vec3<f32>) -> f32 {
    if mf.beckmann {
        return mf_d(mf, m) * max(m.z, 0.0);
    }
    if w.z == 0.0 {
        return 0.0;
    }
    return ggx_g1(mf.alpha, w, m) * abs(dot(w, m)) * ggx_d(mf.alpha, m) / abs(w.z);
}

// ---- the BSDF at a surface point (glint_core::bsdf::SurfaceBsdf) ----

struct SurfaceBsdf {
    index: u32,
    color: vec3<f32>,
    alpha: f32,
    metallic: f32,
}

struct BsdfSample {
    found: bool,
    wi: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    delta: bool,
    eta: f32,
}

fn no_sample() -> BsdfSample {
    return BsdfSample(false, vec3<f32>(0.0), vec3<f32>(0.0), 0.0, false, 1.0);
}

fn surface_bsdf(index: u32, uv: vec2<f32>) -> SurfaceBsdf {
    let r = bsdfs[index];
    var color = v3(r.color);
    if r.color_texture != NO_INDEX {
        let t = texture_sample(r.color_texture, uv * v2(r.uv_repeat));
        color = mix(color, v3(r.texture_scale) * t, r.blend);
    }
    var alpha = r.alpha;
    if r.alpha_texture != NO_INDEX {
        alpha *= sum3(texture_sample(r.alpha_texture, uv * v2(r.uv_repeat))) / 3.0;
    }
    var metallic = r.metallic;
    if r.metallic_texture != NO_INDEX {
        metallic *= sum3(texture_sample(r.metallic_texture, uv * v2(r.uv_repeat))) / 3.0;
    }
    return SurfaceBsdf(index, color, select(alpha, 0.0, alpha < MIN_ALPHA), clamp(metallic, 0.0, 1.0));
}

fn microfacet_of(s: SurfaceBsdf) -> Microfacet {
    return Microfacet(s.alpha, (bsdfs[s.index].flags & BECKMANN) != 0u);
}

fn has_non_delta(s: SurfaceBsdf) -> bool {
    switch bsdfs[s.index].kind {
        case 0u, 4u: { return true; }
        case 1u, 2u: { return s.alpha > 0.0; }
        case 3u: { return false; }
        case 6u: { return s.alpha > 0.0 || s.metallic < 1.0; }
        default: {
            let p = phong_lobes(s).p;
            return p[0] + p[1] > 0.0;
        }
    }
}

fn bsdf_albedo(s: SurfaceBsdf) -> vec3<f32> {
    let r = bsdfs[s.index];
    switch r.kind {
        case 2u, 3u: { return v3(r.transmittance); }
        case 1u: { return s.color * fresnel_conductor(1.0, v3(r.eta), v3(r.k)); }
        default: { return s.color; }
    }
}

// +1 or −1: the side reflection happens on; 0 when `wo` is behind a one-sided surface.
fn reflection_side(s: SurfaceBsdf, wo: vec3<f32>) -> f32 {
    if wo.z > 0.0 {
        return 1.0;
    }
    if wo.z < 0.0 && (bsdfs[s.index].flags & TWO_SIDED) != 0u {
        return -1.0;
    }
    return 0.0;
}

fn bsdf_eval(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    switch bsdfs[s.index].kind {
        case 2u: { return rough_dielectric(s, wo, wi).value; }
        case 3u: { return vec3<f32>(0.0); }
        case 5u: { return phong_eval(s, wo, wi); }
        default: {
            let side = reflection_side(s, wo);
            if side == 0.0 {
                return vec3<f32>(0.0);
            }
            let flip = vec3<f32>(1.0, 1.0, side);
            if wi.z * side <= 0.0 {
                return vec3<f32>(0.0);
            }
            return eval_front(s, wo * flip, wi * flip);
        }
    }
}

fn bsdf_pdf(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch bsdfs[s.index].kind {
        case 2u: { return rough_dielectric(s, wo, wi).pdf; }
        case 3u: { return 0.0; }
        case 5u: { return phong_pdf(s, wo, wi); }
        default: {
            let side = reflection_side(s, wo);
            if side == 0.0 {
                return 0.0;
            }
            let flip = vec3<f32>(1.0, 1.0, side);
            if wi.z * side <= 0.0 {
                return 0.0;
            }
            return pdf_front(s, wo * flip, wi * flip);
        }
    }
}

fn bsdf_sample(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    switch bsdfs[s.index].kind {
        case 2u: { return sample_dielectric(s, wo, u_lobe, u); }
        case 3u: { return sample_thin(s, wo, u_lobe); }
        case 5u: { return phong_sample(s, wo, u_lobe, u); }
        default: {
            let side = reflection_side(s, wo);
            if side == 0.0 {
                return no_sample();
            }
            let flip = vec3<f32>(1.0, 1.0, side);
            var out = sample_front(s, wo * flip, u_lobe, u);
            out.wi *= flip;
            return out;
        }
    }
}

// ---- reflection-only kinds, wo and wi on the +z side ----

fn eval_front(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    switch bsdfs[s.index].kind {
        case 0u: { return s.color * INV_PI; }
        case 1u: { return metal_eval(s, wo, wi); }
        case 4u: { return plastic_eval(s, wo, wi); }
        case 6u: {
            var f = vec3<f32>(0.0);
            if s.metallic > 0.0 {
                f += metal_eval(s, wo, wi) * s.metallic;
            }
            if s.metallic < 1.0 {
                f += plastic_eval(s, wo, wi) * (1.0 - s.metallic);
            }
            return f;
        }
        default: { return vec3<f32>(0.0); }
    }
}

fn pdf_front(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch bsdfs[s.index].kind {
        case 0u: { return cosine_hemisphere_pdf(wi); }
        case 1u: { return metal_pdf(s, wo, wi); }
        case 4u: { return plastic_pdf(s, wo, wi); }
        case 6u: {
            var pdf = 0.0;
            if s.metallic > 0.0 {
                pdf += metal_pdf(s, wo, wi) * s.metallic;
            }
            if s.metallic < 1.0 {
                pdf += plastic_pdf(s, wo, wi) * (1.0 - s.metallic);
            }
            return pdf;
        }
        default: { return 0.0; }
    }
}

// A metal's reflectance: the complex-index Fresnel of a conductor, Schlick's with the
// base colour as F0 for metallic-roughness.
fn metal_fresnel(s: SurfaceBsdf, cos_i: f32) -> vec3<f32> {
    let r = bsdfs[s.index];
    if r.kind == BSDF_METALLIC_ROUGHNESS {
        let c = 1.0 - clamp(cos_i, 0.0, 1.0);
        let c2 = c * c;
        return s.color + (vec3<f32>(1.0) - s.color) * (c2 * c2 * c);
    }
    return s.color * fresnel_conductor(cos_i, v3(r.eta), v3(r.k));
}

fn metal_eval(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if s.alpha == 0.0 {
        return vec3<f32>(0.0);
    }
    let m = normalize(wo + wi);
    let mf = microfacet_of(s);
    return metal_fresnel(s, dot(wo, m)) * (mf_d(mf, m) * mf_g(mf, wo, wi, m) / (4.0 * wo.z * wi.z));
}

fn metal_pdf(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if s.alpha == 0.0 {
        return 0.0;
    }
    let m = normalize(wo + wi);
    return mf_normal_pdf(microfacet_of(s), wo, m) / (4.0 * dot(wo, m));
}

fn plastic_eval(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let r = bsdfs[s.index];
    var f = plastic_diffuse(s, wo, wi);
    if s.alpha > 0.0 {
        let m = normalize(wo + wi);
        let mf = microfacet_of(s);
        let fr = fresnel_dielectric(dot(wo, m), r.eta[0]).r;
        f += v3(r.specular) * (fr * mf_d(mf, m) * mf_g(mf, wo, wi, m) / (4.0 * wo.z * wi.z));
    }
    return f;
}

fn plastic_pdf(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let p_specular = plastic_specular_probability(s, wo);
    var pdf = (1.0 - p_specular) * cosine_hemisphere_pdf(wi);
    if s.alpha > 0.0 {
        let m = normalize(wo + wi);
        pdf += p_specular * mf_normal_pdf(microfacet_of(s), wo, m) / (4.0 * dot(wo, m));
    }
    return pdf;
}

fn sample_front(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    switch bsdfs[s.index].kind {
        case 0u: {
            let wi = cosine_hemisphere(u);
            if wi.z <= 0.0 {
                return no_sample();
            }
            return BsdfSample(true, wi, s.color, cosine_hemisphere_pdf(wi), false, 1.0);
        }
        case 1u: { return sample_metal(s, wo, u); }
        case 4u: { return sample_plastic(s, wo, u_lobe, u); }
        case 6u: { return sample_metallic_roughness(s, wo, u_lobe, u); }
        default: { return no_sample(); }
    }
}

fn sample_metal(s: SurfaceBsdf, wo: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    if s.alpha == 0.0 {
        return BsdfSample(true, mirror(wo), metal_fresnel(s, wo.z), 1.0, true, 1.0);
    }
    let mf = microfacet_of(s);
    let m = mf_sample_normal(mf, wo, u);
    let wi = reflect_about(wo, m);
    if wi.z <= 0.0 {
        return no_sample();
    }
    let normal_pdf = mf_normal_pdf(mf, wo, m);
    if normal_pdf <= 0.0 {
        return no_sample();
    }
    let pdf = normal_pdf / (4.0 * dot(wo, m));
    let weight = metal_fresnel(s, dot(wo, m)) * (mf_d(mf, m) * mf_g(mf, wo, wi, m) * dot(wo, m) / (wo.z * normal_pdf));
    return BsdfSample(true, wi, weight, pdf, false, 1.0);
}

// The metal with probability `metallic`, else the plastic (as the CPU's
// sample_metallic_roughness).
fn sample_metallic_roughness(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    let m = s.metallic;
    if u_lobe < m {
        var out = sample_metal(s, wo, u);
        if !out.found {
            return out;
        }
        if out.delta {
            out.pdf = m;
            return out;
        }
        return weighed(s, wo, out.wi);
    }
    var out = sample_plastic(s, wo, min((u_lobe - m) / (1.0 - m), ONE_MINUS_EPSILON), u);
    if out.found && s.alpha == 0.0 {
        out.pdf *= 1.0 - m;
    }
    return out;
}

// ---- plastic ----

fn coat_lookup(index: u32, mu: f32) -> f32 {
    let x = clamp(mu, 0.0, 1.0) * 31.0;
    let i = min(u32(x), 30u);
    let w = x - f32(i);
    return bsdfs[index].coat_transmittance[i] * (1.0 - w) + bsdfs[index].coat_transmittance[i + 1u] * w;
}

fn coat_transmittance(s: SurfaceBsdf, mu: f32) -> f32 {
    if s.alpha == 0.0 {
        return 1.0 - fresnel_dielectric(mu, bsdfs[s.index].eta[0]).r;
    }
    return coat_lookup(s.index, mu);
}

fn plastic_specular_probability(s: SurfaceBsdf, wo: vec3<f32>) -> f32 {
    let sp = sum3(v3(bsdfs[s.index].specular)) / 3.0;
    let d = sum3(s.color) / 3.0;
    let weight = select(0.5, sp / (sp + d), sp + d > 0.0);
    let f = 1.0 - coat_transmittance(s, wo.z);
    let ps = f * weight;
    let pd = (1.0 - f) * (1.0 - weight);
    return select(0.0, ps / (ps + pd), ps + pd > 0.0);
}

fn plastic_diffuse(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let r = bsdfs[s.index];
    let eta = r.eta[0];
    let fo = 1.0 - coat_transmittance(s, wo.z);
    let fi = 1.0 - coat_transmittance(s, wi.z);
    var denominator = vec3<f32>(1.0 - r.internal_reflectance);
    if (r.flags & NONLINEAR) != 0u {
        denominator = vec3<f32>(1.0) - s.color * r.internal_reflectance;
    }
    return s.color / denominator * ((1.0 - fo) * (1.0 - fi) * INV_PI / (eta * eta));
}

fn sample_plastic(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    let p_specular = plastic_specular_probability(s, wo);
    if s.alpha == 0.0 {
        if u_lobe < p_specular {
            let f = fresnel_dielectric(wo.z, bsdfs[s.index].eta[0]).r;
            return BsdfSample(true, mirror(wo), v3(bsdfs[s.index].specular) * (f / p_specular), p_specular, true, 1.0);
        }
        let wi = cosine_hemisphere(u);
        let pdf = (1.0 - p_specular) * cosine_hemisphere_pdf(wi);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return no_sample();
        }
        return BsdfSample(true, wi, plastic_diffuse(s, wo, wi) * (wi.z / pdf), pdf, false, 1.0);
    }
    var wi: vec3<f32>;
    if u_lobe < p_specular {
        wi = reflect_about(wo, mf_sample_normal(microfacet_of(s), wo, u));
    } else {
        wi = cosine_hemisphere(u);
    }
    return weighed(s, wo, wi);
}

fn weighed(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> BsdfSample {
    if wi.z * wo.z <= 0.0 && bsdfs[s.index].kind != BSDF_DIELECTRIC {
        return no_sample();
    }
    let pdf = bsdf_pdf(s, wo, wi);
    if !(pdf > 0.0) {
        return no_sample();
    }
    return BsdfSample(true, wi, bsdf_eval(s, wo, wi) * (abs(wi.z) / pdf), pdf, false, 1.0);
}

// ---- dielectrics ----

fn sample_thin(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32) -> BsdfSample {
    let r = bsdfs[s.index];
    var reflect = fresnel_dielectric(abs(wo.z), r.eta[0]).r;
    if reflect < 1.0 {
        reflect += (1.0 - reflect) * (1.0 - reflect) * reflect / (1.0 - reflect * reflect);
    }
    if u_lobe < reflect {
        return BsdfSample(true, mirror(wo), v3(r.specular), reflect, true, 1.0);
    }
    return BsdfSample(true, -wo, v3(r.transmittance), 1.0 - reflect, true, 1.0);
}

fn sample_dielectric(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    let r = bsdfs[s.index];
    let eta = r.eta[0];
    if s.alpha == 0.0 {
        let fr = fresnel_dielectric(wo.z, eta);
        if u_lobe < fr.r {
            return BsdfSample(true, mirror(wo), v3(r.specular), fr.r, true, 1.0);
        }
        let wi = refract_about(wo, vec3<f32>(0.0, 0.0, 1.0), fr.cos_t, fr.eta_ti);
        let weight = v3(r.transmittance) * (fr.eta_ti * fr.eta_ti);
        return BsdfSample(true, wi, weight, 1.0 - fr.r, true, fr.eta_it);
    }
    let mf = microfacet_of(s);
    let m = mf_sample_normal(mf, wo * signum(wo.z), u);
    let fr = fresnel_dielectric(dot(wo, m), eta);
    var wi: vec3<f32>;
    var transmitted = false;
    if u_lobe < fr.r {
        wi = reflect_about(wo, m);
    } else {
        wi = refract_about(wo, m, fr.cos_t, fr.eta_ti);
        transmitted = true;
    }
    if transmitted == (wi.z * wo.z > 0.0) || wi.z == 0.0 {
        return no_sample();
    }
    let vp = rough_dielectric(s, wo, wi);
    if !(vp.pdf > 0.0) {
        return no_sample();
    }
    return BsdfSample(true, wi, vp.value * (abs(wi.z) / vp.pdf), vp.pdf, false, select(1.0, fr.eta_it, transmitted));
}

struct ValuePdf {
    value: vec3<f32>,
    pdf: f32,
}

fn rough_dielectric(s: SurfaceBsdf, wo: vec3<f32>, wi: vec3<f32>) -> ValuePdf {
    let none = ValuePdf(vec3<f32>(0.0), 0.0);
    let r = bsdfs[s.index];
    if s.alpha == 0.0 || wo.z == 0.0 || wi.z == 0.0 {
        return none;
    }
    let eta = r.eta[0];
    let reflect = wo.z * wi.z > 0.0;
    var etap = 1.0;
    if !reflect {
        etap = select(1.0 / eta, eta, wo.z > 0.0);
    }
    var m = wi * etap + wo;
    if dot(m, m) == 0.0 {
        return none;
    }
    m = normalize(m);
    if m.z < 0.0 {
        m = -m;
    }
    if dot(m, wi) * wi.z < 0.0 || dot(m, wo) * wo.z < 0.0 {
        return none;
    }
    let mf = microfacet_of(s);
    let f = fresnel_dielectric(dot(wo, m), eta).r;
    let visible = mf_normal_pdf(mf, wo, m);
    if reflect {
        let value = v3(r.specular) * (mf_d(mf, m) * mf_g(mf, wo, wi, m) * f / abs(4.0 * wi.z * wo.z));
        return ValuePdf(value, visible / (4.0 * abs(dot(wo, m))) * f);
    }
    let denom = dot(wi, m) + dot(wo, m) / etap;
    let denom2 = denom * denom;
    let v = mf_d(mf, m) * (1.0 - f) * mf_g(mf, wo, wi, m) * abs(dot(wi, m) * dot(wo, m) / (wi.z * wo.z * denom2));
    let dm_dwi = abs(dot(wi, m)) / denom2;
    return ValuePdf(v3(r.transmittance) * (v / (etap * etap)), visible * dm_dwi * (1.0 - f));
}

// ---- Phong read as a BSDF (glint_core::bsdf::phong) ----

struct PhongLobes {
    w: array<vec3<f32>, 4>,
    p: array<f32, 4>,
}

fn phong_lobes(s: SurfaceBsdf) -> PhongLobes {
    let r = bsdfs[s.index];
    var w = array<vec3<f32>, 4>(
        max(s.color, vec3<f32>(0.0)),
        max(v3(r.glossy), vec3<f32>(0.0)),
        max(v3(r.specular), vec3<f32>(0.0)),
        max(v3(r.transmittance), vec3<f32>(0.0)),
    );
    let total = max3(w[0] + w[1] + w[2] + w[3]);
    if total > 1.0 {
        for (var i = 0u; i < 4u; i += 1u) {
            w[i] = w[i] / total;
        }
    }
    let sum = sum3(w[0]) + sum3(w[1]) + sum3(w[2]) + sum3(w[3]);
    var p = array<f32, 4>(0.0, 0.0, 0.0, 0.0);
    if sum > 0.0 {
        for (var i = 0u; i < 4u; i += 1u) {
            p[i] = sum3(w[i]) / sum;
        }
    }
    return PhongLobes(w, p);
}

fn phong_eval(s: SurfaceBsdf, wo_in: vec3<f32>, wi_in: vec3<f32>) -> vec3<f32> {
    let flip = select(vec3<f32>(1.0), vec3<f32>(1.0, 1.0, -1.0), wo_in.z < 0.0);
    let wo = wo_in * flip;
    let wi = wi_in * flip;
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let l = phong_lobes(s);
    let n = bsdfs[s.index].exponent;
    let cos_a = max(dot(mirror(wo), wi), 0.0);
    return l.w[0] * INV_PI + l.w[1] * ((n + 2.0) / (2.0 * PI) * pow(cos_a, n));
}

fn phong_pdf(s: SurfaceBsdf, wo_in: vec3<f32>, wi_in: vec3<f32>) -> f32 {
    let flip = select(vec3<f32>(1.0), vec3<f32>(1.0, 1.0, -1.0), wo_in.z < 0.0);
    let wo = wo_in * flip;
    let wi = wi_in * flip;
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    let p = phong_lobes(s).p;
    return p[0] * cosine_hemisphere_pdf(wi) + p[1] * phong_lobe_pdf(mirror(wo), bsdfs[s.index].exponent, wi);
}

fn phong_sample(s: SurfaceBsdf, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    let l = phong_lobes(s);
    let p = l.p;
    let flip = select(vec3<f32>(1.0), vec3<f32>(1.0, 1.0, -1.0), wo.z < 0.0);
    let wo_front = wo * flip;
    let c0 = p[0];
    let c1 = p[0] + p[1];
    let c2 = p[0] + p[1] + p[2];
    if u_lobe < c1 {
        var wi_front: vec3<f32>;
        if u_lobe < c0 {
            wi_front = cosine_hemisphere(u);
        } else {
            wi_front = phong_lobe(mirror(wo_front), bsdfs[s.index].exponent, u);
        }
        let wi = wi_front * flip;
        let pdf = phong_pdf(s, wo, wi);
        if wi_front.z <= 0.0 || !(pdf > 0.0) {
            return no_sample();
        }
        return BsdfSample(true, wi, phong_eval(s, wo, wi) * (wi_front.z / pdf), pdf, false, 1.0);
    }
    if u_lobe < c2 {
        return BsdfSample(true, mirror(wo), l.w[2] / p[2], p[2], true, 1.0);
    }
    if p[3] <= 0.0 {
        return no_sample();
    }
    let ior = bsdfs[s.index].eta[0];
    if ior == 1.0 {
        return BsdfSample(true, -wo, l.w[3] / p[3], p[3], true, 1.0);
    }
    let eta_it = select(1.0 / ior, ior, wo.z > 0.0);
    let eta_ti = 1.0 / eta_it;
    let sin2_t = eta_ti * eta_ti * max(1.0 - wo.z * wo.z, 0.0);
    if sin2_t >= 1.0 {
        return BsdfSample(true, mirror(wo), l.w[3] / p[3], p[3], true, 1.0);
    }
    let cos_t = sqrt(1.0 - sin2_t) * -signum(wo.z);
    let wi = vec3<f32>(-eta_ti * wo.x, -eta_ti * wo.y, cos_t);
    return BsdfSample(true, wi, l.w[3] / p[3] * (eta_ti * eta_ti), p[3], true, eta_it);
}
