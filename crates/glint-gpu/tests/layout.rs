//! Every record reads the same on the GPU as Rust wrote it: a shader echoes each field
//! of each record, word by word, and the words must equal the Rust record's bytes at
//! the field offsets.

mod common;

use glint_gpu::records::ALL;
use wgpu::util::DeviceExt;

/// Distinct, finite float bit patterns (a GPU may quieten NaN payloads it loads).
fn pattern(words: usize, salt: usize) -> Vec<u32> {
    (0..words).map(|i| (1.0f32 + (i * 7 + salt) as f32 * 0.25).to_bits()).collect()
}

#[test]
fn every_record_echoes_back_field_by_field() {
    let Some(gpu) = common::gpu() else { return };
    const COUNT: usize = 3;
    for (salt, record) in ALL.iter().enumerate() {
        let source = format!(
            "{structs}\n@group(0) @binding(0) var<storage, read> input: array<{name}>;\n\
             @group(0) @binding(1) var<storage, read_write> out: array<u32>;\n\
             @compute @workgroup_size(1) fn echo(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             let r = input[id.x];\n    var k = id.x * {words}u;\n{body}}}\n",
            structs = glint_gpu::shader::structs(),
            name = record.name,
            words = record.data_words(),
            body = record.echo_statements("r"),
        );
        let input = pattern(record.size / 4 * COUNT, salt);
        let bytes: &[u8] = bytemuck::cast_slice(&input);
        let expected: Vec<u32> = bytes.chunks(record.size).flat_map(|r| record.expected_words(r)).collect();
        let device = &gpu.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(record.name),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(record.name),
            layout: None,
            module: &module,
            entry_point: Some("echo"),
            compilation_options: Default::default(),
            cache: None,
        });
        let input_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = (expected.len() * 4) as u64;
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: input_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: out.as_entire_binding() },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(COUNT as u32, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, size);
        gpu.queue.submit([encoder.finish()]);
        readback.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("map"));
        device.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
        let echoed: Vec<u32> = bytemuck::cast_slice(&readback.slice(..).get_mapped_range().expect("mapped")).to_vec();
        assert_eq!(echoed, expected, "record {} reads differently on the GPU", record.name);
    }
}
