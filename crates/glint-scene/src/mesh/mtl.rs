//! Wavefront MTL material libraries, mapped onto glint's Phong material.
//!
//! | MTL | glint |
//! |-----|-------|
//! | `Kd`, `map_Kd` | diffuse colour and texture |
//! | `Ks`, `Ns` | specular colour and Phong exponent |
//! | `Ke` | emission (an area light for the path tracer) |
//! | `d` < 1 or `Tr` > 0 (times `Tf`) | transmission straight through (ior 1), diffuse scaled by `d` |
//! | `illum` 3, 5, 7 (and 4, 6) | mirror reflection in the `Ks` colour |
//! | `illum` 4, 6, 7, 9 | glass: transmission `Tf` refracted with ior `Ni` (1.5 when absent); a smooth dielectric for the path tracer |
//!
//! | `norm`, and `bump`/`map_Bump` holding a normal map | a tangent-space normal map (its `-bm` scales it) |
//!
//! Without an `illum` of 3 to 7 a surface has no mirror reflection (illum 2, a
//! highlight only, is what exporters write for ordinary surfaces). Exporters (Blender's
//! among them) write normal maps as `map_Bump`: a bump image whose mean texel is the
//! bluish (0.5, 0.5, ≥ 0.6) of a tangent-space normal map is read as one; a height map
//! is not used. `map_Ks` and the other maps have no slot in glint's material: they are
//! named in one warning per material.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use glint_core::desc::{BsdfDesc, MaterialDesc, NormalMapDesc, ScalarParam, TextureDesc, Transfer};

use super::decode_text;

/// One `newmtl` block as its statements were read.
#[derive(Clone, Debug, Default)]
struct Entry {
    kd: Option<Vec3>,
    ks: Option<Vec3>,
    ke: Option<Vec3>,
    tf: Option<Vec3>,
    ns: Option<f32>,
    ni: Option<f32>,
    /// Opacity: `d`, or `1 − Tr`.
    opacity: Option<f32>,
    illum: Option<u32>,
    map_kd: Option<PathBuf>,
    /// A normal or bump map: the file, its `-bm` scale, and whether it was given as
    /// `norm` (certainly a normal map) rather than as a bump map.
    map_normal: Option<(PathBuf, f32, bool)>,
    /// Maps glint reads past (`map_Ks`, `bump`, …), by keyword.
    unused_maps: Vec<String>,
    /// The MTL file the material came from, for warnings.
    file: PathBuf,
}

/// The materials of the MTL files an OBJ names.
#[derive(Default)]
pub struct Library {
    materials: HashMap<String, Entry>,
}

/// Maps read but not drawn: glint's material has no slot for them.
const UNUSED_MAPS: [&str; 8] = ["map_Ks", "map_Ka", "map_Ns", "map_d", "map_Ke", "disp", "decal", "refl"];

impl Library {
    /// Reads one MTL file; a missing or broken library is a warning (the model still shows).
    pub fn read(&mut self, path: &Path, warnings: &mut Vec<String>) {
        let bytes = match crate::input::read_bytes(path, crate::input::InputKind::Mesh) {
            Ok(b) => b,
            Err(e) => {
                warnings.push(format!("{}: cannot read material library: {}", path.display(), e.problem));
                return;
            }
        };
        let text = decode_text(&bytes);
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut current: Option<String> = None;
        for (n, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            let Some((keyword, rest)) = split_keyword(line) else { continue };
            if keyword == "newmtl" {
                let entry = Entry { file: path.to_path_buf(), ..Default::default() };
                self.materials.insert(rest.to_owned(), entry);
                current = Some(rest.to_owned());
                continue;
            }
            let Some(entry) = current.as_ref().and_then(|c| self.materials.get_mut(c)) else { continue };
            if let Err(message) = entry.statement(keyword, rest, dir) {
                warnings.push(format!("{}:{}: {message}", path.display(), n + 1));
            }
        }
    }

    /// The material `name`, its texture loaded into `textures`; unknown names get the
    /// default material with a warning.
    pub fn material(&self, name: &str, textures: &mut Vec<TextureDesc>, warnings: &mut Vec<String>) -> MaterialDesc {
        let Some(entry) = self.materials.get(name) else {
            warnings.push(format!("material '{name}' is not in any material library; using the default"));
            return MaterialDesc { name: name.to_owned(), ..Default::default() };
        };
        if !entry.unused_maps.is_empty() {
            warnings.push(format!(
                "{}: material '{name}': {} read but not used (glint's material has no slot for them)",
                entry.file.display(),
                entry.unused_maps.join(", ")
            ));
        }
        let mut m = entry.material(name);
        if let Some(file) = &entry.map_kd {
            match crate::texture_io::load_texture(name, file) {
                Ok(t) => {
                    textures.push(t);
                    m.texture = Some(textures.len() - 1);
                    m.blend = 1.0;
                }
                Err(e) => warnings.push(format!("material '{name}': texture not loaded: {e}")),
            }
        }
        if let Some((file, scale, certain)) = &entry.map_normal {
            m.normal_map = normal_map(name, file, *scale, *certain, textures, warnings);
        }
        m
    }
}

/// The normal map in `file`, loaded as data into `textures`; `None`, with a warning,
/// when it cannot be loaded or (given as a bump map) holds heights, not normals.
fn normal_map(
    name: &str,
    file: &Path,
    scale: f32,
    certain: bool,
    textures: &mut Vec<TextureDesc>,
    warnings: &mut Vec<String>,
) -> Option<NormalMapDesc> {
    let texture = match crate::texture_io::load_texture_encoded(name, file, Transfer::Identity) {
        Ok(t) => t,
        Err(e) => {
            warnings.push(format!("material '{name}': normal map not loaded: {e}"));
            return None;
        }
    };
    if !certain && !looks_like_normal_map(&texture) {
        warnings.push(format!(
            "material '{name}': {} is a bump (height) map, which glint does not use; only normal maps bend normals",
            file.display()
        ));
        return None;
    }
    textures.push(texture);
    Some(NormalMapDesc { texture: textures.len() - 1, scale })
}

/// Whether an image's mean texel is the bluish (0.5, 0.5, high) of a tangent-space
/// normal map, rather than the grey of a height map.
fn looks_like_normal_map(texture: &TextureDesc) -> bool {
    let TextureDesc::Image { texels, .. } = texture else { return false };
    let mean = texels.iter().copied().sum::<Vec3>() / texels.len().max(1) as f32;
    mean.z >= 0.6 && (mean.x - 0.5).abs() < 0.2 && (mean.y - 0.5).abs() < 0.2
}

/// The `-bm` option of a map statement (the bump multiplier), 1 without one.
fn bump_scale(rest: &str) -> f32 {
    let mut words = rest.split_whitespace();
    while let Some(word) = words.next() {
        if word == "-bm" {
            return words.next().and_then(|w| w.parse().ok()).filter(|x: &f32| x.is_finite()).unwrap_or(1.0);
        }
    }
    1.0
}

/// The first word of `line` and the rest, trimmed (names and file names may hold spaces).
fn split_keyword(line: &str) -> Option<(&str, &str)> {
    let keyword = line.split_whitespace().next()?;
    Some((keyword, line[keyword.len()..].trim()))
}

impl Entry {
    /// Takes one statement of the material; an error is a message for a warning.
    fn statement(&mut self, keyword: &str, rest: &str, dir: &Path) -> Result<(), String> {
        let numbers: Vec<f32> =
            rest.split_whitespace().map_while(|w| w.parse().ok()).filter(|x: &f32| x.is_finite()).collect();
        let color = || match numbers[..] {
            [r, g, b, ..] => Ok(Vec3::new(r, g, b)),
            [grey] => Ok(Vec3::splat(grey)),
            _ => Err(format!("'{keyword}' needs 3 numbers, found '{rest}'")),
        };
        let number = || numbers.first().copied().ok_or_else(|| format!("'{keyword}' needs a number, found '{rest}'"));
        match keyword {
            "Kd" => self.kd = Some(color()?),
            "Ks" => self.ks = Some(color()?),
            "Ke" => self.ke = Some(color()?),
            "Tf" => self.tf = Some(color()?),
            "Ns" => self.ns = Some(number()?.max(0.0)),
            "Ni" => self.ni = Some(number()?),
            "d" => self.opacity = Some(number()?.clamp(0.0, 1.0)),
            "Tr" => self.opacity = Some(1.0 - number()?.clamp(0.0, 1.0)),
            "illum" => self.illum = Some(number()? as u32),
            "map_Kd" => {
                let file = map_file(rest).ok_or_else(|| "'map_Kd' names no file".to_owned())?;
                self.map_kd = Some(find_texture(dir, &file));
            }
            "norm" | "bump" | "map_bump" | "map_Bump" => {
                let file = map_file(rest).ok_or_else(|| format!("'{keyword}' names no file"))?;
                self.map_normal = Some((find_texture(dir, &file), bump_scale(rest), keyword == "norm"));
            }
            _ if UNUSED_MAPS.contains(&keyword) && !self.unused_maps.iter().any(|m| m == keyword) => {
                self.unused_maps.push(keyword.to_owned());
            }
            _ => {}
        }
        Ok(())
    }

    /// The glint material these statements describe (see the module's table).
    fn material(&self, name: &str) -> MaterialDesc {
        let illum = self.illum.unwrap_or(2);
        let glass = matches!(illum, 4 | 6 | 7 | 9);
        let mirror = matches!(illum, 3..=7);
        let opacity = self.opacity.unwrap_or(1.0);
        let specular = self.ks.unwrap_or(Vec3::ZERO);
        let filter = self.tf.unwrap_or(Vec3::ONE);
        let mut m = MaterialDesc {
            name: name.to_owned(),
            ks: 1.0,
            specular,
            reflective: Some(if mirror { specular } else { Vec3::ZERO }),
            emission: self.ke.unwrap_or(Vec3::ZERO),
            ..Default::default()
        };
        m.diffuse = self.kd.unwrap_or(m.diffuse);
        m.shininess = self.ns.unwrap_or(m.shininess);
        if glass {
            m.transmissive = if opacity < 1.0 { (1.0 - opacity) * filter } else { filter };
            m.ior = self.ni.filter(|&n| n > 0.0).unwrap_or(1.5);
            m.kd = opacity.min(1.0 - m.transmissive.max_element()).max(0.0);
            // The path tracer draws it as smooth glass, with Fresnel weighting.
            m.bsdf = Some(BsdfDesc::Dielectric {
                int_ior: m.ior,
                ext_ior: 1.0,
                reflectance: Vec3::ONE,
                transmittance: m.transmissive,
                alpha: ScalarParam::constant(0.0),
            });
        } else if opacity < 1.0 {
            m.transmissive = (1.0 - opacity) * filter;
            m.kd = opacity;
        }
        m
    }
}

/// The file name of a texture statement: what follows its options (`-s 1 1`, `-bm 0.5`,
/// `-clamp on`, …), spaces included; `\ ` is an escaped space.
pub fn map_file(rest: &str) -> Option<String> {
    let mut tail = rest.trim_start();
    while tail.starts_with('-') {
        let (option, after) = split_keyword(tail).unwrap_or((tail, ""));
        tail = after;
        let (min, max) = match option {
            "-o" | "-s" | "-t" => (1, 3),
            "-mm" => (2, 2),
            _ => (1, 1),
        };
        for k in 0..max {
            let Some((word, after)) = split_keyword(tail) else { break };
            let numeric = word.parse::<f32>().is_ok();
            // Numbers (or the one word of an on/off or name option) belong to the option.
            if !numeric && (k >= min || max > 1) {
                break;
            }
            tail = after;
        }
    }
    let file = tail.trim().replace("\\ ", " ");
    (!file.is_empty()).then_some(file)
}

/// Where texture `file` of an MTL in `dir` is: as written, with Windows separators
/// turned around, or (for an absolute path from another machine) by its name alone.
fn find_texture(dir: &Path, file: &str) -> PathBuf {
    let written = dir.join(file);
    if written.exists() {
        return written;
    }
    let portable = file.replace('\\', "/");
    let candidate = dir.join(&portable);
    if candidate.exists() {
        return candidate;
    }
    match portable.rsplit('/').next().map(|name| dir.join(name)).filter(|p| p.exists()) {
        Some(by_name) => by_name,
        None => candidate,
    }
}
