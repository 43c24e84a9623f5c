//! Feeds arbitrary bytes to the course_json reader ([`glint_fuzz::readers::course_json`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::course_json(data));
