//! Feeds arbitrary bytes to the native reader ([`glint_fuzz::readers::native`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::native(data));
