//! glint-scene: scene files in and images out, for the glint renderer.
//!
//! Every importer produces a [`glint_core::desc::SceneDesc`]; this crate owns the files
//! (the native `.glint` format, the CS123/CS1230 course formats, Mitsuba 3 XML, pbrt-v4 and texture images) so that glint-core never touches I/O.
//! Every file is read through [`input`], which bounds its size.

pub mod atomic_file;
pub mod challenge;
pub mod convert;
pub mod course;
pub mod detect;
pub mod error;
pub mod image_out;
pub mod input;
pub mod mesh;
pub mod mitsuba;
pub mod native;
pub mod overrides;
pub mod part_file;
pub mod pbrt;
pub mod ply_out;
pub mod source;
pub mod texture_io;

pub use detect::{Loaded, SceneFormat, detect, load_any, load_any_at};
pub use error::{SceneError, SceneErrorKind};
pub use native::{DEFAULT_SCENE_SOURCE, default_scene, load_scene, parse_scene, parse_scene_at};
