//! Builds a small random scene from the fuzzer's bytes and renders it at 8×8
//! ([`glint_fuzz::scene_gen`]): no panic, and every pixel finite.
#![no_main]

libfuzzer_sys::fuzz_target!(|scene: glint_fuzz::scene_gen::FuzzScene| glint_fuzz::scene_gen::render_checked(&scene));
