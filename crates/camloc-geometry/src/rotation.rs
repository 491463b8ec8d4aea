//! Rotation helpers.

use crate::{GeometryError, Matrix3, Vector3};

/// Rotation by `angle` radians about the world z axis (right-handed, counter-clockwise seen from
/// above).
pub fn rotation_about_z(angle: f64) -> Matrix3 {
    let (s, c) = angle.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Rotation by `angle` radians about a unit `axis` (Rodrigues); a zero axis gives the identity.
pub fn rotation_about_axis(axis: Vector3, angle: f64) -> Matrix3 {
    let n = axis.norm();
    if !(n > 0.0) || !n.is_finite() {
        return Matrix3::identity();
    }
    nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_unchecked(axis / n), angle)
        .into_inner()
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
