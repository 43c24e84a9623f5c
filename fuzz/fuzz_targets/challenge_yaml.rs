//! Feeds arbitrary bytes to the challenge_yaml reader ([`glint_fuzz::readers::challenge_yaml`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::challenge_yaml(data));
