//! Wavefront OBJ geometry: `v` (with optional vertex colours), `vt`, `vn` and `f`.
//! Polygons are triangulated in their own plane ([`super::polygon`]), concave ones
//! too; each `usemtl` run becomes its own mesh so it keeps its material, read from the
//! MTL libraries by [`super::mtl`].
//!
//! Vertex colours (`v x y z r g b`, as MeshLab, ZBrush and Blender write them) are
//! display colours: sRGB-encoded, in 0..1, or in 0..255 when any colour of the file
//! exceeds 1. They are decoded to linear RGB.
//!
//! Why not the `tobj` crate: side by side on the same files (tobj 4.0.5), tobj fans
//! concave faces (an L of area 3 came out as 4), refuses a whole file for one face naming
//! a missing `vt`, refuses Latin-1 MTL and OBJ text, hands texture statements back with
//! their options (`-s 2 2 1 … my tex.png`) and escapes unparsed, drops `Ke`, and reads a
//! Git LFS pointer as an empty model. This reader does each of those as other loaders do.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::MeshDesc;

use super::mtl::Library;
use super::{MeshImport, Placement, decode_text, degenerate_warning, mesh_error, polygon, read_limited};
use crate::error::SceneError;

/// No index: the corner names no texture coordinate or normal.
const NONE: u32 = u32::MAX;

/// One `usemtl` run being gathered: per-corner tuples mapped to new vertices.
#[derive(Default)]
struct Group {
    material: Option<String>,
    vertex_of: HashMap<(u32, u32, u32), u32>,
    /// (position, uv, normal) of each vertex; [`NONE`] = absent.
    corners: Vec<(u32, u32, u32)>,
    indices: Vec<u32>,
}

/// The vertex data of the whole file, which every group indexes into.
#[derive(Default)]
struct Pool {
    positions: Vec<Vec3>,
    /// The colour written after each position, if any (as written: 0..1 or 0..255).
    colors: Vec<Option<Vec3>>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    /// Faces that referred to a texture coordinate or normal not defined.
    missing_uv_faces: usize,
    missing_normal_faces: usize,
}

/// Refuses a file whose first bytes are binary, before the rest of it is read.
pub fn check_head(path: &Path, head: &[u8]) -> Result<(), SceneError> {
    if head.contains(&0) {
        return Err(mesh_error(path, 0, "not an OBJ file: it holds binary data"));
    }
    Ok(())
}

/// Reads the OBJ file `path` (and the MTL libraries it names, relative to it).
pub fn load(path: &Path) -> Result<MeshImport, SceneError> {
    parse(path, &read_limited(path, |head| check_head(path, head))?)
}

/// Reads OBJ `bytes` that came from `path` (which names it and locates its MTL files).
pub fn parse(path: &Path, bytes: &[u8]) -> Result<MeshImport, SceneError> {
    let text = decode_text(bytes);
    let mut pool = Pool::default();
    let mut groups: Vec<Group> = vec![Group::default()];
    let mut libraries: Vec<String> = Vec::new();
    let mut skipped: HashMap<String, usize> = HashMap::new();
    let mut warnings = Vec::new();
    let dir = path.parent().unwrap_or(Path::new(""));
    for (number, raw) in text.lines().enumerate() {
        let err = |m: String| mesh_error(path, (number + 1) as u32, m);
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        match keyword {
            "v" | "vn" | "vt" => pool.vertex_statement(keyword, words, err)?,
            "f" => {
                let group = groups.last_mut().unwrap_or_else(|| unreachable!("there is always a group"));
                pool.face(group, words, err)?;
            }
            "usemtl" => {
                let name = words.collect::<Vec<_>>().join(" ");
                groups.push(Group { material: Some(name), ..Default::default() });
            }
            "mtllib" => {
                // One file whose name holds spaces, or several names.
                let rest = line["mtllib".len()..].trim();
                if dir.join(rest).is_file() {
                    libraries.push(rest.to_owned());
                } else {
                    libraries.extend(words.map(str::to_owned));
                }
            }
            "o" | "g" | "s" => {}
            other => *skipped.entry(other.to_owned()).or_default() += 1,
        }
    }
    let mut unknown: Vec<_> = skipped.into_iter().collect();
    unknown.sort();
    for (keyword, count) in unknown {
        warnings.push(format!("{}: skipped {count} '{keyword}' statements (not surface geometry)", path.display()));
    }
    pool.missing_warnings(path, &mut warnings);

    let mut library = Library::default();
    for lib in &libraries {
        library.read(&dir.join(lib), &mut warnings);
    }
    let mut import = MeshImport { warnings, ..Default::default() };
    let mut material_index: HashMap<String, usize> = HashMap::new();
    let colors = pool.linear_colors();
    for (k, group) in groups.into_iter().enumerate().filter(|(_, g)| !g.indices.is_empty()) {
        let mesh = pool.mesh(path, k, group.corners, group.indices, colors.as_deref());
        degenerate_warning(path, &mesh, &mut import.warnings);
        let material = group.material.map(|name| {
            *material_index.entry(name.clone()).or_insert_with(|| {
                let m = library.material(&name, &mut import.textures, &mut import.warnings);
                import.materials.push(m);
                import.materials.len() - 1
            })
        });
        import.placements.push(Placement { mesh: import.meshes.len(), material, world_from_object: Mat4::IDENTITY });
        import.meshes.push(mesh);
    }
    Ok(import)
}

impl Pool {
    /// `v x y z [w | r g b]`, `vn x y z` or `vt u v`.
    fn vertex_statement<'a>(
        &mut self,
        keyword: &str,
        words: impl Iterator<Item = &'a str>,
        err: impl Fn(String) -> SceneError,
    ) -> Result<(), SceneError> {
        let want = if keyword == "vt" { 2 } else { 3 };
        let mut xs = Vec::with_capacity(7);
        for (k, word) in words.enumerate().take(7) {
            match word.parse::<f32>().ok().filter(|x| x.is_finite()) {
                Some(x) => xs.push(x),
                None if k < want => {
                    return Err(err(format!("coordinate {} of '{keyword}' is '{word}', not a finite number", k + 1)));
                }
                None => break,
            }
        }
        if xs.len() < want {
            return Err(err(format!("'{keyword}' needs {want} numbers")));
        }
        match keyword {
            "v" => {
                self.positions.push(Vec3::new(xs[0], xs[1], xs[2]));
                // x y z r g b, or x y z w r g b (a weight, then the colour).
                let rgb = match xs.len() {
                    6 => Some(Vec3::new(xs[3], xs[4], xs[5])),
                    7 => Some(Vec3::new(xs[4], xs[5], xs[6])),
                    _ => None,
                };
                self.colors.push(rgb);
            }
            "vn" => self.normals.push(Vec3::new(xs[0], xs[1], xs[2])),
            _ => self.uvs.push(Vec2::new(xs[0], xs[1])),
        }
        Ok(())
    }

    /// One `f` statement: its corners become vertices of `group`, its polygon triangles.
    fn face<'a>(
        &mut self,
        group: &mut Group,
        words: impl Iterator<Item = &'a str>,
        err: impl Fn(String) -> SceneError,
    ) -> Result<(), SceneError> {
        let mut face = Vec::new();
        let (mut missing_uv, mut missing_normal) = (false, false);
        for word in words {
            let mut parts = word.split('/');
            let v = resolve(parts.next(), self.positions.len(), word, &err)?
                .ok_or_else(|| err(format!("face corner '{word}' has no vertex index")))?
                .map_err(|i| {
                    err(format!("vertex index {i} is out of range: {} are defined so far", self.positions.len()))
                })?;
            // A missing texture coordinate or normal drops just that attribute.
            let t = resolve(parts.next(), self.uvs.len(), word, &err)?.map_or(NONE, |r| {
                missing_uv |= r.is_err();
                r.unwrap_or(NONE)
            });
            let n = resolve(parts.next(), self.normals.len(), word, &err)?.map_or(NONE, |r| {
                missing_normal |= r.is_err();
                r.unwrap_or(NONE)
            });
            let next = group.corners.len() as u32;
            let vertex = *group.vertex_of.entry((v, t, n)).or_insert(next);
            if vertex == next {
                group.corners.push((v, t, n));
            }
            face.push(vertex);
        }
        if face.len() < 3 {
            return Err(err(format!("a face needs at least 3 corners, found {}", face.len())));
        }
        self.missing_uv_faces += usize::from(missing_uv);
        self.missing_normal_faces += usize::from(missing_normal);
        if face.len() == 3 {
            group.indices.extend(face);
            return Ok(());
        }
        let points: Vec<Vec3> = face.iter().map(|&c| self.positions[group.corners[c as usize].0 as usize]).collect();
        for [a, b, c] in polygon::triangulate(&points) {
            group.indices.extend([face[a], face[b], face[c]]);
        }
        Ok(())
    }

    /// One warning per attribute that faces referred to but the file lacks.
    fn missing_warnings(&self, path: &Path, warnings: &mut Vec<String>) {
        for (count, what) in
            [(self.missing_uv_faces, "texture coordinates ('vt')"), (self.missing_normal_faces, "normals ('vn')")]
        {
            if count > 0 {
                warnings.push(format!(
                    "{}: {count} faces referenced missing {what}; they keep their positions without them",
                    path.display()
                ));
            }
        }
    }

    /// The vertex colours in linear RGB, when every position has one.
    fn linear_colors(&self) -> Option<Vec<Vec3>> {
        let colors: Option<Vec<Vec3>> = self.colors.iter().copied().collect();
        let colors = colors.filter(|c| !c.is_empty())?;
        let scale = if colors.iter().any(|c| c.max_element() > 1.0) { 255.0 } else { 1.0 };
        let decode = |x: f32| crate::texture_io::srgb_to_linear((x / scale).clamp(0.0, 1.0));
        Some(colors.into_iter().map(|c| c.map(decode)).collect())
    }

    /// The mesh of group number `k`, with the attributes all its corners have.
    fn mesh(
        &self,
        path: &Path,
        k: usize,
        corners: Vec<(u32, u32, u32)>,
        indices: Vec<u32>,
        colors: Option<&[Vec3]>,
    ) -> MeshDesc {
        let has = |f: fn(&(u32, u32, u32)) -> u32| corners.iter().all(|c| f(c) != NONE);
        MeshDesc {
            name: format!("{}#{k}", path.file_stem().and_then(|s| s.to_str()).unwrap_or("obj")),
            path: path.display().to_string(),
            positions: corners.iter().map(|c| self.positions[c.0 as usize]).collect(),
            normals: if has(|c| c.2) { corners.iter().map(|c| self.normals[c.2 as usize]).collect() } else { vec![] },
            uvs: if has(|c| c.1) { corners.iter().map(|c| self.uvs[c.1 as usize]).collect() } else { vec![] },
            colors: colors.map_or_else(Vec::new, |colors| corners.iter().map(|c| colors[c.0 as usize]).collect()),
            indices,
        }
    }
}

/// One index of a face corner among `count` defined so far: `None` when the part is
/// absent, `Some(Err(i))` when `i` names nothing. 1-based; negative counts back from the
/// latest element.
fn resolve(
    part: Option<&str>,
    count: usize,
    word: &str,
    err: impl Fn(String) -> SceneError,
) -> Result<Option<Result<u32, i64>>, SceneError> {
    let Some(part) = part.filter(|p| !p.is_empty()) else { return Ok(None) };
    let i: i64 = part.parse().map_err(|_| err(format!("'{part}' in face '{word}' is not an index")))?;
    let index = if i < 0 { count as i64 + i } else { i - 1 };
    if i == 0 || index < 0 || index >= count as i64 {
        return Ok(Some(Err(i)));
    }
    Ok(Some(Ok(index as u32)))
}
