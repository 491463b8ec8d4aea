//! How well the bone lengths given for a person fit the person's frames ([`LengthsFit`]),
//! against the lengths estimated from those frames: another person's file, limbs swapped or
//! lengths in another unit fit the image worse, and nothing else says so.

/// How many times the estimated lengths' reprojection error the given lengths' must reach for
/// [`LengthsFit::is_poor`]. On a simulated animator's views of CMU actors (6 clips of 5
/// actors, 25-299 frames, four cameras: front, side, back, 2 m up at 45 deg; 2 px noise), a
/// temporary build printing the ratio gave each actor's own lengths 0.95-1.12 times (24 runs)
/// and the thighs and forearms swapped 4.9-12.7 times on one actor's four views; a reviewer
/// measured from the JSON's errors 0.96-1.15 on the own lengths (48 runs, with and without
/// the focal length), another actor's lengths 1.01-4.10 (96 runs, 69% at 1.5 or more), the
/// swapped file 2.9-12.8 (23 of 24 runs). docs/measured.md.
pub const POOR_LENGTHS_FIT_RATIO: f64 = 1.5;

/// The median over a person's frames of the reprojection error of their reconstruction with
/// the bone lengths given, and of a reconstruction of the same frames with the lengths
/// estimated from them (input image units, `Reconstruction::projection_error`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LengthsFit {
    /// Frames both reconstructions have (with a finite error).
    pub frames: usize,
    /// Median reprojection error with the lengths given.
    pub given: f64,
    /// Median reprojection error with the lengths estimated.
    pub estimated: f64,
}

impl LengthsFit {
    /// The fit of `pairs` (per frame, the error with the given lengths and with the estimated
    /// ones; `None` where either has none); `None` without a frame that has both.
    pub fn of(pairs: impl Iterator<Item = Option<(f64, f64)>>) -> Option<LengthsFit> {
        let (mut given, mut estimated): (Vec<f64>, Vec<f64>) = pairs
            .flatten()
            .filter(|(g, e)| g.is_finite() && e.is_finite())
            .unzip();
        Some(LengthsFit {
            frames: given.len(),
            given: camloc_reconstruct::median(&mut given)?,
            estimated: camloc_reconstruct::median(&mut estimated)?,
        })
    }

    /// Whether the given lengths fit [`POOR_LENGTHS_FIT_RATIO`] times worse or more than the
    /// estimated ones.
    pub fn is_poor(&self) -> bool {
        self.given >= POOR_LENGTHS_FIT_RATIO * self.estimated && self.given > 0.0
    }

    /// `None` unless [`is_poor`](Self::is_poor); else e.g. `the bone lengths given fit its 90
    /// frames worse than lengths estimated from them (median reprojection error 14.1 against
    /// 4.9, image units): another person's, limbs swapped, another unit, or lengths of a
    /// skeleton whose neck, pelvis and head are placed otherwise ...?`.
    pub fn warning(&self) -> Option<String> {
        self.is_poor().then(|| {
            format!(
                "the bone lengths given fit its {} frames worse than lengths estimated from them \
                 (median reprojection error {:.1} against {:.1}, image units): another person's, \
                 limbs swapped, another unit, or lengths of a skeleton whose neck, pelvis and \
                 head are placed otherwise than the input's (a detector's neck and pelvis at the \
                 shoulders' and hips' midpoints: docs/keypoints.md)?",
                self.frames, self.given, self.estimated
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_that_fit_twice_worse_are_poor() {
        let fit = |g: f64, e: f64| LengthsFit::of([Some((g, e)), None].into_iter()).unwrap();
        assert!(fit(14.1, 4.9).is_poor());
        assert!(fit(14.1, 4.9).warning().unwrap().contains("its 1 frames"));
        assert!(!fit(5.3, 4.9).is_poor());
        assert_eq!(fit(5.3, 4.9).warning(), None);
        assert!(!fit(0.0, 0.0).is_poor());
        assert_eq!(
            LengthsFit::of([None, Some((f64::NAN, 1.0))].into_iter()),
            None
        );
    }
}
