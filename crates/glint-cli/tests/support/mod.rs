//! Shared by the CLI tests: reading back what the binary wrote.
#![allow(dead_code)]

use std::path::Path;

/// Every channel of an OpenEXR file's first layer, by name, each pixel's value.
pub fn exr_channels(path: &Path) -> Vec<(String, Vec<f32>)> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .expect("an OpenEXR file");
    let channels = &image.layer_data.channel_data.list;
    let values = |c: &exr::prelude::AnyChannel<exr::prelude::FlatSamples>| {
        (0..c.sample_data.len()).map(|i| c.sample_data.value_by_flat_index(i).to_f32()).collect()
    };
    channels.iter().map(|c| (c.name.to_string(), values(c))).collect()
}

/// One channel of an OpenEXR file's first layer.
pub fn exr_channel(path: &Path, name: &str) -> Vec<f32> {
    let channels = exr_channels(path);
    let found = channels.into_iter().find(|(n, _)| n == name);
    found.unwrap_or_else(|| panic!("no channel {name} in {}", path.display())).1
}
