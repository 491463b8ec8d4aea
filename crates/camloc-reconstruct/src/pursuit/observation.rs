//! The 2D input normalised for the pursuit.

use camloc_geometry::WeakPerspective;
use camloc_skeleton::{NUM_LANDMARKS, Pose2, centroid, rms_radius};

use crate::{Intrinsics, ReconstructError, check_finite_landmarks, is_positive_finite};

/// Number of image coordinates of a pose (15 landmarks x 2).
pub(super) const IMAGE_DIM: usize = 2 * NUM_LANDMARKS;

/// The 2D input, centred on its centroid and divided by its RMS radius, so that every
/// tolerance is unit-free.
pub(super) struct Observation {
    pub(super) points: [[f64; 2]; NUM_LANDMARKS],
    centroid: [f64; 2],
    pub(super) scale: f64,
}

impl Observation {
    pub(super) fn new(pose: &Pose2) -> Result<Observation, ReconstructError> {
        check_finite_landmarks(pose)?;
        // Extreme magnitudes (1e154, 1e-200, ...) are first brought into range by an exact
        // power of two `factor` (1 for ordinary poses), so that the squares below neither
        // overflow nor underflow; centroid and scale are mapped back at the end.
        let (pose, factor) = pose.within_safe_range();
        let centroid = centroid(&pose.points);
        let centred = pose
            .points
            .map(|p| [p[0] - centroid[0], p[1] - centroid[1]]);
        let scale = rms_radius(&pose.points);
        if !is_positive_finite(scale) {
            return Err(ReconstructError::DegenerateInput("all landmarks coincide"));
        }
        let has_torso = pose.torso_length() > 1e-9 * scale;
        if !has_torso {
            return Err(ReconstructError::DegenerateInput(
                "the torso (pelvis to neck) has zero length",
            ));
        }
        Ok(Observation {
            points: centred.map(|p| [p[0] / scale, p[1] / scale]),
            centroid: [centroid[0] / factor, centroid[1] / factor],
            scale: scale / factor,
        })
    }

    /// Intrinsics in the normalised units: the focal length and the principal point (when the
    /// intrinsics have none, the centre of the bounding box of the points given: those with
    /// bit `i` set in `imputed` were filled in and are left out, unless all were).
    pub(super) fn normalise_intrinsics(
        &self,
        intrinsics: &Intrinsics,
        imputed: u16,
    ) -> (f64, [f64; 2]) {
        let given = |i: usize| imputed & (1 << i) == 0;
        let all = (0..self.points.len()).all(|i| !given(i));
        let principal = match intrinsics.principal_point {
            Some(c) => [
                (c[0] - self.centroid[0]) / self.scale,
                (c[1] - self.centroid[1]) / self.scale,
            ],
            None => std::array::from_fn(|k| {
                let (lo, hi) = (self.points.iter().enumerate())
                    .filter(|(i, _)| all || given(*i))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, p)| {
                        (lo.min(p[k]), hi.max(p[k]))
                    });
                0.5 * (lo + hi)
            }),
        };
        (intrinsics.focal_px / self.scale, principal)
    }

    /// A normalised image point in the input's image units.
    pub(super) fn denormalise_point(&self, p: [f64; 2]) -> [f64; 2] {
        [
            p[0] * self.scale + self.centroid[0],
            p[1] * self.scale + self.centroid[1],
        ]
    }

    /// A camera fitted to the normalised points, expressed in the input's image units.
    pub(super) fn denormalise(&self, camera: &WeakPerspective) -> WeakPerspective {
        WeakPerspective {
            scale: camera.scale * self.scale,
            rotation: camera.rotation,
            translation: [
                camera.translation[0] * self.scale + self.centroid[0],
                camera.translation[1] * self.scale + self.centroid[1],
            ],
        }
    }
}
