//! The 2D frame a descriptor is expressed in: an origin and a torso length as unit.

use camloc_skeleton::{LIMBS, Landmark, NUM_LIMBS, Pose2, TORSO_LIMB};

use crate::FeatureError;

/// The origin and unit length of a descriptor's 2D frame.
pub(super) struct TorsoFrame {
    origin: [f64; 2],
    torso: f64,
    /// `1 / torso`: offsets and lengths are multiplied by it.
    inv_torso: f64,
}

/// Length of the vector `(du, dv)`. Descriptors are computed on poses within
/// [`Pose2::within_safe_range`], where squares of coordinate differences neither overflow nor
/// underflow, so the plain formula is exact enough and much cheaper than `hypot`.
fn length(du: f64, dv: f64) -> f64 {
    (du * du + dv * dv).sqrt()
}

impl TorsoFrame {
    /// Pelvis origin, pelvis-to-neck unit.
    pub(super) fn new(pose: &Pose2) -> Result<TorsoFrame, FeatureError> {
        Self::checked(
            pose,
            (pose.get(Landmark::Pelvis), "the pelvis"),
            (pose.get(Landmark::Neck), "the neck"),
        )
    }

    /// Mid-hip origin and mid-hip-to-mid-shoulder unit; the pelvis (neck) stands in when a
    /// hip (shoulder) is missing.
    pub(super) fn from_joints(
        pose: &Pose2,
        is_present: &dyn Fn(Landmark) -> bool,
    ) -> Result<TorsoFrame, FeatureError> {
        let mid_or = |a: Landmark, b: Landmark, fallback: Landmark, names: [&'static str; 2]| {
            if is_present(a) && is_present(b) {
                let (p, q) = (pose.get(a), pose.get(b));
                ([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])], names[0])
            } else {
                (pose.get(fallback), names[1])
            }
        };
        let origin = mid_or(
            Landmark::LeftHip,
            Landmark::RightHip,
            Landmark::Pelvis,
            ["the hip midpoint", "the pelvis"],
        );
        let top = mid_or(
            Landmark::LeftShoulder,
            Landmark::RightShoulder,
            Landmark::Neck,
            ["the shoulder midpoint", "the neck"],
        );
        Self::checked(pose, origin, top)
    }

    /// The frame with `origin` and unit `|top - origin|`, after checking that the pose is
    /// finite and the unit is not degenerate (the names go into the error).
    pub(super) fn checked(
        pose: &Pose2,
        (origin, origin_name): ([f64; 2], &'static str),
        (top, top_name): ([f64; 2], &'static str),
    ) -> Result<TorsoFrame, FeatureError> {
        for (i, p) in pose.points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(FeatureError::NonFinite {
                    landmark: Landmark::ALL[i].name(),
                });
            }
        }
        let torso = length(top[0] - origin[0], top[1] - origin[1]);
        let extent = pose
            .points
            .iter()
            .map(|p| p[0].abs().max(p[1].abs()))
            .fold(0.0, f64::max);
        if !(torso > 1e-9 * extent) || torso == 0.0 {
            return Err(FeatureError::DegenerateTorso {
                length: if extent > 0.0 { torso / extent } else { 0.0 },
                origin: origin_name,
                top: top_name,
            });
        }
        Ok(TorsoFrame {
            origin,
            torso,
            inv_torso: 1.0 / torso,
        })
    }

    /// Unit direction from `p` to `q`; `(0, 0)` for a (near) zero-length segment, which has
    /// no direction.
    pub(super) fn direction(&self, p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
        let (du, dv) = (q[0] - p[0], q[1] - p[1]);
        let n = length(du, dv);
        if n > self.torso * 1e-12 {
            let inv = 1.0 / n;
            [du * inv, dv * inv]
        } else {
            [0.0, 0.0]
        }
    }

    /// Distance from `p` to `q` in torso units.
    pub(super) fn relative(&self, p: [f64; 2], q: [f64; 2]) -> f64 {
        length(q[0] - p[0], q[1] - p[1]) * self.inv_torso
    }

    /// Offset of landmark `i` from the origin, in torso lengths.
    pub(super) fn offset(&self, pose: &Pose2, i: usize) -> [f64; 2] {
        let p = pose.points[i];
        [
            (p[0] - self.origin[0]) * self.inv_torso,
            (p[1] - self.origin[1]) * self.inv_torso,
        ]
    }

    /// The 13 non-torso limbs and their lengths divided by the torso length, in [`LIMBS`]
    /// order.
    pub(super) fn relative_lengths<'a>(
        &'a self,
        pose: &'a Pose2,
    ) -> impl Iterator<Item = (usize, f64)> + 'a {
        (0..NUM_LIMBS).filter(|&l| l != TORSO_LIMB).map(move |l| {
            let (a, b) = LIMBS[l];
            (l, self.relative(pose.get(a), pose.get(b)))
        })
    }
}
