//! The mesh shapes: `trianglemesh` (P, indices, N, uv), `bilinearmesh` (each patch
//! split into two triangles), `plymesh` (glint's PLY reader; `.ply.gz` decompressed
//! first), `loopsubdiv` (Loop subdivision, [`super::subdivision`]) and `cylinder`
//! (pbrt's open tube around z, tessellated).

use std::f32::consts::TAU;
use std::io::Read;
use std::path::Path;

use glam::{Vec2, Vec3};
use glint_core::desc::MeshDesc;

use super::Reader;
use super::params::Params;
use super::subdivision;
use crate::error::{SceneError, SceneErrorKind};

/// Quads around a full `cylinder` (fewer for a partial `phimax`).
const CYLINDER_SEGMENTS: u32 = 256;

/// The mesh of a mesh shape, or `None` when it was skipped with a warning.
pub(super) fn mesh(r: &mut Reader, ty: &str, p: &Params) -> Result<Option<MeshDesc>, SceneError> {
    let name = format!("{ty}@{}", p.origin());
    let mesh = match ty {
        "trianglemesh" => triangle_mesh(p, name)?,
        "bilinearmesh" => bilinear_mesh(p, name)?,
        "plymesh" => ply_mesh(r, p)?,
        "loopsubdiv" => {
            let mut control = indexed(p, name, 3, "P")?;
            let levels = p.int("levels")?.unwrap_or(3);
            let levels = u32::try_from(levels).map_err(|_| p.error("levels must not be negative"))?;
            let affordable = subdivision::affordable_levels(control.indices.len() / 3, levels);
            if affordable < levels {
                r.warnings.push(p.warning(format!(
                    "subdivided {affordable} times, not {levels}: more would exceed {} triangles",
                    subdivision::MAX_TRIANGLES
                )));
            }
            subdivision::loop_subdivide(&mut control, affordable);
            control
        }
        "cylinder" => cylinder(p, name)?,
        _ => unreachable!("shapes::shape sends only mesh shapes"),
    };
    if mesh.indices.is_empty() {
        r.warnings.push(p.warning("the mesh has no faces and is skipped"));
        return Ok(None);
    }
    Ok(Some(mesh))
}

/// Turns a mesh inside out: reversed winding, negated normals (`ReverseOrientation`).
pub(super) fn flip(mesh: &mut MeshDesc) {
    for tri in mesh.indices.chunks_exact_mut(3) {
        tri.swap(1, 2);
    }
    for n in &mut mesh.normals {
        *n = -*n;
    }
}

/// Positions from `P` and `indices` (`per_face` per face; optional when `P` holds one
/// face), checked.
fn indexed(p: &Params, name: String, per_face: usize, positions: &str) -> Result<MeshDesc, SceneError> {
    let points = p.vec3s(positions, &["point3"])?.ok_or_else(|| p.error(format!("needs \"point3 {positions}\"")))?;
    let indices = match p.ints("indices")? {
        Some(i) => i,
        None if points.len() == per_face => (0..per_face as i64).collect(),
        None => return Err(p.error("needs \"integer indices\"")),
    };
    if indices.len() % per_face != 0 {
        return Err(p.error(format!("the {} indices are not a multiple of {per_face}", indices.len())));
    }
    if let Some(bad) = indices.iter().find(|&&i| i < 0 || i as usize >= points.len()) {
        return Err(p.error(format!("index {bad} is out of range: there are {} points", points.len())));
    }
    let indices = indices.iter().map(|&i| i as u32).collect();
    Ok(MeshDesc { name, positions: points, indices, ..MeshDesc::default() })
}

/// Per-vertex `N` and `uv`, which must match the positions in number.
fn attributes(p: &Params, mesh: &mut MeshDesc) -> Result<(), SceneError> {
    let n = mesh.positions.len();
    if let Some(normals) = p.vec3s("N", &["normal3"])? {
        if normals.len() != n {
            return Err(p.error(format!("has {} normals for {n} points", normals.len())));
        }
        mesh.normals = normals;
    }
    let uvs = match p.vec2s("uv")? {
        Some(uv) => Some(uv),
        None => p.vec2s("st")?,
    };
    if let Some(uvs) = uvs {
        if uvs.len() != n {
            return Err(p.error(format!("has {} uvs for {n} points", uvs.len())));
        }
        mesh.uvs = uvs;
    }
    for ignored in ["S", "faceIndices", "tangents"] {
        p.get(ignored);
    }
    Ok(())
}

fn triangle_mesh(p: &Params, name: String) -> Result<MeshDesc, SceneError> {
    let mut mesh = indexed(p, name, 3, "P")?;
    attributes(p, &mut mesh)?;
    Ok(mesh)
}

/// Each patch `p00 p10 p01 p11` as the triangles (p00, p10, p11) and (p00, p11, p01),
/// which face the patch's normal ∂p/∂u × ∂p/∂v.
fn bilinear_mesh(p: &Params, name: String) -> Result<MeshDesc, SceneError> {
    let mut mesh = indexed(p, name, 4, "P")?;
    attributes(p, &mut mesh)?;
    mesh.indices = mesh.indices.chunks_exact(4).flat_map(|q| [q[0], q[1], q[3], q[0], q[3], q[2]]).collect();
    Ok(mesh)
}

/// pbrt's cylinder: radius `radius` around z from `zmin` to `zmax`, swept through
/// `phimax` degrees, open at both ends; u = φ/φmax, v from zmin to zmax.
fn cylinder(p: &Params, name: String) -> Result<MeshDesc, SceneError> {
    let radius = p.float_or("radius", 1.0)?;
    let (z0, z1) = (p.float_or("zmin", -1.0)?, p.float_or("zmax", 1.0)?);
    let phimax = p.float_or("phimax", 360.0)?.clamp(0.0, 360.0);
    if radius <= 0.0 || z0 == z1 || phimax == 0.0 {
        return Err(p.error("needs a positive radius, zmin ≠ zmax and phimax > 0"));
    }
    let segments = ((CYLINDER_SEGMENTS as f32 * phimax / 360.0).ceil() as u32).max(1);
    let mut mesh = MeshDesc { name, ..MeshDesc::default() };
    for i in 0..=segments {
        let u = i as f32 / segments as f32;
        let (sin, cos) = (u * phimax / 360.0 * TAU).sin_cos();
        let n = Vec3::new(cos, sin, 0.0);
        for (v, z) in [(0.0, z0), (1.0, z1)] {
            mesh.positions.push(Vec3::new(radius * cos, radius * sin, z));
            mesh.normals.push(n);
            mesh.uvs.push(Vec2::new(u, v));
        }
    }
    for i in 0..segments {
        let [a, d, b, c] = [2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3];
        mesh.indices.extend([a, b, c, a, c, d]);
    }
    if z1 < z0 {
        flip(&mut mesh);
    }
    Ok(mesh)
}

/// A `plymesh` through glint's PLY reader, all its parts merged; a `.gz` file is
/// decompressed within the mesh size limit first.
fn ply_mesh(r: &mut Reader, p: &Params) -> Result<MeshDesc, SceneError> {
    let file = p.string("filename")?.ok_or_else(|| p.error("needs a \"string filename\""))?;
    for unsupported in ["displacement", "edgelength"] {
        if p.has(unsupported) {
            p.get(unsupported);
            r.warnings.push(p.warning(format!("\"{unsupported}\" is not supported and is ignored")));
        }
    }
    let path = p.src.dir.join(file);
    let import = if file.to_ascii_lowercase().ends_with(".gz") {
        let bytes = gunzip(&path).map_err(|m| p.src.error(SceneErrorKind::Io, p.pos, format!("{}: {m}", p.what)))?;
        crate::mesh::parse_mesh(&path.with_extension(""), bytes)
    } else {
        crate::mesh::load_mesh(&path)
    }
    .map_err(|e| p.error(e.to_string()))?;
    r.warnings.extend(import.warnings.iter().cloned());
    let merged_path =
        if file.to_ascii_lowercase().ends_with(".gz") { String::new() } else { path.display().to_string() };
    Ok(crate::mesh::merged(&import, file, &merged_path))
}

/// The decompressed bytes of a gzip file, refused beyond the mesh size limit.
fn gunzip(path: &Path) -> Result<Vec<u8>, String> {
    let compressed = crate::input::read_bytes(path, crate::input::InputKind::Mesh).map_err(|e| e.to_string())?;
    let limit = crate::input::limits().mesh_bytes;
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(compressed.as_slice())
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| format!("cannot decompress '{}': {e}", path.display()))?;
    if out.len() as u64 > limit {
        return Err(format!(
            "'{}' decompresses to more than the mesh limit of {}; raise it with --input-limit",
            path.display(),
            crate::input::human_size(limit)
        ));
    }
    Ok(out)
}
