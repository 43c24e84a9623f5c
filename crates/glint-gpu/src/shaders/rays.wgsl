// Closest hits of a batch of rays, for testing traversal against the CPU and for
// timing rays per second: ray i is samples[2i] (origin, t_max) and samples[2i + 1]
// (direction, unused); its hit goes to accum[i] as (t, instance, part, found), the
// integers as bits.

@compute @workgroup_size(64, 1, 1)
fn trace_rays(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * 65535u * 64u;
    if i >= params.pass_samples {
        return;
    }
    let o = samples[2u * i];
    let d = samples[2u * i + 1u];
    let h = trace_scene(Ray(o.xyz, d.xyz, 0.0), o.w, false);
    var out = vec4<f32>(0.0);
    if h.found {
        out = vec4<f32>(h.shape.t, bitcast<f32>(h.instance), bitcast<f32>(h.shape.part), 1.0);
    }
    accum[i] = out;
}
