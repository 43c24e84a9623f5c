//! PLY (Turk's polygon file format), ASCII and binary of either byte order, with LF, CRLF
//! or CR line ends: the `vertex` element's `x y z` with the normals, texture coordinates
//! and colours under their common names ([`VertexNames`]), the `face` element's polygons
//! (triangulated in their plane) and the `tristrips` element's strips (`-1` restarts a
//! strip). Other elements and properties are skipped; unknown header lines too, with a
//! warning.
//!
//! Colours are display colours as scanners and MeshLab write them: sRGB-encoded, in
//! 0..1 for float types and in 0..max for integer types (0..255 for `uchar`). They are
//! decoded to linear RGB.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::MeshDesc;

use super::{MeshImport, Placement, degenerate_warning, mesh_error, polygon, read_limited};
use crate::error::SceneError;
use crate::texture_io::srgb_to_linear;

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

    /// The largest value of an integer type (what full intensity is in a colour); 1 for floats.
    fn full_scale(self) -> f64 {
        match self {
            Scalar::I8 => i8::MAX as f64,
            Scalar::U8 => u8::MAX as f64,
            Scalar::I16 => i16::MAX as f64,
            Scalar::U16 => u16::MAX as f64,
            Scalar::I32 => i32::MAX as f64,
            Scalar::U32 => u32::MAX as f64,
            Scalar::F32 | Scalar::F64 => 1.0,
        }
    }

    /// The value at the start of `b`, stored in either byte order.
    fn read(self, b: &[u8], big_endian: bool) -> f64 {
        if big_endian {
            let mut flipped = [0u8; 8];
            flipped[..self.size()].copy_from_slice(&b[..self.size()]);
            flipped[..self.size()].reverse();
            self.read_le(&flipped)
        } else {
            self.read_le(b)
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
    Binary { bytes: &'a [u8], at: usize, big_endian: bool },
}

/// How the body is stored.
#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Binary { big_endian: bool },
}

/// The header: its elements, where the body starts and how lines end.
struct Header {
    format: Format,
    elements: Vec<Element>,
    body_start: usize,
    lines: u32,
    /// The line end of the file: `\n`, `\r\n` or `\r`, as the magic line ends.
    eol: &'static str,
    warnings: Vec<String>,
}

/// The property names a vertex attribute goes by in the files of different tools.
struct VertexNames;

impl VertexNames {
    const POSITION: [&[&str]; 3] = [&["x"], &["y"], &["z"]];
    const NORMAL: [&[&str]; 3] = [&["nx", "normal_x"], &["ny", "normal_y"], &["nz", "normal_z"]];
    const UV: [&[&str]; 2] = [&["u", "s", "texture_u", "texture_s"], &["v", "t", "texture_v", "texture_t"]];
    const COLOR: [&[&str]; 3] =
        [&["red", "r", "diffuse_red"], &["green", "g", "diffuse_green"], &["blue", "b", "diffuse_blue"]];
}

/// The line end the magic line uses, or `None` when `head` is not a PLY file.
fn line_end(head: &[u8]) -> Option<&'static str> {
    match head {
        [b'p', b'l', b'y', b'\r', b'\n', ..] => Some("\r\n"),
        [b'p', b'l', b'y', b'\r', ..] => Some("\r"),
        [b'p', b'l', b'y', b'\n', ..] => Some("\n"),
        _ => None,
    }
}

/// Refuses a file that does not start with the PLY magic, before the rest of it is read.
pub fn check_head(path: &Path, head: &[u8]) -> Result<(), SceneError> {
    if line_end(head).is_none() {
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
    let header = parse_header(path, bytes)?;
    let body_bytes = &bytes[header.body_start..];
    // Every element needs at least its fixed-size part: refuse counts the file cannot hold
    // before allocating for them.
    let minimum: u128 = header
        .elements
        .iter()
        .map(|e| e.count as u128 * e.properties.iter().map(|p| p.list.unwrap_or(p.value).size() as u128).sum::<u128>())
        .sum();
    let floor = if header.format == Format::Ascii { minimum / 8 } else { minimum };
    if floor > body_bytes.len() as u128 {
        return Err(mesh_error(path, 0, "the PLY header announces more data than the file holds"));
    }
    let text;
    let line_starts: Vec<usize>;
    let line_of;
    let mut body = match header.format {
        Format::Binary { big_endian } => Body::Binary { bytes: body_bytes, at: 0, big_endian },
        Format::Ascii => {
            text = String::from_utf8_lossy(body_bytes);
            let eol = if header.eol == "\r" { '\r' } else { '\n' };
            line_starts = text.match_indices(eol).map(|(i, _)| i).collect();
            let base = text.as_ptr() as usize;
            let first = header.lines + 1;
            line_of = move |ptr: usize| first + line_starts.partition_point(|&s| s < ptr - base) as u32;
            Body::Ascii { words: text.split_ascii_whitespace().peekable(), line_of: &line_of }
        }
    };
    let vertex_count = element_count(&header.elements, "vertex");
    let mut data = Data::default();
    for element in &header.elements {
        data.element(path, element, &mut body, vertex_count)?;
    }
    let mut warnings = header.warnings;
    if data.non_triangles > 0 {
        warnings.push(format!("{}: skipped {} faces with fewer than 3 corners", path.display(), data.non_triangles));
    }
    let indices = data.triangles();
    let n = data.positions.len();
    let mesh = MeshDesc {
        name: path.file_stem().and_then(|s| s.to_str()).unwrap_or("ply").to_owned(),
        path: path.display().to_string(),
        normals: if data.normals.len() == n { data.normals } else { vec![] },
        uvs: if data.uvs.len() == n { data.uvs } else { vec![] },
        colors: if data.colors.len() == n { data.colors } else { vec![] },
        positions: data.positions,
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

/// Reads the header up to `end_header`; unknown lines are skipped with a warning.
fn parse_header(path: &Path, bytes: &[u8]) -> Result<Header, SceneError> {
    let eol = line_end(bytes).ok_or_else(|| mesh_error(path, 0, "not a PLY file: it does not start with 'ply'"))?;
    // The header is text ending at `end_header`; refuse to look further than 64 KiB for it.
    let search = &bytes[..bytes.len().min(1 << 16)];
    let end = search
        .windows(10)
        .position(|w| w == b"end_header")
        .ok_or_else(|| mesh_error(path, 0, "the PLY header has no 'end_header' in its first 64 KiB"))?;
    // The body starts after the line end of `end_header` (spaces before it are allowed);
    // only the file's own line end is taken, as a binary body may start with 10 or 13.
    let mut body_start = end + 10;
    while matches!(bytes.get(body_start), Some(b' ' | b'\t')) {
        body_start += 1;
    }
    if bytes[body_start..].starts_with(eol.as_bytes()) {
        body_start += eol.len();
    } else if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let text = String::from_utf8_lossy(&bytes[..end]);
    let mut header =
        Header { format: Format::Ascii, elements: Vec::new(), body_start, lines: 0, eol, warnings: Vec::new() };
    let mut format = None;
    let mut unknown = Vec::new();
    // `text` ends with the line end before `end_header`: its last, empty piece stands for
    // the `end_header` line, so `lines` counts that too.
    for (n, line) in text.split(eol).enumerate() {
        header.lines = n as u32 + 1;
        let err = |m: String| mesh_error(path, n as u32 + 1, m);
        let line = line.trim_matches(['\r', '\n']);
        let words: Vec<&str> = line.split_whitespace().collect();
        let elements = &mut header.elements;
        match words.as_slice() {
            ["ply"] | [] => {}
            ["comment", ..] => {}
            ["format", "ascii", _] => format = Some(Format::Ascii),
            ["format", "binary_little_endian", _] => format = Some(Format::Binary { big_endian: false }),
            ["format", "binary_big_endian", _] => format = Some(Format::Binary { big_endian: true }),
            ["format", other, ..] => {
                return Err(err(format!(
                    "PLY format '{other}' is not one of ascii, binary_little_endian and binary_big_endian"
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
            [keyword, ..] => unknown.push(format!("'{keyword}' (line {})", n + 1)),
        }
    }
    header.format = format.ok_or_else(|| mesh_error(path, 0, "the PLY header has no 'format' line"))?;
    if !unknown.is_empty() {
        header.warnings.push(format!("{}: skipped unknown PLY header lines: {}", path.display(), unknown.join(", ")));
    }
    Ok(header)
}

/// Marks the end of a triangle strip in [`Data::strips`].
const RESTART: u32 = u32::MAX;

/// What the elements hold, as read.
#[derive(Default)]
struct Data {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    colors: Vec<Vec3>,
    /// The corners of every polygon, one after another; `polygon_starts` marks each start.
    polygons: Vec<u32>,
    polygon_starts: Vec<usize>,
    /// Triangle strips, each ended by [`RESTART`].
    strips: Vec<u32>,
    non_triangles: usize,
}

impl Data {
    /// Reads every record of `element`, keeping what glint draws.
    fn element(
        &mut self,
        path: &Path,
        element: &Element,
        body: &mut Body,
        vertex_count: usize,
    ) -> Result<(), SceneError> {
        let find = |names: &[&str]| element.properties.iter().position(|p| names.contains(&p.name.as_str()));
        let find3 = |names: [&[&str]; 3]| names.map(&find);
        let xyz = find3(VertexNames::POSITION);
        let nxyz = find3(VertexNames::NORMAL);
        let rgb = find3(VertexNames::COLOR);
        let uv = VertexNames::UV.map(find);
        let indices = element
            .properties
            .iter()
            .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"));
        let is_vertex = element.name == "vertex";
        if is_vertex && element.count > 0 && xyz.contains(&None) {
            return Err(mesh_error(path, 0, "the PLY vertex element lacks x, y or z"));
        }
        // An element without properties holds no bytes: however large its count, there is
        // nothing to read, and counting through it could take minutes.
        if element.properties.is_empty() {
            return Ok(());
        }
        let strips = element.name == "tristrips";
        let faces = element.name == "face";
        let mut values = vec![0.0f64; element.properties.len()];
        let mut list: Vec<f64> = Vec::new();
        for _ in 0..element.count {
            for (k, p) in element.properties.iter().enumerate() {
                match p.list {
                    Some(count_type) => body.list(path, p, count_type, (indices == Some(k)).then_some(&mut list))?,
                    None => values[k] = body.next(p.value, path)?,
                }
            }
            if is_vertex {
                self.vertex(path, body, element, &values, [xyz, nxyz, rgb], uv)?;
            } else if (faces || strips) && indices.is_some() {
                let mut corners = Vec::with_capacity(list.len());
                for &i in &list {
                    if strips && i == -1.0 {
                        corners.push(RESTART);
                    } else if i >= 0.0 && (i as usize) < vertex_count {
                        corners.push(i as u32);
                    } else {
                        return Err(body.error(path, format!("face index {i} is out of range")));
                    }
                }
                if strips {
                    self.strips.extend(corners);
                    self.strips.push(RESTART);
                } else if corners.len() < 3 {
                    self.non_triangles += 1;
                } else {
                    self.polygon_starts.push(self.polygons.len());
                    self.polygons.extend(corners);
                }
            }
        }
        Ok(())
    }

    /// One vertex record: its position and whichever attributes the element has.
    fn vertex(
        &mut self,
        path: &Path,
        body: &mut Body,
        element: &Element,
        values: &[f64],
        [xyz, nxyz, rgb]: [[Option<usize>; 3]; 3],
        uv: [Option<usize>; 2],
    ) -> Result<(), SceneError> {
        let get = |i: Option<usize>| i.map(|i| values[i] as f32);
        let get3 = |i: [Option<usize>; 3]| Some(Vec3::new(get(i[0])?, get(i[1])?, get(i[2])?));
        let Some(p) = get3(xyz) else {
            return Err(mesh_error(path, 0, "the PLY vertex element lacks x, y or z"));
        };
        if !p.is_finite() {
            let message = format!("vertex {} has a coordinate that is not a finite number", self.positions.len());
            return Err(body.error(path, message));
        }
        self.positions.push(p);
        if let Some(n) = get3(nxyz) {
            self.normals.push(n);
        }
        if let (Some(u), Some(v)) = (get(uv[0]), get(uv[1])) {
            self.uvs.push(Vec2::new(u, v));
        }
        if let Some(c) = get3(rgb) {
            let scale = rgb.map(|i| i.map_or(1.0, |i| element.properties[i].value.full_scale() as f32));
            let encoded = c / Vec3::from(scale);
            self.colors.push(encoded.map(|x| srgb_to_linear(x.clamp(0.0, 1.0))));
        }
        Ok(())
    }

    /// The triangles of the polygons (triangulated in their plane) and of the strips.
    fn triangles(&self) -> Vec<u32> {
        let mut indices = Vec::with_capacity(3 * self.polygon_starts.len());
        for (k, &start) in self.polygon_starts.iter().enumerate() {
            let end = self.polygon_starts.get(k + 1).copied().unwrap_or(self.polygons.len());
            let polygon = &self.polygons[start..end];
            if polygon.len() == 3 {
                indices.extend(polygon);
                continue;
            }
            let points: Vec<Vec3> = polygon.iter().map(|&i| self.positions[i as usize]).collect();
            for t in polygon::triangulate(&points) {
                indices.extend(t.map(|c| polygon[c]));
            }
        }
        for strip in self.strips.split(|&i| i == RESTART) {
            for (k, w) in strip.windows(3).enumerate() {
                // Every second triangle of a strip is wound the other way round; repeated
                // corners (how strips turn) make no triangle.
                if w[0] != w[1] && w[1] != w[2] && w[0] != w[2] {
                    indices.extend(if k % 2 == 0 { [w[0], w[1], w[2]] } else { [w[1], w[0], w[2]] });
                }
            }
        }
        indices
    }
}

fn element_count(elements: &[Element], name: &str) -> usize {
    elements.iter().find(|e| e.name == name).map_or(0, |e| e.count)
}

impl Body<'_> {
    fn next(&mut self, ty: Scalar, path: &Path) -> Result<f64, SceneError> {
        match self {
            Body::Binary { bytes, at, big_endian } => {
                let b =
                    bytes.get(*at..*at + ty.size()).ok_or_else(|| mesh_error(path, 0, "the PLY data ends early"))?;
                *at += ty.size();
                Ok(ty.read(b, *big_endian))
            }
            Body::Ascii { words, line_of } => {
                let word = words.next().ok_or_else(|| mesh_error(path, 0, "the PLY data ends early"))?;
                word.parse::<f64>()
                    .map_err(|_| mesh_error(path, line_of(word.as_ptr() as usize), format!("'{word}' is not a number")))
            }
        }
    }

    /// A list property; its values go into `keep` when given, else they are skipped.
    fn list(
        &mut self,
        path: &Path,
        p: &Property,
        count_type: Scalar,
        mut keep: Option<&mut Vec<f64>>,
    ) -> Result<(), SceneError> {
        let n = self.next(count_type, path)?;
        if !(0.0..=1e6).contains(&n) {
            return Err(self.error(path, format!("list length {n} of '{}' is out of range", p.name)));
        }
        if let Some(keep) = keep.as_deref_mut() {
            keep.clear();
        }
        for _ in 0..n as usize {
            let x = self.next(p.value, path)?;
            if let Some(keep) = keep.as_deref_mut() {
                keep.push(x);
            }
        }
        Ok(())
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
