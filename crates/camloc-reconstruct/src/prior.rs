//! Priors that keep a reconstruction human where the 2D is ambiguous: joint-angle limits
//! learned from motion capture, and left/right limb-length symmetry.
//!
//! # Joint-angle limits
//!
//! Each of the four limb bones (thigh, shin, upper arm, forearm) has a direction in a frame
//! attached to its parent segment:
//!
//! * thigh (hip to knee) and upper arm (shoulder to elbow): in the body frame of the hips or
//!   shoulders, `x` from the left joint to the right one, `z` the pelvis-to-neck direction made
//!   orthogonal to `x`, `y = z x x`;
//! * shin (knee to ankle) and forearm (elbow to wrist): in the frame of the thigh or upper arm,
//!   `z` along that bone, `x` the body frame's `x` made orthogonal to it, `y = z x x`.
//!
//! Left limbs are mirrored (`x -> -x`) so that one set of directions serves both sides. The
//! limits are the directions seen in training: [`JointLimits::fit`] keeps a set of
//! representative directions per bone (farthest-point sampling of the training directions)
//! and a radius (the 99.5th percentile of the training directions' angle to the nearest
//! representative), and a direction is within the limits when some representative is within
//! that radius. [`JointLimits::project`] turns every bone that is outside onto the border of
//! the allowed set (towards its nearest representative), the bones below it following.

use camloc_skeleton::{Landmark, NUM_LANDMARKS, Pose3};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use crate::ReconstructError;

/// The four limb bones whose directions are limited, by kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Bone {
    Thigh,
    Shin,
    UpperArm,
    Forearm,
}

/// A limited bone of one side: its kind, proximal and distal landmarks, and whether it is a
/// left limb (mirrored into the right-side frame).
struct LimitedBone {
    bone: Bone,
    from: Landmark,
    to: Landmark,
    left: bool,
}

/// The limited bones in kinematic order (a parent bone before its child).
const LIMITED: [LimitedBone; 8] = [
    LimitedBone {
        bone: Bone::Thigh,
        from: Landmark::LeftHip,
        to: Landmark::LeftKnee,
        left: true,
    },
    LimitedBone {
        bone: Bone::Shin,
        from: Landmark::LeftKnee,
        to: Landmark::LeftAnkle,
        left: true,
    },
    LimitedBone {
        bone: Bone::Thigh,
        from: Landmark::RightHip,
        to: Landmark::RightKnee,
        left: false,
    },
    LimitedBone {
        bone: Bone::Shin,
        from: Landmark::RightKnee,
        to: Landmark::RightAnkle,
        left: false,
    },
    LimitedBone {
        bone: Bone::UpperArm,
        from: Landmark::LeftShoulder,
        to: Landmark::LeftElbow,
        left: true,
    },
    LimitedBone {
        bone: Bone::Forearm,
        from: Landmark::LeftElbow,
        to: Landmark::LeftWrist,
        left: true,
    },
    LimitedBone {
        bone: Bone::UpperArm,
        from: Landmark::RightShoulder,
        to: Landmark::RightElbow,
        left: false,
    },
    LimitedBone {
        bone: Bone::Forearm,
        from: Landmark::RightElbow,
        to: Landmark::RightWrist,
        left: false,
    },
];

/// Left/right pairs of bones (parent, child landmarks) whose lengths the symmetry prior
/// equalises: hip offsets, thighs, shins, shoulder offsets, upper arms, forearms.
const SYMMETRIC_PAIRS: [((Landmark, Landmark), (Landmark, Landmark)); 6] = [
    (
        (Landmark::Pelvis, Landmark::LeftHip),
        (Landmark::Pelvis, Landmark::RightHip),
    ),
    (
        (Landmark::LeftHip, Landmark::LeftKnee),
        (Landmark::RightHip, Landmark::RightKnee),
    ),
    (
        (Landmark::LeftKnee, Landmark::LeftAnkle),
        (Landmark::RightKnee, Landmark::RightAnkle),
    ),
    (
        (Landmark::Neck, Landmark::LeftShoulder),
        (Landmark::Neck, Landmark::RightShoulder),
    ),
    (
        (Landmark::LeftShoulder, Landmark::LeftElbow),
        (Landmark::RightShoulder, Landmark::RightElbow),
    ),
    (
        (Landmark::LeftElbow, Landmark::LeftWrist),
        (Landmark::RightElbow, Landmark::RightWrist),
    ),
];

/// Share of the training directions a [`JointLimits`] radius covers.
const COVERAGE: f64 = 0.995;

/// Joint-angle limits learned from training poses (see the module documentation): per bone
/// kind, unit representative directions in the parent frame and an angular radius.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointLimits {
    /// Per bone kind (thigh, shin, upper arm, forearm): representative unit directions.
    directions: [Vec<[f64; 3]>; 4],
    /// Per bone kind: the angular radius, radians.
    radii: [f64; 4],
}

impl Bone {
    fn index(self) -> usize {
        match self {
            Bone::Thigh => 0,
            Bone::Shin => 1,
            Bone::UpperArm => 2,
            Bone::Forearm => 3,
        }
    }
}

fn point(pose: &Pose3, l: Landmark) -> Vector3<f64> {
    Vector3::from(pose.points[l.index()])
}

/// How far outside the limits (radians of violation, its two bones summed) a limb must lie
/// for [`JointLimits::flip_depths`] to try its flips: only clear cases, for the limits,
/// learned on the motion capture's proportions, misjudge a few limbs of other skeletons
/// (docs/RESULTS.md).
const FLIP_MIN_VIOLATION_RAD: f64 = 0.3;

/// How much further into the limits (radians of violation) a flip must take a limb for
/// [`JointLimits::flip_depths`] to keep it.
const FLIP_MARGIN_RAD: f64 = 0.2;

/// Flips the depth of bone `b` of `pose` along the optical axis of a camera with `rotation`
/// (body frame to camera frame), the bones below it following.
fn flip_depth(pose: &mut Pose3, b: &LimitedBone, rotation: &Matrix3<f64>) {
    let bone = point(pose, b.to) - point(pose, b.from);
    let mut seen = rotation * bone;
    seen.z = -seen.z;
    let shift = rotation.transpose() * seen - bone;
    for l in b.to.subtree() {
        pose.points[l.index()] = (point(pose, l) + shift).into();
    }
}

/// The unit part of `v` orthogonal to the unit vector `axis`, `None` when (nearly) zero.
fn orthogonal_unit(v: Vector3<f64>, axis: &Vector3<f64>) -> Option<Vector3<f64>> {
    (v - axis * axis.dot(&v)).try_normalize(1e-12)
}

/// The right-handed frame (rows: x, y = z x x, z) of the orthonormal axes `x` and `z`.
fn frame_rows(x: Vector3<f64>, z: Vector3<f64>) -> Matrix3<f64> {
    let y = z.cross(&x);
    Matrix3::from_rows(&[x.transpose(), y.transpose(), z.transpose()])
}

/// The body frame (rows: x, y, z axes) of the hips or shoulders of `pose`, `None` when
/// degenerate.
fn body_frame(pose: &Pose3, upper: bool) -> Option<Matrix3<f64>> {
    let (left, right) = if upper {
        (Landmark::LeftShoulder, Landmark::RightShoulder)
    } else {
        (Landmark::LeftHip, Landmark::RightHip)
    };
    let x = (point(pose, right) - point(pose, left)).try_normalize(1e-12)?;
    let up = point(pose, Landmark::Neck) - point(pose, Landmark::Pelvis);
    let z = orthogonal_unit(up, &x)?;
    Some(frame_rows(x, z))
}

/// The frame (rows) in which `bone`'s direction is measured, for the current `pose`.
fn parent_frame(pose: &Pose3, b: &LimitedBone) -> Option<Matrix3<f64>> {
    let upper = matches!(b.bone, Bone::UpperArm | Bone::Forearm);
    let body = body_frame(pose, upper)?;
    match b.bone {
        Bone::Thigh | Bone::UpperArm => Some(body),
        Bone::Shin | Bone::Forearm => {
            // The parent bone: hip to knee, or shoulder to elbow.
            let parent_from = b.from.parent()?;
            let z = (point(pose, b.from) - point(pose, parent_from)).try_normalize(1e-12)?;
            let x = orthogonal_unit(body.row(0).transpose(), &z)?;
            Some(frame_rows(x, z))
        }
    }
}

/// `bone`'s unit direction in its parent frame (mirrored for left limbs), with the frame.
fn local_direction(pose: &Pose3, b: &LimitedBone) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    let frame = parent_frame(pose, b)?;
    let d = (point(pose, b.to) - point(pose, b.from)).try_normalize(1e-12)?;
    let mut local = frame * d;
    if b.left {
        local.x = -local.x;
    }
    Some((local, frame))
}

/// Angle between unit vectors, radians.
fn angle(a: &Vector3<f64>, b: &[f64; 3]) -> f64 {
    let b = Vector3::from(*b);
    a.cross(&b).norm().atan2(a.dot(&b))
}

impl JointLimits {
    /// Learns the limits from training poses: per bone kind, up to `per_bone` representative
    /// directions by farthest-point sampling, and the radius that covers 99.5% of the
    /// training directions.
    ///
    /// # Errors
    /// [`ReconstructError::InvalidConfig`] for `per_bone = 0`;
    /// [`ReconstructError::EmptyTrainingSet`] when no pose has a usable frame.
    pub fn fit(poses: &[Pose3], per_bone: usize) -> Result<JointLimits, ReconstructError> {
        if per_bone == 0 {
            return Err(ReconstructError::InvalidConfig {
                field: "BasisConfig::limit_directions",
                value: "0".into(),
                reason: "at least one direction per bone is needed",
            });
        }
        let mut samples: [Vec<Vector3<f64>>; 4] = Default::default();
        for pose in poses {
            for b in &LIMITED {
                if let Some((d, _)) = local_direction(pose, b) {
                    samples[b.bone.index()].push(d);
                }
            }
        }
        if samples.iter().any(Vec::is_empty) {
            return Err(ReconstructError::EmptyTrainingSet);
        }
        let mut directions: [Vec<[f64; 3]>; 4] = Default::default();
        let mut radii = [0.0; 4];
        for (k, all) in samples.iter().enumerate() {
            // Farthest-point sampling from the first direction.
            let mut kept: Vec<[f64; 3]> = vec![all[0].into()];
            let mut nearest: Vec<f64> = all.iter().map(|d| angle(d, &kept[0])).collect();
            while kept.len() < per_bone {
                let (far, &gap) = nearest
                    .iter()
                    .enumerate()
                    .max_by(|a, b| a.1.total_cmp(b.1))
                    .unwrap_or((0, &0.0));
                if !(gap > 0.0) {
                    break;
                }
                let new: [f64; 3] = all[far].into();
                for (n, d) in nearest.iter_mut().zip(all) {
                    *n = n.min(angle(d, &new));
                }
                kept.push(new);
            }
            nearest.sort_by(f64::total_cmp);
            let at = ((nearest.len() as f64 * COVERAGE) as usize).min(nearest.len() - 1);
            radii[k] = nearest[at];
            directions[k] = kept;
        }
        Ok(JointLimits { directions, radii })
    }

    /// How far `pose`'s limb bones lie outside the limits: the sum over the 8 bones of the
    /// angle (radians) beyond the radius of the nearest representative direction; 0 for a
    /// pose within the limits.
    pub fn violation(&self, pose: &Pose3) -> f64 {
        LIMITED.iter().map(|b| self.bone_violation(pose, b)).sum()
    }

    /// How far the bone `b` of `pose` lies outside the limits (radians; 0 within them or
    /// when it has no direction).
    fn bone_violation(&self, pose: &Pose3, b: &LimitedBone) -> f64 {
        local_direction(pose, b)
            .and_then(|(d, _)| {
                let k = b.bone.index();
                let (_, a) = self.nearest(k, &d)?;
                Some((a - self.radii[k]).max(0.0))
            })
            .unwrap_or(0.0)
    }

    /// `pose` with, in each limb (thigh and shin, upper arm and forearm), the depth of its
    /// two bones along the optical axis of a camera with `rotation` (body frame to camera
    /// frame) flipped where the limb lies at least 0.3 rad outside the limits and a flip
    /// takes it at least 0.2 rad further into them: of the four ways (neither, the proximal bone, the distal one, both)
    /// the one with the smallest violation. A flip leaves the limb's image under weak
    /// perspective as it was: it is the depth ambiguity of each bone that one view leaves
    /// (a knee seen bent backwards or forwards), which the limits decide. A limb with a
    /// landmark whose bit is set in `imputed` (filled in, not seen: its image is no evidence
    /// of either reading) is left as it is. Bone lengths are kept; the bones below a flipped
    /// one follow it.
    pub fn flip_depths(&self, pose: &Pose3, rotation: &Matrix3<f64>, imputed: u16) -> Pose3 {
        let mut out = *pose;
        for limb in LIMITED.chunks_exact(2) {
            let seen = |l: Landmark| imputed & (1 << l.index()) == 0;
            if !(seen(limb[0].from) && seen(limb[0].to) && seen(limb[1].to)) {
                continue;
            }
            let violation = |p: &Pose3| limb.iter().map(|b| self.bone_violation(p, b)).sum::<f64>();
            let original = violation(&out);
            if original <= FLIP_MIN_VIOLATION_RAD {
                continue;
            }
            let mut best = (original - FLIP_MARGIN_RAD, None);
            for flips in [[true, false], [false, true], [true, true]] {
                let mut flipped = out;
                for (b, _) in limb.iter().zip(flips).filter(|(_, flip)| *flip) {
                    flip_depth(&mut flipped, b, rotation);
                }
                let v = violation(&flipped);
                if v < best.0 {
                    best = (v, Some(flipped));
                }
            }
            if let (_, Some(flipped)) = best {
                out = flipped;
            }
        }
        out
    }

    /// The representative of bone kind `k` nearest to `d` (largest cosine), and the angle to
    /// it.
    fn nearest(&self, k: usize, d: &Vector3<f64>) -> Option<([f64; 3], f64)> {
        let best = self.directions[k]
            .iter()
            .map(|c| (c, d.x * c[0] + d.y * c[1] + d.z * c[2]))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        Some((*best.0, angle(d, best.0)))
    }

    /// `pose` with every bone outside the limits turned (about its proximal joint, the bones
    /// below it following) onto the border of the allowed set, towards its nearest
    /// representative direction. Bone lengths are kept.
    pub fn project(&self, pose: &Pose3) -> Pose3 {
        let mut out = *pose;
        for b in &LIMITED {
            let Some((d, frame)) = local_direction(&out, b) else {
                continue;
            };
            let k = b.bone.index();
            let Some((c, a)) = self.nearest(k, &d) else {
                continue;
            };
            if a <= self.radii[k] || !(a > 0.0) {
                continue;
            }
            // The point at the radius from c on the great circle towards d.
            let c = Vector3::from(c);
            let t = self.radii[k] / a;
            let sin = a.sin();
            let mut target = if sin > 1e-9 {
                c * (((1.0 - t) * a).sin() / sin) + d * ((t * a).sin() / sin)
            } else {
                c
            };
            if b.left {
                target.x = -target.x;
            }
            let old = frame.transpose()
                * if b.left {
                    Vector3::new(-d.x, d.y, d.z)
                } else {
                    d
                };
            let new = frame.transpose() * target;
            let Some(rotation) = camloc_geometry::rotation_between(&old, &new) else {
                continue;
            };
            let pivot = point(&out, b.from);
            for l in b.to.subtree() {
                let p = point(&out, l) - pivot;
                out.points[l.index()] = (pivot + rotation * p).into();
            }
        }
        out
    }

    /// Checks the invariants after decoding: at least one representative per bone kind, unit
    /// directions, finite radii in `[0, pi]`.
    pub(crate) fn check(&self) -> Result<(), String> {
        for (k, dirs) in self.directions.iter().enumerate() {
            if dirs.is_empty() {
                return Err(format!("joint limits: bone kind {k} has no direction"));
            }
            if dirs.iter().any(|d| {
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                !((n - 1.0).abs() < 1e-9)
            }) {
                return Err(format!(
                    "joint limits: bone kind {k} has a non-unit direction"
                ));
            }
            if !(0.0..=std::f64::consts::PI).contains(&self.radii[k]) {
                return Err(format!(
                    "joint limits: bone kind {k} has radius {} outside [0, pi]",
                    self.radii[k]
                ));
            }
        }
        Ok(())
    }
}

/// `pose` with the left and right bones of each pair (hip and shoulder offsets, thighs,
/// shins, upper arms, forearms) brought to their mean length, each along its own direction,
/// the bones below following.
pub fn symmetrise(pose: &Pose3) -> Pose3 {
    let mut out = *pose;
    for (l, r) in SYMMETRIC_PAIRS {
        let length = |p: &Pose3, (a, b): (Landmark, Landmark)| (point(p, b) - point(p, a)).norm();
        let mean = 0.5 * (length(&out, l) + length(&out, r));
        for (a, b) in [l, r] {
            let v = point(&out, b) - point(&out, a);
            let n = v.norm();
            if !(n > 0.0) {
                continue;
            }
            let shift = v * (mean / n - 1.0);
            for m in b.subtree() {
                out.points[m.index()] = (point(&out, m) + shift).into();
            }
        }
    }
    debug_assert_eq!(out.points.len(), NUM_LANDMARKS);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn standing(knee_bend: f64) -> Pose3 {
        // Canonical: facing -x, right towards +y, z up; as a knee flexes by `knee_bend` the
        // ankle swings back (+x).
        let (s, c) = knee_bend.sin_cos();
        let mut p = [[0.0; 3]; NUM_LANDMARKS];
        p[Landmark::LeftHip.index()] = [0.0, -0.1, -0.05];
        p[Landmark::RightHip.index()] = [0.0, 0.1, -0.05];
        p[Landmark::LeftKnee.index()] = [0.0, -0.1, -0.45];
        p[Landmark::RightKnee.index()] = [0.0, 0.1, -0.45];
        p[Landmark::LeftAnkle.index()] = [0.4 * s, -0.1, -0.45 - 0.4 * c];
        p[Landmark::RightAnkle.index()] = [0.4 * s, 0.1, -0.45 - 0.4 * c];
        p[Landmark::Neck.index()] = [0.0, 0.0, 0.5];
        p[Landmark::Head.index()] = [0.0, 0.0, 0.7];
        p[Landmark::LeftShoulder.index()] = [0.0, -0.18, 0.48];
        p[Landmark::RightShoulder.index()] = [0.0, 0.18, 0.48];
        p[Landmark::LeftElbow.index()] = [0.0, -0.2, 0.2];
        p[Landmark::RightElbow.index()] = [0.0, 0.2, 0.2];
        p[Landmark::LeftWrist.index()] = [-0.2, -0.2, 0.05];
        p[Landmark::RightWrist.index()] = [-0.2, 0.2, 0.05];
        Pose3::new(p)
    }

    #[test]
    fn knees_bent_backwards_are_outside_and_projected_back() {
        // Training: shins bent backwards (+x, behind the body) by 0 to 90 degrees.
        let training: Vec<Pose3> = (0..=90)
            .map(|d| standing((d as f64).to_radians()))
            .collect();
        let limits = JointLimits::fit(&training, 16).unwrap();
        limits.check().unwrap();
        assert_eq!(limits.violation(&training[45]), 0.0);
        // A knee bent the other way (the ankle in front of the body) is outside.
        let wrong = standing(-60f64.to_radians());
        let v = limits.violation(&wrong);
        assert!(v > 0.5, "{v}");
        let fixed = limits.project(&wrong);
        assert!(
            limits.violation(&fixed) < 1e-6,
            "{}",
            limits.violation(&fixed)
        );
        // Bone lengths are kept, the thighs and the upper body did not move.
        for l in [Landmark::LeftHip, Landmark::LeftKnee, Landmark::Neck] {
            assert_eq!(fixed.points[l.index()], wrong.points[l.index()]);
        }
        let shin =
            |p: &Pose3| (point(p, Landmark::LeftAnkle) - point(p, Landmark::LeftKnee)).norm();
        assert!((shin(&fixed) - shin(&wrong)).abs() < 1e-12);
        assert!(JointLimits::fit(&training, 0).is_err());
        assert!(JointLimits::fit(&[], 4).is_err());
    }

    /// A camera looking along +x (from behind the body, whose front faces -x) cannot tell a
    /// knee bent 60 degrees backwards from one bent the human way: the flip finds the human
    /// one and leaves the image as it was; a knee filled in is left alone, and a camera
    /// looking from the side (the bend across its axis) flips nothing.
    #[test]
    fn a_knee_bent_backwards_along_the_camera_axis_is_flipped_into_the_limits() {
        let training: Vec<Pose3> = (0..=90)
            .map(|d| standing((d as f64).to_radians()))
            .collect();
        let limits = JointLimits::fit(&training, 16).unwrap();
        let wrong = standing(-60f64.to_radians());
        // Body to camera: camera x = -body y, camera y = -body z, camera z (depth) = body x.
        let behind: Matrix3<f64> = Matrix3::new(0.0, -1.0, 0.0, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0);
        assert!((behind.determinant() - 1.0).abs() < 1e-12);
        let flipped = limits.flip_depths(&wrong, &behind, 0);
        assert!(
            limits.violation(&flipped) < 1e-9,
            "{}",
            limits.violation(&flipped)
        );
        let right = standing(60f64.to_radians());
        for (a, b) in flipped.points.iter().zip(&right.points) {
            assert!((Vector3::from(*a) - Vector3::from(*b)).norm() < 1e-12);
        }
        let image = |p: &Pose3| p.points.map(|x| (behind * Vector3::from(x)).xy());
        for (a, b) in image(&flipped).iter().zip(&image(&wrong)) {
            assert!((a - b).norm() < 1e-12);
        }
        let ankles = (1 << Landmark::LeftAnkle.index()) | (1 << Landmark::RightAnkle.index());
        assert_eq!(limits.flip_depths(&wrong, &behind, ankles), wrong);
        // From the side the bend is in the image: no flip reaches the limits.
        let side = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
        assert_eq!(limits.flip_depths(&wrong, &side, 0), wrong);
        assert_eq!(limits.flip_depths(&right, &behind, 0), right);
    }

    #[test]
    fn symmetrise_equalises_pairs_and_keeps_directions() {
        let mut p = standing(0.3);
        p.points[Landmark::LeftWrist.index()] = [-0.3, -0.2, -0.05];
        let s = symmetrise(&p);
        for ((a, b), (c, d)) in SYMMETRIC_PAIRS {
            let l = (point(&s, b) - point(&s, a)).norm();
            let r = (point(&s, d) - point(&s, c)).norm();
            assert!((l - r).abs() < 1e-12, "{a:?}-{b:?}: {l} vs {r}");
        }
        let dir =
            |p: &Pose3| (point(p, Landmark::LeftWrist) - point(p, Landmark::LeftElbow)).normalize();
        assert!((dir(&s) - dir(&p)).norm() < 1e-12);
        // A symmetric pose is left as it is.
        let q = symmetrise(&s);
        for (x, y) in q.points.iter().zip(&s.points) {
            assert!((0..3).all(|k| (x[k] - y[k]).abs() < 1e-12));
        }
    }
}
