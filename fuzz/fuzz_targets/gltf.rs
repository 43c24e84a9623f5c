//! Feeds arbitrary bytes to the gltf reader ([`glint_fuzz::readers::gltf`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::gltf(data));
