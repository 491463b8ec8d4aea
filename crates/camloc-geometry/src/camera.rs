//! Projection models: weak perspective (eq. 2) and full perspective.

use serde::{Deserialize, Serialize};

use crate::{GeometryError, Matrix3, Vector3};

/// Weak-perspective (scaled orthographic) camera, eq. 2 with one scale:
/// `L = s [I2 0] R X + t`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WeakPerspective {
    /// Scale `s`, image units per metre.
    pub scale: f64,
    /// Rotation `R` (rows: camera x, y, z axes in world coordinates).
    pub rotation: Matrix3,
    /// Image translation `t`, image units.
    pub translation: [f64; 2],
}

impl WeakPerspective {
    /// Orthographic camera with rotation `rotation`, unit scale and no translation.
    pub fn orthographic(rotation: Matrix3) -> Self {
        WeakPerspective {
            scale: 1.0,
            rotation,
            translation: [0.0, 0.0],
        }
    }

    /// Projects one world point (metres) to image coordinates.
    pub fn project_point(&self, x: [f64; 3]) -> [f64; 2] {
        let p = self.rotation * Vector3::from(x);
        [
            self.scale * p.x + self.translation[0],
            self.scale * p.y + self.translation[1],
        ]
    }

    /// Projects `N` world points (metres) to image coordinates.
    pub fn project<const N: usize>(&self, points: &[[f64; 3]; N]) -> [[f64; 2]; N] {
        points.map(|x| self.project_point(x))
    }

    /// Sum of squared distances between the projection of `points3` and `points2` (image
    /// units squared); the quantity eq. 6 minimises.
    ///
    /// # Errors
    /// [`GeometryError::Size`] when the slices differ in length.
    pub fn squared_error(
        &self,
        points3: &[[f64; 3]],
        points2: &[[f64; 2]],
    ) -> Result<f64, GeometryError> {
        check_same_len(points3.len(), points2.len())?;
        Ok(points3
            .iter()
            .zip(points2)
            .map(|(x, l)| {
                let p = self.project_point(*x);
                (p[0] - l[0]).powi(2) + (p[1] - l[1]).powi(2)
            })
            .sum())
    }

    /// Least-squares scale and translation for a fixed `rotation`: the camera the paper's
    /// section 8.2 uses when the rotation comes from the classifier. The scale is positive:
    /// a negative one would turn the image by 180 degrees, i.e. change the rotation.
    ///
    /// # Errors
    /// [`GeometryError::Size`] on mismatched or empty input, [`GeometryError::NonFinite`] for
    /// NaN/inf, [`GeometryError::Degenerate`] when the rotated points all project to one point
    /// or when no positive scale fits (their centred projection is anti-correlated with the
    /// centred image points).
    pub fn fit_with_rotation(
        rotation: Matrix3,
        points3: &[[f64; 3]],
        points2: &[[f64; 2]],
    ) -> Result<WeakPerspective, GeometryError> {
        check_same_len(points3.len(), points2.len())?;
        check_finite(points3, points2)?;
        let projected: Vec<[f64; 2]> = points3
            .iter()
            .map(|x| {
                let p = rotation * Vector3::from(*x);
                [p.x, p.y]
            })
            .collect();
        let (pm, lm) = (mean2(&projected), mean2(points2));
        let (mut num, mut den) = (0.0, 0.0);
        for (p, l) in projected.iter().zip(points2) {
            let (px, py) = (p[0] - pm[0], p[1] - pm[1]);
            num += px * (l[0] - lm[0]) + py * (l[1] - lm[1]);
            den += px * px + py * py;
        }
        if !(den > 0.0) {
            return Err(GeometryError::Degenerate(
                "the rotated 3D points project to a single image point",
            ));
        }
        let scale = num / den;
        if !(scale > 0.0) {
            return Err(GeometryError::Degenerate(
                "no positive scale fits: the rotated 3D points project anti-correlated with the image points",
            ));
        }
        Ok(WeakPerspective {
            scale,
            rotation,
            translation: [lm[0] - scale * pm[0], lm[1] - scale * pm[1]],
        })
    }
}

/// Full perspective (pinhole) camera: `Xc = R (X - c)`, `u = f Xc / Zc`, `v = f Yc / Zc`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Perspective {
    /// Rotation `R` (rows: camera x, y, z axes in world coordinates).
    pub rotation: Matrix3,
    /// Camera centre `c` in world coordinates, metres.
    pub centre: Vector3,
    /// Focal length `f`, image units per unit of normalised image coordinate.
    pub focal: f64,
}

impl Perspective {
    /// Projects one world point (metres) to image coordinates.
    ///
    /// # Errors
    /// [`GeometryError::BehindCamera`] (with `index` 0) when the point is not in front of the
    /// camera.
    pub fn project_point(&self, x: [f64; 3]) -> Result<[f64; 2], GeometryError> {
        self.project_indexed(0, x)
    }

    fn project_indexed(&self, index: usize, x: [f64; 3]) -> Result<[f64; 2], GeometryError> {
        let p = self.rotation * (Vector3::from(x) - self.centre);
        if !(p.z > 1e-9) {
            return Err(GeometryError::BehindCamera { index, depth: p.z });
        }
        Ok([self.focal * p.x / p.z, self.focal * p.y / p.z])
    }

    /// Projects `N` world points (metres) to image coordinates.
    ///
    /// # Errors
    /// [`GeometryError::BehindCamera`] naming the first point that is not in front of the camera.
    pub fn project<const N: usize>(
        &self,
        points: &[[f64; 3]; N],
    ) -> Result<[[f64; 2]; N], GeometryError> {
        let mut out = [[0.0; 2]; N];
        for (i, (o, x)) in out.iter_mut().zip(points).enumerate() {
            *o = self.project_indexed(i, *x)?;
        }
        Ok(out)
    }
}

pub(crate) fn check_same_len(n3: usize, n2: usize) -> Result<(), GeometryError> {
    if n3 != n2 || n3 == 0 {
        return Err(GeometryError::Size {
            what: "2D points",
            expected: format!("as many as the {n3} 3D points (at least one)"),
            got: n2,
        });
    }
    Ok(())
}

pub(crate) fn check_finite(
    points3: &[[f64; 3]],
    points2: &[[f64; 2]],
) -> Result<(), GeometryError> {
    if !points3.iter().flatten().all(|c| c.is_finite()) {
        return Err(GeometryError::NonFinite { what: "3D points" });
    }
    if !points2.iter().flatten().all(|c| c.is_finite()) {
        return Err(GeometryError::NonFinite { what: "2D points" });
    }
    Ok(())
}

pub(crate) fn mean2(points: &[[f64; 2]]) -> [f64; 2] {
    let n = points.len().max(1) as f64;
    let s = points
        .iter()
        .fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
    [s[0] / n, s[1] / n]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{look_at_origin, rotation_about_axis, sphere_point};
    use proptest::prelude::*;

    fn cloud() -> [[f64; 3]; 6] {
        [
            [0.0, 0.0, 0.0],
            [0.1, -0.2, 0.9],
            [-0.3, 0.25, 0.4],
            [0.2, 0.1, -0.8],
            [0.05, -0.3, -0.1],
            [-0.2, 0.2, 1.3],
        ]
    }

    proptest! {
        /// Rotating the body by Q and the camera by Q^T gives the same image: projection of a
        /// rotated pose equals projection through the composed rotation.
        #[test]
        fn projection_commutes_with_rotation(ax in -1.0f64..1.0, ay in -1.0f64..1.0,
                                             az in 0.1f64..1.0, angle in -3.0f64..3.0,
                                             s in 0.1f64..10.0, tx in -5.0f64..5.0) {
            let q = rotation_about_axis(Vector3::new(ax, ay, az), angle);
            let cam = WeakPerspective { scale: s, rotation: look_at_origin(sphere_point(30.0, 20.0, 1.0)).unwrap(), translation: [tx, -tx] };
            let rotated: [[f64; 3]; 6] = cloud().map(|x| (q * Vector3::from(x)).into());
            let composed = WeakPerspective { rotation: cam.rotation * q, ..cam };
            let a = cam.project(&rotated);
            let b = composed.project(&cloud());
            for (p, r) in a.iter().zip(&b) {
                prop_assert!((p[0] - r[0]).abs() < 1e-12 && (p[1] - r[1]).abs() < 1e-12);
            }
            // A rotation about the optical axis rotates the image about the principal point.
            let roll = crate::roll_about_optical_axis(&cam.rotation, angle);
            let rolled = WeakPerspective { rotation: roll, translation: [0.0, 0.0], ..cam };
            let flat = WeakPerspective { translation: [0.0, 0.0], ..cam };
            let (c, sn) = (angle.cos(), angle.sin());
            for (p, r) in flat.project(&cloud()).iter().zip(rolled.project(&cloud())) {
                prop_assert!((c * p[0] + sn * p[1] - r[0]).abs() < 1e-12);
                prop_assert!((-sn * p[0] + c * p[1] - r[1]).abs() < 1e-12);
            }
        }

        #[test]
        fn fit_with_rotation_recovers_scale_and_translation(s in 0.01f64..100.0,
                                                            tx in -50.0f64..50.0, ty in -50.0f64..50.0) {
            let r = look_at_origin(sphere_point(200.0, -30.0, 1.0)).unwrap();
            let cam = WeakPerspective { scale: s, rotation: r, translation: [tx, ty] };
            let fit = WeakPerspective::fit_with_rotation(r, &cloud(), &cam.project(&cloud())).unwrap();
            prop_assert!((fit.scale - s).abs() < 1e-9 * s.max(1.0));
            prop_assert!((fit.translation[0] - tx).abs() < 1e-9 && (fit.translation[1] - ty).abs() < 1e-9);
        }
    }

    #[test]
    fn perspective_matches_weak_perspective_far_away() {
        let r = look_at_origin(sphere_point(180.0, 0.0, 1.0)).unwrap();
        let far = 1e6;
        let p = Perspective {
            rotation: r,
            centre: sphere_point(180.0, 0.0, far),
            focal: far,
        };
        let wp = WeakPerspective::orthographic(r);
        for (a, b) in p
            .project(&cloud())
            .unwrap()
            .iter()
            .zip(wp.project(&cloud()))
        {
            assert!((a[0] - b[0]).abs() < 1e-5 && (a[1] - b[1]).abs() < 1e-5);
        }
        let behind = Perspective {
            centre: sphere_point(180.0, 0.0, 0.5),
            focal: 1.0,
            rotation: r,
        };
        assert!(matches!(
            behind.project(&[[-1.0, 0.0, 0.0]]),
            Err(GeometryError::BehindCamera { index: 0, .. })
        ));
    }

    #[test]
    fn an_image_turned_by_half_a_turn_has_no_positive_scale() {
        let r = look_at_origin(sphere_point(200.0, -30.0, 1.0)).unwrap();
        let cam = WeakPerspective {
            scale: 3.0,
            rotation: r,
            translation: [1.0, 2.0],
        };
        let turned = cam.project(&cloud()).map(|p| [-p[0], -p[1]]);
        assert!(matches!(
            WeakPerspective::fit_with_rotation(r, &cloud(), &turned),
            Err(GeometryError::Degenerate(_))
        ));
    }

    #[test]
    fn bad_sizes_and_nan_are_errors() {
        let r = Matrix3::identity();
        assert!(WeakPerspective::fit_with_rotation(r, &cloud(), &[[0.0, 0.0]]).is_err());
        let mut l = [[0.0; 2]; 6];
        l[3][1] = f64::NAN;
        assert!(matches!(
            WeakPerspective::fit_with_rotation(r, &cloud(), &l),
            Err(GeometryError::NonFinite { .. })
        ));
    }
}
