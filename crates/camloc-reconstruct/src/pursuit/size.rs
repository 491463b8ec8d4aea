//! [`Reconstruction::resize`]: the pose and its cameras scaled together, so that the person
//! has another size and every landmark is seen where it was (a person `k` times as large,
//! `k` times as far from the camera, looks the same).

use crate::{BoneLengthError, BoneLengths};

use super::hypotheses::Reconstruction;

impl Reconstruction {
    /// Scales the pose by `factor` (finite and positive) about its pelvis, and the cameras so
    /// that its image is unchanged: the weak-perspective scale is divided by `factor`, the
    /// perspective camera's translation (the pelvis in the camera frame, metres) multiplied by
    /// it. The pursuit's [`coefficients`](Self::coefficients) stay at the basis's size.
    pub fn resize(&mut self, factor: f64) {
        let pelvis = self.pose.points[0];
        for point in &mut self.pose.points {
            *point = std::array::from_fn(|a| pelvis[a] + (point[a] - pelvis[a]) * factor);
        }
        self.camera.scale /= factor;
        if let Some(perspective) = &mut self.perspective {
            perspective.translation = perspective.translation.map(|t| t * factor);
        }
    }

    /// [`resize`](Self::resize)s the reconstruction so that the person is `height_m` tall
    /// standing ([`BoneLengths::standing_height_m`] of its pose's limbs), returning the
    /// factor it was scaled by.
    ///
    /// # Errors
    /// [`BoneLengthError`] when the pose's limbs are not plausible bone lengths (then nothing
    /// changes).
    pub fn resize_to_height(&mut self, height_m: f64) -> Result<f64, BoneLengthError> {
        let factor = height_m / BoneLengths::of_pose(&self.pose)?.standing_height_m();
        self.resize(factor);
        Ok(factor)
    }
}
