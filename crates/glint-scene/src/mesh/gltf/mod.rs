//! glTF 2.0 (`.gltf` with its buffers, or a binary `.glb`) through the `gltf` crate:
//! the default scene's node tree with its transforms; triangle lists, strips and fans
//! with normals, uvs and vertex colours; materials ([`material`]); the first camera and
//! the punctual lights ([`punctual`]). A mesh used by several nodes is stored once.
//!
//! The crate's `import` would read the buffers and images a model names itself, with no
//! bound on their size; so the JSON is parsed from bytes read within the limits of
//! [`crate::input`], buffers are read here the same way, and only the images materials
//! use are decoded, by [`crate::texture_io`] under its pixel limit.

mod material;
mod punctual;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{ImageSampling, MeshDesc, TextureDesc};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use self::material::Texels;

use super::{MeshImport, Placement, degenerate_warning, mesh_error, read_limited};
use crate::error::SceneError;
use crate::input::{self, InputKind};

/// Refuses a large file that is neither binary glTF nor JSON from its first bytes.
pub fn check_head(path: &Path, head: &[u8]) -> Result<(), SceneError> {
    let is_glb = head.starts_with(b"glTF");
    let is_json = head.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{') || head.starts_with(b"\xef\xbb\xbf{");
    if !(is_glb || is_json) {
        return Err(mesh_error(path, 0, "not a glTF file: neither binary glTF ('glTF' magic) nor JSON"));
    }
    Ok(())
}

/// Reads the glTF or GLB file `path` and the buffers and images it names.
pub fn load(path: &Path) -> Result<MeshImport, SceneError> {
    parse(path, read_limited(path, |head| check_head(path, head))?)
}

/// Reads glTF or GLB `bytes` that came from `path` (which names it and locates the
/// files it refers to). Takes the bytes by value so they are freed before the buffers
/// are read.
pub fn parse(path: &Path, bytes: Vec<u8>) -> Result<MeshImport, SceneError> {
    check_glb_length(path, &bytes)?;
    let invalid = |e: gltf::Error| mesh_error(path, 0, format!("invalid glTF: {e}"));
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(&bytes).map_err(invalid)?;
    drop(bytes);
    check_position_accessors(path, document.as_json())?;
    check_required_extensions(path, document.as_json())?;
    let mut json = document.into_json();
    let unknown_attributes = drop_unknown_attributes(&mut json);
    let doc = gltf::Document::from_json(json).map_err(|e| invalid_document(path, e))?;
    let buffers = buffers(path, &doc, blob)?;
    let mut state = State {
        path,
        buffers: &buffers,
        import: MeshImport::default(),
        meshes: HashMap::new(),
        materials: HashMap::new(),
        textures: HashMap::new(),
        channel_means: HashMap::new(),
        metallic_roughness_image: None,
        skipped_modes: HashMap::new(),
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
    for (mesh, count) in unknown_attributes {
        state.warn(format!("mesh {mesh}: ignored {count} vertex attributes with names glTF does not define"));
    }
    state.finish_warnings();
    Ok(state.import)
}

/// Removes the vertex attributes whose names glTF does not define (application
/// attributes should start with `_`, which the `gltf` crate accepts; some exporters
/// forget): they are not glint's to read, and would fail validation. Returns how many
/// each mesh lost.
fn drop_unknown_attributes(json: &mut gltf::json::Root) -> Vec<(usize, usize)> {
    use gltf::json::validation::Checked;
    let mut dropped = Vec::new();
    for (m, mesh) in json.meshes.iter_mut().enumerate() {
        let mut count = 0;
        for primitive in &mut mesh.primitives {
            let before = primitive.attributes.len();
            primitive.attributes.retain(|semantic, _| matches!(semantic, Checked::Valid(_)));
            count += before - primitive.attributes.len();
        }
        if count > 0 {
            dropped.push((m, count));
        }
    }
    dropped
}

/// The extensions whose meaning glint renders (or may leave out without changing the
/// geometry: KTX2 and WebP images are warned about and left out).
const IMPLEMENTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_texture_transform",
    "KHR_texture_basisu",
    "EXT_texture_webp",
];

/// Refuses, in one sentence, a model that requires an extension glint does not
/// implement (Draco compression, mesh quantization, …): without it the data cannot be
/// read as the model means it.
fn check_required_extensions(path: &Path, json: &gltf::json::Root) -> Result<(), SceneError> {
    let missing: Vec<&str> =
        json.extensions_required.iter().map(String::as_str).filter(|e| !IMPLEMENTED_EXTENSIONS.contains(e)).collect();
    match missing.as_slice() {
        [] => Ok(()),
        [one] => Err(mesh_error(
            path,
            0,
            format!("the model requires the glTF extension {one}, which glint does not implement"),
        )),
        many => {
            let list = many.join(", ");
            Err(mesh_error(
                path,
                0,
                format!("the model requires the glTF extensions {list}, which glint does not implement"),
            ))
        }
    }
}

/// The first problems of a document that fails validation, counted beyond three, so
/// that a broken model reads as a sentence, not a list of every accessor.
fn invalid_document(path: &Path, error: gltf::Error) -> SceneError {
    let gltf::Error::Validation(problems) = &error else {
        return mesh_error(path, 0, format!("invalid glTF: {error}"));
    };
    let shown: Vec<String> = problems.iter().take(3).map(|(at, problem)| format!("{at}: {problem}")).collect();
    let more = problems.len().saturating_sub(shown.len());
    let tail = if more > 0 { format!(" (and {more} more problems)") } else { String::new() };
    mesh_error(path, 0, format!("invalid glTF: {}{tail}", shown.join("; ")))
}

/// Refuses a GLB whose header declares a total length shorter than the 12-byte header
/// itself: gltf 1.4 subtracts 12 from it unchecked (`binary.rs`), which panics in a
/// build with overflow checks.
fn check_glb_length(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    const HEADER_BYTES: u32 = 12;
    let Some(length) = bytes.strip_prefix(b"glTF").and_then(|rest| rest.get(4..8)) else { return Ok(()) };
    let length = u32::from_le_bytes([length[0], length[1], length[2], length[3]]);
    if length < HEADER_BYTES {
        let message = format!("invalid glTF: the GLB header declares {length} bytes, fewer than the header itself");
        return Err(mesh_error(path, 0, message));
    }
    Ok(())
}

/// Refuses a primitive whose `POSITION` names an accessor that does not exist: the
/// validation of gltf-json 1.4 indexes the accessor list with it unchecked
/// (`primitive_validate_hook`) and panics, so this one index is checked first.
fn check_position_accessors(path: &Path, json: &gltf::json::Root) -> Result<(), SceneError> {
    use gltf::json::mesh::Semantic as JsonSemantic;
    use gltf::json::validation::Checked;
    let count = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let Some(index) = primitive.attributes.get(&Checked::Valid(JsonSemantic::Positions)) else { continue };
            if index.value() >= count {
                let message = format!(
                    "invalid glTF: mesh {m} primitive {p}: POSITION names accessor {}, but there are {count}",
                    index.value()
                );
                return Err(mesh_error(path, 0, message));
            }
        }
    }
    Ok(())
}

/// Where a URI in a glTF file points: bytes it carries (`data:`) or a file.
enum Resource {
    Bytes(Vec<u8>),
    File(PathBuf),
}

/// Resolves `uri` as glTF does: `data:…;base64,…`, `file:` (an absolute path) or a
/// percent-encoded path relative to the model's folder `dir`.
fn resolve(dir: &Path, uri: &str) -> Result<Resource, String> {
    if uri.starts_with("data:") {
        // The gltf crate decodes data URIs on its own when it has no folder to look in.
        let data = gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), None)
            .map_err(|e| format!("invalid data URI: {e}"))?;
        return Ok(Resource::Bytes(data.0));
    }
    if let Some(file) = uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")) {
        return Ok(Resource::File(PathBuf::from(file)));
    }
    if uri.contains(':') {
        return Err(format!("unsupported URI '{uri}': only data:, file: and relative paths are read"));
    }
    let relative = urlencoding::decode(uri).map_err(|e| format!("URI '{uri}' is not UTF-8 once decoded: {e}"))?;
    Ok(Resource::File(dir.join(&*relative)))
}

/// The data of every buffer: the binary chunk of a GLB, a `data:` URI, or a file read
/// within the mesh size limit.
fn buffers(
    path: &Path,
    doc: &gltf::Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>, SceneError> {
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let fail = |message: String| mesh_error(path, 0, format!("buffer {}: {message}", buffer.index()));
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| fail("the GLB has no binary chunk".into()))?,
            gltf::buffer::Source::Uri(uri) => match resolve(dir, uri).map_err(fail)? {
                Resource::Bytes(bytes) => bytes,
                Resource::File(file) => {
                    let bytes = input::read_bytes(&file, InputKind::Mesh).map_err(|e| fail(e.to_string()))?;
                    super::check_lfs_pointer(&file, &bytes).map_err(|e| fail(e.message))?;
                    bytes
                }
            },
        };
        if data.len() < buffer.length() {
            return Err(fail(format!("it holds {} bytes, fewer than the {} it declares", data.len(), buffer.length())));
        }
        // As the gltf crate does: accessors may read whole 4-byte words at the end.
        data.resize(data.len().next_multiple_of(4), 0);
        out.push(gltf::buffer::Data(data));
    }
    Ok(out)
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
const COLOR_0_RGB: Expect =
    Expect { what: "COLOR_0", dimensions: Dimensions::Vec3, types: &[DataType::F32, DataType::U8, DataType::U16] };
const COLOR_0_RGBA: Expect = Expect { dimensions: Dimensions::Vec4, ..COLOR_0_RGB };
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
    import: MeshImport,
    /// (mesh, primitive) → index into `import.meshes`.
    meshes: HashMap<(usize, usize), usize>,
    materials: HashMap<usize, usize>,
    /// (image, how its texels are meant, its sampler) → index into `import.textures`;
    /// `None`: an image glint cannot decode, already warned about.
    textures: HashMap<(usize, Texels, ImageSampling), Option<usize>>,
    /// Mean of each metallic texture (a metallic-roughness texture's blue channel), by
    /// its index in `import.textures`.
    channel_means: HashMap<usize, f32>,
    /// A metallic-roughness image decoded for its green channel, by image index, kept
    /// until its blue channel is taken from it, so the image is decoded once for both.
    metallic_roughness_image: Option<(usize, Option<TextureDesc>)>,
    /// Primitives of each mode glint does not draw (points, lines).
    skipped_modes: HashMap<&'static str, usize>,
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
        if let Some(camera) = node.camera() {
            self.camera(&camera, world);
        }
        if let Some(light) = node.light() {
            self.light(&light, world);
        }
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                if let Some(mode) = undrawn_mode(primitive.mode()) {
                    *self.skipped_modes.entry(mode).or_default() += 1;
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
                let material = match primitive.material().index() {
                    Some(m) => Some(self.material(&primitive.material(), m)?),
                    None => None,
                };
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
        // The base colour's texture transform is baked into the uvs (a primitive has one
        // material); glTF's v runs down the image, glint's up.
        let transform = uv_transform(primitive);
        let uvs: Vec<Vec2> = if readable(&Semantic::TexCoords(0), &TEXCOORD_0)? {
            let uvs = reader.read_tex_coords(0).ok_or_else(|| unreadable(TEXCOORD_0.what))?;
            uvs.into_f32().map(|uv| transform.apply(Vec2::from(uv))).map(|uv| Vec2::new(uv.x, 1.0 - uv.y)).collect()
        } else {
            vec![]
        };
        let rgba = primitive.get(&Semantic::Colors(0)).is_some_and(|a| a.dimensions() == Dimensions::Vec4);
        let colors: Vec<Vec3> = if readable(&Semantic::Colors(0), if rgba { &COLOR_0_RGBA } else { &COLOR_0_RGB })? {
            // glTF's vertex colours are linear already; alpha is not used.
            reader.read_colors(0).ok_or_else(|| unreadable(COLOR_0_RGB.what))?.into_rgb_f32().map(Vec3::from).collect()
        } else {
            vec![]
        };
        let indices: Vec<u32> = match primitive.indices() {
            Some(accessor) if !self.readable(m, &accessor, &INDICES)? => return Ok(None),
            Some(_) => reader.read_indices().ok_or_else(|| unreadable(INDICES.what))?.into_u32().collect(),
            None => (0..positions.len() as u32).collect(),
        };
        let indices = triangles_of(primitive.mode(), indices);
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
            colors: if colors.len() == count { colors } else { vec![] },
            positions,
            indices,
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
}

impl State<'_> {
    /// Turns the counts gathered while reading into one warning each.
    fn finish_warnings(&mut self) {
        let mut modes: Vec<_> = self.skipped_modes.iter().map(|(m, n)| (*m, *n)).collect();
        modes.sort_unstable();
        for (mode, count) in modes {
            self.warn(format!("skipped {count} primitives drawn as {mode} (glint draws triangles)"));
        }
        let count = self.import.cameras.len();
        if count > 1 {
            self.warn(format!("the first of {count} cameras is used; `--camera N` (0 to {}) picks another", count - 1));
        }
    }
}

/// The name of a primitive mode glint does not draw, or `None` for the triangle modes.
fn undrawn_mode(mode: Mode) -> Option<&'static str> {
    match mode {
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => None,
        Mode::Points => Some("points"),
        Mode::Lines | Mode::LineLoop | Mode::LineStrip => Some("lines"),
    }
}

/// The triangle list of a primitive's vertex sequence: lists as they are (a partial
/// last triangle dropped), strips with every other triangle turned so all keep the
/// first one's winding, fans around their first vertex.
fn triangles_of(mode: Mode, indices: Vec<u32>) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
            .flat_map(|i| {
                let [a, b, c] = [indices[i], indices[i + 1], indices[i + 2]];
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => {
            (1..indices.len().saturating_sub(1)).flat_map(|i| [indices[0], indices[i], indices[i + 1]]).collect()
        }
        _ => {
            let mut indices = indices;
            indices.truncate(indices.len() / 3 * 3);
            indices
        }
    }
}

/// `KHR_texture_transform` of a texture reference: scale, then rotate, then offset.
#[derive(Clone, Copy, Debug, PartialEq)]
struct UvTransform {
    offset: Vec2,
    rotation: f32,
    scale: Vec2,
}

impl UvTransform {
    const IDENTITY: UvTransform = UvTransform { offset: Vec2::ZERO, rotation: 0.0, scale: Vec2::ONE };

    /// The transformed uv, in glTF's convention (v down the image): `T·R·S`, with the
    /// rotation `[cos sin; −sin cos]` that the sample model, Blender and Babylon use
    /// (the extension's GLSL listing has it transposed: KhronosGroup/glTF#1563).
    fn apply(&self, uv: Vec2) -> Vec2 {
        let s = uv * self.scale;
        let (sin, cos) = self.rotation.sin_cos();
        Vec2::new(cos * s.x + sin * s.y, -sin * s.x + cos * s.y) + self.offset
    }
}

/// The texture transform of the primitive's base-colour texture (the one texture whose
/// placement glint keeps per mesh), or the identity.
fn uv_transform(primitive: &gltf::Primitive) -> UvTransform {
    let material = primitive.material();
    let Some(info) = material.pbr_metallic_roughness().base_color_texture() else { return UvTransform::IDENTITY };
    info.texture_transform().map_or(UvTransform::IDENTITY, |t| UvTransform {
        offset: Vec2::from(t.offset()),
        rotation: t.rotation(),
        scale: Vec2::from(t.scale()),
    })
}

#[cfg(test)]
mod tests;
