//! `material:` blocks and their `pattern:`, mapped onto glint's Whitted material.
//!
//! The book's `lighting()` gives, per light of intensity `L`,
//! `colour·L·ambient + colour·L·diffuse·(n·l) + L·specular·(r·v)^shininess`, plus
//! `reflective·I_r + transparency·I_t`. With `L_a = Σ L`, `k_a = ambient`, `O_d = colour`,
//! `k_d = diffuse`, `k_s = 1`, `O_s = specular` (grey), `O_r = reflective` (grey), `k_t = 1`
//! and `O_t = transparency` (grey), glint's equation is the same sum term by term.

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use glint_core::desc::{MaterialDesc, ShapeDesc, TextureDesc};

use super::Reader;
use super::values::{self, Result};
use super::yaml::Yaml;
use crate::native::lexer::Pos;
use glint_core::desc::matrix_of;

/// The material keys of the book.
const MATERIAL_KEYS: [&str; 9] = [
    "color",
    "ambient",
    "diffuse",
    "specular",
    "shininess",
    "reflective",
    "transparency",
    "refractive-index",
    "pattern",
];

/// The pattern types of the book and its bonus chapters.
const PATTERN_TYPES: [&str; 8] =
    ["stripes", "gradient", "rings", "checkers", "radial-gradient", "blended", "perturbed", "map"];

/// Keys a pattern may carry (those of the types glint cannot draw are accepted silently,
/// since the whole pattern is already reported).
const PATTERN_KEYS: [&str; 16] = [
    "type",
    "colors",
    "transform",
    "mapping",
    "uv_pattern",
    "a",
    "b",
    "pattern",
    "scale",
    "left",
    "right",
    "front",
    "back",
    "up",
    "down",
    "file",
];

/// The book's `material()` defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BookMaterial {
    pub color: Vec3,
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    pub reflective: f32,
    pub transparency: f32,
    pub refractive_index: f32,
}

impl Default for BookMaterial {
    fn default() -> Self {
        Self {
            color: Vec3::ONE,
            ambient: 0.1,
            diffuse: 0.9,
            specular: 0.9,
            shininess: 200.0,
            reflective: 0.0,
            transparency: 0.0,
            refractive_index: 1.0,
        }
    }
}

/// A pattern as glint can draw it: a checker texture with its repeat, or one colour.
struct Surface {
    color: Vec3,
    checker: Option<(Vec3, Vec3, Vec2, Vec2)>,
}

/// Materials and textures already added, by content, so that objects sharing a
/// material share one glint material.
#[derive(Default)]
pub struct MaterialCache {
    materials: HashMap<String, usize>,
    textures: HashMap<String, usize>,
    names: HashMap<String, usize>,
}

impl MaterialCache {
    /// `base`, or `base-2`, `base-3`, … if it is taken.
    fn unique(&mut self, base: &str) -> String {
        let count = self.names.entry(base.to_owned()).or_insert(0);
        *count += 1;
        if *count == 1 { base.to_owned() } else { format!("{base}-{count}") }
    }
}

impl Reader {
    /// The index of the glint material for an object of `shape` with the book material
    /// `node` (a mapping or the name of a defined one; `None` for the book's default).
    pub(super) fn material(&mut self, node: Option<&Yaml>, shape: ShapeDesc, object: &str, pos: Pos) -> Result<usize> {
        let (entries, name): (Vec<(Yaml, Yaml)>, String) = match node {
            None => (Vec::new(), "default".to_owned()),
            Some(node) => match node.scalar() {
                Some(define_name) => {
                    let define = self.define(node, define_name, "material")?;
                    let entries = values::mapping(&self.src, &define.value, &format!("material '{define_name}'"))?;
                    (entries.to_vec(), define_name.to_owned())
                }
                None => {
                    let entries = values::mapping(&self.src, node, "'material'")?;
                    (entries.to_vec(), format!("{object} at line {}", pos.line))
                }
            },
        };
        let book = self.book_material(&entries)?;
        let surface = match values::get(&entries, "pattern") {
            Some(pattern) => self.pattern(pattern, shape, book.color)?,
            None => Surface { color: book.color, checker: None },
        };
        let mut desc = MaterialDesc {
            name: String::new(),
            ka: book.ambient,
            kd: book.diffuse,
            ks: 1.0,
            kt: 1.0,
            ambient: None,
            diffuse: surface.color,
            specular: Vec3::splat(book.specular),
            reflective: Some(Vec3::splat(book.reflective)),
            transmissive: Vec3::splat(book.transparency),
            shininess: book.shininess,
            ior: book.refractive_index,
            ..MaterialDesc::default()
        };
        if let Some((even, odd, cells, repeat)) = surface.checker {
            let texture = TextureDesc::Checker { name: String::new(), even, odd, cells, filtered: false };
            desc.texture = Some(self.add_texture(texture, &name));
            desc.blend = 1.0;
            desc.texture_repeat = repeat;
            // glint's ambient term does not see textures: the mean colour is closest.
            desc.ambient = Some(0.5 * (even + odd));
        }
        let key = format!("{desc:?}");
        if let Some(&index) = self.materials.materials.get(&key) {
            return Ok(index);
        }
        desc.name = self.materials.unique(&name);
        let index = self.desc.materials.len();
        self.desc.materials.push(desc);
        self.materials.materials.insert(key, index);
        Ok(index)
    }

    fn add_texture(&mut self, mut texture: TextureDesc, material: &str) -> usize {
        let key = format!("{texture:?}");
        if let Some(&index) = self.materials.textures.get(&key) {
            return index;
        }
        if let TextureDesc::Checker { name, .. } = &mut texture {
            *name = self.materials.unique(&format!("{material} pattern"));
        }
        let index = self.desc.textures.len();
        self.desc.textures.push(texture);
        self.materials.textures.insert(key, index);
        index
    }

    /// The book's material keys over its defaults.
    fn book_material(&mut self, entries: &[(Yaml, Yaml)]) -> Result<BookMaterial> {
        for (key, _) in entries {
            let name = key.scalar().unwrap_or("");
            if !MATERIAL_KEYS.contains(&name) {
                self.warn(key.pos, values::unknown_key(name, "in 'material'", &MATERIAL_KEYS));
            }
        }
        let src = &self.src;
        let mut m = BookMaterial::default();
        for (key, value) in entries {
            let name = key.scalar().unwrap_or("");
            let coefficient = || values::number_where(src, value, name, "0 or more", |x| x >= 0.0);
            match name {
                "color" => m.color = values::color(src, value, name)?,
                "ambient" => m.ambient = coefficient()?,
                "diffuse" => m.diffuse = coefficient()?,
                "specular" => m.specular = coefficient()?,
                "shininess" => m.shininess = coefficient()?,
                "reflective" => m.reflective = coefficient()?,
                "transparency" => m.transparency = coefficient()?,
                "refractive-index" => {
                    m.refractive_index = values::number_where(src, value, name, "greater than 0", |x| x > 0.0)?;
                }
                _ => {}
            }
        }
        Ok(m)
    }

    /// A warning, given once even when a shared definition triggers it many times.
    pub(super) fn warn(&mut self, pos: Pos, message: impl std::fmt::Display) {
        let warning = self.src.warning(pos, message);
        if !self.warnings.contains(&warning) {
            self.warnings.push(warning);
        }
    }

    /// What glint can draw of a `pattern:` on `shape`.
    fn pattern(&mut self, node: &Yaml, shape: ShapeDesc, color: Vec3) -> Result<Surface> {
        let entries = match node.scalar() {
            Some(name) => {
                let define = self.define(node, name, "pattern")?;
                values::mapping(&self.src, &define.value, &format!("pattern '{name}'"))?.to_vec()
            }
            None => values::mapping(&self.src, node, "'pattern'")?.to_vec(),
        };
        let src = &self.src;
        let mut unknown = Vec::new();
        values::unknown_keys(src, &entries, &PATTERN_KEYS, "in 'pattern'", &mut unknown);
        let kind = values::word(src, values::required(src, &entries, node.pos, "type", "a pattern")?, "type")?;
        if !PATTERN_TYPES.contains(&kind) {
            let at = values::get(&entries, "type").map_or(node.pos, |t| t.pos);
            return Err(src.invalid(
                at,
                format!(
                    "unknown pattern type '{kind}'{}; expected one of: {}",
                    values::did_you_mean(kind, &PATTERN_TYPES),
                    PATTERN_TYPES.join(", ")
                ),
            ));
        }
        let colors = match values::get(&entries, "colors") {
            Some(list) => pattern_colors(src, list)?,
            None => Vec::new(),
        };
        let transform = match values::get(&entries, "transform") {
            Some(t) => self.transform(t, "transform")?,
            None => Vec::new(),
        };
        for warning in unknown {
            if !self.warnings.contains(&warning) {
                self.warnings.push(warning);
            }
        }
        let first = match colors.first() {
            Some(&c) => c,
            None => nested_first_color(src, &entries, 0)?.unwrap_or(color),
        };
        let fallback = |reader: &mut Self, why: String| {
            reader.warn(node.pos, format!("{why}; the pattern's first colour {first} is used instead"));
            Surface { color: first, checker: None }
        };
        match (kind, shape) {
            ("checkers", ShapeDesc::Plane) => {
                let [a, b] = two_colors(&self.src, node, &colors)?;
                Ok(self.solid_checkers_on_plane(node.pos, a, b, &transform))
            }
            ("checkers", _) => Ok(fallback(
                self,
                format!(
                    "the book's 3-D checkers on a {} cannot be drawn with glint's surface (uv) checker",
                    shape_name(shape)
                ),
            )),
            ("map", _) => self.uv_map(node, &entries, shape, color, !transform.is_empty()),
            _ => Ok(fallback(self, format!("glint has no solid '{kind}' pattern"))),
        }
    }

    /// 3-D `checkers` on a plane: on y = 0 the cells are glint's checker over the
    /// plane's uv `(x, −z)`, exactly when the pattern's transform is a scale (with
    /// translations by whole cells).
    fn solid_checkers_on_plane(
        &mut self,
        pos: Pos,
        a: Vec3,
        b: Vec3,
        transform: &[glint_core::desc::TransformOp],
    ) -> Surface {
        let m = matrix_of(transform);
        let (s, t) = (Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z), m.w_axis.truncate());
        let off_diagonal = [m.x_axis.y, m.x_axis.z, m.y_axis.x, m.y_axis.z, m.z_axis.x, m.z_axis.y];
        let whole_cells = |t: f32, s: f32| ((t / s) - (t / s).round()).abs() < 1e-4;
        let exact = off_diagonal.iter().all(|x| x.abs() < 1e-6) && whole_cells(t.x, s.x) && whole_cells(t.z, s.z);
        if !exact {
            self.warn(
                pos,
                "glint's checker can only scale the book's checkers on a plane; the pattern's rotation, shear \
                 or offset is left out",
            );
        }
        let size = Vec2::new(s.x.abs(), s.z.abs());
        // Which colour is "even" follows from one cell centre seen both ways.
        let p = Vec3::new(0.5 * size.x, 0.0, 0.5 * size.y);
        let q = m.inverse().transform_point3(p);
        let book = q.x.floor() + q.y.floor() + q.z.floor();
        let glint = (p.x / size.x).floor() + (-p.z / size.y).floor();
        let swap = (book - glint).rem_euclid(2.0) != 0.0;
        let (even, odd) = if swap { (b, a) } else { (a, b) };
        Surface { color: a, checker: Some((even, odd, Vec2::ONE, Vec2::ONE / size)) }
    }

    /// `type: map` with a `uv_pattern` of `checkers`: spherical on spheres and planar on
    /// planes are glint's own uv maps, up to the choice of the starting cell.
    fn uv_map(
        &mut self,
        node: &Yaml,
        entries: &[(Yaml, Yaml)],
        shape: ShapeDesc,
        color: Vec3,
        transformed: bool,
    ) -> Result<Surface> {
        let src = &self.src;
        let mapping = match values::get(entries, "mapping") {
            Some(m) => values::word(src, m, "mapping")?.to_owned(),
            None => String::new(),
        };
        let uv = values::get(entries, "uv_pattern").map(|p| values::mapping(src, p, "'uv_pattern'")).transpose()?;
        let uv_kind = uv.and_then(|e| values::get(e, "type")).and_then(Yaml::scalar).unwrap_or("");
        let uv_colors = match uv.and_then(|e| values::get(e, "colors")) {
            Some(list) => pattern_colors(src, list)?,
            None => Vec::new(),
        };
        let first = uv_colors.first().copied().unwrap_or(color);
        let supported =
            matches!((mapping.as_str(), shape), ("spherical", ShapeDesc::Sphere) | ("planar", ShapeDesc::Plane));
        if !supported || uv_kind != "checkers" {
            let what = if uv_kind == "checkers" {
                format!("'{mapping}' mapping on a {}", shape_name(shape))
            } else {
                format!("uv pattern '{uv_kind}'")
            };
            self.warn(node.pos, format!("glint cannot draw the {what}; the first colour {first} is used instead"));
            return Ok(Surface { color: first, checker: None });
        }
        let uv = uv.unwrap_or_default();
        let size = |key| -> Result<u32> {
            let node = values::required(src, uv, node.pos, key, "a 'checkers' uv pattern")?;
            values::whole(src, node, key, 1, 1 << 20)
        };
        let (w, h) = (size("width")?, size("height")?);
        let [a, b] = two_colors(src, node, &uv_colors)?;
        let exact = if shape == ShapeDesc::Sphere { w % 4 == 0 } else { w % 2 == 0 && h % 2 == 0 };
        if transformed {
            self.warn(node.pos, "the transform of a mapped pattern is left out");
        }
        if !exact {
            let rule = if shape == ShapeDesc::Sphere { "a width divisible by 4" } else { "an even width and height" };
            self.warn(
                node.pos,
                format!("glint's checker matches the book's {mapping} checkers only for {rule}; cells are shifted"),
            );
        }
        let (fw, fh) = (w as f32, h as f32);
        let (book, glint) = if shape == ShapeDesc::Sphere {
            // The centre of glint's first cell, on the unit sphere.
            let (u, v) = (0.5 / fw, 0.5 / fh);
            let theta = -std::f32::consts::TAU * u;
            let lat = (v - 0.5) * std::f32::consts::PI;
            let p = Vec3::new(lat.cos() * theta.cos(), lat.sin(), lat.cos() * theta.sin());
            let (bu, bv) = spherical_map(p);
            ((bu * fw).floor() + (bv * fh).floor(), 0.0)
        } else {
            let p = Vec3::new(0.5 / fw, 0.0, 0.5 / fh);
            let (bu, bv) = (p.x.rem_euclid(1.0), p.z.rem_euclid(1.0));
            ((bu * fw).floor() + (bv * fh).floor(), (p.x * fw).floor() + (-p.z * fh).floor())
        };
        let (even, odd) = if (book - glint).rem_euclid(2.0) != 0.0 { (b, a) } else { (a, b) };
        Ok(Surface { color: a, checker: Some((even, odd, Vec2::new(fw, fh), Vec2::ONE)) })
    }
}

/// The book's `spherical_map`: `u` from the azimuth `atan2(x, z)`, `v` from the polar
/// angle, both in [0, 1].
pub fn spherical_map(p: Vec3) -> (f32, f32) {
    let theta = p.x.atan2(p.z);
    let radius = p.length();
    let phi = (p.y / radius).acos();
    let raw_u = theta / std::f32::consts::TAU;
    (1.0 - (raw_u + 0.5), 1.0 - phi / std::f32::consts::PI)
}

fn shape_name(shape: ShapeDesc) -> &'static str {
    match shape {
        ShapeDesc::Sphere => "sphere",
        ShapeDesc::Cube => "cube",
        ShapeDesc::Cylinder => "cylinder",
        ShapeDesc::Cone => "cone",
        ShapeDesc::Plane => "plane",
        ShapeDesc::Disk => "disk",
        ShapeDesc::Rectangle => "rectangle",
        ShapeDesc::Torus { .. } => "torus",
        ShapeDesc::Mesh { .. } => "mesh",
    }
}

/// Where a pattern without `colors` finds its first colour: the nested patterns of
/// `blended` (`a`, `b`), `perturbed` (`pattern`), `map` (`uv_pattern`) and cube maps (the
/// faces), in that order.
const NESTED_PATTERN_KEYS: [&str; 10] =
    ["a", "b", "pattern", "uv_pattern", "left", "right", "front", "back", "up", "down"];

/// The first colour of the first nested pattern that has one (patterns named by a
/// `define` are not followed), for a pattern drawn in one colour.
fn nested_first_color(src: &values::Src, entries: &[(Yaml, Yaml)], depth: usize) -> Result<Option<Vec3>> {
    if depth > 8 {
        return Ok(None);
    }
    for key in NESTED_PATTERN_KEYS {
        let Some(nested) = values::get(entries, key).and_then(Yaml::map) else { continue };
        if let Some(list) = values::get(nested, "colors")
            && let Some(&c) = pattern_colors(src, list)?.first()
        {
            return Ok(Some(c));
        }
        if let Some(c) = nested_first_color(src, nested, depth + 1)? {
            return Ok(Some(c));
        }
    }
    Ok(None)
}

fn pattern_colors(src: &values::Src, list: &Yaml) -> Result<Vec<Vec3>> {
    values::list(src, list, "colors")?.iter().map(|c| values::color(src, c, "colors")).collect()
}

fn two_colors(src: &values::Src, node: &Yaml, colors: &[Vec3]) -> Result<[Vec3; 2]> {
    match colors {
        [a, b, ..] => Ok([*a, *b]),
        _ => Err(src
            .invalid(node.pos, format!("a checkers pattern needs 'colors' with two colours, found {}", colors.len()))),
    }
}
