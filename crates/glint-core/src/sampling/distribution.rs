//! Piecewise-constant distributions: choosing lights by power and environment-map
//! texels by brightness, with exact pdfs for multiple importance sampling.

use glam::Vec2;

/// A discrete/piecewise-constant distribution over `n` equal bins of [0, 1), sampled by
/// inverting its cumulative sum.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Distribution1D {
    /// The non-negative weights as given.
    pub weights: Vec<f32>,
    /// `cdf[i]` = Σ_{j<i} weight_j / total; `n + 1` entries, the last exactly 1.
    cdf: Vec<f32>,
    /// Σ weights.
    pub total: f32,
}

impl Distribution1D {
    /// `None` when every weight is zero (nothing to sample) or one is negative or not
    /// finite.
    pub fn new(weights: Vec<f32>) -> Option<Self> {
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return None;
        }
        // Partial sums in f64, normalized once: bins of zero weight get exactly zero width
        // (trailing ones included), so they can never be chosen.
        let mut partial = Vec::with_capacity(weights.len() + 1);
        let mut sum = 0.0f64;
        partial.push(0.0f64);
        for &w in &weights {
            sum += w as f64;
            partial.push(sum);
        }
        if sum.is_nan() || sum <= 0.0 {
            return None;
        }
        let cdf: Vec<f32> = partial.iter().map(|&p| (p / sum) as f32).collect();
        Some(Self { weights, cdf, total: sum as f32 })
    }

    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// The normalized partial sums, `len() + 1` of them from 0 to 1: what a GPU
    /// backend uploads to sample the same bins by the same search.
    pub fn cdf(&self) -> &[f32] {
        &self.cdf
    }

    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// The probability of choosing bin `i`.
    #[inline]
    pub fn probability(&self, i: usize) -> f32 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// A bin drawn with probability ∝ its weight, and `u` rescaled to [0, 1) within it
    /// (a fresh number for the next choice).
    #[inline]
    pub fn sample_discrete(&self, u: f32) -> (usize, f32) {
        // The last bin whose cdf start is ≤ u, skipping zero-width bins.
        let i = self.cdf.partition_point(|&c| c <= u).saturating_sub(1).min(self.len() - 1);
        let width = self.probability(i);
        let rescaled = if width > 0.0 { ((u - self.cdf[i]) / width).clamp(0.0, 0.999_999_94) } else { 0.5 };
        (i, rescaled)
    }

    /// A point of [0, 1) distributed as the piecewise-constant density, its density, and
    /// its bin.
    #[inline]
    pub fn sample_continuous(&self, u: f32) -> (f32, f32, usize) {
        let (i, within) = self.sample_discrete(u);
        let n = self.len() as f32;
        let x = ((i as f32 + within) / n).min(0.999_999_94);
        (x, self.probability(i) * n, i)
    }

    /// The density at `x` in [0, 1).
    #[inline]
    pub fn density(&self, x: f32) -> f32 {
        let n = self.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.probability(i) * n as f32
    }
}

/// A piecewise-constant density over [0, 1)²: a marginal over rows and, per row, a
/// conditional over columns (Pharr, Jakob & Humphreys, PBRT 4th ed., §A.5).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Distribution2D {
    rows: Vec<Distribution1D>,
    marginal: Distribution1D,
    width: usize,
}

impl Distribution2D {
    /// From `width`×`height` non-negative weights, row 0 first; `None` if all are zero.
    /// Rows of zeros get a uniform conditional (they are never chosen).
    pub fn new(weights: &[f32], width: usize, height: usize) -> Option<Self> {
        if width == 0 || height == 0 || weights.len() != width * height {
            return None;
        }
        let rows: Vec<Distribution1D> = weights
            .chunks(width)
            .map(|row| Distribution1D::new(row.to_vec()).or_else(|| Distribution1D::new(vec![1.0; width])))
            .collect::<Option<_>>()?;
        let row_sums: Vec<f32> = weights.chunks(width).map(|row| row.iter().sum()).collect();
        let marginal = Distribution1D::new(row_sums)?;
        Some(Self { rows, marginal, width })
    }

    /// A point of [0, 1)² (x along a row, y across rows) and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (y, pdf_y, row) = self.marginal.sample_continuous(u.y);
        let (x, pdf_x, _) = self.rows[row].sample_continuous(u.x);
        (Vec2::new(x, y), pdf_x * pdf_y)
    }

    /// The density at `p` in [0, 1)².
    pub fn density(&self, p: Vec2) -> f32 {
        let h = self.rows.len();
        let row = ((p.y * h as f32) as usize).min(h - 1);
        self.marginal.density(p.y) * self.rows[row].density(p.x)
    }

    /// Columns per row.
    /// The distribution over rows, then one distribution per row: the tables a GPU
    /// backend uploads.
    pub fn parts(&self) -> (&Distribution1D, &[Distribution1D]) {
        (&self.marginal, &self.rows)
    }

    pub fn width(&self) -> usize {
        self.width
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn discrete_choices_follow_the_weights() {
        let d = Distribution1D::new(vec![1.0, 0.0, 3.0, 4.0]).unwrap();
        assert_eq!(d.probability(1), 0.0);
        assert!((d.probability(3) - 0.5).abs() < 1e-6);
        let mut counts = [0u32; 4];
        let mut rng = Rng::new(1);
        let n = 80_000;
        for _ in 0..n {
            let (i, rest) = d.sample_discrete(rng.next_f32());
            assert!((0.0..1.0).contains(&rest));
            counts[i] += 1;
        }
        assert_eq!(counts[1], 0);
        for (i, &c) in counts.iter().enumerate() {
            assert!((c as f32 / n as f32 - d.probability(i)).abs() < 0.01, "{i}: {c}");
        }
        assert!(Distribution1D::new(vec![0.0, 0.0]).is_none());
        // Zero weights after the last positive one are never chosen, whatever the rounding.
        let tail = Distribution1D::new(vec![0.1, 0.7, 0.3, 0.0, 0.0]).unwrap();
        assert_eq!((tail.probability(3), tail.probability(4)), (0.0, 0.0));
        assert_eq!(tail.sample_discrete(0.999_999_94).0, 2);
        assert!(Distribution1D::new(vec![1.0, f32::NAN]).is_none());
    }

    #[test]
    fn two_dimensional_density_integrates_to_one_and_matches_samples() {
        let (w, h) = (8, 4);
        let weights: Vec<f32> = (0..w * h).map(|i| ((i * 7) % 5) as f32).collect();
        let d = Distribution2D::new(&weights, w, h).unwrap();
        // ∫ density = 1 (midpoints of every cell).
        let integral: f32 = (0..w * h)
            .map(|i| d.density(Vec2::new(((i % w) as f32 + 0.5) / w as f32, ((i / w) as f32 + 0.5) / h as f32)))
            .sum::<f32>()
            / (w * h) as f32;
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        // Sampled points land in cells in proportion to their weights, with the
        // density the sampler reports.
        let total: f32 = weights.iter().sum();
        let mut counts = vec![0u32; w * h];
        let mut rng = Rng::new(9);
        let n = 200_000;
        for _ in 0..n {
            let (p, pdf) = d.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            let cell = (p.y * h as f32) as usize * w + (p.x * w as f32) as usize;
            assert!((pdf - d.density(p)).abs() < 1e-4 * pdf.max(1.0));
            counts[cell] += 1;
        }
        for (i, &c) in counts.iter().enumerate() {
            assert!((c as f32 / n as f32 - weights[i] / total).abs() < 0.005, "cell {i}");
        }
    }
}
