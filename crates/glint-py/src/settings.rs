//! Keyword arguments of `render` → the [`Overrides`] the command line applies too.

use glint_core::desc::{AdaptiveDesc, FilterKind, SamplePattern, SamplerKind};
use glint_scene::overrides::{IntegratorChoice, OverrideError, Overrides, PathOnly};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `render`'s settings as Python gives them; `None` keeps the scene's.
#[derive(Default)]
pub struct RenderKwargs {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub samples: Option<u32>,
    pub spp: Option<u32>,
    pub integrator: Option<String>,
    pub max_depth: Option<MaxDepth>,
    pub rr_depth: Option<u32>,
    pub sampler: Option<String>,
    pub pattern: Option<String>,
    pub filter: Option<String>,
    pub filter_radius: Option<f32>,
    pub adaptive: Option<(u32, u32, f32)>,
    pub seed: Option<u32>,
    /// Which of the file's cameras looks, from 0 (`glint render --camera`).
    pub camera: Option<usize>,
}

/// `max_depth`: a whole number, or -1 / `"unlimited"` (path integrator only).
#[derive(FromPyObject)]
pub enum MaxDepth {
    Whole(i64),
    Word(String),
}

impl RenderKwargs {
    /// The overrides, with the same meaning as the command line's flags.
    ///
    /// # Errors
    ///
    /// A `ValueError` naming the argument and the values it accepts.
    pub fn overrides(&self) -> PyResult<Overrides> {
        Ok(Overrides {
            width: self.width,
            height: self.height,
            samples: self.samples,
            spp: self.spp,
            integrator: choice(
                "integrator",
                &self.integrator,
                &[("whitted", IntegratorChoice::Whitted), ("path", IntegratorChoice::Path)],
            )?,
            max_depth: self.max_depth.as_ref().map(max_depth).transpose()?,
            rr_depth: self.rr_depth,
            sampler: choice(
                "sampler",
                &self.sampler,
                &[("sobol", SamplerKind::Sobol), ("independent", SamplerKind::Independent)],
            )?,
            pattern: choice(
                "pattern",
                &self.pattern,
                &[
                    ("grid", SamplePattern::Grid),
                    ("corners", SamplePattern::CornersAndCentre),
                    ("jittered", SamplePattern::Jittered),
                    ("sobol", SamplePattern::Sobol),
                ],
            )?,
            filter: choice(
                "filter",
                &self.filter,
                &[
                    ("box", FilterKind::Box),
                    ("tent", FilterKind::Tent),
                    ("gaussian", FilterKind::Gaussian),
                    ("mitchell", FilterKind::Mitchell),
                    ("lanczos", FilterKind::Lanczos),
                ],
            )?,
            filter_radius: self.filter_radius,
            adaptive: self.adaptive.map(|(min_samples, max_samples, threshold)| AdaptiveDesc {
                min_samples,
                max_samples,
                threshold,
            }),
            seed: self.seed,
            camera: self.camera,
        })
    }
}

/// The override error in the words of the Python API.
pub fn override_error(error: OverrideError) -> PyErr {
    let setting = match error {
        OverrideError::PathOnly(PathOnly::UnlimitedMaxDepth) => {
            "an unlimited max_depth (the Whitted integrator needs a finite depth)"
        }
        OverrideError::PathOnly(PathOnly::RrDepth) => "rr_depth",
        OverrideError::PathOnly(PathOnly::Sampler) => "sampler",
        OverrideError::RrDepthZero | OverrideError::NoSuchCamera { .. } => {
            return PyValueError::new_err(error.to_string());
        }
    };
    PyValueError::new_err(format!(
        "{setting} applies only to the path integrator; pass integrator=\"path\" or render a path-traced scene"
    ))
}

/// One of a fixed list of words, or a `ValueError` listing them.
fn choice<T: Copy>(argument: &str, given: &Option<String>, choices: &[(&str, T)]) -> PyResult<Option<T>> {
    let Some(given) = given else { return Ok(None) };
    match choices.iter().find(|(word, _)| word == given) {
        Some(&(_, value)) => Ok(Some(value)),
        None => {
            let words: Vec<String> = choices.iter().map(|(w, _)| format!("'{w}'")).collect();
            Err(PyValueError::new_err(format!("{argument}='{given}' is not one of {}", words.join(", "))))
        }
    }
}

/// `max_depth` as the command line's `--max-depth` reads it: `u32::MAX` is unlimited.
fn max_depth(depth: &MaxDepth) -> PyResult<u32> {
    match depth {
        MaxDepth::Whole(-1) => Ok(u32::MAX),
        MaxDepth::Word(word) if word == "unlimited" => Ok(u32::MAX),
        MaxDepth::Whole(n) => u32::try_from(*n).ok().ok_or_else(|| bad_depth(&n.to_string())),
        MaxDepth::Word(word) => Err(bad_depth(&format!("'{word}'"))),
    }
}

fn bad_depth(given: &str) -> PyErr {
    PyValueError::new_err(format!("max_depth={given}: expected a whole number 0 or more, -1 or 'unlimited'"))
}
