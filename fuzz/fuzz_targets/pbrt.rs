//! Feeds arbitrary bytes to the pbrt-v4 reader ([`glint_fuzz::readers::pbrt`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::pbrt(data));
