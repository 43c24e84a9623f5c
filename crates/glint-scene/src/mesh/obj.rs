//! Wavefront OBJ with its MTL materials (diffuse colour and texture, specular colour and
//! exponent). Polygons are split into triangle fans; each `usemtl` run becomes its own
//! mesh so it keeps its material.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{MaterialDesc, MeshDesc, TextureDesc};

use super::{MeshImport, Placement, degenerate_warning, mesh_error, read_limited};
use crate::error::SceneError;

/// One `usemtl` run being gathered: per-corner tuples mapped to new vertices.
#[derive(Default)]
struct Group {
    material: Option<String>,
    vertex_of: HashMap<(u32, u32, u32), u32>,
    /// (position, uv, normal) of each vertex; `u32::MAX` = absent.
    corners: Vec<(u32, u32, u32)>,
    indices: Vec<u32>,
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
    let text = String::from_utf8_lossy(bytes);
    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut uvs: Vec<Vec2> = Vec::new();
    let mut groups: Vec<Group> = vec![Group::default()];
    let mut libraries: Vec<String> = Vec::new();
    let mut skipped: HashMap<String, usize> = HashMap::new();
    let mut warnings = Vec::new();
    for (number, raw) in text.lines().enumerate() {
        let line_no = (number + 1) as u32;
        let err = |m: String| mesh_error(path, line_no, m);
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        match keyword {
            "v" | "vn" | "vt" => {
                let want = if keyword == "vt" { 2 } else { 3 };
                let mut xs = [0.0f32; 3];
                for (k, x) in xs.iter_mut().enumerate().take(want) {
                    let word = words.next().ok_or_else(|| err(format!("'{keyword}' needs {want} numbers")))?;
                    *x = word.parse::<f32>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                        err(format!("coordinate {} of '{keyword}' is '{word}', not a finite number", k + 1))
                    })?;
                }
                match keyword {
                    "v" => positions.push(Vec3::from(xs)),
                    "vn" => normals.push(Vec3::from(xs)),
                    _ => uvs.push(Vec2::new(xs[0], xs[1])),
                }
            }
            "f" => {
                let group = groups.last_mut().unwrap_or_else(|| unreachable!("there is always a group"));
                let mut face = Vec::new();
                for word in words {
                    let mut parts = word.split('/');
                    let resolve = |part: Option<&str>, count: usize, what: &str| -> Result<u32, SceneError> {
                        let Some(part) = part.filter(|p| !p.is_empty()) else { return Ok(u32::MAX) };
                        let i: i64 =
                            part.parse().map_err(|_| err(format!("'{part}' in face '{word}' is not an index")))?;
                        // 1-based; negative counts back from the latest element.
                        let index = if i < 0 { count as i64 + i } else { i - 1 };
                        if i == 0 || index < 0 || index >= count as i64 {
                            return Err(err(format!("{what} index {i} is out of range: {count} are defined so far")));
                        }
                        Ok(index as u32)
                    };
                    let v = resolve(parts.next(), positions.len(), "vertex")?;
                    if v == u32::MAX {
                        return Err(err(format!("face corner '{word}' has no vertex index")));
                    }
                    let t = resolve(parts.next(), uvs.len(), "texture coordinate")?;
                    let n = resolve(parts.next(), normals.len(), "normal")?;
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
                for k in 1..face.len() - 1 {
                    group.indices.extend([face[0], face[k], face[k + 1]]);
                }
            }
            "usemtl" => {
                let name = words.collect::<Vec<_>>().join(" ");
                groups.push(Group { material: Some(name), ..Default::default() });
            }
            "mtllib" => libraries.extend(words.map(str::to_owned)),
            "o" | "g" | "s" => {}
            other => *skipped.entry(other.to_owned()).or_default() += 1,
        }
    }
    let mut unknown: Vec<_> = skipped.into_iter().collect();
    unknown.sort();
    for (keyword, count) in unknown {
        warnings.push(format!("{}: skipped {count} '{keyword}' statements (not surface geometry)", path.display()));
    }

    let dir = path.parent().unwrap_or(Path::new(""));
    let mut library = Library::default();
    for lib in &libraries {
        library.read(&dir.join(lib), &mut warnings);
    }
    let mut import = MeshImport { warnings, ..Default::default() };
    let mut material_index: HashMap<String, usize> = HashMap::new();
    for (k, group) in groups.into_iter().enumerate().filter(|(_, g)| !g.indices.is_empty()) {
        let has = |f: fn(&(u32, u32, u32)) -> u32| group.corners.iter().all(|c| f(c) != u32::MAX);
        let mesh = MeshDesc {
            name: format!("{}#{k}", path.file_stem().and_then(|s| s.to_str()).unwrap_or("obj")),
            path: path.display().to_string(),
            positions: group.corners.iter().map(|c| positions[c.0 as usize]).collect(),
            normals: if has(|c| c.2) { group.corners.iter().map(|c| normals[c.2 as usize]).collect() } else { vec![] },
            uvs: if has(|c| c.1) { group.corners.iter().map(|c| uvs[c.1 as usize]).collect() } else { vec![] },
            colors: vec![],
            indices: group.indices,
        };
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

/// The materials of the MTL files, as their statements were read.
#[derive(Default)]
struct Library {
    materials: HashMap<String, (MaterialDesc, Option<std::path::PathBuf>)>,
}

impl Library {
    /// Reads one MTL file; a missing or broken library is a warning (the model still shows).
    fn read(&mut self, path: &Path, warnings: &mut Vec<String>) {
        let text = match crate::input::read_text(path, crate::input::InputKind::Mesh) {
            Ok(t) => t,
            Err(e) => {
                warnings.push(format!("{}: cannot read material library: {}", path.display(), e.problem));
                return;
            }
        };
        let dir = path.parent().unwrap_or(Path::new(""));
        let mut current: Option<String> = None;
        for (n, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            let mut words = line.split_whitespace();
            let Some(keyword) = words.next() else { continue };
            let rest: Vec<&str> = words.collect();
            let numbers: Vec<f32> =
                rest.iter().filter_map(|w| w.parse().ok()).filter(|x: &f32| x.is_finite()).collect();
            let color = || (numbers.len() >= 3).then(|| Vec3::new(numbers[0], numbers[1], numbers[2]));
            if keyword == "newmtl" {
                let name = rest.join(" ");
                let m = MaterialDesc { name: name.clone(), ks: 1.0, specular: Vec3::ZERO, ..Default::default() };
                self.materials.insert(name.clone(), (m, None));
                current = Some(name);
                continue;
            }
            let Some((m, texture)) = current.as_ref().and_then(|c| self.materials.get_mut(c)) else { continue };
            match keyword {
                "Kd" => match color() {
                    Some(c) => m.diffuse = c,
                    None => warnings.push(format!("{}:{}: 'Kd' needs 3 numbers", path.display(), n + 1)),
                },
                "Ks" => m.specular = color().unwrap_or(m.specular),
                "Ns" => m.shininess = numbers.first().copied().unwrap_or(m.shininess).max(0.0),
                // The file name is the last word (options come before it).
                "map_Kd" => *texture = rest.last().map(|f| dir.join(f)),
                _ => {}
            }
        }
    }

    /// The material `name`, its texture loaded into `textures`; unknown names get the
    /// default material with a warning.
    fn material(&self, name: &str, textures: &mut Vec<TextureDesc>, warnings: &mut Vec<String>) -> MaterialDesc {
        let Some((m, texture)) = self.materials.get(name) else {
            warnings.push(format!("material '{name}' is not in any material library; using the default"));
            return MaterialDesc { name: name.to_owned(), ..Default::default() };
        };
        let mut m = m.clone();
        if let Some(file) = texture {
            match crate::texture_io::load_texture(name, file) {
                Ok(t) => {
                    textures.push(t);
                    m.texture = Some(textures.len() - 1);
                    m.blend = 1.0;
                }
                Err(e) => warnings.push(format!("material '{name}': texture not loaded: {e}")),
            }
        }
        m
    }
}
