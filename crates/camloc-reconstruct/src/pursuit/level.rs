//! [`Reconstruction::level_to_elevation`]: the pose and its cameras turned together about the
//! camera's horizontal axis, so that the camera stands at a given elevation above the body's
//! horizontal plane (the image is unchanged).

use camloc_geometry::{Vector3, rotation_between};

use super::hypotheses::Reconstruction;

/// How far, in azimuth, the camera may stand from a viewpoint for
/// [`Reconstruction::level_to_viewpoint`] to take its elevation, degrees: farther, the
/// reconstruction saw the body from the other side and that side's elevation is not its own.
pub const LEVEL_AZIMUTH_AGREEMENT_DEG: f64 = 90.0;

impl Reconstruction {
    /// [`level_to_elevation`](Self::level_to_elevation) to the elevation of the viewpoint
    /// (`azimuth_deg`, `elevation_deg`; degrees, the body frame's azimuth) when the camera's
    /// azimuth lies within [`LEVEL_AZIMUTH_AGREEMENT_DEG`] of its; returns whether it did.
    pub fn level_to_viewpoint(&mut self, azimuth_deg: f64, elevation_deg: f64) -> bool {
        let towards_camera = self.towards_camera();
        let own = towards_camera.y.atan2(towards_camera.x).to_degrees();
        let apart = (own - azimuth_deg + 540.0).rem_euclid(360.0) - 180.0;
        if !(apart.abs() <= LEVEL_AZIMUTH_AGREEMENT_DEG) {
            return false;
        }
        self.level_to_elevation(elevation_deg);
        true
    }

    /// Turns the pose, [`camera`](Self::camera) and [`perspective`](Self::perspective)
    /// together by the least rotation that puts the direction from the pelvis to the camera
    /// at `elevation_deg` (degrees above the body frame's horizontal plane, z up), keeping its
    /// azimuth. Every landmark is seen where it was (the rotation cancels between pose and
    /// camera) and the pose keeps its shape: only which way is up in the body frame changes.
    /// The direction is to the perspective camera's centre when there is one (with known
    /// intrinsics and the person off the optical axis it is not the optical axis: levelling
    /// the axis tilted the world by the pelvis's angle off it), else along the
    /// weak-perspective camera's axis.
    ///
    /// A single view leaves the camera's elevation and the body's lean partly exchangeable;
    /// the localizer's continuous viewpoint tells the elevation better than the refined
    /// camera (docs/RESULTS.md), which this gives to the pose. Nothing changes for a
    /// non-finite elevation or a camera looking straight up or down.
    pub fn level_to_elevation(&mut self, elevation_deg: f64) {
        let towards_camera = self.towards_camera();
        let across = towards_camera.x.hypot(towards_camera.y);
        if !elevation_deg.is_finite() || !(across >= 1e-9) {
            return;
        }
        let e = elevation_deg.clamp(-90.0, 90.0).to_radians();
        let target = Vector3::new(
            e.cos() * towards_camera.x / across,
            e.cos() * towards_camera.y / across,
            e.sin(),
        );
        let Some(q) = rotation_between(&towards_camera, &target) else {
            return;
        };
        for p in &mut self.pose.points {
            *p = (q * Vector3::from(*p)).into();
        }
        self.camera.rotation *= q.transpose();
        if let Some(perspective) = &mut self.perspective {
            perspective.rotation *= q.transpose();
        }
    }

    /// The unit direction from the pelvis to the camera in the body frame (NaN for a camera
    /// at the pelvis): to the perspective camera's centre (`-R^T T`), else along the
    /// weak-perspective camera's axis.
    fn towards_camera(&self) -> Vector3 {
        match &self.perspective {
            Some(p) => -(p.rotation.transpose() * Vector3::from(p.translation)).normalize(),
            None => {
                let rotation = &self.camera.rotation;
                -Vector3::new(rotation[(2, 0)], rotation[(2, 1)], rotation[(2, 2)])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use camloc_geometry::{Matrix3, WeakPerspective, look_at_origin, sphere_point};
    use camloc_skeleton::Pose3;

    use super::*;
    use crate::PerspectiveCamera;

    #[test]
    fn levelling_keeps_the_image_and_sets_the_elevation() {
        let points: [[f64; 3]; 15] = std::array::from_fn(|i| {
            [
                0.1 * i as f64,
                (0.37 * i as f64).sin(),
                0.05 * (i * i) as f64,
            ]
        });
        let rotation = look_at_origin(sphere_point(130.0, 25.0, 5.0)).unwrap();
        let mut r = Reconstruction::seen_by(
            Pose3 { points },
            WeakPerspective {
                scale: 300.0,
                rotation,
                translation: [10.0, 20.0],
            },
        );
        let before = r.reprojection();
        let shape: Vec<f64> = (1..15)
            .map(|i| (Vector3::from(points[i]) - Vector3::from(points[0])).norm())
            .collect();
        r.level_to_elevation(5.0);
        let after = r.reprojection();
        for (a, b) in before.iter().zip(&after) {
            assert!((a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9);
        }
        let p = &r.pose.points;
        for (i, length) in shape.iter().enumerate() {
            let now = (Vector3::from(p[i + 1]) - Vector3::from(p[0])).norm();
            assert!((now - length).abs() < 1e-12);
        }
        let rot = &r.camera.rotation;
        assert!((rot.determinant() - 1.0).abs() < 1e-12);
        assert!((rot * rot.transpose() - Matrix3::identity()).norm() < 1e-12);
        let towards = -Vector3::new(rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]);
        assert!((towards.z.asin().to_degrees() - 5.0).abs() < 1e-9);
        // The azimuth is kept.
        let azimuth = towards.y.atan2(towards.x).to_degrees().rem_euclid(360.0);
        assert!((azimuth - 130.0).abs() < 1e-9, "{azimuth}");
        // A viewpoint on the other side is not taken; one near it is.
        let levelled = r.camera.rotation;
        assert!(!r.level_to_viewpoint(310.0, 20.0));
        assert_eq!(r.camera.rotation, levelled);
        assert!(r.level_to_viewpoint(150.0, 20.0));
        let rot = &r.camera.rotation;
        assert!((rot[(2, 2)] + 20f64.to_radians().sin()).abs() < 1e-9);
        // Levelled again to the elevation it has (a review found NaN poses in a third of such
        // cases, from `acos` of a dot product rounded above 1): nothing changes.
        for elevation in [20.0, 20.0 + 1e-9, 20.0 - 1e-12] {
            let before = r.clone();
            r.level_to_elevation(elevation);
            assert!(r.pose.points.iter().flatten().all(|v| v.is_finite()));
            for (a, b) in r.pose.points.iter().zip(&before.pose.points) {
                assert!((Vector3::from(*a) - Vector3::from(*b)).norm() < 1e-6);
            }
        }
    }

    /// A known camera with the person off its optical axis: what is levelled is the direction
    /// from the pelvis to the camera's centre, not the axis (trial52: the axis took the
    /// viewpoint's elevation and the world was tilted by the pelvis's 8 deg off the axis).
    #[test]
    fn a_perspective_camera_is_levelled_by_the_direction_to_its_centre() {
        let points: [[f64; 3]; 15] = std::array::from_fn(|i| {
            let t = i as f64;
            [0.05 * t.cos(), 0.2 * (0.7 * t).sin(), 0.1 * t - 0.5]
        });
        let rotation = look_at_origin(sphere_point(200.0, 10.0, 1.0)).unwrap();
        let camera = WeakPerspective {
            scale: 300.0,
            rotation,
            translation: [0.0, 0.0],
        };
        let mut r = Reconstruction::seen_by(Pose3 { points }, camera);
        // The pelvis 0.6 m right of the axis and 0.3 m below it, 3.5 m deep.
        r.perspective = Some(PerspectiveCamera {
            rotation,
            translation: [0.6, 0.3, 3.5],
            focal_px: 1000.0,
            principal_point: [960.0, 540.0],
        });
        let before = r.reprojection();
        assert!(r.level_to_viewpoint(190.0, 5.0));
        for (a, b) in before.iter().zip(&r.reprojection()) {
            assert!((a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9);
        }
        let p = r.perspective.unwrap();
        let centre = -(p.rotation.transpose() * Vector3::from(p.translation));
        let elevation = (centre.z / centre.norm()).asin().to_degrees();
        assert!((elevation - 5.0).abs() < 1e-9, "{elevation}");
        // The axis is not at 5 deg: the pelvis is seen below it.
        let axis = -Vector3::new(p.rotation[(2, 0)], p.rotation[(2, 1)], p.rotation[(2, 2)]);
        assert!((axis.z.asin().to_degrees() - 5.0).abs() > 2.0);
        assert!((p.rotation.determinant() - 1.0).abs() < 1e-12);
    }
}
