//! Feeds arbitrary bytes to the course_xml reader ([`glint_fuzz::readers::course_xml`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::course_xml(data));
