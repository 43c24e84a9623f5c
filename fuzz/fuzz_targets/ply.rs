//! Feeds arbitrary bytes to the ply reader ([`glint_fuzz::readers::ply`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::ply(data));
