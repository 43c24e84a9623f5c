//! glTF 2.0 (`.gltf` with its buffers, or a binary `.glb`) through the `gltf` crate:
//! the default scene's node tree with its transforms, triangle primitives, and each
//! material's base-colour factor and texture. A mesh used by several nodes is stored once.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{MaterialDesc, MeshDesc, TextureDesc};

use super::{MAX_MESH_FILE_BYTES, MeshImport, Placement, degenerate_warning, io_error, mesh_error};
use crate::error::SceneError;
use crate::texture_io::srgb_to_linear;

/// Checks the size and the first bytes before handing the file to the parser, so a
/// large file that is not glTF is refused without being read.
fn check_header(path: &Path) -> Result<(), SceneError> {
    let meta = std::fs::metadata(path).map_err(|e| io_error(path, format!("cannot read glTF file: {e}")))?;
    if meta.len() > MAX_MESH_FILE_BYTES {
        return Err(io_error(path, format!("the file is {} bytes, more than a mesh file may have", meta.len())));
    }
    let mut head = [0u8; 64];
    let mut file = std::fs::File::open(path).map_err(|e| io_error(path, format!("cannot read glTF file: {e}")))?;
    let n = file.read(&mut head).map_err(|e| io_error(path, format!("cannot read glTF file: {e}")))?;
    let head = &head[..n];
    let is_glb = head.starts_with(b"glTF");
    let is_json = head.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{') || head.starts_with(b"\xef\xbb\xbf{");
    if !(is_glb || is_json) {
        return Err(mesh_error(path, 0, "not a glTF file: neither binary glTF ('glTF' magic) nor JSON"));
    }
    Ok(())
}

pub fn load(path: &Path) -> Result<MeshImport, SceneError> {
    check_header(path)?;
    let (doc, buffers, images) = gltf::import(path).map_err(|e| mesh_error(path, 0, format!("invalid glTF: {e}")))?;
    let mut state = State {
        path,
        buffers: &buffers,
        images: &images,
        import: MeshImport::default(),
        meshes: HashMap::new(),
        materials: HashMap::new(),
        textures: HashMap::new(),
    };
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    match scene {
        Some(scene) => {
            for node in scene.nodes() {
                state.node(&node, Mat4::IDENTITY, 0)?;
            }
        }
        None => state.import.warnings.push(format!("{}: the file has no scene", path.display())),
    }
    Ok(state.import)
}

struct State<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    images: &'a [gltf::image::Data],
    import: MeshImport,
    /// (mesh, primitive) → index into `import.meshes`.
    meshes: HashMap<(usize, usize), usize>,
    materials: HashMap<usize, usize>,
    textures: HashMap<usize, Option<usize>>,
}

impl State<'_> {
    fn node(&mut self, node: &gltf::Node, parent: Mat4, depth: usize) -> Result<(), SceneError> {
        if depth > 256 {
            return Err(mesh_error(self.path, 0, "the node tree is deeper than 256 levels (a cycle?)"));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        // A zero scale (a common way to hide a node) has no inverse: skip what it holds.
        let det = world.determinant();
        if !(world.is_finite() && det.is_finite() && det.abs() > f32::MIN_POSITIVE) {
            let message = format!("{}: skipped node {} with a singular transform", self.path.display(), node.index());
            self.import.warnings.push(message);
            return Ok(());
        }
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                if primitive.mode() != gltf::mesh::Mode::Triangles {
                    let message =
                        format!("{}: skipped a {:?} primitive (only triangles)", self.path.display(), primitive.mode());
                    self.import.warnings.push(message);
                    continue;
                }
                let key = (mesh.index(), primitive.index());
                let index = match self.meshes.get(&key) {
                    Some(&i) => i,
                    None => {
                        let desc = self.primitive(&mesh, &primitive)?;
                        degenerate_warning(self.path, &desc, &mut self.import.warnings);
                        self.import.meshes.push(desc);
                        self.meshes.insert(key, self.import.meshes.len() - 1);
                        self.import.meshes.len() - 1
                    }
                };
                let material = primitive.material().index().map(|m| self.material(&primitive.material(), m));
                self.import.placements.push(Placement { mesh: index, material, world_from_object: world });
            }
        }
        for child in node.children() {
            self.node(&child, world, depth + 1)?;
        }
        Ok(())
    }

    fn primitive(&self, mesh: &gltf::Mesh, primitive: &gltf::Primitive) -> Result<MeshDesc, SceneError> {
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| &d.0[..]));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| {
                mesh_error(self.path, 0, format!("mesh {} has a primitive without positions", mesh.index()))
            })?
            .map(Vec3::from)
            .collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(mesh_error(self.path, 0, format!("mesh {}: vertex {i} is not finite", mesh.index())));
        }
        let normals: Vec<Vec3> = reader.read_normals().map(|n| n.map(Vec3::from).collect()).unwrap_or_default();
        // glTF's v runs down the image; glint's runs up.
        let uvs: Vec<Vec2> = reader
            .read_tex_coords(0)
            .map(|t| t.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect())
            .unwrap_or_default();
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..positions.len() as u32).collect(),
        };
        if let Some(&i) = indices.iter().find(|&&i| i as usize >= positions.len()) {
            let message = format!("mesh {}: index {i} is out of range ({} vertices)", mesh.index(), positions.len());
            return Err(mesh_error(self.path, 0, message));
        }
        let count = positions.len();
        Ok(MeshDesc {
            name: mesh.name().map_or_else(|| format!("mesh{}", mesh.index()), str::to_owned),
            path: self.path.display().to_string(),
            normals: if normals.len() == count { normals } else { vec![] },
            uvs: if uvs.len() == count { uvs } else { vec![] },
            positions,
            indices: indices[..indices.len() / 3 * 3].to_vec(),
        })
    }

    fn material(&mut self, material: &gltf::Material, index: usize) -> usize {
        if let Some(&i) = self.materials.get(&index) {
            return i;
        }
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let name = material.name().map_or_else(|| format!("material{index}"), str::to_owned);
        let mut desc = MaterialDesc { name, diffuse: Vec3::new(r, g, b), specular: Vec3::ZERO, ..Default::default() };
        if let Some(info) = pbr.base_color_texture() {
            let image = info.texture().source().index();
            if let Some(t) = self.texture(image) {
                desc.texture = Some(t);
                desc.blend = 1.0;
            }
        }
        self.import.materials.push(desc);
        self.materials.insert(index, self.import.materials.len() - 1);
        self.import.materials.len() - 1
    }

    fn texture(&mut self, image: usize) -> Option<usize> {
        if let Some(&t) = self.textures.get(&image) {
            return t;
        }
        let data = self.images.get(image)?;
        let channels = match data.format {
            gltf::image::Format::R8G8B8 => Some(3),
            gltf::image::Format::R8G8B8A8 => Some(4),
            other => {
                self.import
                    .warnings
                    .push(format!("{}: image {image} is {other:?}; only 8-bit RGB(A) is used", self.path.display()));
                None
            }
        };
        let result = channels.map(|c| {
            let texels = data
                .pixels
                .chunks_exact(c)
                .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32).map(|x| srgb_to_linear(x / 255.0)))
                .collect();
            let name = format!("image{image}");
            let path = self.path.display().to_string();
            self.import.textures.push(TextureDesc::Image {
                name,
                path,
                width: data.width,
                height: data.height,
                texels,
            });
            self.import.textures.len() - 1
        });
        self.textures.insert(image, result);
        result
    }
}
