//! The `rig` protocol: a studio or a room filmed from tripods (docs/conventions.md section 7).
//! Cameras stand fixed in the world around a capture area and aim at its centre, not at the
//! person; the person stands, sits or kneels on the floor somewhere in the area; the image is a
//! full perspective projection with mild radial distortion and detector-like 2D noise.

use camloc_geometry::{
    GeometryError, Matrix3, Perspective, Vector3, look_at_origin, roll_about_optical_axis,
};
use camloc_skeleton::{Landmark, NUM_LANDMARKS, Pose3};
use rand::Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use crate::posture::pelvis_height_m;

/// The studio of the `rig` protocol: uniform ranges `(lo, hi)` drawn per sample.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rig {
    /// Camera centre height above the floor, metres.
    pub camera_height_m: (f64, f64),
    /// Camera distance from the centre of the capture area (horizontal), metres.
    pub camera_radius_m: (f64, f64),
    /// The person's pelvis is within this horizontal distance of the capture area's centre,
    /// metres, and within the camera's circle less 1.5 m (no camera nearer than that).
    pub person_radius_m: f64,
    /// Height above the floor of the point the cameras aim at, metres.
    pub aim_height_m: (f64, f64),
    /// Focal length, pixels.
    pub focal_px: (f64, f64),
    /// Image width, pixels; the height is the width times a ratio in `[9/16, 1]`. The person
    /// is placed so that every landmark is inside the image (up to 16 tries; the last one is
    /// kept).
    pub image_width_px: (f64, f64),
    /// First radial distortion coefficient `k1`: a normalised image point `p` is seen at
    /// `p (1 + k1 |p|^2)`.
    pub distortion_k1: (f64, f64),
    /// Camera roll about the optical axis bound, degrees (tripods are about level).
    pub roll_deg: f64,
    /// The 2D noise of a keypoint detector.
    pub noise: DetectorNoise,
}

impl Default for Rig {
    /// Cameras 1.0-2.2 m high, 2.5-7 m from the centre, aimed at a point 0.8-1.3 m high;
    /// the person within 2 m of the centre; focal lengths 500-2000 px, images 1000-1920 px
    /// wide; `k1` in `[-0.2, 0.05]`; roll up to 3 deg; [`DetectorNoise::default`].
    fn default() -> Self {
        Rig {
            camera_height_m: (1.0, 2.2),
            camera_radius_m: (2.5, 7.0),
            person_radius_m: 2.0,
            aim_height_m: (0.8, 1.3),
            focal_px: (500.0, 2000.0),
            image_width_px: (1000.0, 1920.0),
            distortion_k1: (-0.2, 0.05),
            roll_deg: 3.0,
            noise: DetectorNoise::default(),
        }
    }
}

/// 2D noise like a keypoint detector's: per sample a noise level, larger at the limb ends,
/// and occasional gross errors.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DetectorNoise {
    /// Per-sample Gaussian sigma range as a fraction of the 2D torso length (hips and
    /// shoulders; knees and elbows get 1.3 times it, ankles, wrists and the head 1.6 times).
    pub sigma_fraction: (f64, f64),
    /// Probability that a landmark is a gross error instead.
    pub outlier_probability: f64,
    /// Sigma of a gross error as a fraction of the 2D torso length.
    pub outlier_fraction: f64,
}

impl Default for DetectorNoise {
    /// Sigma 1-5% of the torso, 2% gross errors of sigma 25%.
    fn default() -> Self {
        DetectorNoise {
            sigma_fraction: (0.01, 0.05),
            outlier_probability: 0.02,
            outlier_fraction: 0.25,
        }
    }
}

impl DetectorNoise {
    /// How much noisier than the hips and shoulders a landmark is.
    fn landmark_factor(landmark: Landmark) -> f64 {
        match landmark {
            Landmark::LeftKnee
            | Landmark::RightKnee
            | Landmark::LeftElbow
            | Landmark::RightElbow => 1.3,
            Landmark::LeftAnkle
            | Landmark::RightAnkle
            | Landmark::LeftWrist
            | Landmark::RightWrist
            | Landmark::Head => 1.6,
            _ => 1.0,
        }
    }

    /// Adds the noise to `points` whose 2D torso length is `torso`.
    pub fn apply(&self, points: &mut [[f64; 2]; NUM_LANDMARKS], torso: f64, rng: &mut impl Rng) {
        let sigma = torso * uniform(rng, self.sigma_fraction);
        for (landmark, p) in Landmark::ALL.into_iter().zip(points.iter_mut()) {
            let s = if self.outlier_probability > 0.0 && rng.random_bool(self.outlier_probability) {
                torso * self.outlier_fraction
            } else {
                sigma * Self::landmark_factor(landmark)
            };
            if let Ok(normal) = Normal::new(0.0, s) {
                for c in p.iter_mut() {
                    *c += normal.sample(rng);
                }
            }
        }
    }

    /// An error message when a setting is out of range.
    fn check(&self) -> Result<(), String> {
        let (lo, hi) = self.sigma_fraction;
        if !(lo >= 0.0 && hi >= lo && hi < 1.0) {
            return Err(format!(
                "detector noise sigma range must satisfy 0 <= lo <= hi < 1, got {lo}..{hi}"
            ));
        }
        let outliers_valid = (0.0..=1.0).contains(&self.outlier_probability)
            && (0.0..10.0).contains(&self.outlier_fraction);
        if !outliers_valid {
            return Err(format!(
                "detector outliers must have a probability in [0, 1] and a sigma in [0, 10) torsos, got {} and {}",
                self.outlier_probability, self.outlier_fraction
            ));
        }
        Ok(())
    }
}

fn uniform(rng: &mut impl Rng, (lo, hi): (f64, f64)) -> f64 {
    if hi > lo {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
}

/// Tries at placing the person inside the image before the last draw is kept.
const PLACEMENT_TRIES: usize = 16;

/// Closest a camera may stand to the person, metres.
const MIN_CAMERA_DISTANCE_M: f64 = 1.5;

/// What one `rig` camera saw.
#[derive(Clone, Debug, PartialEq)]
pub struct RigView {
    /// The 2D landmarks, pixels from the principal point (u right, v down), distorted,
    /// without noise.
    pub points: [[f64; 2]; NUM_LANDMARKS],
    /// The camera seen from the person: a rotation looking from the camera centre at the
    /// pelvis (row 3 along that ray, so that the direction from the pelvis to the camera is
    /// minus row 3), rolled so that its x axis is the real camera's as nearly as possible.
    /// This is the truth of the continuous viewpoint.
    pub rotation: Matrix3,
    /// The real camera's rotation (aimed at the capture area's centre), in the canonical
    /// frame of the pose.
    pub camera_rotation: Matrix3,
    /// The camera centre relative to the pelvis, canonical frame, metres.
    pub centre: Vector3,
    /// The focal length drawn, pixels (the principal point is the image origin of
    /// `points`).
    pub focal: f64,
}

impl Rig {
    /// An error message when a setting is out of range.
    pub(crate) fn check(&self) -> Result<(), String> {
        let ranges = [
            ("camera height", self.camera_height_m, 0.0, 50.0),
            ("camera radius", self.camera_radius_m, 0.0, 100.0),
            ("aim height", self.aim_height_m, -10.0, 50.0),
            ("focal length", self.focal_px, 1.0, 1e6),
            ("image width", self.image_width_px, 1.0, 1e6),
            ("distortion k1", self.distortion_k1, -0.5, 0.5),
        ];
        for (name, (lo, hi), min, max) in ranges {
            if !(lo >= min && hi >= lo && hi <= max) {
                return Err(format!(
                    "rig {name} range must satisfy {min} <= lo <= hi <= {max}, got {lo}..{hi}"
                ));
            }
        }
        if !(self.person_radius_m >= 0.0 && self.person_radius_m <= 100.0) {
            return Err(format!(
                "rig person radius must be in [0, 100] m, got {}",
                self.person_radius_m
            ));
        }
        if !(self.camera_radius_m.0 > MIN_CAMERA_DISTANCE_M) {
            return Err(format!(
                "rig cameras must stand more than {MIN_CAMERA_DISTANCE_M} m from the centre, got {}",
                self.camera_radius_m.0
            ));
        }
        if !(0.0..=45.0).contains(&self.roll_deg) {
            return Err(format!(
                "rig roll bound must be in [0, 45] degrees, got {}",
                self.roll_deg
            ));
        }
        self.noise.check()
    }

    /// A view of the canonical `pose` by a camera of this rig whose horizontal direction
    /// from the pelvis has azimuth `azimuth_deg` (docs/conventions.md section 2): the person
    /// stands on the floor ([`pelvis_height_m`]) at a random place of the capture area, the
    /// camera on its circle around the area's centre where the ray from the pelvis at that
    /// azimuth meets it, at a random height, aimed at the centre.
    ///
    /// # Errors
    /// [`GeometryError`] when a landmark is behind the camera or the camera straight above
    /// the pelvis (impossible with valid settings and a human pose).
    pub fn view(
        &self,
        pose: &Pose3,
        azimuth_deg: f64,
        rng: &mut impl Rng,
    ) -> Result<RigView, GeometryError> {
        let floor = -pelvis_height_m(pose);
        let height = floor + uniform(rng, self.camera_height_m);
        let radius = uniform(rng, self.camera_radius_m);
        let aim = floor + uniform(rng, self.aim_height_m);
        let focal = uniform(rng, self.focal_px);
        let width = uniform(rng, self.image_width_px);
        let image_height = width * uniform(rng, (9.0 / 16.0, 1.0));
        let k1 = uniform(rng, self.distortion_k1);
        let roll = uniform(rng, (-self.roll_deg, self.roll_deg)).to_radians();
        let (sa, ca) = azimuth_deg.to_radians().sin_cos();
        let mut last = None;
        let reach = self.person_radius_m.min(radius - MIN_CAMERA_DISTANCE_M);
        for _ in 0..PLACEMENT_TRIES {
            // The capture area's centre, seen from the pelvis: uniform over the disc.
            let rho = reach * rng.random_range(0.0f64..=1.0).sqrt();
            let gamma = rng.random_range(0.0..std::f64::consts::TAU);
            let (ox, oy) = (rho * gamma.cos(), rho * gamma.sin());
            // The camera: t (cos a, sin a) on the circle |c - o| = radius, t > 0.
            let along = ca * ox + sa * oy;
            let t = along + (along * along - rho * rho + radius * radius).sqrt();
            let centre = Vector3::new(t * ca, t * sa, height);
            let target = Vector3::new(ox, oy, aim);
            let camera_rotation = roll_about_optical_axis(&look_at_origin(centre - target)?, roll);
            let camera = Perspective {
                rotation: camera_rotation,
                centre,
                focal,
            };
            let mut points = camera.project(&pose.points)?;
            for p in &mut points {
                let (x, y) = (p[0] / focal, p[1] / focal);
                let factor = 1.0 + k1 * (x * x + y * y);
                *p = [p[0] * factor, p[1] * factor];
            }
            let inside = points
                .iter()
                .all(|p| p[0].abs() <= 0.5 * width && p[1].abs() <= 0.5 * image_height);
            let seen = look_at_origin(centre)?;
            let x_axis = camera_rotation.row(0);
            let angle = x_axis.dot(&seen.row(1)).atan2(x_axis.dot(&seen.row(0)));
            let view = RigView {
                points,
                rotation: roll_about_optical_axis(&seen, angle),
                camera_rotation,
                centre,
                focal,
            };
            if inside {
                return Ok(view);
            }
            last = Some(view);
        }
        // `PLACEMENT_TRIES` > 0: the loop ran and filled `last`.
        last.ok_or(GeometryError::DegeneratePosition)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::augment::camera_direction_deg;
    use crate::test_poses::standing;
    use camloc_geometry::{azimuth_gap_deg, check_rotation};
    use proptest::prelude::*;
    use rand::SeedableRng;

    proptest! {
        /// The truth rotation looks from the camera centre at the pelvis along the requested
        /// azimuth, is a rotation, and its x axis is the real camera's turned about the ray;
        /// the camera stands within its ranges and the elevation is that of its height.
        #[test]
        fn rig_views_look_from_the_camera_at_the_pelvis(seed in 0u64..300, az in 0.0f64..360.0) {
            let rig = Rig::default();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let pose = standing();
            let v = rig.view(&pose, az, &mut rng).unwrap();
            prop_assert!(check_rotation(&v.rotation, 1e-9).is_ok());
            prop_assert!(check_rotation(&v.camera_rotation, 1e-9).is_ok());
            let (a, e) = camera_direction_deg(&v.rotation);
            prop_assert!(azimuth_gap_deg(a, az) < 1e-6, "{} vs {}", a, az);
            let ray = v.centre / v.centre.norm();
            prop_assert!((e.to_radians().sin() - ray.z).abs() < 1e-9);
            let floor = -pelvis_height_m(&pose);
            prop_assert!(v.centre.z - floor >= 1.0 - 1e-9 && v.centre.z - floor <= 2.2 + 1e-9);
            // The truth's x axis is the real one's projection on the image plane of the ray.
            let x = v.camera_rotation.row(0).transpose();
            let projected = x - ray * ray.dot(&x);
            prop_assert!((v.rotation.row(0).transpose() - projected / projected.norm()).norm() < 1e-9);
            // A standing person seen by a camera 1-2.2 m high: middle-ring elevations.
            prop_assert!(e > -10.0 && e < 35.0, "elevation {}", e);
        }
    }

    #[test]
    fn a_lower_pelvis_sees_the_camera_higher() {
        let rig = Rig {
            camera_height_m: (1.6, 1.6),
            camera_radius_m: (4.0, 4.0),
            person_radius_m: 0.0,
            ..Rig::default()
        };
        let standing_pose = standing();
        let mut seated = standing_pose;
        for p in seated.points.iter_mut().skip(1) {
            // Ankles 0.45 m below the pelvis instead of 0.9 m.
            p[2] = p[2].max(-0.45);
        }
        let elevation = |pose: &Pose3| {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
            camera_direction_deg(&rig.view(pose, 180.0, &mut rng).unwrap().rotation).1
        };
        // 1.6 - 0.97 = 0.63 m above a standing pelvis, 1.6 - 0.52 = 1.08 m above a seated one.
        assert!((elevation(&standing_pose) - 0.63f64.atan2(4.0).to_degrees()).abs() < 1e-9);
        assert!((elevation(&seated) - 1.08f64.atan2(4.0).to_degrees()).abs() < 1e-9);
    }

    #[test]
    fn detector_noise_is_larger_at_the_limb_ends() {
        let noise = DetectorNoise {
            outlier_probability: 0.0,
            ..DetectorNoise::default()
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        let (mut hips, mut wrists) = (0.0, 0.0);
        for _ in 0..2000 {
            let mut points = [[0.0; 2]; NUM_LANDMARKS];
            noise.apply(&mut points, 100.0, &mut rng);
            hips += points[Landmark::LeftHip.index()][0].powi(2);
            wrists += points[Landmark::LeftWrist.index()][0].powi(2);
        }
        let ratio = (wrists / hips).sqrt();
        assert!((ratio - 1.6).abs() < 0.15, "{ratio}");
    }

    #[test]
    fn bad_rig_settings_are_refused() {
        assert!(Rig::default().check().is_ok());
        let bad = [
            Rig {
                camera_height_m: (2.0, 1.0),
                ..Rig::default()
            },
            Rig {
                camera_radius_m: (1.0, 7.0),
                ..Rig::default()
            },
            Rig {
                focal_px: (f64::NAN, 1.0),
                ..Rig::default()
            },
            Rig {
                noise: DetectorNoise {
                    outlier_probability: 2.0,
                    ..DetectorNoise::default()
                },
                ..Rig::default()
            },
        ];
        for rig in bad {
            assert!(rig.check().is_err(), "{rig:?}");
        }
    }
}
