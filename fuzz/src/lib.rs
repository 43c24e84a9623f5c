//! The code the fuzz targets run, kept out of `fuzz_targets/` so that the stable
//! regression test (`crates/glint-scene/tests/fuzz_regressions.rs`) replays saved
//! inputs through exactly the same calls.

pub mod readers;
pub mod scene_gen;
