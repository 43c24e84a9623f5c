//! PLY (Turk's polygon file format), ASCII and binary little-endian: the `vertex`
//! element's `x y z` (and `nx ny nz`, `u v`/`s t` when present) and the `face`
//! element's index list; other elements and properties are skipped.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::MeshDesc;

use super::{MeshImport, Placement, degenerate_warning, mesh_error, read_limited};
use crate::error::SceneError;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn read_le(self, b: &[u8]) -> f64 {
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

struct Property {
    name: String,
    /// `Some(count type)` for a list property.
    list: Option<Scalar>,
    value: Scalar,
}

struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads values one at a time from the body, ASCII or binary.
enum Body<'a> {
    Ascii { words: std::iter::Peekable<std::str::SplitAsciiWhitespace<'a>>, line_of: &'a dyn Fn(usize) -> u32 },
    Binary { bytes: &'a [u8], at: usize },
}

/// Refuses a file that does not start with the PLY magic, before the rest of it is read.
pub fn check_head(path: &Path, head: &[u8]) -> Result<(), SceneError> {
    if !head.starts_with(b"ply\n") && !head.starts_with(b"ply\r\n") {
        return Err(mesh_error(path, 0, "not a PLY file: it does not start with 'ply'"));
    }
    Ok(())
}

/// Reads the PLY file `path`.
pub fn load(path: &Path) -> Result<MeshImport, SceneError> {
    parse(path, &read_limited(path, |head| check_head(path, head))?)
}

/// Reads PLY `bytes` that came from `path` (which names it in errors).
pub fn parse(path: &Path, bytes: &[u8]) -> Result<MeshImport, SceneError> {
    // The header is text ending at `end_header`; refuse to look further than 64 KiB for it.
    let search = &bytes[..bytes.len().min(1 << 16)];
    let end = search
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| mesh_error(path, 0, "the PLY header has no 'end_header' in its first 64 KiB"))?;
    let body_start = bytes[end..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |p| end + p + 1);
    let header = String::from_utf8_lossy(&bytes[..end]);
    let mut binary = None;
    let mut elements: Vec<Element> = Vec::new();
    for (n, line) in header.lines().enumerate() {
        let err = |m: String| mesh_error(path, n as u32 + 1, m);
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] | [] => {}
            ["comment", ..] | ["obj_info", ..] => {}
            ["format", "ascii", _] => binary = Some(false),
            ["format", "binary_little_endian", _] => binary = Some(true),
            ["format", other, ..] => {
                return Err(err(format!(
                    "PLY format '{other}' is not supported (only ascii and binary_little_endian)"
                )));
            }
            ["element", name, count] => {
                let count = count.parse().map_err(|_| err(format!("element count '{count}' is not a number")))?;
                elements.push(Element { name: (*name).to_owned(), count, properties: Vec::new() });
            }
            ["property", "list", count, value, name] => {
                let (Some(c), Some(v)) = (Scalar::parse(count), Scalar::parse(value)) else {
                    return Err(err(format!("unknown PLY type in '{line}'")));
                };
                let element = elements.last_mut().ok_or_else(|| err("a property before any element".into()))?;
                element.properties.push(Property { name: (*name).to_owned(), list: Some(c), value: v });
            }
            ["property", ty, name] => {
                let v = Scalar::parse(ty).ok_or_else(|| err(format!("unknown PLY type '{ty}'")))?;
                let element = elements.last_mut().ok_or_else(|| err("a property before any element".into()))?;
                element.properties.push(Property { name: (*name).to_owned(), list: None, value: v });
            }
            _ => return Err(err(format!("unexpected PLY header line '{line}'"))),
        }
    }
    let binary = binary.ok_or_else(|| mesh_error(path, 0, "the PLY header has no 'format' line"))?;
    let body_bytes = &bytes[body_start..];
    // Every element needs at least its fixed-size part: refuse counts the file cannot hold
    // before allocating for them.
    let minimum: u128 = elements
        .iter()
        .map(|e| e.count as u128 * e.properties.iter().map(|p| p.list.unwrap_or(p.value).size() as u128).sum::<u128>())
        .sum();
    let floor = if binary { minimum } else { minimum / 8 };
    if floor > body_bytes.len() as u128 {
        return Err(mesh_error(path, 0, "the PLY header announces more data than the file holds"));
    }
    let text;
    let header_lines = header.lines().count() as u32 + 1;
    let line_starts: Vec<usize>;
    let line_of;
    let mut body = if binary {
        Body::Binary { bytes: body_bytes, at: 0 }
    } else {
        text = String::from_utf8_lossy(body_bytes);
        line_starts = text.match_indices('\n').map(|(i, _)| i).collect();
        let base = text.as_ptr() as usize;
        line_of = move |ptr: usize| header_lines + 1 + line_starts.partition_point(|&s| s < ptr - base) as u32;
        Body::Ascii { words: text.split_ascii_whitespace().peekable(), line_of: &line_of }
    };

    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut indices = Vec::new();
    let mut non_triangles = 0usize;
    for element in &elements {
        let find = |names: &[&str]| element.properties.iter().position(|p| names.contains(&p.name.as_str()));
        let xyz = [find(&["x"]), find(&["y"]), find(&["z"])];
        let nxyz = [find(&["nx"]), find(&["ny"]), find(&["nz"])];
        let uv = [find(&["u", "s", "texture_u", "texture_s"]), find(&["v", "t", "texture_v", "texture_t"])];
        let list = element
            .properties
            .iter()
            .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"));
        if element.name == "vertex" && element.count > 0 && xyz.contains(&None) {
            return Err(mesh_error(path, 0, "the PLY vertex element lacks x, y or z"));
        }
        // An element without properties holds no bytes: however large its count, there is
        // nothing to read, and counting through it could take minutes.
        if element.properties.is_empty() {
            continue;
        }
        let mut values = vec![0.0f64; element.properties.len()];
        let mut polygon: Vec<f64> = Vec::new();
        for _ in 0..element.count {
            for (k, p) in element.properties.iter().enumerate() {
                if let Some(count_type) = p.list {
                    let n = body.next(count_type, path)?;
                    if !(0.0..=1e6).contains(&n) {
                        return Err(body.error(path, format!("list length {n} of '{}' is out of range", p.name)));
                    }
                    let keep = list == Some(k);
                    if keep {
                        polygon.clear();
                    }
                    for _ in 0..n as usize {
                        let x = body.next(p.value, path)?;
                        if keep {
                            polygon.push(x);
                        }
                    }
                } else {
                    values[k] = body.next(p.value, path)?;
                }
            }
            if element.name == "vertex" {
                let get = |i: Option<usize>| i.map(|i| values[i] as f32);
                let (Some(x), Some(y), Some(z)) = (get(xyz[0]), get(xyz[1]), get(xyz[2])) else {
                    return Err(mesh_error(path, 0, "the PLY vertex element lacks x, y or z"));
                };
                let p = Vec3::new(x, y, z);
                if !p.is_finite() {
                    return Err(body.error(
                        path,
                        format!("vertex {} has a coordinate that is not a finite number", positions.len()),
                    ));
                }
                positions.push(p);
                if let (Some(x), Some(y), Some(z)) = (get(nxyz[0]), get(nxyz[1]), get(nxyz[2])) {
                    normals.push(Vec3::new(x, y, z));
                }
                if let (Some(u), Some(v)) = (get(uv[0]), get(uv[1])) {
                    uvs.push(Vec2::new(u, v));
                }
            } else if element.name == "face" && list.is_some() {
                if polygon.len() < 3 {
                    non_triangles += 1;
                    continue;
                }
                for k in 1..polygon.len() - 1 {
                    for i in [polygon[0], polygon[k], polygon[k + 1]] {
                        if !(i >= 0.0 && (i as usize) < element_count(&elements, "vertex")) {
                            return Err(body.error(path, format!("face index {i} is out of range")));
                        }
                        indices.push(i as u32);
                    }
                }
            }
        }
    }
    let mut warnings = Vec::new();
    if non_triangles > 0 {
        warnings.push(format!("{}: skipped {non_triangles} faces with fewer than 3 corners", path.display()));
    }
    let mesh = MeshDesc {
        name: path.file_stem().and_then(|s| s.to_str()).unwrap_or("ply").to_owned(),
        path: path.display().to_string(),
        normals: if normals.len() == positions.len() { normals } else { vec![] },
        uvs: if uvs.len() == positions.len() { uvs } else { vec![] },
        colors: vec![],
        positions,
        indices,
    };
    degenerate_warning(path, &mesh, &mut warnings);
    Ok(MeshImport {
        meshes: vec![mesh],
        placements: vec![Placement { mesh: 0, material: None, world_from_object: Mat4::IDENTITY }],
        warnings,
        ..Default::default()
    })
}

fn element_count(elements: &[Element], name: &str) -> usize {
    elements.iter().find(|e| e.name == name).map_or(0, |e| e.count)
}

impl Body<'_> {
    fn next(&mut self, ty: Scalar, path: &Path) -> Result<f64, SceneError> {
        match self {
            Body::Binary { bytes, at } => {
                let b =
                    bytes.get(*at..*at + ty.size()).ok_or_else(|| mesh_error(path, 0, "the PLY data ends early"))?;
                *at += ty.size();
                Ok(ty.read_le(b))
            }
            Body::Ascii { words, line_of } => {
                let word = words.next().ok_or_else(|| mesh_error(path, 0, "the PLY data ends early"))?;
                word.parse::<f64>()
                    .map_err(|_| mesh_error(path, line_of(word.as_ptr() as usize), format!("'{word}' is not a number")))
            }
        }
    }

    /// An error at the current line (ASCII) or about the whole file (binary).
    fn error(&mut self, path: &Path, message: String) -> SceneError {
        let line = match self {
            Body::Ascii { words, line_of } => {
                words.peek().map_or(0, |w| line_of(w.as_ptr() as usize).saturating_sub(1))
            }
            Body::Binary { .. } => 0,
        };
        mesh_error(path, line, message)
    }
}
