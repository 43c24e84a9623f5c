//! Feeds arbitrary bytes to the obj reader ([`glint_fuzz::readers::obj`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::obj(data));
