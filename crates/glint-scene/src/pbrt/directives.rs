//! The directive loop: each directive reads its arguments and parameter list from the
//! token stream and changes the graphics state or adds to the scene.
//!
//! Transforms follow pbrt: every transform directive post-multiplies the current
//! transformation matrix (`CTM ← CTM · T`), so the one written last acts on the object
//! first; `Transform` and `ConcatTransform` take their 16 numbers column by column.

use std::rc::Rc;

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::lexer::{Token, TokenKind, tokenize};
use super::params::Params;
use super::spectra::ColorSpace;
use super::{Reader, Saved, camera, lights, materials, shapes, textures};
use crate::error::{SceneError, SceneErrorKind};
use crate::source::{Pos, Source};

/// How deep `Include`/`Import` may nest: deeper is almost surely a file including itself.
const MAX_INCLUDE_DEPTH: usize = 32;

/// The token stream of one file and the read position.
pub(super) struct Cursor<'t> {
    tokens: &'t [Token],
    at: usize,
    src: &'t Rc<Source>,
    /// Where the directive being read starts.
    pos: Pos,
    name: &'t str,
}

impl Cursor<'_> {
    fn error(&self, message: impl AsRef<str>) -> SceneError {
        self.src.invalid(self.pos, format!("{}: {}", self.name, message.as_ref()))
    }

    /// The next token, which must be a string argument.
    fn string(&mut self) -> Result<String, SceneError> {
        match self.tokens.get(self.at) {
            Some(Token { kind: TokenKind::Str(s), .. }) => {
                self.at += 1;
                Ok(s.clone())
            }
            Some(t) => Err(self
                .src
                .invalid(t.pos, format!("{} needs a quoted string here, found {}", self.name, t.describe()))),
            None => Err(self.error("needs a quoted string argument")),
        }
    }

    /// `n` numbers, optionally inside brackets.
    fn numbers(&mut self, n: usize) -> Result<Vec<f32>, SceneError> {
        let bracketed = self.tokens.get(self.at).is_some_and(|t| t.kind == TokenKind::Open);
        if bracketed {
            self.at += 1;
        }
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            match self.tokens.get(self.at) {
                Some(Token { kind: TokenKind::Number(v), .. }) => {
                    out.push(*v as f32);
                    self.at += 1;
                }
                Some(t) => {
                    return Err(self
                        .src
                        .invalid(t.pos, format!("{} takes {n} numbers; found {}", self.name, t.describe())));
                }
                None => return Err(self.error(format!("takes {n} numbers; the file ends first"))),
            }
        }
        if bracketed {
            match self.tokens.get(self.at) {
                Some(Token { kind: TokenKind::Close, .. }) => self.at += 1,
                Some(t) => {
                    return Err(self.src.invalid(t.pos, format!("{} takes {n} numbers; expected ']'", self.name)));
                }
                None => return Err(self.error("the '[' is never closed")),
            }
        }
        Ok(out)
    }

    /// The parameter list that follows, described as `what` in messages.
    fn params(&mut self, what: String) -> Result<Params, SceneError> {
        Params::parse(self.tokens, &mut self.at, self.src, self.pos, what)
    }
}

impl Reader {
    /// Reads the directives of `text`, which came from `src`, `depth` includes deep.
    pub(super) fn run(&mut self, text: &str, src: &Rc<Source>, depth: usize) -> Result<(), SceneError> {
        let tokens = tokenize(text, src)?;
        let mut at = 0;
        while let Some(token) = tokens.get(at) {
            let TokenKind::Word(name) = &token.kind else {
                return Err(src.error(
                    SceneErrorKind::Syntax,
                    token.pos,
                    format!("expected a directive (such as Shape or AttributeBegin), found {}", token.describe()),
                ));
            };
            let mut c = Cursor { tokens: &tokens, at: at + 1, src, pos: token.pos, name };
            self.directive(&mut c, depth)?;
            at = c.at;
        }
        Ok(())
    }

    fn directive(&mut self, c: &mut Cursor, depth: usize) -> Result<(), SceneError> {
        match c.name {
            "Identity" => self.gs.ctm = Mat4::IDENTITY,
            "Translate" => {
                let v = c.numbers(3)?;
                self.concat(c, Mat4::from_translation(Vec3::new(v[0], v[1], v[2])))?;
            }
            "Scale" => {
                let v = c.numbers(3)?;
                self.concat(c, Mat4::from_scale(Vec3::new(v[0], v[1], v[2])))?;
            }
            "Rotate" => {
                let v = c.numbers(4)?;
                let axis = Vec3::new(v[1], v[2], v[3]);
                if axis.length_squared() == 0.0 {
                    return Err(c.error("the rotation axis is the zero vector"));
                }
                self.concat(c, Mat4::from_axis_angle(axis.normalize(), v[0].to_radians()))?;
            }
            "LookAt" => {
                let v = c.numbers(9)?;
                let m = look_at(Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]), Vec3::new(v[6], v[7], v[8]))
                    .ok_or_else(|| c.error("the eye, the point looked at and the up vector are degenerate"))?;
                self.concat(c, m)?;
            }
            "Transform" => {
                let m = Mat4::from_cols_slice(&c.numbers(16)?);
                self.gs.ctm = Mat4::IDENTITY;
                self.concat(c, m)?;
            }
            "ConcatTransform" => {
                let m = Mat4::from_cols_slice(&c.numbers(16)?);
                self.concat(c, m)?;
            }
            "CoordinateSystem" => {
                let name = c.string()?;
                self.named_coordinate_systems.insert(name, self.gs.ctm);
            }
            "CoordSysTransform" => {
                let name = c.string()?;
                match self.named_coordinate_systems.get(&name) {
                    Some(&m) => self.gs.ctm = m,
                    None => {
                        self.warn(c, format!("no coordinate system is named \"{name}\"; the transform is unchanged"))
                    }
                }
            }
            "ActiveTransform" => {
                let which = c.tokens.get(c.at).map(|t| t.kind.clone());
                c.at += 1;
                if which != Some(TokenKind::Word("All".into())) {
                    self.warn(c, "motion blur is not read: only the start transform is used");
                }
            }
            "TransformTimes" => {
                c.numbers(2)?;
            }
            "ReverseOrientation" => self.gs.reverse_orientation = !self.gs.reverse_orientation,
            "AttributeBegin" | "TransformBegin" => self.stack.push(Saved {
                state: self.gs.clone(),
                transform_only: c.name == "TransformBegin",
                pos: c.pos,
                src: Rc::clone(c.src),
            }),
            "AttributeEnd" | "TransformEnd" => self.end_block(c)?,
            "Attribute" => {
                let target = c.string()?;
                let p = c.params(format!("Attribute \"{target}\""))?;
                self.warnings.push(p.warning("default parameters for later objects are not supported and are ignored"));
                for param in &p.list {
                    p.get(&param.name);
                }
            }
            "Option" => {
                let p = c.params("Option".to_owned())?;
                for param in &p.list {
                    p.get(&param.name);
                    self.warnings.push(format!("{}: Option \"{}\" is ignored", c.src.origin(param.pos), param.name));
                }
            }
            "ColorSpace" => {
                let name = c.string()?;
                self.gs.color_space = ColorSpace::named(&name).ok_or_else(|| {
                    c.error(format!("unknown colour space \"{name}\"; pbrt's are srgb, rec2020, aces2065-1 and dci-p3"))
                })?;
            }
            "Camera" | "Film" | "Sampler" | "Integrator" | "PixelFilter" | "Accelerator" => self.render_option(c)?,
            "MakeNamedMedium" | "MediumInterface" => self.medium(c)?,
            "WorldBegin" => {
                if self.in_world {
                    return Err(c.error("the scene already began its world"));
                }
                self.begin_world();
            }
            "WorldEnd" => {}
            "Include" | "Import" => self.include(c, depth)?,
            "Shape" => {
                let ty = c.string()?;
                let p = c.params(format!("Shape \"{ty}\""))?;
                self.require_world(c)?;
                shapes::shape(self, &ty, &p)?;
                p.finish(&mut self.warnings);
            }
            "ObjectBegin" => {
                let name = c.string()?;
                self.require_world(c)?;
                if self.current_object.is_some() {
                    return Err(c.error("object definitions cannot nest; close the previous one with ObjectEnd"));
                }
                self.stack.push(Saved {
                    state: self.gs.clone(),
                    transform_only: false,
                    pos: c.pos,
                    src: Rc::clone(c.src),
                });
                self.current_object = Some((name, Vec::new()));
            }
            "ObjectEnd" => {
                let Some((name, nodes)) = self.current_object.take() else {
                    return Err(c.error("there is no ObjectBegin to end"));
                };
                self.objects.insert(name, nodes);
                self.end_block(c)?;
            }
            "ObjectInstance" => {
                let name = c.string()?;
                self.require_world(c)?;
                shapes::instance(self, c.src, c.pos, &name)?;
            }
            "Material" => {
                let ty = c.string()?;
                let p = c.params(format!("Material \"{ty}\""))?;
                let m = materials::material(self, &ty, &p, None)?;
                p.finish(&mut self.warnings);
                self.gs.material = Some(m);
            }
            "MakeNamedMaterial" => {
                let name = c.string()?;
                let p = c.params(format!("MakeNamedMaterial \"{name}\""))?;
                let ty = p.string("type")?.ok_or_else(|| p.error("needs a \"string type\""))?.to_owned();
                let m = materials::material(self, &ty, &p, Some(&name))?;
                p.finish(&mut self.warnings);
                self.named_materials.insert(name, m);
            }
            "NamedMaterial" => {
                let name = c.string()?;
                let m = *self.named_materials.get(&name).ok_or_else(|| {
                    c.error(format!("no material is named \"{name}\" (MakeNamedMaterial must come first)"))
                })?;
                self.gs.material = Some(m);
            }
            "Texture" => {
                let name = c.string()?;
                let kind = c.string()?;
                let class = c.string()?;
                let p = c.params(format!("Texture \"{name}\" \"{class}\""))?;
                textures::texture(self, &name, &kind, &class, &p)?;
                p.finish(&mut self.warnings);
            }
            "LightSource" => {
                let ty = c.string()?;
                let p = c.params(format!("LightSource \"{ty}\""))?;
                lights::light_source(self, &ty, &p)?;
                p.finish(&mut self.warnings);
            }
            "AreaLightSource" => {
                let ty = c.string()?;
                let p = c.params(format!("AreaLightSource \"{ty}\""))?;
                lights::area_light(self, &ty, &p)?;
                p.finish(&mut self.warnings);
            }
            other => {
                return Err(c.src.error(
                    SceneErrorKind::Syntax,
                    c.pos,
                    format!("unknown directive '{other}' (directives are case-sensitive, e.g. Shape, AttributeBegin)"),
                ));
            }
        }
        Ok(())
    }

    /// `CTM ← CTM · m`, refusing a transform that is not finite.
    fn concat(&mut self, c: &Cursor, m: Mat4) -> Result<(), SceneError> {
        let ctm = self.gs.ctm * m;
        if !ctm.is_finite() {
            return Err(c.error("the transform is not finite"));
        }
        self.gs.ctm = ctm;
        Ok(())
    }

    fn warn(&mut self, c: &Cursor, message: impl AsRef<str>) {
        self.warnings.push(format!("{}: {}: {}", c.src.origin(c.pos), c.name, message.as_ref()));
    }

    fn require_world(&self, c: &Cursor) -> Result<(), SceneError> {
        if self.in_world { Ok(()) } else { Err(c.error("must come after WorldBegin")) }
    }

    /// `AttributeEnd`/`TransformEnd`/`ObjectEnd`: restores what the matching begin saved.
    fn end_block(&mut self, c: &Cursor) -> Result<(), SceneError> {
        let Some(saved) = self.stack.pop() else {
            return Err(c.error("there is no AttributeBegin to end"));
        };
        if saved.transform_only != (c.name == "TransformEnd") {
            self.warn(c, "closes a block opened by a different kind of Begin");
        }
        if saved.transform_only {
            self.gs.ctm = saved.state.ctm;
        } else {
            self.gs = saved.state;
        }
        Ok(())
    }

    /// Camera, film, sampler, integrator and filter: before `WorldBegin` only.
    fn render_option(&mut self, c: &mut Cursor) -> Result<(), SceneError> {
        let ty = c.string()?;
        let p = c.params(format!("{} \"{ty}\"", c.name))?;
        if self.in_world {
            return Err(p.error("must come before WorldBegin"));
        }
        match c.name {
            "Camera" => {
                if Mat3::from_mat4(self.gs.ctm).determinant().abs() <= f32::MIN_POSITIVE || !is_affine(self.gs.ctm) {
                    return Err(p.error("the camera transform is singular or projective"));
                }
                camera::camera(self, &ty, &p)?;
                self.camera_from_world = Some(self.gs.ctm);
                self.named_coordinate_systems.insert("camera".to_owned(), self.gs.ctm.inverse());
            }
            "Film" => camera::film(self, &ty, &p)?,
            "Sampler" => camera::sampler(self, &ty, &p)?,
            "Integrator" => {
                camera::integrator(self, &ty, &p)?;
                self.integrator_seen = true;
            }
            "PixelFilter" => camera::filter(self, &ty, &p)?,
            _ => {
                for param in &p.list {
                    p.get(&param.name);
                }
            }
        }
        p.finish(&mut self.warnings);
        Ok(())
    }

    /// Participating media: glint has none, so they are read and ignored.
    fn medium(&mut self, c: &mut Cursor) -> Result<(), SceneError> {
        if c.name == "MakeNamedMedium" {
            let name = c.string()?;
            let p = c.params(format!("MakeNamedMedium \"{name}\""))?;
            for param in &p.list {
                p.get(&param.name);
            }
        } else {
            c.string()?;
            if matches!(c.tokens.get(c.at), Some(Token { kind: TokenKind::Str(_), .. })) {
                c.string()?;
            }
        }
        self.warn(c, "participating media are not supported and are ignored");
        Ok(())
    }

    /// `Include`/`Import "file"`: the file's directives, read as if written here (glint
    /// reads `Import` like `Include`: the graphics state carries over).
    fn include(&mut self, c: &mut Cursor, depth: usize) -> Result<(), SceneError> {
        let file = c.string()?;
        if depth >= MAX_INCLUDE_DEPTH {
            return Err(
                c.error(format!("includes nest more than {MAX_INCLUDE_DEPTH} deep (does a file include itself?)"))
            );
        }
        let path = c.src.dir.join(&file);
        let text = crate::input::read_text(&path, crate::input::InputKind::Scene)
            .map_err(|e| c.src.error(SceneErrorKind::Io, c.pos, format!("{}: {e}", c.name)))?;
        let dir = path.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
        let src = Rc::new(Source { name: path.display().to_string(), dir });
        self.run(&text, &src, depth + 1)
    }
}

/// pbrt's `LookAt`: camera-from-world for a camera at `eye` looking at `target`, with
/// camera +x = `up × dir` and +y = `dir × x` (pbrt-v4 `LookAt`, transform.cpp).
pub(super) fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (target - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = Mat4::from_cols(right.extend(0.0), new_up.extend(0.0), dir.extend(0.0), eye.extend(1.0));
    Some(world_from_camera.inverse())
}

/// Whether `m` maps points affinely (its last row is (0, 0, 0, 1)).
pub(super) fn is_affine(m: Mat4) -> bool {
    m.row(3).abs_diff_eq(Vec4::W, 1e-6)
}
