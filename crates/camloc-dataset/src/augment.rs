//! Augmentation of 3D poses for what differs between people and between skeleton
//! conventions, and the camera direction helpers the `sphere` protocol and the continuous
//! viewpoint evaluation use.

use camloc_geometry::{CameraSet, Matrix3, Viewpoint};
use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, Pose3, mirror_landmark_index};
use rand::Rng;
use serde::{Deserialize, Serialize};

/// Per-sample changes to the 3D pose before projection (each sample is a new virtual person
/// and annotation). All zero ([`Augmentation::default`]) changes nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Augmentation {
    /// Bone-length scaling: every limb (the 14 of docs/conventions.md section 3, left and right alike) is
    /// scaled by its own factor drawn from `U(1 - b, 1 + b)`, joints moved along the
    /// kinematic tree from the pelvis. `0 <= b < 0.5`.
    pub bone_scale: f64,
    /// Probability that a sample takes the landmark placements of photo annotations and
    /// detectors instead of mocap's: the neck at the mid-shoulder point and the pelvis at the
    /// mid-hip point (as derived from COCO-17, which has neither), and the head moved along
    /// the neck-to-head direction to between 0.8 and 1.6 times its distance from the neck
    /// (CMU's head is the top of the neck; annotations mark the head top or the nose).
    pub photo_landmarks: f64,
}

impl Augmentation {
    /// The augmentation recommended for training: 10% bone-length scaling and photo landmark
    /// placements for half of the samples.
    pub const TRAINING: Augmentation = Augmentation {
        bone_scale: 0.1,
        photo_landmarks: 0.5,
    };

    /// Whether anything is changed.
    pub fn is_active(&self) -> bool {
        self.bone_scale > 0.0 || self.photo_landmarks > 0.0
    }

    /// An error message when a setting is out of range.
    pub(crate) fn check(&self) -> Result<(), String> {
        if !(self.bone_scale >= 0.0 && self.bone_scale < 0.5) {
            return Err(format!(
                "bone scale bound must be in [0, 0.5), got {}",
                self.bone_scale
            ));
        }
        if !(0.0..=1.0).contains(&self.photo_landmarks) {
            return Err(format!(
                "photo landmark probability must be in [0, 1], got {}",
                self.photo_landmarks
            ));
        }
        Ok(())
    }

    /// `pose` changed as configured, with random draws from `rng`. The pelvis stays at the
    /// origin unless photo placements move it to the mid-hip point.
    pub fn apply(&self, pose: &Pose3, rng: &mut impl Rng) -> Pose3 {
        let mut out = *pose;
        if self.bone_scale > 0.0 {
            let mut scale = [1.0; NUM_LANDMARKS];
            for (_, child) in LIMBS {
                let c = child.index();
                let m = mirror_landmark_index(c);
                scale[c] = if m < c {
                    scale[m]
                } else {
                    rng.random_range(1.0 - self.bone_scale..=1.0 + self.bone_scale)
                };
            }
            // LIMBS lists every parent before its children.
            for (parent, child) in LIMBS {
                let (p, c) = (parent.index(), child.index());
                for k in 0..3 {
                    out.points[c][k] =
                        out.points[p][k] + scale[c] * (pose.points[c][k] - pose.points[p][k]);
                }
            }
        }
        if self.photo_landmarks > 0.0 && rng.random_bool(self.photo_landmarks) {
            let points = out.points;
            let mid = |a: Landmark, b: Landmark| {
                let (p, q) = (points[a.index()], points[b.index()]);
                [
                    0.5 * (p[0] + q[0]),
                    0.5 * (p[1] + q[1]),
                    0.5 * (p[2] + q[2]),
                ]
            };
            let neck = points[Landmark::Neck.index()];
            let head = points[Landmark::Head.index()];
            let new_neck = mid(Landmark::LeftShoulder, Landmark::RightShoulder);
            let reach = rng.random_range(0.8..=1.6);
            out.points[Landmark::Head.index()] =
                std::array::from_fn(|k| new_neck[k] + reach * (head[k] - neck[k]));
            out.points[Landmark::Neck.index()] = new_neck;
            out.points[Landmark::Pelvis.index()] = mid(Landmark::LeftHip, Landmark::RightHip);
        }
        out
    }
}

/// The direction from the person to the camera of `rotation` (rows: camera axes in the
/// canonical body frame; the optical axis, row 3, points from the camera to the person), as
/// `(azimuth_deg in [0, 360), elevation_deg in [-90, 90])` in the convention of docs/conventions.md
/// section 2 (azimuth 180 = front, 270 = left, 0 = back, 90 = right; elevation + above).
pub fn camera_direction_deg(rotation: &Matrix3) -> (f64, f64) {
    let (x, y, z) = (-rotation[(2, 0)], -rotation[(2, 1)], -rotation[(2, 2)]);
    let azimuth = y.atan2(x).to_degrees().rem_euclid(360.0);
    let elevation = z.clamp(-1.0, 1.0).asin().to_degrees();
    (azimuth, elevation)
}

/// The unit vector of a direction given as azimuth and elevation in degrees.
pub fn direction_vector(azimuth_deg: f64, elevation_deg: f64) -> [f64; 3] {
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    [ce * ca, ce * sa, se]
}

/// The angle in degrees between two directions given as (azimuth, elevation) in degrees.
pub fn angle_between_deg(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (u, v) = (direction_vector(a.0, a.1), direction_vector(b.0, b.1));
    let dot: f64 = (0..3).map(|k| u[k] * v[k]).sum();
    let cross = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    // atan2 of |u x v| and u . v: accurate at small angles, where acos is not.
    let sin: f64 = cross.iter().map(|c| c * c).sum::<f64>().sqrt();
    sin.atan2(dot).to_degrees()
}

/// The camera of `cameras` whose direction is nearest (smallest angle) to the direction
/// `(azimuth_deg, elevation_deg)`.
pub fn nearest_by_direction(
    cameras: &CameraSet,
    azimuth_deg: f64,
    elevation_deg: f64,
) -> &Viewpoint {
    let u = direction_vector(azimuth_deg, elevation_deg);
    let mut best = &cameras.viewpoints()[0];
    let mut best_dot = f64::NEG_INFINITY;
    for v in cameras.viewpoints() {
        let w = direction_vector(v.azimuth_deg, v.elevation_deg);
        let dot: f64 = (0..3).map(|k| u[k] * w[k]).sum();
        if dot > best_dot {
            best_dot = dot;
            best = v;
        }
    }
    best
}

/// Whether the direction `(azimuth_deg, elevation_deg)` lies in the class box of `view`:
/// azimuth within `+-azimuth_bound_deg` and elevation within `+-elevation_bound_deg` of its
/// centre (the box the `jittered` protocol draws from).
pub fn in_class_box(
    view: &Viewpoint,
    azimuth_deg: f64,
    elevation_deg: f64,
    azimuth_bound_deg: f64,
    elevation_bound_deg: f64,
) -> bool {
    let d = (azimuth_deg - view.azimuth_deg).rem_euclid(360.0);
    d.min(360.0 - d) <= azimuth_bound_deg
        && (elevation_deg - view.elevation_deg).abs() <= elevation_bound_deg
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_geometry::{look_at_origin, roll_about_optical_axis, sphere_point};
    use proptest::prelude::*;
    use rand::SeedableRng;

    fn standing() -> Pose3 {
        crate::generate::tests::standing()
    }

    proptest! {
        #[test]
        fn direction_round_trips_through_the_rotation(az in 0.0f64..360.0, el in -80.0f64..80.0,
                                                       roll in -0.5f64..0.5) {
            let r = roll_about_optical_axis(&look_at_origin(sphere_point(az, el, 4.0)).unwrap(), roll);
            let (a, e) = camera_direction_deg(&r);
            prop_assert!(angle_between_deg((a, e), (az, el)) < 1e-6);
            prop_assert!((e - el).abs() < 1e-9);
        }

        #[test]
        fn bone_scaling_keeps_symmetry_and_bounds(seed in 0u64..1000) {
            let aug = Augmentation { bone_scale: 0.2, photo_landmarks: 0.0 };
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let p = standing();
            let q = aug.apply(&p, &mut rng);
            let len = |pose: &Pose3, l: usize| {
                let (a, b) = LIMBS[l];
                let (x, y) = (pose.points[a.index()], pose.points[b.index()]);
                (0..3).map(|k| (x[k] - y[k]).powi(2)).sum::<f64>().sqrt()
            };
            for (l, (pa, pb)) in LIMBS.iter().enumerate() {
                let ratio = len(&q, l) / len(&p, l);
                prop_assert!((0.8 - 1e-12..=1.2 + 1e-12).contains(&ratio));
                let m = LIMBS.iter().position(|&(a, b)| {
                    a.index() == mirror_landmark_index(pa.index())
                        && b.index() == mirror_landmark_index(pb.index())
                }).unwrap();
                prop_assert!((ratio - len(&q, m) / len(&p, m)).abs() < 1e-12);
            }
            prop_assert_eq!(q.points[0], [0.0; 3]);
        }
    }

    #[test]
    fn photo_placements_put_neck_and_pelvis_between_the_joints() {
        let aug = Augmentation {
            bone_scale: 0.0,
            photo_landmarks: 1.0,
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let p = standing();
        let q = aug.apply(&p, &mut rng);
        for k in 0..3 {
            let mid_s = 0.5 * (p.points[9][k] + p.points[12][k]);
            let mid_h = 0.5 * (p.points[1][k] + p.points[4][k]);
            assert!((q.points[7][k] - mid_s).abs() < 1e-12);
            assert!((q.points[0][k] - mid_h).abs() < 1e-12);
        }
        assert_eq!(Augmentation::default().apply(&p, &mut rng), p);
    }

    #[test]
    fn nearest_and_box_follow_table1() {
        let cameras = CameraSet::table1();
        assert_eq!(nearest_by_direction(&cameras, 170.0, 40.0).label, 9);
        assert_eq!(nearest_by_direction(&cameras, 0.0, -10.0).label, 7);
        let v = cameras.get(7).unwrap();
        assert!(in_class_box(v, 350.0, 10.0, 30.0, 15.0));
        assert!(!in_class_box(v, 320.0, 10.0, 30.0, 15.0));
        assert!(!in_class_box(v, 10.0, 20.0, 30.0, 15.0));
    }
}
