//! Feeds arbitrary bytes to the mitsuba_xml reader ([`glint_fuzz::readers::mitsuba_xml`]).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| glint_fuzz::readers::mitsuba_xml(data));
