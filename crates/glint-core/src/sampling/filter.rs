//! Pixel reconstruction filters: each sample is splatted into every pixel its filter
//! touches, and a pixel is the weighted average of the samples it received.

use serde::{Deserialize, Serialize};

/// The filter shapes glint offers, each with a radius in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum FilterKind {
    /// Equal weight inside the radius: 0.5 is the classic "average the pixel's samples".
    Box,
    /// Linear falloff to zero at the radius.
    Tent,
    /// A Gaussian with σ = radius/3, shifted so it reaches zero at the radius.
    Gaussian,
    /// Mitchell–Netravali with B = C = 1/3: sharp with little ringing (negative lobes).
    Mitchell,
    /// Windowed sinc `sinc(x)·sinc(x/r)`: sharpest, rings most.
    Lanczos,
}

/// A separable filter `f(x)·f(y)`, normalized so that it integrates to one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    pub kind: FilterKind,
    pub radius: f32,
    /// `1 / ∫f(x)dx`, applied to each axis.
    scale: f32,
}

impl Filter {
    /// `None` unless the radius is positive and finite (and at most 8 pixels, beyond
    /// which splatting cost explodes for no visible gain).
    pub fn new(kind: FilterKind, radius: f32) -> Option<Self> {
        if !(radius > 0.0 && radius <= 8.0) {
            return None;
        }
        let mut filter = Self { kind, radius, scale: 1.0 };
        // Midpoint rule on a fine grid: exact enough for normalization (the render
        // normalizes by the weight sum anyway; this keeps `eval` meaningful on its own).
        let steps = 4096;
        let dx = 2.0 * radius / steps as f32;
        let integral: f32 = (0..steps).map(|i| filter.eval_1d(-radius + (i as f32 + 0.5) * dx) * dx).sum();
        filter.scale = 1.0 / integral;
        Some(filter)
    }

    /// The weight of a sample at offset (`dx`, `dy`) pixels from a pixel centre.
    /// The factor `eval` applies to make the filter integrate to one, for backends
    /// that evaluate the same formula themselves.
    pub fn normalization(&self) -> f32 {
        self.scale
    }

    /// The box filter's weight anywhere inside it ([`Filter::eval`] there, without the
    /// evaluation): all a sample strictly inside one pixel needs.
    #[inline]
    pub fn box_weight(&self) -> f32 {
        debug_assert_eq!(self.kind, FilterKind::Box);
        self.scale * self.scale
    }

    #[inline]
    pub fn eval(&self, dx: f32, dy: f32) -> f32 {
        self.eval_1d(dx) * self.eval_1d(dy) * self.scale * self.scale
    }

    fn eval_1d(&self, x: f32) -> f32 {
        let r = self.radius;
        let ax = x.abs();
        if ax > r {
            return 0.0;
        }
        match self.kind {
            FilterKind::Box => 1.0,
            FilterKind::Tent => 1.0 - ax / r,
            FilterKind::Gaussian => {
                let sigma = r / 3.0;
                let g = |v: f32| (-v * v / (2.0 * sigma * sigma)).exp();
                (g(ax) - g(r)).max(0.0)
            }
            FilterKind::Mitchell => mitchell(2.0 * ax / r, 1.0 / 3.0, 1.0 / 3.0),
            FilterKind::Lanczos => sinc(ax) * sinc(ax / r),
        }
    }
}

/// Mitchell & Netravali (1988), "Reconstruction Filters in Computer Graphics", for
/// `x` in [0, 2].
fn mitchell(x: f32, b: f32, c: f32) -> f32 {
    let x2 = x * x;
    let x3 = x2 * x;
    let value = if x < 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x3 + (-18.0 + 12.0 * b + 6.0 * c) * x2 + (6.0 - 2.0 * b)
    } else {
        (-b - 6.0 * c) * x3 + (6.0 * b + 30.0 * c) * x2 + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)
    };
    value / 6.0
}

fn sinc(x: f32) -> f32 {
    if x.abs() < 1e-5 {
        return 1.0;
    }
    let px = std::f32::consts::PI * x;
    px.sin() / px
}

#[cfg(test)]
mod tests {
    use super::*;

    const KINDS: [FilterKind; 5] =
        [FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell, FilterKind::Lanczos];

    #[test]
    fn every_filter_integrates_to_one_in_two_dimensions() {
        for kind in KINDS {
            for radius in [0.5f32, 1.0, 2.0, 3.0] {
                let f = Filter::new(kind, radius).unwrap();
                let n = 400;
                let d = 2.0 * radius / n as f32;
                let mut sum = 0.0f64;
                for i in 0..n {
                    for j in 0..n {
                        let x = -radius + (i as f32 + 0.5) * d;
                        let y = -radius + (j as f32 + 0.5) * d;
                        sum += (f.eval(x, y) * d * d) as f64;
                    }
                }
                assert!((sum - 1.0).abs() < 2e-3, "{kind:?} r={radius}: {sum}");
            }
        }
    }

    #[test]
    fn filters_vanish_outside_their_radius_and_peak_at_the_centre() {
        for kind in KINDS {
            let f = Filter::new(kind, 2.0).unwrap();
            assert_eq!(f.eval(2.01, 0.0), 0.0);
            assert!(f.eval(0.0, 0.0) >= f.eval(0.7, 0.3), "{kind:?}");
        }
        // Mitchell and Lanczos have negative lobes; the others never go negative.
        assert!(Filter::new(FilterKind::Mitchell, 2.0).unwrap().eval(1.6, 0.0) < 0.0);
        assert!(Filter::new(FilterKind::Lanczos, 3.0).unwrap().eval(1.5, 0.0) < 0.0);
        assert!(Filter::new(FilterKind::Box, 0.0).is_none());
    }
}
