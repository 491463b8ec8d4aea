//! Augmentation of 3D poses for what differs between people and between skeleton
//! conventions, and the camera direction helpers the `sphere` protocol and the continuous
//! viewpoint evaluation use.

use camloc_geometry::{Matrix3, Vector3, Viewpoint, azimuth_gap_deg, rotation_about_axis};
use camloc_mocap::canonicalise;
use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, Pose3, mirror_landmark_index};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::posture::{PostureKind, PostureLimits, make_posture};

/// The distal ends of the 8 limb bones that [`Augmentation::limb_rotation_deg`] turns about
/// their proximal joint: thighs, shins, upper arms and forearms.
const ROTATED_BONE_ENDS: [Landmark; 8] = [
    Landmark::LeftKnee,
    Landmark::LeftAnkle,
    Landmark::RightKnee,
    Landmark::RightAnkle,
    Landmark::LeftElbow,
    Landmark::LeftWrist,
    Landmark::RightElbow,
    Landmark::RightWrist,
];

/// Per-sample changes to the 3D pose before projection (each sample is a new virtual person,
/// pose and annotation). All zero ([`Augmentation::default`]) changes nothing.
///
/// Applied in this order: bone lengths, hip and shoulder widths, upper body of a donor pose,
/// limb rotations, a posture (seated, squatting, kneeling, sitting on the floor), then the
/// pose is canonicalised again (docs/conventions.md section 1: the changes can turn the body)
/// and, last, the photo landmark placements.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Augmentation {
    /// Bone-length scaling: every limb (the 14 of docs/conventions.md section 3, left and right alike) is
    /// scaled by its own factor drawn from `U(1 - b, 1 + b)`, joints moved along the
    /// kinematic tree from the pelvis. `0 <= b < 0.5`.
    pub bone_scale: f64,
    /// Probability that a sample takes the landmark placements of photo annotations and
    /// detectors instead of mocap's: the neck at the mid-shoulder point and the pelvis at the
    /// mid-hip point (as derived from COCO-17, which has neither), and the head moved along
    /// the neck-to-head direction to a factor from [`head_reach`](Self::head_reach) of its
    /// distance from the neck (CMU's head is the top of the neck; annotations mark the head
    /// top, lab skeletons the nose or the face).
    pub photo_landmarks: f64,
    /// Range `(lo, hi)` of the neck-to-head factor of photo placements
    /// ([`photo_landmarks`](Self::photo_landmarks)); `0 < lo <= hi <= 3`.
    pub head_reach: (f64, f64),
    /// Joint-angle variation, degrees: each of the 8 limb bones (thighs, shins, upper arms,
    /// forearms; left and right independently) is turned about a random axis through its
    /// proximal joint by an angle drawn from `U(-b, b)`, the bones below it following, so that
    /// the samples hold poses that no clip has. `0 <= b <= 90`.
    pub limb_rotation_deg: f64,
    /// Hip width factor range `(lo, hi)`: both pelvis-to-hip segments are scaled by one
    /// factor from `U(lo, hi)`, the legs following (skeleton conventions and people differ:
    /// the hip joints of some CMU BVH skeletons are twice as far apart as the ASF ones).
    /// `(1, 1)` changes nothing; `0 < lo <= hi <= 3`.
    pub hip_width: (f64, f64),
    /// Shoulder width factor range `(lo, hi)`: both neck-to-shoulder segments are scaled by
    /// one factor from `U(lo, hi)`, the arms following. `(1, 1)` changes nothing;
    /// `0 < lo <= hi <= 3`.
    pub shoulder_width: (f64, f64),
    /// Probability that the upper body (neck, head and arms, relative to the pelvis) is taken
    /// from another random pose of the generated set (both canonical), making combinations of
    /// upper and lower body that no clip has. In `[0, 1]`.
    pub mix_upper_body: f64,
    /// Probability that the body is put in a posture ([`make_posture`]): seated on a chair,
    /// squatting, kneeling on one or both knees, sitting on the floor with legs forward or
    /// crossed ([`PostureKind::MIX`]), thighs, shins and torso pitch drawn within the
    /// joint-angle limits learned from the poses being generated, the upper body kept
    /// relative to the torso. In `[0, 1]`.
    pub posture: f64,
}

impl Default for Augmentation {
    /// Nothing changed: no scaling, no photo placements, no limb rotation, widths `(1, 1)`,
    /// no mixing.
    fn default() -> Self {
        Self::NONE
    }
}

impl Augmentation {
    /// Nothing changed ([`Augmentation::default`], usable in constants).
    const NONE: Augmentation = Augmentation {
        bone_scale: 0.0,
        photo_landmarks: 0.0,
        head_reach: (0.8, 1.6),
        limb_rotation_deg: 0.0,
        hip_width: (1.0, 1.0),
        shoulder_width: (1.0, 1.0),
        mix_upper_body: 0.0,
        posture: 0.0,
    };

    /// What differs between people and annotation conventions, without new poses: 10%
    /// bone-length scaling and photo landmark placements for half of the samples.
    pub const PEOPLE: Augmentation = Augmentation {
        bone_scale: 0.1,
        photo_landmarks: 0.5,
        ..Self::NONE
    };

    /// The augmentation recommended for training (measured by `cargo xtask generalise`,
    /// docs/RESULTS.md): [`PEOPLE`](Self::PEOPLE) (10% bone-length scaling, photo landmark
    /// placements for half of the samples) and limb rotations up to 25 deg, hip widths
    /// 0.8-1.6 and shoulder widths 0.85-1.2, the upper body of another pose for half of the
    /// samples.
    pub const TRAINING: Augmentation = Augmentation {
        limb_rotation_deg: 25.0,
        hip_width: (0.8, 1.6),
        shoulder_width: (0.85, 1.2),
        mix_upper_body: 0.5,
        ..Self::PEOPLE
    };

    /// Whether anything is changed.
    pub fn is_active(&self) -> bool {
        self.bone_scale > 0.0 || self.photo_landmarks > 0.0 || self.changes_structure()
    }

    /// Whether the pose itself (not only its landmark placements or bone lengths) changes,
    /// so that it must be canonicalised again.
    fn changes_structure(&self) -> bool {
        self.limb_rotation_deg > 0.0
            || self.hip_width != (1.0, 1.0)
            || self.shoulder_width != (1.0, 1.0)
            || self.mix_upper_body > 0.0
            || self.posture > 0.0
    }

    /// Whether [`apply`](Self::apply) uses its donor pose.
    pub fn needs_donor(&self) -> bool {
        self.mix_upper_body > 0.0
    }

    /// An error message when a setting is out of range.
    pub(crate) fn check(&self) -> Result<(), String> {
        if !(self.bone_scale >= 0.0 && self.bone_scale < 0.5) {
            return Err(format!(
                "bone scale bound must be in [0, 0.5), got {}",
                self.bone_scale
            ));
        }
        for (name, p) in [
            ("photo landmark", self.photo_landmarks),
            ("upper-body mixing", self.mix_upper_body),
            ("posture", self.posture),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(format!("{name} probability must be in [0, 1], got {p}"));
            }
        }
        if !(0.0..=90.0).contains(&self.limb_rotation_deg) {
            return Err(format!(
                "limb rotation bound must be in [0, 90] degrees, got {}",
                self.limb_rotation_deg
            ));
        }
        for (name, (lo, hi)) in [
            ("hip width", self.hip_width),
            ("shoulder width", self.shoulder_width),
            ("head reach", self.head_reach),
        ] {
            if !(lo > 0.0 && lo <= hi && hi <= 3.0) {
                return Err(format!(
                    "{name} factor range must satisfy 0 < lo <= hi <= 3, got {lo}..{hi}"
                ));
            }
        }
        Ok(())
    }

    /// `pose` changed as configured, with random draws from `rng`; `donor` is the pose whose
    /// upper body [`mix_upper_body`](Self::mix_upper_body) takes (canonical, like `pose`),
    /// `limits` the joint-angle limits of [`posture`](Self::posture).
    /// The pelvis stays at the origin unless photo placements move it to the mid-hip point.
    pub fn apply(
        &self,
        pose: &Pose3,
        donor: &Pose3,
        limits: &PostureLimits,
        rng: &mut impl Rng,
    ) -> Pose3 {
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
        if self.changes_structure() {
            self.change_structure(&mut out, donor, limits, rng);
        }
        if self.photo_landmarks > 0.0 && rng.random_bool(self.photo_landmarks) {
            out = annotated(&out, draw_factor(self.head_reach, rng));
        }
        out
    }

    /// Widths, donor upper body, limb rotations and posture, then canonicalisation (a pose
    /// whose lateral direction vanished keeps the frame it had).
    fn change_structure(
        &self,
        out: &mut Pose3,
        donor: &Pose3,
        limits: &PostureLimits,
        rng: &mut impl Rng,
    ) {
        for ((lo, hi), centre, sides) in [
            (
                self.hip_width,
                Landmark::Pelvis,
                [Landmark::LeftHip, Landmark::RightHip],
            ),
            (
                self.shoulder_width,
                Landmark::Neck,
                [Landmark::LeftShoulder, Landmark::RightShoulder],
            ),
        ] {
            if (lo, hi) != (1.0, 1.0) {
                let factor = draw_factor((lo, hi), rng);
                let c = out.get(centre);
                for side in sides {
                    let s = out.get(side);
                    let shift: [f64; 3] = std::array::from_fn(|k| (factor - 1.0) * (s[k] - c[k]));
                    move_subtree(out, side, |p| std::array::from_fn(|k| p[k] + shift[k]));
                }
            }
        }
        if self.mix_upper_body > 0.0 && rng.random_bool(self.mix_upper_body) {
            let (pelvis, donor_pelvis) = (out.get(Landmark::Pelvis), donor.get(Landmark::Pelvis));
            // The upper body: the neck and everything below it (head and arms).
            for l in Landmark::Neck.subtree() {
                let d = donor.get(l);
                out.points[l.index()] = std::array::from_fn(|k| pelvis[k] + d[k] - donor_pelvis[k]);
            }
        }
        if self.limb_rotation_deg > 0.0 {
            let bound = self.limb_rotation_deg.to_radians();
            for end in ROTATED_BONE_ENDS {
                let pivot = out.get(end.parent().unwrap_or(Landmark::Pelvis));
                let z: f64 = rng.random_range(-1.0..=1.0);
                let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let r = (1.0 - z * z).max(0.0).sqrt();
                let axis = Vector3::new(r * phi.cos(), r * phi.sin(), z);
                let rotation = rotation_about_axis(axis, rng.random_range(-bound..=bound));
                move_subtree(out, end, |p| {
                    let v =
                        rotation * Vector3::new(p[0] - pivot[0], p[1] - pivot[1], p[2] - pivot[2]);
                    [pivot[0] + v[0], pivot[1] + v[1], pivot[2] + v[2]]
                });
            }
        }
        if self.posture > 0.0 && rng.random_bool(self.posture) {
            *out = make_posture(out, PostureKind::draw(rng), limits, rng);
        }
        if let Ok(canonical) = canonicalise(out) {
            *out = canonical;
        }
    }
}

/// `pose` with the landmarks placed as photo annotations, detectors and lab skeletons place
/// them ([`Augmentation::photo_landmarks`]): the neck at the mid-shoulder point, the pelvis
/// at the mid-hip point, and the head moved with the neck and along the neck-to-head
/// direction to `head_reach` times its distance from the neck (1: where it was relative to
/// the neck). Metres, the frame of `pose`.
pub fn annotated(pose: &Pose3, head_reach: f64) -> Pose3 {
    let mid = |a: Landmark, b: Landmark| {
        let (p, q) = (pose.get(a), pose.get(b));
        [
            0.5 * (p[0] + q[0]),
            0.5 * (p[1] + q[1]),
            0.5 * (p[2] + q[2]),
        ]
    };
    let (neck, head) = (pose.get(Landmark::Neck), pose.get(Landmark::Head));
    let new_neck = mid(Landmark::LeftShoulder, Landmark::RightShoulder);
    let mut out = *pose;
    out.points[Landmark::Head.index()] =
        std::array::from_fn(|k| new_neck[k] + head_reach * (head[k] - neck[k]));
    out.points[Landmark::Neck.index()] = new_neck;
    out.points[Landmark::Pelvis.index()] = mid(Landmark::LeftHip, Landmark::RightHip);
    out
}

/// A factor from `U(lo, hi)`, or `lo` without a draw when the range is one value.
fn draw_factor((lo, hi): (f64, f64), rng: &mut impl Rng) -> f64 {
    if hi > lo {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
}

/// Applies `f` to `root` and every landmark below it in the kinematic tree.
fn move_subtree(pose: &mut Pose3, root: Landmark, f: impl Fn([f64; 3]) -> [f64; 3]) {
    for l in root.subtree() {
        pose.points[l.index()] = f(pose.points[l.index()]);
    }
}

/// The direction from the person to the camera of `rotation` (rows: camera axes in the
/// canonical body frame; the optical axis, row 3, points from the camera to the person), as
/// `(azimuth_deg in [0, 360), elevation_deg in [-90, 90])` in the convention of docs/conventions.md
/// section 2 (azimuth 180 = front, 270 = left, 0 = back, 90 = right; elevation + above).
pub fn camera_direction_deg(rotation: &Matrix3) -> (f64, f64) {
    let (x, y, z) = (-rotation[(2, 0)], -rotation[(2, 1)], -rotation[(2, 2)]);
    let azimuth = y.atan2(x).to_degrees().rem_euclid(360.0) % 360.0;
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
    azimuth_gap_deg(azimuth_deg, view.azimuth_deg) <= azimuth_bound_deg
        && (elevation_deg - view.elevation_deg).abs() <= elevation_bound_deg
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::posture::tests::LIMITS;
    use camloc_geometry::{CameraSet, look_at_origin, roll_about_optical_axis, sphere_point};
    use proptest::prelude::*;
    use rand::SeedableRng;

    use crate::test_poses::standing;

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
            let aug = Augmentation { bone_scale: 0.2, ..Augmentation::default() };
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let p = standing();
            let q = aug.apply(&p, &p, &LIMITS, &mut rng);
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

    fn lateral_angle_deg(p: &Pose3) -> f64 {
        let r = |a: Landmark, b: Landmark| {
            let (x, y) = (p.get(a), p.get(b));
            [x[0] - y[0], x[1] - y[1]]
        };
        let (h, s) = (
            r(Landmark::RightHip, Landmark::LeftHip),
            r(Landmark::RightShoulder, Landmark::LeftShoulder),
        );
        (h[0] + s[0]).atan2(h[1] + s[1]).to_degrees()
    }

    proptest! {
        /// Limb rotations and upper-body mixing keep every bone length (of the pose, or of the
        /// donor for its upper body) and leave a canonical pose; widths scale only the
        /// pelvis-hip and neck-shoulder segments, within their ranges.
        #[test]
        fn structural_changes_keep_bones_and_the_canonical_frame(seed in 0u64..500,
                                                                 mix in any::<bool>()) {
            let aug = Augmentation {
                limb_rotation_deg: 40.0,
                hip_width: (0.7, 1.8),
                shoulder_width: (0.8, 1.3),
                mix_upper_body: if mix { 1.0 } else { 0.0 },
                ..Augmentation::default()
            };
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let p = standing();
            let mut donor = standing();
            donor.points[11] = [-0.3, -0.25, 0.3];
            donor.points[14] = [-0.35, 0.2, 0.6];
            let q = aug.apply(&p, &donor, &LIMITS, &mut rng);
            prop_assert!(q.get(Landmark::Pelvis).iter().all(|c| c.abs() < 1e-12));
            prop_assert!(lateral_angle_deg(&q).abs() < 1e-6);
            for (l, (a, b)) in LIMBS.iter().enumerate() {
                let source = if mix && Landmark::Neck.subtree().any(|u| u == *b) && *a != Landmark::Pelvis { &donor } else { &p };
                let ratio = q.limb_length(l) / source.limb_length(l);
                let (lo, hi) = match (a, b) {
                    (Landmark::Pelvis, Landmark::LeftHip | Landmark::RightHip) => aug.hip_width,
                    (Landmark::Neck, Landmark::LeftShoulder | Landmark::RightShoulder) if !mix => aug.shoulder_width,
                    (Landmark::Neck, Landmark::LeftShoulder | Landmark::RightShoulder) => (ratio, ratio),
                    _ => (1.0, 1.0),
                };
                prop_assert!(ratio >= lo - 1e-9 && ratio <= hi + 1e-9, "limb {} ratio {}", l, ratio);
            }
        }
    }

    #[test]
    fn bad_structural_settings_are_refused() {
        for bad in [
            Augmentation {
                limb_rotation_deg: 91.0,
                ..Augmentation::default()
            },
            Augmentation {
                hip_width: (1.2, 1.1),
                ..Augmentation::default()
            },
            Augmentation {
                shoulder_width: (0.0, 1.0),
                ..Augmentation::default()
            },
            Augmentation {
                mix_upper_body: f64::NAN,
                ..Augmentation::default()
            },
        ] {
            assert!(bad.check().is_err(), "{bad:?}");
        }
        assert!(Augmentation::TRAINING.check().is_ok());
        assert!(!Augmentation::default().is_active());
    }

    #[test]
    fn photo_placements_put_neck_and_pelvis_between_the_joints() {
        let aug = Augmentation {
            photo_landmarks: 1.0,
            ..Augmentation::default()
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let p = standing();
        let q = aug.apply(&p, &p, &LIMITS, &mut rng);
        for k in 0..3 {
            let mid_s = 0.5 * (p.points[9][k] + p.points[12][k]);
            let mid_h = 0.5 * (p.points[1][k] + p.points[4][k]);
            assert!((q.points[7][k] - mid_s).abs() < 1e-12);
            assert!((q.points[0][k] - mid_h).abs() < 1e-12);
        }
        assert_eq!(Augmentation::default().apply(&p, &p, &LIMITS, &mut rng), p);
    }

    #[test]
    fn box_follows_table1() {
        let cameras = CameraSet::table1();
        let v = cameras.get(7).unwrap();
        assert!(in_class_box(v, 350.0, 10.0, 30.0, 15.0));
        assert!(!in_class_box(v, 320.0, 10.0, 30.0, 15.0));
        assert!(!in_class_box(v, 10.0, 20.0, 30.0, 15.0));
    }
}
