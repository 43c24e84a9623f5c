//! glTF 2.0 (`.gltf` with its buffers, or a binary `.glb`) through the `gltf` crate:
//! the default scene's node tree with its transforms, triangle primitives, and each
//! material's base-colour factor and texture. A mesh used by several nodes is stored once.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{MaterialDesc, MeshDesc, TextureDesc};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Semantic;

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

/// What a primitive's accessor must hold to be read: the element shape and the
/// component types its reader takes.
struct Expect {
    what: &'static str,
    dimensions: Dimensions,
    types: &'static [DataType],
}

const POSITION: Expect = Expect { what: "POSITION", dimensions: Dimensions::Vec3, types: &[DataType::F32] };
const NORMAL: Expect = Expect { what: "NORMAL", dimensions: Dimensions::Vec3, types: &[DataType::F32] };
const TEXCOORD_0: Expect =
    Expect { what: "TEXCOORD_0", dimensions: Dimensions::Vec2, types: &[DataType::F32, DataType::U8, DataType::U16] };
const INDICES: Expect =
    Expect { what: "indices", dimensions: Dimensions::Scalar, types: &[DataType::U8, DataType::U16, DataType::U32] };

/// Whether `count` (at least one) elements of `size` bytes, `stride` (at least `size`)
/// apart from byte `offset`, end within `length` bytes; checked, so that no count or
/// offset a file claims can overflow.
fn fits(length: usize, offset: usize, stride: usize, count: usize, size: usize) -> bool {
    let end = count.checked_sub(1).and_then(|n| n.checked_mul(stride)).and_then(|b| b.checked_add(offset));
    stride >= size && end.and_then(|b| b.checked_add(size)).is_some_and(|end| end <= length)
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
                        let Some(desc) = self.primitive(&mesh, &primitive)? else {
                            let message = format!(
                                "{}: skipped an empty primitive of mesh {} (an accessor with no elements)",
                                self.path.display(),
                                mesh.index()
                            );
                            self.import.warnings.push(message);
                            continue;
                        };
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

    /// The primitive's triangles, or `None` where an accessor it needs has no elements
    /// (a zero-length buffer view).
    fn primitive(&self, mesh: &gltf::Mesh, primitive: &gltf::Primitive) -> Result<Option<MeshDesc>, SceneError> {
        let m = mesh.index();
        let unreadable = |what: &str| mesh_error(self.path, 0, format!("mesh {m}: the {what} data cannot be read"));
        let positions = primitive
            .get(&Semantic::Positions)
            .ok_or_else(|| mesh_error(self.path, 0, format!("mesh {m} has a primitive without positions")))?;
        if !self.readable(m, &positions, &POSITION)? {
            return Ok(None);
        }
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| &d.0[..]));
        let positions: Vec<Vec3> =
            reader.read_positions().ok_or_else(|| unreadable(POSITION.what))?.map(Vec3::from).collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(mesh_error(self.path, 0, format!("mesh {m}: vertex {i} is not finite")));
        }
        let readable = |semantic: &Semantic, expect: &Expect| -> Result<bool, SceneError> {
            primitive.get(semantic).map_or(Ok(false), |a| self.readable(m, &a, expect))
        };
        let normals: Vec<Vec3> = if readable(&Semantic::Normals, &NORMAL)? {
            reader.read_normals().ok_or_else(|| unreadable(NORMAL.what))?.map(Vec3::from).collect()
        } else {
            vec![]
        };
        // glTF's v runs down the image; glint's runs up.
        let uvs: Vec<Vec2> = if readable(&Semantic::TexCoords(0), &TEXCOORD_0)? {
            let uvs = reader.read_tex_coords(0).ok_or_else(|| unreadable(TEXCOORD_0.what))?;
            uvs.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect()
        } else {
            vec![]
        };
        let indices: Vec<u32> = match primitive.indices() {
            Some(accessor) if !self.readable(m, &accessor, &INDICES)? => return Ok(None),
            Some(_) => reader.read_indices().ok_or_else(|| unreadable(INDICES.what))?.into_u32().collect(),
            None => (0..positions.len() as u32).collect(),
        };
        if let Some(&i) = indices.iter().find(|&&i| i as usize >= positions.len()) {
            let message = format!("mesh {m}: index {i} is out of range ({} vertices)", positions.len());
            return Err(mesh_error(self.path, 0, message));
        }
        let count = positions.len();
        Ok(Some(MeshDesc {
            name: mesh.name().map_or_else(|| format!("mesh{m}"), str::to_owned),
            path: self.path.display().to_string(),
            normals: if normals.len() == count { normals } else { vec![] },
            uvs: if uvs.len() == count { uvs } else { vec![] },
            positions,
            indices: indices[..indices.len() / 3 * 3].to_vec(),
        }))
    }

    /// Checks what the `gltf` crate's readers take for granted of an accessor and
    /// panic on otherwise (some only in debug builds): elements of the type the reader
    /// handles, no closer together than their size, and within their buffer views (it
    /// computes where the data ends from `count − 1`, which underflows for an empty
    /// accessor). `Ok(false)`: the accessor has no elements, so there is nothing to read.
    fn readable(&self, mesh: usize, accessor: &gltf::Accessor, expect: &Expect) -> Result<bool, SceneError> {
        let fail = |problem: String| {
            let message = format!("mesh {mesh}: the {} accessor ({}) {problem}", expect.what, accessor.index());
            Err(mesh_error(self.path, 0, message))
        };
        let (dimensions, data_type) = (accessor.dimensions(), accessor.data_type());
        if dimensions != expect.dimensions || !expect.types.contains(&data_type) {
            let expected = format!("{:?} of {:?}", expect.dimensions, expect.types);
            return fail(format!("holds {dimensions:?} of {data_type:?}; expected {expected}"));
        }
        if accessor.count() == 0 {
            return Ok(false);
        }
        let size = accessor.size();
        if let Some(view) = accessor.view() {
            let stride = view.stride().unwrap_or(size);
            if stride < size {
                return fail(format!("has {size}-byte elements only {stride} bytes apart (the buffer view's stride)"));
            }
            if !fits(view.length(), accessor.offset(), stride, accessor.count(), size) {
                let (count, offset, length) = (accessor.count(), accessor.offset(), view.length());
                return fail(format!("runs past its {length}-byte buffer view ({count} elements from byte {offset})"));
            }
        }
        if let Some(sparse) = accessor.sparse() {
            let (indices, values) = (sparse.indices(), sparse.values());
            let index_size = indices.index_type().size();
            let [index_view, value_view] = [indices.view(), values.view()];
            let index_stride = index_view.stride().unwrap_or(index_size);
            let value_stride = value_view.stride().unwrap_or(size);
            if !(fits(index_view.length(), indices.offset(), index_stride, sparse.count(), index_size)
                && fits(value_view.length(), values.offset(), value_stride, sparse.count(), size))
            {
                return fail(format!(
                    "has a sparse part of {} elements that does not fit its buffer views",
                    sparse.count()
                ));
            }
        }
        Ok(true)
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
