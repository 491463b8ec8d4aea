//! The orthogonal Procrustes weak-perspective camera (OPT, eq. 3).

use nalgebra::{Matrix2x3, Matrix3x2, SVD};

use crate::camera::{check_finite, check_same_len, mean2};
use crate::{GeometryError, Matrix3, Vector3, WeakPerspective};

/// The weak-perspective camera that best maps `points3` (metres) onto `points2` (image units),
/// by eq. 3: the least-squares linear map `T = L X^T (X X^T)^-1` of the centred points, made a
/// scaled rotation through its SVD `T = U D V^T`, `R_2 = U V^T` (the two image rows). The third
/// row is `r1 x r2`, so `det R = +1`. The scale is then the least-squares scale for `R`, and the
/// translation maps the 3D centroid onto the 2D centroid.
///
/// Noiseless projections of three or more non-coplanar points are recovered exactly.
///
/// # Errors
/// [`GeometryError::Size`] for mismatched or fewer than 3 points, [`GeometryError::NonFinite`]
/// for NaN/inf, [`GeometryError::Degenerate`] when the points do not determine a camera (all 3D
/// points collinear, or all 2D points coincide).
pub fn procrustes_camera(
    points3: &[[f64; 3]],
    points2: &[[f64; 2]],
) -> Result<WeakPerspective, GeometryError> {
    check_same_len(points3.len(), points2.len())?;
    if points3.len() < 3 {
        return Err(GeometryError::Size {
            what: "Procrustes points",
            expected: "at least 3".into(),
            got: points3.len(),
        });
    }
    check_finite(points3, points2)?;
    let n = points3.len() as f64;
    let xm = points3
        .iter()
        .fold(Vector3::zeros(), |a, x| a + Vector3::from(*x))
        / n;
    let lm = mean2(points2);

    // Moments of the centred points: C = sum x x^T (3x3), M = sum l x^T (2x3).
    let mut c = Matrix3::zeros();
    let mut m = Matrix2x3::zeros();
    for (x, l) in points3.iter().zip(points2) {
        let xc = Vector3::from(*x) - xm;
        let lc = nalgebra::Vector2::new(l[0] - lm[0], l[1] - lm[1]);
        c += xc * xc.transpose();
        m += lc * xc.transpose();
    }
    // T = M C^+ (pseudo-inverse so that planar 3D points still give a camera).
    let c_svd = SVD::new(c, true, true);
    let c_max = c_svd.singular_values.max();
    if !(c_max > 0.0) {
        return Err(GeometryError::Degenerate("all 3D points coincide"));
    }
    let c_pinv = c_svd
        .pseudo_inverse(c_max * 1e-12)
        .map_err(|_| GeometryError::Degenerate("3D moment matrix has no pseudo-inverse"))?;
    let t = m * c_pinv;
    let t_svd = SVD::new(t, true, true);
    let (Some(u), Some(v_t)) = (t_svd.u, t_svd.v_t) else {
        return Err(GeometryError::Degenerate("SVD of the linear camera failed"));
    };
    if !(t_svd.singular_values[0] > 0.0) {
        return Err(GeometryError::Degenerate(
            "the 2D points do not vary along any direction explained by the 3D points",
        ));
    }
    let v_t = if t_svd.singular_values[1] <= t_svd.singular_values[0] * 1e-12 {
        rank_one_completion(&v_t, &c)?
    } else {
        v_t
    };
    let r2 = u * v_t; // 2x3, orthonormal rows
    let r1: Vector3 = r2.row(0).transpose();
    let r2v: Vector3 = r2.row(1).transpose();
    let rotation =
        Matrix3::from_rows(&[r1.transpose(), r2v.transpose(), r1.cross(&r2v).transpose()]);
    // Least-squares scale for this rotation: s = <L_c, R2 X_c> / |R2 X_c|^2.
    let r2_t: Matrix3x2<f64> = r2.transpose();
    let num = (m * r2_t).trace();
    let den = (r2 * c * r2_t).trace();
    if !(den > 0.0) {
        return Err(GeometryError::Degenerate(
            "3D points project to a single point",
        ));
    }
    let scale = num / den;
    let pm = r2 * xm;
    Ok(WeakPerspective {
        scale,
        rotation,
        translation: [lm[0] - scale * pm[0], lm[1] - scale * pm[1]],
    })
}

/// The right singular vectors of a rank-1 linear camera, completed: the 2D points lie on a
/// line (e.g. a planar skeleton seen edge-on), so only the first image axis has a 3D direction
/// `v1`; the second image axis, along which the 2D points do not spread, gets the direction
/// orthogonal to `v1` along which the 3D points spread least (smallest eigenvector of their
/// moment matrix `c` restricted to the plane orthogonal to `v1`), which is the least-squares
/// choice. Its sign is arbitrary (the two signs are depth-mirrored cameras).
fn rank_one_completion(v_t: &Matrix2x3<f64>, c: &Matrix3) -> Result<Matrix2x3<f64>, GeometryError> {
    let v1: Vector3 = v_t.row(0).transpose();
    // An orthonormal basis (a, b) of the plane orthogonal to v1.
    let axis = if v1.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let a = v1.cross(&axis).normalize();
    let b = v1.cross(&a);
    let m = nalgebra::Matrix2::new(
        a.dot(&(c * a)),
        a.dot(&(c * b)),
        b.dot(&(c * a)),
        b.dot(&(c * b)),
    );
    let eig = nalgebra::SymmetricEigen::new(m);
    let i = if eig.eigenvalues[0] <= eig.eigenvalues[1] {
        0
    } else {
        1
    };
    let e = eig.eigenvectors.column(i);
    let r2 = (a * e[0] + b * e[1]).normalize();
    if !r2.iter().all(|x| x.is_finite()) {
        return Err(GeometryError::Degenerate(
            "the 2D points are collinear and no second camera axis can be chosen",
        ));
    }
    Ok(Matrix2x3::from_rows(&[v1.transpose(), r2.transpose()]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{check_rotation, rotation_about_axis};
    use proptest::prelude::*;

    fn body() -> [[f64; 3]; 15] {
        let mut p = [[0.0; 3]; 15];
        for (i, x) in p.iter_mut().enumerate() {
            let t = i as f64;
            *x = [(t * 0.7).sin() * 0.3, (t * 1.3).cos() * 0.2, t * 0.1 - 0.6];
        }
        p
    }

    proptest! {
        #[test]
        fn recovers_rotation_scale_translation(ax in -1.0f64..1.0, ay in -1.0f64..1.0, az in -1.0f64..1.0,
                                               angle in -3.1f64..3.1, s in 0.05f64..500.0,
                                               tx in -100.0f64..100.0, ty in -100.0f64..100.0) {
            prop_assume!(ax.abs() + ay.abs() + az.abs() > 0.1);
            let r = rotation_about_axis(Vector3::new(ax, ay, az), angle);
            let cam = WeakPerspective { scale: s, rotation: r, translation: [tx, ty] };
            let fit = procrustes_camera(&body(), &cam.project(&body())).unwrap();
            prop_assert!(check_rotation(&fit.rotation, 1e-9).is_ok());
            prop_assert!((fit.rotation - r).abs().max() < 1e-8, "rotation error {}", (fit.rotation - r).abs().max());
            prop_assert!((fit.scale - s).abs() < 1e-8 * s);
            prop_assert!((fit.translation[0] - tx).abs() < 1e-7 * s.max(1.0));
            prop_assert!((fit.translation[1] - ty).abs() < 1e-7 * s.max(1.0));
        }
    }

    #[test]
    fn degenerate_inputs_are_errors() {
        let same = [[1.0, 2.0, 3.0]; 4];
        assert!(procrustes_camera(&same, &[[0.0, 0.0]; 4]).is_err());
        assert!(procrustes_camera(&body()[..2], &[[0.0, 0.0]; 2]).is_err());
        let flat2 = [[5.0, 5.0]; 15];
        assert!(matches!(
            procrustes_camera(&body(), &flat2),
            Err(GeometryError::Degenerate(_))
        ));
    }

    #[test]
    fn a_planar_body_seen_edge_on_gets_an_exact_camera() {
        // All points in the plane x = 0 (a planar skeleton), seen by cameras looking along
        // the plane: the 2D points are collinear.
        let planar = body().map(|p| [0.0, p[1], p[2]]);
        for angle in [0.0, 0.4, -1.2] {
            let r = rotation_about_axis(Vector3::z(), std::f64::consts::FRAC_PI_2)
                * rotation_about_axis(Vector3::x(), angle);
            let cam = WeakPerspective {
                scale: 3.0,
                rotation: r,
                translation: [10.0, -4.0],
            };
            let projected = cam.project(&planar);
            let spread_u = projected
                .iter()
                .map(|p| p[0])
                .fold(f64::NEG_INFINITY, f64::max)
                - projected.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min);
            let spread_v = projected
                .iter()
                .map(|p| p[1])
                .fold(f64::NEG_INFINITY, f64::max)
                - projected.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
            assert!(spread_u.min(spread_v) < 1e-12, "the view is edge-on");
            let fit = procrustes_camera(&planar, &projected).unwrap();
            assert!(check_rotation(&fit.rotation, 1e-9).is_ok());
            let error = fit.squared_error(&planar, &projected).unwrap();
            assert!(error < 1e-18, "angle {angle}: squared error {error}");
        }
    }
}
