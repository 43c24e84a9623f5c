//! A part of a render as an OpenEXR file, for batch schedulers: `glint render --part
//! I/N` writes one, `glint merge` reads them all back.
//!
//! Besides the part's own image (`R`, `G`, `B`, for a look), the file keeps what the
//! merge needs bit for bit, as 32-bit float layers named by a tile's offset from a
//! pixel's own tile: `tile-1+0.R`, `.G`, `.B` (weighted colour sums) and `.W` (weights);
//! `samples.N` (samples per pixel, 32-bit unsigned); and, in the header attribute
//! `glint:part` (a list of `key=value`), the part, the render's fingerprint, the
//! filter's reach, the rays traced, the output transfer and the non-finite samples.

use std::collections::HashMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, Layer, LayerAttributes, ReadChannels,
    ReadLayers, SmallVec, Text, WritableImage,
};
use glint_core::film::Transfer;
use glint_core::integrator::SurfaceId;
use glint_core::render::{NonFiniteSamples, Part, PartialFilm, SourceTally};

use crate::atomic_file::write_atomically;
use crate::input::{InputKind, read_bytes};

/// What a part's file says about the render it belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PartMeta {
    /// The hash of the scene and settings: parts of one render share it.
    pub fingerprint: u64,
    /// How 8/16-bit outputs of the merged image are encoded.
    pub transfer: Transfer,
}

/// Why a part's file cannot be written or read.
#[derive(Debug, thiserror::Error)]
pub enum PartFileError {
    #[error("cannot write {path}: {message}")]
    Write { path: PathBuf, message: String },
    #[error("cannot read {path}: {message}")]
    Read { path: PathBuf, message: String },
    #[error("{path} is not a part of a glint render: {message}")]
    NotAPart { path: PathBuf, message: String },
}

/// The header attribute: a list of `key=value` entries with these keys.
const PART: &str = "glint:part";
const INDEX: &str = "part";
const FINGERPRINT: &str = "fingerprint";
const REACH: &str = "reach";
const RAYS: &str = "rays";
const TRANSFER: &str = "transfer";
const NON_FINITE: &str = "non-finite";

/// The layer name of a tile `(dx, dy)` tiles from a pixel's own.
fn layer_name(layer: usize, reach: u32) -> String {
    let side = 2 * reach as i64 + 1;
    let (dx, dy) = (layer as i64 % side - reach as i64, layer as i64 / side - reach as i64);
    format!("tile{dx:+}{dy:+}")
}

/// Writes `film` to `path` (atomically).
pub fn write_part(path: &Path, film: &PartialFilm, meta: PartMeta) -> Result<(), PartFileError> {
    let fail = |message: String| PartFileError::Write { path: path.to_owned(), message };
    let bytes = encode_part(film, meta).map_err(fail)?;
    write_atomically(path, |tmp| std::fs::write(tmp, &bytes).map_err(|e| fail(e.to_string())), |e| fail(e.to_string()))
}

/// `film` as the bytes of its OpenEXR file: what a part file holds, and what a
/// distributed render sends back from a worker.
pub fn encode_part(film: &PartialFilm, meta: PartMeta) -> Result<Vec<u8>, String> {
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    let preview = film.preview();
    for (k, name) in ["R", "G", "B"].into_iter().enumerate() {
        channels.push(AnyChannel::new(name, FlatSamples::F32(preview.pixels.iter().map(|p| p[k]).collect())));
    }
    for (layer, sums) in film.layers.iter().enumerate() {
        let prefix = layer_name(layer, film.reach);
        for (k, name) in ["R", "G", "B", "W"].into_iter().enumerate() {
            let values = sums.iter().map(|s| s[k]).collect();
            channels.push(AnyChannel::new(format!("{prefix}.{name}").as_str(), FlatSamples::F32(values)));
        }
    }
    channels.push(AnyChannel::new("samples.N", FlatSamples::U32(film.samples.clone())));
    let attributes = LayerAttributes { other: header(film, meta), ..LayerAttributes::default() };
    let size = (film.width as usize, film.height as usize);
    let image = Image::from_layer(Layer::new(size, attributes, Encoding::SMALL_LOSSLESS, AnyChannels::sort(channels)));
    let mut bytes = Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

fn header(film: &PartialFilm, meta: PartMeta) -> HashMap<Text, AttributeValue> {
    let transfer = match meta.transfer {
        Transfer::Srgb => "srgb",
        Transfer::Identity => "identity",
    };
    let non_finite = film
        .non_finite
        .by_source()
        .iter()
        .map(|(source, tally)| {
            let (instance, material) = source.map_or((-1, -1), |s| (s.instance as i64, s.material as i64));
            let (x, y) = tally.example_pixel;
            format!("{instance} {material} {} {x} {y}", tally.count)
        })
        .collect::<Vec<_>>()
        .join(";");
    // One attribute holding an ordered list: exr keeps other attributes in a HashMap,
    // whose order (and so the file's bytes) would change from run to run.
    let entries = [
        (INDEX, format!("{}/{}", film.part.index, film.part.count)),
        (FINGERPRINT, format!("{:016x}", meta.fingerprint)),
        (REACH, film.reach.to_string()),
        (RAYS, film.rays.to_string()),
        (TRANSFER, transfer.to_string()),
        (NON_FINITE, non_finite),
    ];
    let list = entries.into_iter().map(|(key, value)| Text::new_or_panic(format!("{key}={value}"))).collect();
    HashMap::from([(Text::new_or_panic(PART), AttributeValue::TextVector(list))])
}

/// Reads a part written by [`write_part`], within the image file size limit.
pub fn read_part(path: &Path) -> Result<(PartialFilm, PartMeta), PartFileError> {
    let bytes = read_bytes(path, InputKind::Image)
        .map_err(|e| PartFileError::Read { path: path.to_owned(), message: e.to_string() })?;
    decode_part(&bytes, path)
}

/// A part from the bytes [`encode_part`] made; `origin` names them in errors.
pub fn decode_part(bytes: &[u8], origin: &Path) -> Result<(PartialFilm, PartMeta), PartFileError> {
    let path = origin;
    let not_a_part = |message: String| PartFileError::NotAPart { path: path.to_owned(), message };
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| not_a_part(format!("not a readable OpenEXR file ({e})")))?;
    let layer = &image.layer_data;
    let Some(AttributeValue::TextVector(list)) = layer.attributes.other.get(&Text::new_or_panic(PART)) else {
        return Err(not_a_part(format!("no '{PART}' attribute")));
    };
    let entries: std::collections::BTreeMap<String, String> = list
        .iter()
        .filter_map(|entry| entry.to_string().split_once('=').map(|(k, v)| (k.to_string(), v.to_string())))
        .collect();
    let text = |key: &str| entries.get(key).cloned().ok_or_else(|| not_a_part(format!("no '{key}' in '{PART}'")));
    let number = |key: &str, what: &str| {
        let value = text(key)?;
        let parsed = if key == FINGERPRINT { u64::from_str_radix(&value, 16).ok() } else { value.parse().ok() };
        parsed.ok_or_else(|| not_a_part(format!("'{key}' is not {what}: '{value}'")))
    };
    let part = parse_part(&text(INDEX)?).ok_or_else(|| not_a_part("'part' is not I/N".into()))?;
    let reach = match text(REACH)?.parse::<u32>() {
        Ok(r) if r <= 8 => r,
        _ => return Err(not_a_part("'reach' is not a whole number from 0 to 8".into())),
    };
    let transfer = match text(TRANSFER)?.as_str() {
        "srgb" => Transfer::Srgb,
        "identity" => Transfer::Identity,
        other => return Err(not_a_part(format!("unknown transfer '{other}'"))),
    };
    let (width, height) = (layer.size.0 as u32, layer.size.1 as u32);
    let mut film = PartialFilm::empty(width, height, part, reach);
    film.rays = number(RAYS, "a count")?;
    film.non_finite =
        parse_non_finite(&text(NON_FINITE)?).ok_or_else(|| not_a_part("bad 'non-finite' tallies".into()))?;
    let channel = |name: &str| layer.channel_data.list.iter().find(|c| c.name.to_string() == name);
    let missing = |name: &str| not_a_part(format!("no channel '{name}'"));
    for (index, sums) in film.layers.iter_mut().enumerate() {
        let prefix = layer_name(index, reach);
        for (k, suffix) in ["R", "G", "B", "W"].into_iter().enumerate() {
            let name = format!("{prefix}.{suffix}");
            let Some(FlatSamples::F32(values)) = channel(&name).map(|c| &c.sample_data) else {
                return Err(missing(&name));
            };
            for (sum, &v) in sums.iter_mut().zip(values) {
                sum[k] = v;
            }
        }
    }
    let Some(FlatSamples::U32(samples)) = channel("samples.N").map(|c| &c.sample_data) else {
        return Err(missing("samples.N"));
    };
    film.samples.clone_from(samples);
    Ok((film, PartMeta { fingerprint: number(FINGERPRINT, "a hexadecimal hash")?, transfer }))
}

/// `I/N` with `I < N`.
pub fn parse_part(text: &str) -> Option<Part> {
    let (index, count) = text.split_once('/')?;
    let (index, count) = (index.trim().parse().ok()?, count.trim().parse().ok()?);
    (index < count).then_some(Part { index, count })
}

fn parse_non_finite(text: &str) -> Option<NonFiniteSamples> {
    let mut tally = NonFiniteSamples::default();
    for entry in text.split(';').filter(|e| !e.is_empty()) {
        let numbers: Vec<i64> = entry.split(' ').map(|n| n.parse().ok()).collect::<Option<_>>()?;
        let &[instance, material, count, x, y] = numbers.as_slice() else { return None };
        let source = (instance >= 0).then_some(SurfaceId { instance: instance as u32, material: material as u32 });
        tally.add(source, SourceTally { count: count.max(0) as u64, example_pixel: (x as u32, y as u32) });
    }
    Some(tally)
}
