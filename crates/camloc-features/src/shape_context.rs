//! Log-polar shape-context histogram centred on one key point.

use serde::{Deserialize, Serialize};

/// Bins of a log-polar histogram: radii in torso lengths, angles in image coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeContextBins {
    /// Number of log-spaced radial bins (>= 1).
    pub radial: usize,
    /// Number of angular bins over the full circle (>= 1).
    pub angular: usize,
    /// Inner edge of the first radial bin, torso lengths (> 0); nearer points count in it.
    pub inner_radius: f64,
    /// Outer edge of the last radial bin, torso lengths (> inner); farther points count in it.
    pub outer_radius: f64,
}

impl Default for ShapeContextBins {
    /// 5 radial x 12 angular bins between 0.125 and 2.5 torso lengths (docs/conventions.md section
    /// 4).
    fn default() -> Self {
        ShapeContextBins {
            radial: 5,
            angular: 12,
            inner_radius: 0.125,
            outer_radius: 2.5,
        }
    }
}

/// The most histogram cells [`ShapeContextBins::is_valid`] accepts (the default has 60): a
/// bound that keeps a forged model's bin counts from overflowing their product.
pub const MAX_SHAPE_CONTEXT_CELLS: usize = 1 << 16;

impl ShapeContextBins {
    /// Number of histogram cells (saturating: invalid bins may have more than `usize::MAX`).
    pub fn len(&self) -> usize {
        self.radial.saturating_mul(self.angular)
    }

    /// `true` when there are no cells (invalid bins).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `true` when the bin counts are positive, with at most [`MAX_SHAPE_CONTEXT_CELLS`]
    /// cells, and the radii finite with `0 < inner < outer`.
    pub fn is_valid(&self) -> bool {
        self.radial > 0
            && self.angular > 0
            && self.len() <= MAX_SHAPE_CONTEXT_CELLS
            && self.inner_radius > 0.0
            && self.outer_radius > self.inner_radius
            && self.outer_radius.is_finite()
    }

    /// Cell of a point at offset `(du, dv)` from the centre, in torso lengths: radial bin by
    /// `log(r)` clamped to the first/last bin, angular bin by `atan2(dv, du)` in `[0, 2 pi)`.
    pub fn cell(&self, du: f64, dv: f64) -> usize {
        let r = du.hypot(dv);
        let t = if r > 0.0 {
            (r / self.inner_radius).ln() / (self.outer_radius / self.inner_radius).ln()
        } else {
            0.0
        };
        let radial = ((t * self.radial as f64).floor().max(0.0) as usize).min(self.radial - 1);
        let angle = dv.atan2(du).rem_euclid(std::f64::consts::TAU);
        let angular =
            ((angle / std::f64::consts::TAU * self.angular as f64) as usize).min(self.angular - 1);
        radial * self.angular + angular
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_cover_radii_and_angles() {
        let b = ShapeContextBins::default();
        assert_eq!(b.cell(0.0, 0.0), 0);
        assert_eq!(b.cell(100.0, 0.0), (b.radial - 1) * b.angular);
        // Angle increases towards +v (image down): a point straight down is a quarter turn.
        assert_eq!(b.cell(0.0, 0.01) % b.angular, b.angular / 4);
        assert_eq!(b.cell(-0.01, 0.0) % b.angular, b.angular / 2);
        // Radial bins are log-spaced: each edge is the previous one times (outer/inner)^(1/5).
        let ratio = (b.outer_radius / b.inner_radius).powf(1.0 / b.radial as f64);
        for k in 0..b.radial {
            let mid = b.inner_radius * ratio.powf(k as f64 + 0.5);
            assert_eq!(b.cell(mid, 0.0) / b.angular, k);
        }
    }

    /// A forged file's bin counts whose product wraps to a plausible cell count (2^62 + 15
    /// times 4 is 60 modulo 2^64) are refused, as are more cells than the bound.
    #[test]
    fn bin_counts_whose_product_overflows_are_invalid() {
        let wrapped = ShapeContextBins {
            radial: (1 << 62) + 15,
            angular: 4,
            ..ShapeContextBins::default()
        };
        assert_eq!(wrapped.len(), usize::MAX);
        assert!(!wrapped.is_valid());
        let many = ShapeContextBins {
            radial: MAX_SHAPE_CONTEXT_CELLS + 1,
            angular: 1,
            ..ShapeContextBins::default()
        };
        assert!(!many.is_valid());
        assert!(ShapeContextBins::default().is_valid());
    }
}
