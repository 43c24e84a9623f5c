//! The render kernels are valid WGSL, checked without a GPU by the same front end and
//! validator wgpu runs (naga).

use wgpu::naga;

#[test]
fn the_render_program_parses_and_validates() {
    let source = glint_gpu::shader::source();
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    let mut validator =
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    if let Err(e) = validator.validate(&module) {
        panic!("{}", e.emit_to_string(&source));
    }
    let entries: Vec<_> = module.entry_points.iter().map(|e| e.name.as_str()).collect();
    let expected = [
        "trace_path",
        "trace_whitted",
        "splat",
        "adaptive_update",
        "adaptive_decide",
        "adaptive_drop_pilots",
        "trace_rays",
    ];
    assert_eq!(entries, expected);
}
