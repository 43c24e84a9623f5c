// The film: each pixel gathers, in a fixed order, every sample of the pass whose
// reconstruction filter reaches it (glint_core::film::FilmTile::splat_with seen from
// the receiving pixel), and adds the weighted sum and the weight to its accumulator.
//
// Layouts. A sample takes `film_stride()` vec4s of `samples` (sample k of pixel (x, y)
// at slot ((k·height + y)·width + x)·stride): its colour and a flag in w (0: a sample,
// 1: a non-finite one, 2: none, where adaptive sampling gave the pixel fewer samples in
// this pass), then, with AOVs, its first hit's albedo and depth, and its normal. A
// pixel takes as many vec4s of `accum`: the weighted colour sum and the weight, then
// the weighted AOV sums. With adaptive sampling one more vec4 per pixel follows all of
// those: its sampling state (`AdaptiveState`).

const FILTER_BOX: u32 = 0u;
const FILTER_TENT: u32 = 1u;
const FILTER_GAUSSIAN: u32 = 2u;
const FILTER_MITCHELL: u32 = 3u;

fn mitchell(x: f32) -> f32 {
    let b = 1.0 / 3.0;
    let c = 1.0 / 3.0;
    let x2 = x * x;
    let x3 = x2 * x;
    if x < 1.0 {
        return ((12.0 - 9.0 * b - 6.0 * c) * x3 + (-18.0 + 12.0 * b + 6.0 * c) * x2 + (6.0 - 2.0 * b)) / 6.0;
    }
    return ((-b - 6.0 * c) * x3 + (6.0 * b + 30.0 * c) * x2 + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)) / 6.0;
}

fn sinc(x: f32) -> f32 {
    if abs(x) < 1e-5 {
        return 1.0;
    }
    let px = PI * x;
    return sin(px) / px;
}

fn filter_1d(x: f32) -> f32 {
    let r = params.filter_radius;
    let ax = abs(x);
    if ax > r {
        return 0.0;
    }
    switch params.filter_kind {
        case 0u: { return 1.0; }
        case 1u: { return 1.0 - ax / r; }
        case 2u: {
            let sigma = r / 3.0;
            let g = exp(-ax * ax / (2.0 * sigma * sigma));
            let g_r = exp(-r * r / (2.0 * sigma * sigma));
            return max(g - g_r, 0.0);
        }
        case 3u: { return mitchell(2.0 * ax / r); }
        default: { return sinc(ax) * sinc(ax / r); }
    }
}

fn filter_eval(dx: f32, dy: f32) -> f32 {
    return filter_1d(dx) * filter_1d(dy) * params.filter_scale * params.filter_scale;
}

// Where sample `index` of pixel (px, py) landed on the film: the Whitted integrator's
// pixel pattern, or the path sampler's first two numbers.
fn film_position(px: u32, py: u32, index: u32) -> vec2<f32> {
    if params.integrator == INTEGRATOR_WHITTED {
        return vec2<f32>(f32(px), f32(py)) + whitted_offset(px, py, index);
    }
    var sampler = path_sampler(params.sampler == 0u, px, py, index, params.seed);
    return vec2<f32>(f32(px), f32(py)) + next_2d(&sampler);
}

// The instance whose shading first made the current sample NaN or infinite
// (glint_core's Counters::blame), NO_INDEX while none has (or for the background).
var<private> blamed: u32 = NO_INDEX;

// Blames `instance` when `value`, just updated at a hit on it, is no longer finite and
// no deeper surface was blamed first.
fn blame(instance: u32, value: vec3<f32>) {
    if blamed == NO_INDEX && !finite3(value) {
        blamed = instance;
    }
}

// Sample flags (w of a sample's first vec4).
const SAMPLE_NON_FINITE: f32 = 1.0;
const SAMPLE_ABSENT: f32 = 2.0;

fn film_stride() -> u32 {
    return select(1u, 3u, params.aovs != 0u);
}

fn sample_slot(x: u32, y: u32, k: u32) -> u32 {
    return ((k * params.height + y) * params.width + x) * film_stride();
}

// The current sample's first hit as the AOVs see it (glint_core::film::Aov): albedo
// and depth, normal; zero where the camera ray left the scene.
var<private> aov_albedo_depth: vec4<f32> = vec4<f32>(0.0);
var<private> aov_normal: vec4<f32> = vec4<f32>(0.0);

fn record_first_hit(albedo: vec3<f32>, normal: vec3<f32>, depth: f32) {
    aov_albedo_depth = vec4<f32>(albedo, depth);
    aov_normal = vec4<f32>(normal, 0.0);
}

// Which sample of its pixel thread `id` traces: the pass's `id.z`-th. NO_INDEX, with
// its slot marked empty, where adaptive sampling asks fewer of the pixel.
fn pass_sample(id: vec3<u32>) -> u32 {
    let index = pass_base(id.x, id.y) + id.z;
    if params.adaptive_min != 0u && index >= adaptive_state(id.x, id.y).target_count {
        samples[sample_slot(id.x, id.y, id.z)] = vec4<f32>(0.0, 0.0, 0.0, SAMPLE_ABSENT);
        return NO_INDEX;
    }
    return index;
}

// The index of the pass's first sample in pixel (x, y).
fn pass_base(x: u32, y: u32) -> u32 {
    if params.adaptive_min != 0u {
        return adaptive_state(x, y).count;
    }
    return params.sample_offset;
}

// Stores sample `id` with its AOVs. A NaN or infinite one never reaches the film (its
// flag makes the splat skip it); it is counted by its source in `faults`: for source s
// (0 the background, 1 + i instance i), faults[2s] counts and faults[2s + 1] keeps the
// smallest pixel index.
fn write_sample(id: vec3<u32>, value: vec3<f32>) {
    let slot = sample_slot(id.x, id.y, id.z);
    if params.aovs != 0u {
        samples[slot + 1u] = aov_albedo_depth;
        samples[slot + 2u] = aov_normal;
    }
    if finite3(value) {
        samples[slot] = vec4<f32>(value, 0.0);
        return;
    }
    samples[slot] = vec4<f32>(0.0, 0.0, 0.0, SAMPLE_NON_FINITE);
    let source = select(blamed + 1u, 0u, blamed == NO_INDEX);
    atomicAdd(&faults[2u * source], 1u);
    atomicMin(&faults[2u * source + 1u], id.y * params.width + id.x);
}

@compute @workgroup_size(8, 8, 1)
fn splat(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let r = params.filter_radius;
    let reach = i32(ceil(r));
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    var albedo_depth = vec4<f32>(0.0);
    var normal = vec4<f32>(0.0);
    for (var qy = i32(id.y) - reach; qy <= i32(id.y) + reach; qy += 1) {
        if qy < 0 || qy >= i32(params.height) {
            continue;
        }
        for (var qx = i32(id.x) - reach; qx <= i32(id.x) + reach; qx += 1) {
            if qx < 0 || qx >= i32(params.width) {
                continue;
            }
            // A pilot round splats after its decision, and only the pilots of the pixels
            // that stop there (a settled pixel's m2 is negative).
            if params.adaptive_first == ADAPTIVE_PILOT && !(adaptive_state(u32(qx), u32(qy)).m2 < 0.0) {
                continue;
            }
            let base = pass_base(u32(qx), u32(qy));
            for (var k = 0u; k < params.pass_samples; k += 1u) {
                let slot = sample_slot(u32(qx), u32(qy), k);
                let sample = samples[slot];
                if sample.w != 0.0 {
                    continue;
                }
                let f = film_position(u32(qx), u32(qy), base + k);
                // The pixels this sample reaches, exactly as splat_with bounds them.
                let x_lo = i32(ceil(f.x - 0.5 - r));
                let x_hi = i32(floor(f.x - 0.5 + r));
                let y_lo = i32(ceil(f.y - 0.5 - r));
                let y_hi = i32(floor(f.y - 0.5 + r));
                let x = i32(id.x);
                let y = i32(id.y);
                if x < x_lo || x > x_hi || y < y_lo || y > y_hi {
                    continue;
                }
                let w = filter_eval(f32(id.x) + 0.5 - f.x, f32(id.y) + 0.5 - f.y);
                if w != 0.0 {
                    sum += w * sample.xyz;
                    weight += w;
                    if params.aovs != 0u {
                        albedo_depth += w * samples[slot + 1u];
                        normal += w * samples[slot + 2u];
                    }
                }
            }
        }
    }
    let i = (id.y * params.width + id.x) * film_stride();
    accum[i] += vec4<f32>(sum, weight);
    if params.aovs != 0u {
        accum[i + 1u] += albedo_depth;
        accum[i + 2u] += normal;
    }
}

// ---- adaptive sampling (glint_core::render::adaptive_tile, one round at a time) ----
//
// Each round traces, per pixel, the samples it still needs (up to the pass size),
// splats them, adds them to the pixel's running mean and variance (`adaptive_update`),
// then decides how many the pixel needs next (`adaptive_decide`). The host repeats
// rounds until no pixel needs more.

// A pixel's sampling state: samples taken, running mean and sum of squared deviations
// of their display luminance (Welford), and the count it is to reach.
struct AdaptiveState {
    count: u32,
    mean: f32,
    m2: f32,
    target_count: u32,
}

fn adaptive_slot(x: u32, y: u32) -> u32 {
    return params.width * params.height * film_stride() + y * params.width + x;
}

fn adaptive_state(x: u32, y: u32) -> AdaptiveState {
    let v = accum[adaptive_slot(x, y)];
    return AdaptiveState(bitcast<u32>(v.x), v.y, v.z, bitcast<u32>(v.w));
}

// The two words after the fault tallies: pixels still sampling, and the most samples
// one of them needs in the next round.
fn round_tally() -> u32 {
    return arrayLength(&faults) - 2u;
}

// Luminance after sRGB encoding, as the CPU's stopping rule weighs it.
fn display_luminance(c: vec3<f32>) -> f32 {
    let y = clamp(dot(c, vec3<f32>(0.2126, 0.7152, 0.0722)), 0.0, 1.0);
    if y <= 0.0031308 {
        return 12.92 * y;
    }
    return 1.055 * pow(y, 1.0 / 2.4) - 0.055;
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_update(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    var s = adaptive_state(id.x, id.y);
    for (var k = 0u; k < params.pass_samples; k += 1u) {
        let sample = samples[sample_slot(id.x, id.y, k)];
        if sample.w == SAMPLE_ABSENT {
            break;
        }
        s.count += 1u;
        if sample.w == SAMPLE_NON_FINITE {
            // The CPU's statistics turn NaN: the pixel goes on to the maximum.
            s.m2 = INF;
            continue;
        }
        let x = display_luminance(sample.xyz);
        let delta = x - s.mean;
        s.mean += delta / f32(s.count);
        s.m2 += delta * (x - s.mean);
    }
    accum[adaptive_slot(id.x, id.y)] = vec4<f32>(bitcast<f32>(s.count), s.mean, s.m2, bitcast<f32>(s.target_count));
}

@compute @workgroup_size(8, 8, 1)
fn adaptive_decide(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let s = adaptive_state(id.x, id.y);
    var target_count = s.target_count;
    // One sample tells nothing of a pixel's spread: it stops where its neighbours agree.
    // The first round decides it, and marks it by a negative m2 (which a spread never
    // has), so the rounds after it keep it settled.
    var settled = s.m2 < 0.0;
    if s.count >= target_count {
        if params.adaptive_first != 0u {
            // A pixel whose mean differs from a neighbour's by more than twice the
            // threshold first takes four times the minimum.
            var contrast = 0.0;
            let x = i32(id.x);
            let y = i32(id.y);
            for (var n = 0; n < 4; n += 1) {
                let nx = x + select(select(0, 1, n == 1), -1, n == 0);
                let ny = y + select(select(0, 1, n == 3), -1, n == 2);
                if nx >= 0 && ny >= 0 && nx < i32(params.width) && ny < i32(params.height) {
                    contrast = max(contrast, abs(adaptive_state(u32(nx), u32(ny)).mean - s.mean));
                }
            }
            if contrast > 2.0 * params.adaptive_threshold {
                target_count = max(min(4u * params.adaptive_min, params.adaptive_max), s.count);
            }
            if s.count == 1u && (contrast <= params.adaptive_threshold || params.adaptive_max == 1u) {
                settled = true;
                accum[adaptive_slot(id.x, id.y)].z = -1.0;
            }
        }
        if s.count >= target_count {
            var standard_error = INF;
            if s.count >= 2u {
                standard_error = sqrt(s.m2 / f32(s.count - 1u) / f32(s.count));
            }
            if s.count >= params.adaptive_max || standard_error <= params.adaptive_threshold || settled {
                target_count = s.count;
            } else {
                target_count = min(2u * s.count, params.adaptive_max);
            }
        }
    }
    // A pixel that goes on past its pilot drops it (adaptive_drop_pilots) and takes its
    // own samples from the first, at least four.
    var after = s.count;
    if params.adaptive_first == ADAPTIVE_PILOT && !settled {
        target_count = min(4u, params.adaptive_max);
        after = 0u;
    }
    // Only the target (and a settled pixel's m2) change: the neighbours read this
    // pixel's mean meanwhile.
    accum[adaptive_slot(id.x, id.y)].w = bitcast<f32>(target_count);
    if target_count > after {
        atomicAdd(&faults[round_tally()], 1u);
        atomicMax(&faults[round_tally() + 1u], target_count - after);
    }
}

// After a pilot round's splat: the pixels that go on forget their pilot, so that their
// own samples start from the first (glint_core::render::adaptive_tile).
@compute @workgroup_size(8, 8, 1)
fn adaptive_drop_pilots(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let s = adaptive_state(id.x, id.y);
    if s.m2 < 0.0 {
        return;
    }
    accum[adaptive_slot(id.x, id.y)] = vec4<f32>(bitcast<f32>(0u), 0.0, 0.0, bitcast<f32>(s.target_count));
}
