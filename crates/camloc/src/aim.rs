//! A pose seen off the optical axis by a wide lens, as a camera at the same place aimed at
//! the person would see it ([`aimed_at_pelvis`]): camloc's descriptor and classifier take the
//! person near the image centre (the training views are aimed at the pelvis), and a person
//! near the edge of a wide-angle image is drawn out by the perspective (a simulated user's
//! views at f = 500 px with the pelvis 500 px off-centre: 12-class accuracy 58% against 77%
//! centred).

use camloc_geometry::{Vector3, rotation_about_axis};
use camloc_keypoints::derive_torso;
use camloc_reconstruct::{Intrinsics, ReconstructError};
use camloc_skeleton::{Landmark, PartialPose2};

/// `pose` (pixels) as the camera of `intrinsics` would see it turned about its centre so that
/// its optical axis goes through the pelvis (the hips' midpoint where the pelvis is missing,
/// the mean of the landmarks present without either): each landmark's ray turned by the
/// smallest rotation that takes the pelvis's ray to the optical axis, and projected again
/// with the same focal length and principal point. Without a principal point (its default,
/// the centre of the pose's box) the pose is its own.
///
/// # Errors
/// As [`Intrinsics::check_points`] on the landmarks present: a pose far smaller than the
/// focal length says a person can be ([`ReconstructError::ScaleMismatch`]: normalised
/// coordinates), or spread over or lying off the principal point by more than 10 focal
/// lengths ([`ReconstructError::OutsideView`]: a focal length or principal point wrong by
/// orders of magnitude, which gave confident answers); [`ReconstructError::BeyondView`]
/// when a landmark's turned ray points behind the camera (the pose spans 90 deg or more of
/// the view).
pub fn aimed_at_pelvis(
    pose: &PartialPose2,
    intrinsics: &Intrinsics,
) -> Result<PartialPose2, ReconstructError> {
    let present: Vec<[f64; 2]> = pose.points.iter().flatten().copied().collect();
    intrinsics.check_points(&present)?;
    let Some(centre) = intrinsics.principal_point else {
        return Ok(*pose);
    };
    let f = intrinsics.focal_px;
    // The pelvis, or the hips' midpoint (the torso rule of docs/conventions.md section 3).
    let mut derived = *pose;
    derive_torso(&mut derived);
    let pelvis = derived.points[Landmark::Pelvis.index()].or_else(|| {
        let n = present.len() as f64;
        (n > 0.0).then(|| [0, 1].map(|k| present.iter().map(|p| p[k]).sum::<f64>() / n))
    });
    let Some(pelvis) = pelvis else {
        return Ok(*pose);
    };
    let ray = |p: [f64; 2]| Vector3::new((p[0] - centre[0]) / f, (p[1] - centre[1]) / f, 1.0);
    // The smallest rotation taking the pelvis's ray to the optical axis: about their cross
    // product, by the angle between them (none when the ray is the axis).
    let a = ray(pelvis);
    let axis = a.cross(&Vector3::z());
    if axis.norm() < 1e-12 * a.norm() {
        return Ok(*pose);
    }
    let turn = rotation_about_axis(axis, axis.norm().atan2(a.z));
    let mut aimed = *pose;
    for point in aimed.points.iter_mut().flatten() {
        let r = turn * ray(*point);
        if r[2] <= 1e-9 * r.norm() {
            return Err(ReconstructError::BeyondView { focal: f });
        }
        *point = [centre[0] + f * r[0] / r[2], centre[1] + f * r[1] / r[2]];
    }
    Ok(aimed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::NUM_LANDMARKS;

    /// The landmarks of a small upright figure 4 m away, seen by a camera at the origin whose
    /// axis is turned `off` radians to the left of the figure (so the figure appears right of
    /// the centre), projected with f = 500 px and principal point (960, 540).
    fn seen(off: f64) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        for j in 0..NUM_LANDMARKS {
            // Body points around the pelvis (0, 0, 4): x right, y down, z away (metres).
            let q = [
                0.3 * ((j * 7 % 5) as f64 - 2.0) / 2.0,
                0.9 * ((j * 3 % 7) as f64 - 3.0) / 3.0,
                4.0 + 0.2 * ((j % 3) as f64 - 1.0),
            ];
            // The camera turned about its y axis by -off: the figure moves right.
            let (c, s) = (off.cos(), off.sin());
            let r = [c * q[0] + s * q[2], q[1], -s * q[0] + c * q[2]];
            pose.points[j] = Some([960.0 + 500.0 * r[0] / r[2], 540.0 + 500.0 * r[1] / r[2]]);
        }
        pose.points[Landmark::Pelvis.index()] = {
            let (c, s) = (off.cos(), off.sin());
            let r = [s * 4.0, 0.0, c * 4.0];
            Some([960.0 + 500.0 * r[0] / r[2], 540.0 + 500.0 * r[1] / r[2]])
        };
        pose
    }

    #[test]
    fn an_off_centre_pose_is_seen_as_by_a_camera_aimed_at_it() {
        let intrinsics = Intrinsics {
            focal_px: 500.0,
            principal_point: Some([960.0, 540.0]),
        };
        let centred = seen(0.0);
        let off = seen(0.7);
        // The off-centre pose differs from the centred one beyond a shift; aimed, it is the
        // centred one (the turn about the camera's y axis is the smallest one).
        let aimed = aimed_at_pelvis(&off, &intrinsics).unwrap();
        for (a, b) in aimed.points.iter().zip(&centred.points) {
            let (a, b) = (a.unwrap(), b.unwrap());
            assert!(
                (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6,
                "{a:?} {b:?}"
            );
        }
        // Without a principal point, or at the centre, the pose stays.
        let no_point = Intrinsics {
            principal_point: None,
            ..intrinsics
        };
        assert_eq!(aimed_at_pelvis(&off, &no_point).unwrap(), off);
        let again = aimed_at_pelvis(&centred, &intrinsics).unwrap();
        for (a, b) in again.points.iter().zip(&centred.points) {
            let (a, b) = (a.unwrap(), b.unwrap());
            assert!((a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9);
        }
        // A focal length of 1 px with the principal point far off: refused.
        let absurd = Intrinsics {
            focal_px: 1.0,
            principal_point: Some([0.0, 0.0]),
        };
        assert!(matches!(
            aimed_at_pelvis(&off, &absurd),
            Err(ReconstructError::OutsideView { .. })
        ));
        // Within that reach, but spanning more than 90 deg of the view (at 20 px, the pelvis
        // 72 deg to one side, a wrist 56 deg to the other): refused, not a landmark dropped
        // (which had read "landmark neck is missing").
        let mut wide = PartialPose2::empty();
        wide.points[Landmark::Pelvis.index()] = Some([960.0, 540.0]);
        wide.points[Landmark::LeftWrist.index()] = Some([870.0, 540.0]);
        let short = Intrinsics {
            focal_px: 20.0,
            principal_point: Some([900.0, 540.0]),
        };
        assert!(matches!(
            aimed_at_pelvis(&wide, &short),
            Err(ReconstructError::BeyondView { .. })
        ));
    }
}
