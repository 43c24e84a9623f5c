//! Triangle-mesh files: Wavefront OBJ (+MTL), PLY (ASCII and binary of either byte order)
//! and glTF 2.0 (`.gltf`/`.glb`).
//!
//! Every reader produces a [`MeshImport`]: meshes stored once, the materials and
//! textures they use, and placements (a mesh, a material, a matrix). [`model_scene`]
//! turns one into a whole scene framed by a default camera and two lights, for
//! `glint render model.obj`; [`merged`] bakes it into one mesh for the native format's
//! `mesh "name" { file "…" }`.

mod gltf;
mod mtl;
mod obj;
mod ply;
mod polygon;

use std::borrow::Cow;
use std::path::Path;

use glam::{Mat4, Vec3};
use glint_core::desc::{
    CameraDesc, LightDesc, MaterialDesc, MeshDesc, NodeDesc, NodeKind, RenderSettings, SceneDesc, ShapeDesc,
    TextureDesc, TransformOp,
};

use crate::error::{SceneError, SceneErrorKind};
use crate::input::{self, InputKind};

/// The mesh formats, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Obj,
    Ply,
    Gltf,
}

impl MeshFormat {
    /// The format a file's extension names, if it is a mesh format.
    pub fn from_path(path: &Path) -> Option<MeshFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "obj" => Some(MeshFormat::Obj),
            "ply" => Some(MeshFormat::Ply),
            "gltf" | "glb" => Some(MeshFormat::Gltf),
            _ => None,
        }
    }
}

/// A mesh placed in the model: which mesh, which material (`None`: the default) and
/// `world_from_object`.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    pub mesh: usize,
    pub material: Option<usize>,
    pub world_from_object: Mat4,
}

/// What a mesh file holds, with the harmless oddities met while reading it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshImport {
    pub meshes: Vec<MeshDesc>,
    pub materials: Vec<MaterialDesc>,
    pub textures: Vec<TextureDesc>,
    pub placements: Vec<Placement>,
    /// Lights the file holds (glTF's punctual lights); without any, [`model_scene`]
    /// adds its own.
    pub lights: Vec<LightDesc>,
    /// The file's cameras in order (the first one is used instead of one fitted to
    /// the model; the others can be picked).
    pub cameras: Vec<CameraDesc>,
    /// Width over height of the file's camera's image, if it says.
    pub aspect_ratio: Option<f32>,
    pub warnings: Vec<String>,
}

/// An error about mesh file `file` at `line` (0: the whole file).
pub(crate) fn mesh_error(file: &Path, line: u32, message: impl Into<String>) -> SceneError {
    SceneError::new(SceneErrorKind::Invalid, file.display().to_string(), line, if line == 0 { 0 } else { 1 }, message)
}

/// Reads the whole file within the mesh size limit ([`crate::input`]), after letting
/// `check_head` look at its first 4 KiB: a large file that is not a mesh is refused
/// without being read.
pub(crate) fn read_limited(
    path: &Path,
    check_head: impl Fn(&[u8]) -> Result<(), SceneError>,
) -> Result<Vec<u8>, SceneError> {
    use std::io::Read;
    let mut file = input::open(path, InputKind::Mesh)?;
    let mut head = Vec::with_capacity(4096);
    (&mut file).take(4096).read_to_end(&mut head).map_err(|e| {
        SceneError::new(SceneErrorKind::Io, path.display().to_string(), 0, 0, format!("cannot read mesh file: {e}"))
    })?;
    check_lfs_pointer(path, &head)?;
    check_head(&head)?;
    Ok(file.finish(head)?)
}

/// The first line of a Git LFS pointer file: what a clone without `git lfs` holds in
/// place of a large file.
const LFS_POINTER: &[u8] = b"version https://git-lfs.github.com/spec/v1";

/// Refuses a Git LFS pointer with what to do about it; otherwise it would be read as a
/// broken mesh of its format.
pub(crate) fn check_lfs_pointer(path: &Path, head: &[u8]) -> Result<(), SceneError> {
    if head.starts_with(LFS_POINTER) {
        return Err(mesh_error(
            path,
            0,
            "the file is a Git LFS pointer, not the mesh: run `git lfs pull` in its repository to fetch it",
        ));
    }
    Ok(())
}

/// Text of a file written by any tool: UTF-8 when it is, Latin-1 otherwise (older
/// exporters write material and texture names in the system's 8-bit code page, and
/// every byte sequence is valid Latin-1).
pub(crate) fn decode_text(bytes: &[u8]) -> Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(text) => Cow::Borrowed(text),
        Err(_) => Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
    }
}

/// Reads a mesh file of any supported format (chosen by extension).
///
/// # Errors
///
/// A [`SceneError`] naming the file (and the line, for text formats) when it cannot be
/// read, is not a mesh of its format, or holds invalid data (an index out of range, a
/// coordinate that is not a number).
pub fn load_mesh(path: &Path) -> Result<MeshImport, SceneError> {
    let import = match format_of(path)? {
        MeshFormat::Obj => obj::load(path)?,
        MeshFormat::Ply => ply::load(path)?,
        MeshFormat::Gltf => gltf::load(path)?,
    };
    with_triangles(path, import)
}

/// Reads mesh `bytes` that came from `path`, whose extension names the format; files
/// it refers to (MTL libraries, glTF buffers and images) are found relative to `path`.
/// For meshes held in memory, and for fuzzing the readers without touching the disk.
///
/// # Errors
///
/// As [`load_mesh`].
pub fn parse_mesh(path: &Path, bytes: Vec<u8>) -> Result<MeshImport, SceneError> {
    let format = format_of(path)?;
    let head = &bytes[..bytes.len().min(4096)];
    check_lfs_pointer(path, head)?;
    let import = match format {
        MeshFormat::Obj => obj::check_head(path, head).and_then(|()| obj::parse(path, &bytes))?,
        MeshFormat::Ply => ply::check_head(path, head).and_then(|()| ply::parse(path, &bytes))?,
        MeshFormat::Gltf => gltf::check_head(path, head).and_then(|()| gltf::parse(path, bytes))?,
    };
    with_triangles(path, import)
}

/// The format `path`'s extension names, or an error naming the ones expected.
fn format_of(path: &Path) -> Result<MeshFormat, SceneError> {
    MeshFormat::from_path(path)
        .ok_or_else(|| mesh_error(path, 0, "not a mesh file: expected the extension .obj, .ply, .gltf or .glb"))
}

/// Refuses an import with nothing to draw.
fn with_triangles(path: &Path, import: MeshImport) -> Result<MeshImport, SceneError> {
    if import.meshes.iter().all(|m| m.indices.is_empty()) {
        return Err(mesh_error(path, 0, "the file holds no triangles"));
    }
    Ok(import)
}

/// Counts the triangles without area of `mesh` (they are dropped when the scene is compiled).
pub(crate) fn degenerate_warning(path: &Path, mesh: &MeshDesc, warnings: &mut Vec<String>) {
    let zero = mesh
        .indices
        .chunks_exact(3)
        .filter(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a).length_squared() == 0.0
        })
        .count();
    if zero > 0 {
        warnings.push(format!("{}: {zero} degenerate (zero-area) triangles are ignored", path.display()));
    }
}

/// Every placement baked into one mesh (object space = the model's world space);
/// materials are dropped. For `mesh "name" { file "…" }` definitions.
pub fn merged(import: &MeshImport, name: &str, path: &str) -> MeshDesc {
    let mut out = MeshDesc { name: name.to_owned(), path: path.to_owned(), ..Default::default() };
    let all_normals = import.placements.iter().all(|p| !import.meshes[p.mesh].normals.is_empty());
    let all_uvs = import.placements.iter().all(|p| !import.meshes[p.mesh].uvs.is_empty());
    let all_colors = import.placements.iter().all(|p| !import.meshes[p.mesh].colors.is_empty());
    for p in &import.placements {
        let mesh = &import.meshes[p.mesh];
        let base = out.positions.len() as u32;
        let normal_m = p.world_from_object.inverse().transpose();
        out.positions.extend(mesh.positions.iter().map(|&v| p.world_from_object.transform_point3(v)));
        if all_normals {
            out.normals.extend(mesh.normals.iter().map(|&n| normal_m.transform_vector3(n).normalize_or_zero()));
        }
        if all_uvs {
            out.uvs.extend(&mesh.uvs);
        }
        if all_colors {
            out.colors.extend(&mesh.colors);
        }
        // A mirroring matrix turns the winding around; swap two corners to keep it.
        let mirrored = p.world_from_object.determinant() < 0.0;
        for t in mesh.indices.chunks_exact(3) {
            let t = if mirrored { [t[0], t[2], t[1]] } else { [t[0], t[1], t[2]] };
            out.indices.extend(t.map(|i| base + i));
        }
    }
    out
}

/// The world-space box around every placed mesh.
fn model_bounds(import: &MeshImport) -> (Vec3, Vec3) {
    let mut min = Vec3::INFINITY;
    let mut max = Vec3::NEG_INFINITY;
    for p in &import.placements {
        for &v in &import.meshes[p.mesh].positions {
            let w = p.world_from_object.transform_point3(v);
            if w.is_finite() {
                min = min.min(w);
                max = max.max(w);
            }
        }
    }
    if min.cmpgt(max).any() { (Vec3::splat(-1.0), Vec3::ONE) } else { (min, max) }
}

/// A scene showing the model: a camera fitted to its bounds, looking from the front,
/// slightly above and to the right, and two point lights (a key light and a dimmer fill).
pub fn model_scene(import: MeshImport) -> SceneDesc {
    let (min, max) = model_bounds(&import);
    let center = 0.5 * (min + max);
    let radius = (0.5 * (max - min).length()).max(1e-3);
    let fov_y_degrees = 40.0f32;
    // The bounding sphere of the box just fits the vertical view angle.
    let distance = radius / (0.5 * fov_y_degrees.to_radians()).sin();
    let view = Vec3::new(0.45, 0.35, 1.0).normalize();
    let eye = center + distance * view;
    let fitted = CameraDesc { eye, look: center - eye, up: Vec3::Y, fov_y_degrees, ..Default::default() };
    let key = center + distance * Vec3::new(-0.6, 0.9, 0.8).normalize();
    let fill = center + distance * Vec3::new(1.0, 0.2, 0.3).normalize();
    let MeshImport { meshes, mut materials, textures, placements, lights, cameras, aspect_ratio, .. } = import;
    let lights = if lights.is_empty() {
        vec![
            LightDesc::Point { position: key, color: Vec3::splat(0.8), attenuation: Vec3::X },
            LightDesc::Point { position: fill, color: Vec3::splat(0.35), attenuation: Vec3::X },
        ]
    } else {
        lights
    };
    let mut settings = RenderSettings::default();
    if let (Some(_), Some(aspect)) = (cameras.first(), aspect_ratio) {
        settings.height = ((settings.width as f32 / aspect).round() as u32).clamp(1, 16384);
    }
    let camera = cameras.first().cloned().unwrap_or(fitted);
    let views = if cameras.len() > 1 { cameras } else { Vec::new() };
    let mut default_material = None;
    let objects = placements
        .into_iter()
        .map(|p| {
            let material = p.material.unwrap_or_else(|| {
                *default_material.get_or_insert_with(|| {
                    materials.push(MaterialDesc { name: "default".into(), ..Default::default() });
                    materials.len() - 1
                })
            });
            let rows = p.world_from_object.transpose().to_cols_array_2d();
            let transform =
                if p.world_from_object == Mat4::IDENTITY { vec![] } else { vec![TransformOp::Matrix(rows)] };
            NodeDesc {
                transform,
                kind: NodeKind::Shape { shape: ShapeDesc::Mesh { index: p.mesh }, material },
                origin: meshes[p.mesh].path.clone(),
            }
        })
        .collect();
    SceneDesc { settings, camera, lights, materials, textures, objects, meshes, views }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod wild_tests;
