//! Feeds arbitrary bytes to the image reader ([`glint_fuzz::readers::image`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::image(data));
