//! Rotation helpers.

use crate::{GeometryError, Matrix3, Vector3};

/// Rotation by `angle` radians about the world z axis (right-handed, counter-clockwise seen from
/// above).
pub fn rotation_about_z(angle: f64) -> Matrix3 {
    let (s, c) = angle.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Rotation by `angle` radians about `axis` (any length; Rodrigues); a zero or non-finite axis
/// gives the identity.
pub fn rotation_about_axis(axis: Vector3, angle: f64) -> Matrix3 {
    match direction(&axis) {
        Some(unit) => nalgebra::Rotation3::from_axis_angle(&unit, angle).into_inner(),
        None => Matrix3::identity(),
    }
}

/// The smallest rotation taking the direction of `from` to that of `to` (vectors of any
/// length): the identity for parallel directions, `None` for opposite ones (no single smallest
/// rotation) or a zero or non-finite vector. The angle is `atan2(|a x b|, a . b)` of the unit
/// directions, exact near parallel directions, where nalgebra's `Rotation3::rotation_between`
/// takes `acos` of a dot product that rounds above 1 and gives NaN.
pub fn rotation_between(from: &Vector3, to: &Vector3) -> Option<Matrix3> {
    let (a, b) = (direction(from)?, direction(to)?);
    let cross = a.cross(&b);
    let (sin, cos) = (cross.norm(), a.dot(&b));
    if sin <= 1e-15 {
        return (cos > 0.0).then(Matrix3::identity);
    }
    Some(rotation_about_axis(cross, sin.atan2(cos)))
}

/// The unit direction of `v`, scaled by its largest entry before its norm is taken (so that
/// neither overflows nor underflows); `None` for a zero or non-finite vector.
fn direction(v: &Vector3) -> Option<nalgebra::Unit<Vector3>> {
    let largest = v.amax();
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let scaled = v / largest;
    Some(nalgebra::Unit::new_normalize(scaled))
}

/// A camera rotation rolled by `angle` radians about its own optical axis (row 3 unchanged; the
/// image axes turn by `angle`).
pub fn roll_about_optical_axis(rotation: &Matrix3, angle: f64) -> Matrix3 {
    let (s, c) = angle.sin_cos();
    Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0) * rotation
}

/// Checks that `r` is a proper rotation: `R R^T = I` to `tol` (max entry) and `det R = +1` to
/// `tol`.
pub fn check_rotation(r: &Matrix3, tol: f64) -> Result<(), GeometryError> {
    let orthonormality_error = (r * r.transpose() - Matrix3::identity()).abs().max();
    let determinant = r.determinant();
    if orthonormality_error <= tol && (determinant - 1.0).abs() <= tol {
        Ok(())
    } else {
        Err(GeometryError::NotARotation {
            orthonormality_error,
            determinant,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn rotations_are_proper(ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0,
                                angle in -10.0f64..10.0, roll in -3.2f64..3.2) {
            let r = rotation_about_axis(Vector3::new(ax, ay, az), angle);
            prop_assert!(check_rotation(&r, 1e-12).is_ok());
            prop_assert!(check_rotation(&roll_about_optical_axis(&r, roll), 1e-12).is_ok());
            prop_assert!(check_rotation(&rotation_about_z(angle), 1e-12).is_ok());
        }
    }

    proptest! {
        /// Near-parallel and badly scaled directions (a simulated review found nalgebra's
        /// `rotation_between` NaN for a third of near-parallel pairs).
        #[test]
        fn the_rotation_between_two_directions_is_proper_and_takes_one_to_the_other(
            ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0,
            tilt in prop::sample::select(vec![0.0, 1e-17, 1e-12, 1e-8, 1e-3, 0.5]),
            scale_exponent in -160i32..160,
        ) {
            let from = Vector3::new(ax, ay, az);
            prop_assume!(from.norm() > 1e-3);
            let to = (from.normalize() + Vector3::new(-ay, ax, 0.3) * tilt)
                * 10f64.powi(scale_exponent);
            let r = rotation_between(&from, &to).unwrap();
            prop_assert!(check_rotation(&r, 1e-12).is_ok());
            let unit = |v: Vector3| (v / v.amax()).normalize();
            prop_assert!((r * unit(from) - unit(to)).norm() < 1e-12);
            let axis = Vector3::new(ax, ay, az) * 10f64.powi(scale_exponent);
            prop_assert!(check_rotation(&rotation_about_axis(axis, 0.7), 1e-12).is_ok());
        }
    }

    #[test]
    fn opposite_or_empty_directions_have_no_rotation_between_them() {
        let x = Vector3::new(1.0, 0.0, 0.0);
        assert!(rotation_between(&x, &-x).is_none());
        assert!(rotation_between(&x, &Vector3::zeros()).is_none());
        assert!(rotation_between(&x, &Vector3::new(f64::NAN, 0.0, 0.0)).is_none());
        assert_eq!(rotation_between(&x, &(x * 3.0)), Some(Matrix3::identity()));
    }

    #[test]
    fn reflection_is_refused() {
        let m = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
        assert!(matches!(
            check_rotation(&m, 1e-9),
            Err(GeometryError::NotARotation { .. })
        ));
    }

    #[test]
    fn roll_keeps_optical_axis() {
        let r = rotation_about_axis(Vector3::new(0.3, -0.2, 0.9), 0.7);
        let rolled = roll_about_optical_axis(&r, 0.4);
        assert!((rolled.row(2) - r.row(2)).norm() < 1e-15);
    }
}
