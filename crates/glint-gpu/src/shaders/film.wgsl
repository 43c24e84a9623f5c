// The film: each pixel gathers, in a fixed order, every sample of the pass whose
// reconstruction filter reaches it (glint_core::film::FilmTile::splat_with seen from
// the receiving pixel), and adds the weighted sum and the weight to its accumulator.

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
        return vec2<f32>(f32(px), f32(py)) + pixel_offset(px, py, index);
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

// Stores sample `id`. A NaN or infinite one never reaches the film (w = 1 makes the
// splat skip it); it is counted by its source in `faults`: for source s (0 the
// background, 1 + i instance i), faults[2s] counts and faults[2s + 1] keeps the
// smallest pixel index.
fn write_sample(id: vec3<u32>, value: vec3<f32>) {
    let i = (id.z * params.height + id.y) * params.width + id.x;
    if finite3(value) {
        samples[i] = vec4<f32>(value, 0.0);
        return;
    }
    samples[i] = vec4<f32>(0.0, 0.0, 0.0, 1.0);
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
    for (var qy = i32(id.y) - reach; qy <= i32(id.y) + reach; qy += 1) {
        if qy < 0 || qy >= i32(params.height) {
            continue;
        }
        for (var qx = i32(id.x) - reach; qx <= i32(id.x) + reach; qx += 1) {
            if qx < 0 || qx >= i32(params.width) {
                continue;
            }
            for (var k = 0u; k < params.pass_samples; k += 1u) {
                let f = film_position(u32(qx), u32(qy), params.sample_offset + k);
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
                let sample = samples[(k * params.height + u32(qy)) * params.width + u32(qx)];
                if w != 0.0 && sample.w == 0.0 {
                    sum += w * sample.xyz;
                    weight += w;
                }
            }
        }
    }
    let i = id.y * params.width + id.x;
    accum[i] += vec4<f32>(sum, weight);
}
