//! Which scene format a file is in, decided by its content (the extension only breaks
//! ties), and the one entry point that loads any of them.

use std::path::Path;

use glint_core::desc::SceneDesc;

use crate::error::SceneError;
use crate::input::InputKind;

/// The scene formats glint reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormat {
    /// glint's own `.glint` format.
    Native,
    /// CS123/CS1230 `<scenefile>` XML.
    CourseXml,
    /// CS1230 JSON scenefiles.
    CourseJson,
    /// "The Ray Tracer Challenge" YAML scenes.
    ChallengeYaml,
    /// Mitsuba 3 XML (`<scene version="…">`).
    Mitsuba,
    /// pbrt-v4 scene files (`.pbrt`).
    Pbrt,
    /// A triangle-mesh file (OBJ, PLY, glTF) shown by a camera fitted to it and two lights.
    Mesh,
}

/// A loaded scene and the harmless oddities met on the way (unknown elements that were
/// skipped, …), for the caller to show.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub scene: SceneDesc,
    pub format: SceneFormat,
    pub warnings: Vec<String>,
}

/// Guesses the format from the first meaningful characters of `text`.
pub fn detect(text: &str, path: &Path) -> SceneFormat {
    if crate::mesh::MeshFormat::from_path(path).is_some() {
        return SceneFormat::Mesh;
    }
    let body = text.trim_start_matches('\u{feff}');
    let first_line = body
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with("//"))
        .unwrap_or("");
    if path_ext(path) == "pbrt" || crate::pbrt::is_pbrt(body) {
        return SceneFormat::Pbrt;
    }
    if first_line.starts_with('<') {
        return if crate::mitsuba::is_mitsuba(body) { SceneFormat::Mitsuba } else { SceneFormat::CourseXml };
    }
    if first_line.starts_with('{') && !first_line.contains('}')
        || body.trim_start().starts_with('{') && path_ext(path) == "json"
    {
        return SceneFormat::CourseJson;
    }
    if first_line.starts_with("- ") || first_line == "-" || first_line.starts_with("---") {
        return SceneFormat::ChallengeYaml;
    }
    match path_ext(path).as_str() {
        "xml" if crate::mitsuba::is_mitsuba(body) => SceneFormat::Mitsuba,
        "xml" => SceneFormat::CourseXml,
        "json" => SceneFormat::CourseJson,
        "yml" | "yaml" => SceneFormat::ChallengeYaml,
        _ => SceneFormat::Native,
    }
}

fn path_ext(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()
}

/// Loads a scene file of any supported format.
///
/// # Errors
///
/// A [`SceneError`] naming the file, line and column of the first problem.
pub fn load_any(path: &Path) -> Result<Loaded, SceneError> {
    load_any_at(path, 0.0)
}

/// [`load_any`] with a `.glint` scene's keyed properties taken at `frame` (other
/// formats have no animation: every frame is the same scene).
///
/// # Errors
///
/// As [`load_any`].
pub fn load_any_at(path: &Path, frame: f64) -> Result<Loaded, SceneError> {
    // Mesh files may be binary: decided by extension, before reading the file as text.
    if crate::mesh::MeshFormat::from_path(path).is_some() {
        let (scene, warnings) = load_mesh_scene(path)?;
        return Ok(Loaded { scene, format: SceneFormat::Mesh, warnings });
    }
    let name = path.display().to_string();
    let text = crate::input::read_text(path, InputKind::Scene)?;
    let format = detect(&text, path);
    let (scene, warnings) = match format {
        SceneFormat::Native => (crate::native::load_text(path, &text, frame)?, Vec::new()),
        SceneFormat::ChallengeYaml => crate::challenge::parse_challenge(&text, &name)?,
        SceneFormat::Mesh => load_mesh_scene(path)?,
        SceneFormat::Mitsuba => {
            let loaded = crate::mitsuba::load_text(path, &text)?;
            (loaded.scene, loaded.warnings)
        }
        SceneFormat::Pbrt => {
            let loaded = crate::pbrt::load_text(path, &text)?;
            (loaded.scene, loaded.warnings)
        }
        SceneFormat::CourseXml | SceneFormat::CourseJson => {
            let loaded = crate::course::load_text(path, &text, format, crate::course::CourseOptions::default())?;
            (loaded.scene, loaded.warnings)
        }
    };
    Ok(Loaded { scene, format, warnings })
}

/// A mesh file framed by a default camera and two lights.
fn load_mesh_scene(path: &Path) -> Result<(SceneDesc, Vec<String>), SceneError> {
    let import = crate::mesh::load_mesh(path)?;
    let warnings = import.warnings.clone();
    Ok((crate::mesh::model_scene(import), warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_decides_over_extension() {
        let p = Path::new("scene.txt");
        assert_eq!(detect("<?xml version=\"1.0\"?>\n<scenefile>", p), SceneFormat::CourseXml);
        assert_eq!(detect("  <scenefile>", p), SceneFormat::CourseXml);
        assert_eq!(detect("{\n  \"name\": \"root\"", p), SceneFormat::CourseJson);
        assert_eq!(detect("# a comment\n- add: camera\n", p), SceneFormat::ChallengeYaml);
        assert_eq!(detect("camera { eye [0 0 5] }", p), SceneFormat::Native);
        assert_eq!(detect("<scenefile>", Path::new("x.json")), SceneFormat::CourseXml);
        assert_eq!(detect("sphere {}", Path::new("x.glint")), SceneFormat::Native);
        let mitsuba = "<?xml version=\"1.0\"?>\n<!-- c -->\n<scene version=\"3.0.0\">";
        assert_eq!(detect(mitsuba, p), SceneFormat::Mitsuba);
        assert_eq!(detect("<scenefile>", Path::new("x.xml")), SceneFormat::CourseXml);
        assert_eq!(detect("# pbrt\nLookAt 0 0 5  0 0 0  0 1 0\n", p), SceneFormat::Pbrt);
        assert_eq!(detect("Shape \"sphere\"", Path::new("x.pbrt")), SceneFormat::Pbrt);
        assert_eq!(detect("camera { eye [0 0 5] }", Path::new("x.glint")), SceneFormat::Native);
    }
}
