//! How the pursuit re-estimates the camera: [`CameraUpdate`] and the least-squares
//! translation.

use camloc_geometry::{GeometryError, Matrix3, WeakPerspective};
use camloc_skeleton::NUM_LANDMARKS;

use crate::is_positive_finite;
use camloc_skeleton::rms_radius;

/// How the camera is re-estimated.
#[derive(Clone, Copy, Debug)]
pub(super) enum CameraUpdate {
    /// Procrustes (eq. 3), rotation free.
    Procrustes,
    /// Rotation fixed; least-squares scale and translation.
    Fixed(Matrix3),
}

impl CameraUpdate {
    /// The camera the pursuit starts from for the mean pose `points3`: this update's fit or,
    /// when a fixed rotation admits no positive least-squares scale (the input seen turned
    /// against the mean pose), that rotation with the scale that matches the two poses' RMS
    /// radii and the least-squares translation. Fails with the fit's error when no such
    /// scale exists either.
    pub(super) fn start(
        self,
        points3: &[[f64; 3]; NUM_LANDMARKS],
        points2: &[[f64; 2]; NUM_LANDMARKS],
    ) -> Result<WeakPerspective, GeometryError> {
        let fitted = self.fit(points3, points2);
        let (Err(GeometryError::Degenerate(_)), CameraUpdate::Fixed(rotation)) = (&fitted, self)
        else {
            return fitted;
        };
        let flat = WeakPerspective::orthographic(rotation);
        let scale = rms_radius(points2) / rms_radius(&flat.project(points3));
        if !is_positive_finite(scale) {
            return fitted;
        }
        let camera = WeakPerspective { scale, ..flat };
        Ok(with_optimal_translation(&camera, points3, points2))
    }

    /// This update's fit or, where it fails (a degenerate pose, no positive scale), `current`
    /// with the least-squares translation: as in `alternate`, a failed update keeps the camera.
    pub(super) fn fit_or_keep(
        self,
        current: &WeakPerspective,
        points3: &[[f64; 3]; NUM_LANDMARKS],
        points2: &[[f64; 2]; NUM_LANDMARKS],
    ) -> WeakPerspective {
        self.fit(points3, points2)
            .unwrap_or_else(|_| with_optimal_translation(current, points3, points2))
    }

    pub(super) fn fit(
        self,
        points3: &[[f64; 3]; NUM_LANDMARKS],
        points2: &[[f64; 2]; NUM_LANDMARKS],
    ) -> Result<WeakPerspective, GeometryError> {
        match self {
            CameraUpdate::Procrustes => camloc_geometry::procrustes_camera(points3, points2),
            CameraUpdate::Fixed(r) => WeakPerspective::fit_with_rotation(r, points3, points2),
        }
    }
}

/// The camera with the same scale and rotation and the least-squares translation for
/// `points3` -> `points2` (maps the projected 3D centroid onto the 2D centroid).
pub(super) fn with_optimal_translation(
    camera: &WeakPerspective,
    points3: &[[f64; 3]; NUM_LANDMARKS],
    points2: &[[f64; 2]; NUM_LANDMARKS],
) -> WeakPerspective {
    let centred = WeakPerspective {
        translation: [0.0, 0.0],
        ..*camera
    };
    let n = NUM_LANDMARKS as f64;
    let mut t = [0.0; 2];
    for (p, l) in centred.project(points3).iter().zip(points2) {
        t[0] += (l[0] - p[0]) / n;
        t[1] += (l[1] - p[1]) / n;
    }
    WeakPerspective {
        translation: t,
        ..*camera
    }
}
