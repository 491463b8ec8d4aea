//! Evaluation metrics: 3D error after similarity alignment, and the paper's projection error.

use camloc_skeleton::{NUM_LANDMARKS, Pose2, Pose3};
use nalgebra::{Matrix3, SVD, Vector3};

use crate::{
    ReconstructError, Reconstruction, check_finite_landmarks, is_positive, is_positive_finite,
};

/// The median of `values` (the mean of the two middle ones for an even count), reordering
/// them; `None` for none.
pub fn median(values: &mut [f64]) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let mid = values.len() / 2;
    match values.len() {
        0 => None,
        n if n % 2 == 1 => Some(values[mid]),
        _ => Some(0.5 * (values[mid - 1] + values[mid])),
    }
}

/// `estimate` mapped onto `truth` by the similarity transform (scale, proper rotation with
/// det +1, translation) that minimises the summed squared joint distances (Umeyama 1991 with
/// the reflection excluded). Returned in `truth`'s frame and units.
///
/// A reflection is never used: a mirror-image estimate stays mirrored and is penalised. If the
/// estimate's points all coincide, the scale is 0 and every aligned point is `truth`'s
/// centroid. Returns `None` when either pose holds a non-finite coordinate.
pub fn align_similarity(estimate: &Pose3, truth: &Pose3) -> Option<Pose3> {
    if !estimate.is_finite() || !truth.is_finite() {
        return None;
    }
    let n = NUM_LANDMARKS as f64;
    let xs = estimate.points.map(Vector3::from);
    let ys = truth.points.map(Vector3::from);
    let mx = xs.iter().sum::<Vector3<f64>>() / n;
    let my = ys.iter().sum::<Vector3<f64>>() / n;
    let mut cov = Matrix3::zeros();
    let mut var_x = 0.0;
    for (x, y) in xs.iter().zip(&ys) {
        cov += (y - my) * (x - mx).transpose() / n;
        var_x += (x - mx).norm_squared() / n;
    }
    let aligned = if var_x > 0.0 {
        let svd = SVD::new(cov, true, true);
        let (u, v_t) = (svd.u?, svd.v_t?);
        let sign = if (u * v_t).determinant() < 0.0 {
            -1.0
        } else {
            1.0
        };
        let s = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, sign));
        let rotation = u * s * v_t;
        let d = svd.singular_values;
        let scale = (d[0] + d[1] + sign * d[2]) / var_x;
        xs.map(|x| (my + rotation * (x - mx) * scale).into())
    } else {
        [my.into(); NUM_LANDMARKS]
    };
    Some(Pose3 { points: aligned })
}

/// Mean per-joint position error between `estimate` and `truth` after
/// [`align_similarity`], in millimetres (both poses in metres). NaN when either pose holds a
/// non-finite coordinate.
pub fn mpjpe_after_similarity(estimate: &Pose3, truth: &Pose3) -> f64 {
    match align_similarity(estimate, truth) {
        Some(aligned) => {
            let total: f64 = aligned
                .points
                .iter()
                .zip(&truth.points)
                .map(|(a, t)| (Vector3::from(*a) - Vector3::from(*t)).norm())
                .sum();
            1000.0 * total / NUM_LANDMARKS as f64
        }
        None => f64::NAN,
    }
}

/// Mean per-joint position error between `estimate` and `truth` (metres, both in the canonical
/// body frame) with both pelvises at the origin and `estimate` scaled by the least-squares
/// factor, but not rotated, in millimetres: the error of the pose as the body frame orients
/// it (which way is up and front), what a BVH file or a world placement shows, where
/// [`mpjpe_after_similarity`] measures the shape alone (sizes cannot be told from one camera,
/// so the scale is aligned). NaN for a non-finite coordinate or an estimate of no extent.
pub fn mpjpe_after_scale(estimate: &Pose3, truth: &Pose3) -> f64 {
    let root = |p: &Pose3, i: usize| Vector3::from(p.points[i]) - Vector3::from(p.points[0]);
    let (mut cross, mut own) = (0.0, 0.0);
    for i in 0..NUM_LANDMARKS {
        let (e, t) = (root(estimate, i), root(truth, i));
        cross += e.dot(&t);
        own += e.norm_squared();
    }
    if !(own > 0.0 && own.is_finite() && cross.is_finite()) {
        return f64::NAN;
    }
    let scale = cross / own;
    let total: f64 = (0..NUM_LANDMARKS)
        .map(|i| (root(estimate, i) * scale - root(truth, i)).norm())
        .sum();
    1000.0 * total / NUM_LANDMARKS as f64
}

/// The paper's eq. 12: the Euclidean norm of the 30-vector of residuals between `pose2` and the
/// projection of `recon.pose` by the camera it was fitted with (eq. 6, image units;
/// [`Reconstruction::reprojection`]: its perspective camera when it has one), divided by `width x
/// height` of the image (image units squared). The result has units of 1 / image unit, so it is
/// comparable only between inputs of the same image size; use [`projection_error_eq12_bbox`]
/// when no image size is known.
///
/// # Errors
/// [`ReconstructError::InvalidConfig`] when `width` or `height` is not a positive finite
/// number, [`ReconstructError::NonFiniteInput`] for a non-finite landmark.
pub fn projection_error_eq12(
    pose2: &Pose2,
    recon: &Reconstruction,
    width: f64,
    height: f64,
) -> Result<f64, ReconstructError> {
    for (field, value) in [("image width", width), ("image height", height)] {
        if !is_positive_finite(value) {
            return Err(ReconstructError::InvalidConfig {
                field,
                value: format!("{value:?}"),
                reason: "must be a positive finite number",
            });
        }
    }
    Ok(residual_norm(pose2, recon)? / width / height)
}

/// Smallest side of the box [`projection_error_eq12_bbox`] divides by, in 2D torso lengths
/// (pelvis to neck): a pose seen edge-on (e.g. a planar skeleton from the side) has a box of
/// nearly zero width, which would blow the error up by many orders of magnitude.
pub const BBOX_FLOOR_IN_TORSOS: f64 = 0.25;

/// Eq. 12 with the image replaced by the bounding box of `pose2`'s landmarks (its width x
/// height in image units, each side floored at [`BBOX_FLOOR_IN_TORSOS`] torso lengths): the
/// normalisation used by [`crate::evaluate`], where datasets hold no image size. Computed on
/// the pose brought into range by an exact power of two ([`Pose2::within_safe_range`]), so
/// that coordinates of 1e154 or 1e-200 give the same value as ordinary ones (the error
/// scales as 1 / image unit).
///
/// # Errors
/// [`ReconstructError::NonFiniteInput`] for a non-finite landmark,
/// [`ReconstructError::DegenerateInput`] for a zero torso.
pub fn projection_error_eq12_bbox(
    pose2: &Pose2,
    recon: &Reconstruction,
) -> Result<f64, ReconstructError> {
    check_finite_landmarks(pose2)?;
    let (scaled, factor) = pose2.within_safe_range();
    let floor = BBOX_FLOOR_IN_TORSOS * scaled.torso_length();
    if !is_positive(floor) {
        return Err(ReconstructError::DegenerateInput(
            "the torso (pelvis to neck) has zero length",
        ));
    }
    let (width, height) = bounding_box(&scaled);
    let norm = scaled_residual_norm(&scaled, factor, recon);
    Ok(norm / width.max(floor) / height.max(floor) * factor)
}

/// Width and height of the axis-aligned bounding box of `pose2`'s landmarks, image units (NaN
/// for non-finite input).
pub fn bounding_box(pose2: &Pose2) -> (f64, f64) {
    let extent = |k: usize| {
        let (lo, hi) = pose2
            .points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[k]), hi.max(p[k]))
            });
        if pose2.is_finite() { hi - lo } else { f64::NAN }
    };
    (extent(0), extent(1))
}

/// Root-mean-square reprojection error per landmark divided by `pose2`'s torso length: a
/// unit-free projection error comparable across image sizes and camera distances.
///
/// # Errors
/// [`ReconstructError::NonFiniteInput`] for a non-finite landmark,
/// [`ReconstructError::DegenerateInput`] for a zero torso.
pub fn rms_error_in_torsos(pose2: &Pose2, recon: &Reconstruction) -> Result<f64, ReconstructError> {
    let norm = residual_norm(pose2, recon)?;
    let torso = pose2.torso_length();
    if !is_positive(torso) {
        return Err(ReconstructError::DegenerateInput(
            "the torso (pelvis to neck) has zero length",
        ));
    }
    Ok(norm / (NUM_LANDMARKS as f64).sqrt() / torso)
}

/// Eq. 6: `|L - projection|_2` over the 30 coordinates, image units, by the camera `recon`
/// was fitted with (computed on the pose brought into range, so that it neither overflows
/// nor underflows).
fn residual_norm(pose2: &Pose2, recon: &Reconstruction) -> Result<f64, ReconstructError> {
    check_finite_landmarks(pose2)?;
    let (scaled, factor) = pose2.within_safe_range();
    Ok(scaled_residual_norm(&scaled, factor, recon) / factor)
}

/// Eq. 6 for `scaled = factor x` the input pose (units of `scaled`): the camera is scaled
/// alike.
fn scaled_residual_norm(scaled: &Pose2, factor: f64, recon: &Reconstruction) -> f64 {
    let squared: f64 = recon
        .reprojection_scaled(factor)
        .iter()
        .zip(&scaled.points)
        .map(|(p, l)| (p[0] - l[0]).powi(2) + (p[1] - l[1]).powi(2))
        .sum();
    squared.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PerspectiveCamera;
    use camloc_geometry::{WeakPerspective, rotation_about_axis};
    use proptest::prelude::*;

    fn body() -> Pose3 {
        let mut p = [[0.0; 3]; NUM_LANDMARKS];
        for (i, x) in p.iter_mut().enumerate() {
            let t = i as f64;
            *x = [(t * 0.7).sin() * 0.3, (t * 1.3).cos() * 0.2, t * 0.1 - 0.6];
        }
        Pose3::new(p)
    }

    /// A scaled and moved truth has no error after the scale; a turned one keeps its turn.
    #[test]
    fn the_error_after_scale_keeps_the_orientation() {
        let truth = body();
        let moved = Pose3::new(
            truth
                .points
                .map(|p| [2.0 * p[0] + 1.0, 2.0 * p[1] - 3.0, 2.0 * p[2]]),
        );
        assert!(mpjpe_after_scale(&moved, &truth) < 1e-9);
        let turn = rotation_about_axis(Vector3::z(), 0.5);
        let turned = Pose3::new(truth.points.map(|p| (turn * Vector3::from(p)).into()));
        assert!(mpjpe_after_scale(&turned, &truth) > 50.0);
        assert!(mpjpe_after_similarity(&turned, &truth) < 1e-6);
        let flat = Pose3::new([[0.5; 3]; NUM_LANDMARKS]);
        assert!(mpjpe_after_scale(&flat, &truth).is_nan());
    }

    proptest! {
        /// A similarity transform of the truth has zero error; its mirror image does not.
        #[test]
        fn similarity_invariance(ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0,
                                 angle in -3.1f64..3.1, s in 0.01f64..100.0,
                                 tx in -5.0f64..5.0, ty in -5.0f64..5.0) {
            prop_assume!(ax.abs() + ay.abs() + az.abs() > 0.1);
            let r = rotation_about_axis(nalgebra::Vector3::new(ax, ay, az), angle);
            let truth = body();
            let moved = Pose3::new(truth.points.map(|p| {
                (r * Vector3::from(p) * s + Vector3::new(tx, ty, 1.0)).into()
            }));
            prop_assert!(mpjpe_after_similarity(&moved, &truth) < 1e-6);
            let mirrored = Pose3::new(moved.points.map(|p| [p[0], p[1], -p[2]]));
            prop_assert!(mpjpe_after_similarity(&mirrored, &truth) > 1.0);
        }
    }

    #[test]
    fn alignment_cannot_undo_a_moved_joint_but_never_worsens_the_fit() {
        let truth = body();
        let mut moved = truth;
        moved.points[3][0] += 0.15;
        let e = mpjpe_after_similarity(&moved, &truth);
        assert!(e > 1.0, "{e}");
        let sse = |p: &Pose3| -> f64 {
            p.points
                .iter()
                .zip(&truth.points)
                .map(|(a, t)| (Vector3::from(*a) - Vector3::from(*t)).norm_squared())
                .sum()
        };
        let aligned = align_similarity(&moved, &truth).unwrap();
        assert!(sse(&aligned) < sse(&moved));
        let mut nan = truth;
        nan.points[0][0] = f64::NAN;
        assert!(mpjpe_after_similarity(&nan, &truth).is_nan());
        // A collapsed estimate: every joint at the truth's centroid.
        let collapsed = Pose3::new([[1.0, 2.0, 3.0]; NUM_LANDMARKS]);
        let spread = align_similarity(&collapsed, &truth).unwrap();
        assert!(spread.points.windows(2).all(|w| w[0] == w[1]));
    }

    #[test]
    fn eq12_divides_the_residual_norm_by_the_area() {
        let truth = body();
        let camera = WeakPerspective {
            scale: 100.0,
            rotation: rotation_about_axis(nalgebra::Vector3::new(0.0, 0.0, 1.0), 0.3),
            translation: [320.0, 240.0],
        };
        let mut pose2 = Pose2::new(camera.project(&truth.points));
        pose2.points[4][0] += 3.0;
        pose2.points[9][1] -= 4.0;
        let recon = Reconstruction {
            pose: truth,
            camera,
            projection_error: 5.0,
            selected: vec![],
            coefficients: vec![],
            iterations: 0,
            reflected: false,
            limit_violation_rad: 0.0,
            outside_limits_rad: 0.0,
            perspective: None,
        };
        let e = projection_error_eq12(&pose2, &recon, 640.0, 480.0).unwrap();
        assert!((e - 5.0 / (640.0 * 480.0)).abs() < 1e-15);
        let (w, h) = bounding_box(&pose2);
        assert!(
            (projection_error_eq12_bbox(&pose2, &recon).unwrap() - 5.0 / (w * h)).abs() < 1e-15
        );
        let rms = rms_error_in_torsos(&pose2, &recon).unwrap();
        assert!((rms - 5.0 / 15f64.sqrt() / pose2.torso_length()).abs() < 1e-12);
        assert!(projection_error_eq12(&pose2, &recon, 0.0, 480.0).is_err());
        pose2.points[2][1] = f64::INFINITY;
        assert!(matches!(
            projection_error_eq12(&pose2, &recon, 640.0, 480.0),
            Err(ReconstructError::NonFiniteInput { landmark: 2, .. })
        ));
    }

    /// A reconstruction with a perspective camera is measured through it: its exact
    /// projection has no error, which its weak-perspective approximation would have.
    #[test]
    fn the_projection_error_uses_the_perspective_camera() {
        let truth = body();
        let rotation = rotation_about_axis(nalgebra::Vector3::new(0.0, 0.0, 1.0), 0.3);
        let perspective = PerspectiveCamera {
            rotation,
            translation: [0.0, 0.0, 2.0],
            focal_px: 800.0,
            principal_point: [320.0, 240.0],
        };
        let pose2 = Pose2::new(perspective.project(&truth.points).unwrap());
        let mut recon = Reconstruction {
            pose: truth,
            camera: WeakPerspective {
                scale: 400.0,
                rotation,
                translation: [320.0, 240.0],
            },
            projection_error: 0.0,
            selected: vec![],
            coefficients: vec![],
            iterations: 0,
            reflected: false,
            limit_violation_rad: 0.0,
            outside_limits_rad: 0.0,
            perspective: Some(perspective),
        };
        assert!(projection_error_eq12_bbox(&pose2, &recon).unwrap() < 1e-12);
        recon.perspective = None;
        assert!(projection_error_eq12_bbox(&pose2, &recon).unwrap() > 1e-6);
    }
}
