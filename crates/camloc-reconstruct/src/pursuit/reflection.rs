//! The depth-reflected hypothesis: the pose mirrored in depth, projected back onto the basis.

use camloc_geometry::{Matrix3, Vector3};
use camloc_skeleton::NUM_LANDMARKS;
use nalgebra::{DMatrix, DVector};

use super::camera_update::CameraUpdate;
use super::greedy::Fit;
use super::observation::Observation;
use super::reconstructor::Reconstructor;
use crate::ReconstructError;
use crate::basis::POSE_DIM;

impl Reconstructor {
    /// Start of the depth-reflected hypothesis (see [`Reconstructor::reconstruct`]).
    pub(super) fn reflected_start(
        &self,
        obs: &Observation,
        fit: &Fit,
        update: CameraUpdate,
    ) -> Result<Fit, ReconstructError> {
        let reflected = depth_reflection(&fit.points, &fit.camera.rotation);
        let residual = DVector::from_iterator(POSE_DIM, reflected.iter().flatten().copied())
            - self.basis.mean_vector();
        let full = self.basis.components().transpose() * &residual;
        let mut order: Vec<usize> = (0..full.len()).collect();
        order.sort_by(|&i, &j| full[j].abs().total_cmp(&full[i].abs()));
        let selected: Vec<usize> = order.into_iter().take(fit.selected.len().max(1)).collect();
        let a = DMatrix::from_fn(POSE_DIM, selected.len(), |r, c| {
            self.basis.components()[(r, selected[c])]
        });
        let solution = self.constraint(&selected)?.solve(&a, &residual)?;
        let coefficients: Vec<f64> = solution.w.iter().copied().collect();
        let points = self.points(&selected, &coefficients);
        let camera = update.fit_or_keep(&fit.camera, &points, &obs.points);
        Ok(Fit {
            error: camera.squared_error(&points, &obs.points)?,
            selected,
            coefficients,
            points,
            camera,
            iterations: 0,
            multiplier: fit.multiplier,
        })
    }
}

/// Reflects `points` in the plane through the origin orthogonal to the optical axis (row 3 of
/// `rotation`): `x -> x - 2 (r3 . x) r3`. A weak-perspective camera with this rotation sees the
/// reflected points exactly where it sees the originals, since the reflection only negates
/// their depth `r3 . x`.
pub(super) fn depth_reflection(
    points: &[[f64; 3]; NUM_LANDMARKS],
    rotation: &Matrix3,
) -> [[f64; 3]; NUM_LANDMARKS] {
    let axis: Vector3 = rotation.row(2).transpose();
    points.map(|p| {
        let x = Vector3::from(p);
        (x - axis * (2.0 * axis.dot(&x))).into()
    })
}
