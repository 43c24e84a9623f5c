//! Render settings given on top of a scene's own: the CLI's `--spp`, `--width`, … and the
//! Python API's keyword arguments, so both front ends mean exactly the same thing.

use glint_core::desc::{AdaptiveDesc, FilterKind, IntegratorDesc, PathDesc, SamplePattern, SamplerKind, SceneDesc};

/// The light-transport algorithm a caller asks for, without its settings: a scene that is
/// already path traced keeps its own path settings when `Path` is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorChoice {
    /// The lecture's recursive Whitted model.
    Whitted,
    /// Unidirectional path tracing.
    Path,
}

/// Settings that replace the scene's; `None` keeps the scene's value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Image width in pixels.
    pub width: Option<u32>,
    /// Image height in pixels.
    pub height: Option<u32>,
    /// Samples per pixel along each axis; it replaces a total the scene set with `spp`
    /// and the scene's adaptive sampling.
    pub samples: Option<u32>,
    /// Samples per pixel in total, for any integrator; wins over `samples`, and replaces
    /// the scene's adaptive sampling.
    pub spp: Option<u32>,
    /// The integrator; `Path` keeps a path-traced scene's settings, else takes the defaults.
    pub integrator: Option<IntegratorChoice>,
    /// Depth limit of both integrators; `u32::MAX` is unlimited (path integrator only).
    pub max_depth: Option<u32>,
    /// Path depth from which Russian roulette may end a path (path integrator only).
    pub rr_depth: Option<u32>,
    /// Random-number sequence of the path tracer (path integrator only).
    pub sampler: Option<SamplerKind>,
    /// Where samples go inside each pixel.
    pub pattern: Option<SamplePattern>,
    /// Reconstruction filter.
    pub filter: Option<FilterKind>,
    /// Filter radius in pixels.
    pub filter_radius: Option<f32>,
    /// Adaptive sampling.
    pub adaptive: Option<AdaptiveDesc>,
    /// Seed of every random choice.
    pub seed: Option<u32>,
    /// Which of the file's cameras ([`SceneDesc::views`]) looks, from 0.
    pub camera: Option<usize>,
}

/// A setting that only the path integrator has, asked for while the Whitted one renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathOnly {
    /// An unlimited `max_depth`: the Whitted integrator needs a finite depth.
    UnlimitedMaxDepth,
    /// `rr_depth`.
    RrDepth,
    /// `sampler`.
    Sampler,
}

impl PathOnly {
    /// The setting in the words of the scene format, for messages.
    pub fn setting(self) -> &'static str {
        match self {
            PathOnly::UnlimitedMaxDepth => "an unlimited max_depth",
            PathOnly::RrDepth => "rr_depth",
            PathOnly::Sampler => "sampler",
        }
    }
}

/// Why overrides could not be applied; each front end words it with its own names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum OverrideError {
    /// A path-integrator setting for a scene rendered by the Whitted integrator.
    #[error("{} applies only to the path integrator", .0.setting())]
    PathOnly(PathOnly),
    /// `rr_depth` 0: roulette starts at depth 1 at the earliest.
    #[error("rr_depth must be 1 or more")]
    RrDepthZero,
    /// A camera index past the file's cameras.
    #[error("camera {index} was asked for, but the scene has {count} camera{} (0 to {})", if *.count == 1 { "" } else { "s" }, .count - 1)]
    NoSuchCamera { index: usize, count: usize },
}

impl Overrides {
    /// Writes the overrides into `desc`'s settings.
    ///
    /// # Errors
    ///
    /// [`OverrideError::PathOnly`] when an unlimited `max_depth`, `rr_depth` or `sampler`
    /// is given and the Whitted integrator will render; [`OverrideError::RrDepthZero`].
    pub fn apply(&self, desc: &mut SceneDesc) -> Result<(), OverrideError> {
        if self.rr_depth == Some(0) {
            return Err(OverrideError::RrDepthZero);
        }
        if let Some(index) = self.camera {
            // A file with one camera has no list of views: the camera is view 0.
            let count = desc.views.len().max(1);
            match desc.views.get(index) {
                Some(view) => desc.camera = view.clone(),
                None if index == 0 => {}
                None => return Err(OverrideError::NoSuchCamera { index, count }),
            }
        }
        let s = &mut desc.settings;
        s.width = self.width.unwrap_or(s.width);
        s.height = self.height.unwrap_or(s.height);
        if let Some(samples) = self.samples {
            s.samples_per_axis = samples;
            // An explicit grid replaces the scene's total, or the setting would do nothing.
            s.spp = None;
        }
        s.spp = self.spp.or(s.spp);
        if self.samples.is_some() || self.spp.is_some() {
            // A count asked for is the count rendered: it replaces the scene's adaptive
            // sampling too (unless `adaptive` is also given, just below).
            s.adaptive = None;
        }
        self.apply_integrator(&mut s.integrator);
        match &mut s.integrator {
            IntegratorDesc::Path(path) => self.apply_path(path, &mut s.max_depth),
            IntegratorDesc::Whitted => s.max_depth = self.whitted_depth(s.max_depth)?,
        }
        s.seed = self.seed.unwrap_or(s.seed);
        s.adaptive = self.adaptive.or(s.adaptive);
        s.filter.radius = self.filter_radius.unwrap_or(s.filter.radius);
        s.pattern = self.pattern.unwrap_or(s.pattern);
        s.filter.kind = self.filter.unwrap_or(s.filter.kind);
        Ok(())
    }

    /// Switches the integrator; a path-traced scene asked for `Path` keeps its settings.
    fn apply_integrator(&self, integrator: &mut IntegratorDesc) {
        match (self.integrator, &integrator) {
            (Some(IntegratorChoice::Whitted), _) => *integrator = IntegratorDesc::Whitted,
            (Some(IntegratorChoice::Path), IntegratorDesc::Whitted) => {
                *integrator = IntegratorDesc::Path(PathDesc::default());
            }
            (Some(IntegratorChoice::Path), IntegratorDesc::Path(_)) | (None, _) => {}
        }
    }

    /// The path settings; `whitted_depth` follows a finite `max_depth` too.
    fn apply_path(&self, path: &mut PathDesc, whitted_depth: &mut u32) {
        if let Some(depth) = self.max_depth {
            path.max_depth = depth;
            // The Whitted depth keeps its finite value; an unlimited one would recurse forever.
            if depth != u32::MAX {
                *whitted_depth = depth;
            }
        }
        path.rr_depth = self.rr_depth.unwrap_or(path.rr_depth);
        path.sampler = self.sampler.unwrap_or(path.sampler);
    }

    /// The Whitted depth, refusing the settings only the path integrator has.
    fn whitted_depth(&self, depth: u32) -> Result<u32, OverrideError> {
        if self.max_depth == Some(u32::MAX) {
            return Err(OverrideError::PathOnly(PathOnly::UnlimitedMaxDepth));
        }
        if self.rr_depth.is_some() {
            return Err(OverrideError::PathOnly(PathOnly::RrDepth));
        }
        if self.sampler.is_some() {
            return Err(OverrideError::PathOnly(PathOnly::Sampler));
        }
        Ok(self.max_depth.unwrap_or(depth))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glint_core::desc::AdaptiveDesc;

    fn adaptive_scene() -> SceneDesc {
        let mut desc = SceneDesc::default();
        desc.settings.adaptive = Some(AdaptiveDesc { min_samples: 1, max_samples: 8, threshold: 0.1 });
        desc
    }

    #[test]
    fn a_sample_count_asked_for_replaces_the_scenes_adaptive_sampling() {
        for asked in
            [Overrides { spp: Some(16), ..Default::default() }, Overrides { samples: Some(4), ..Default::default() }]
        {
            let mut desc = adaptive_scene();
            asked.apply(&mut desc).unwrap();
            assert_eq!(desc.settings.adaptive, None);
        }
        // Other overrides keep it, and an adaptive setting given beside a count wins.
        let mut desc = adaptive_scene();
        Overrides { width: Some(64), ..Default::default() }.apply(&mut desc).unwrap();
        assert!(desc.settings.adaptive.is_some());
        let own = AdaptiveDesc { min_samples: 2, max_samples: 32, threshold: 0.01 };
        let mut desc = adaptive_scene();
        Overrides { spp: Some(16), adaptive: Some(own), ..Default::default() }.apply(&mut desc).unwrap();
        assert_eq!(desc.settings.adaptive, Some(own));
    }
}
