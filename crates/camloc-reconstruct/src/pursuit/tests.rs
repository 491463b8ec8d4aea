//! Tests of the pursuit's geometric helpers.

use camloc_geometry::{Vector3, WeakPerspective, rotation_about_axis};
use camloc_skeleton::{NUM_LANDMARKS, Pose3};
use proptest::prelude::*;

use super::camera_update::with_optimal_translation;
use super::reflection::depth_reflection;

fn cloud(seed: f64) -> [[f64; 3]; NUM_LANDMARKS] {
    let mut p = [[0.0; 3]; NUM_LANDMARKS];
    for (i, x) in p.iter_mut().enumerate() {
        let t = i as f64 + seed;
        *x = [(t * 0.7).sin() * 0.3, (t * 1.3).cos() * 0.2, t * 0.1 - 0.6];
    }
    p
}

proptest! {
    /// The depth reflection keeps every projection, is an involution, reverses
    /// handedness (negative triple product) and keeps limb lengths, for any proper camera.
    #[test]
    fn depth_reflection_keeps_projection(ax in -1.0f64..1.0, ay in -1.0f64..1.0,
                                         az in -1.0f64..1.0, angle in -3.1f64..3.1,
                                         s in 0.1f64..10.0, seed in 0.0f64..10.0) {
        prop_assume!(ax.abs() + ay.abs() + az.abs() > 0.1);
        let r = rotation_about_axis(Vector3::new(ax, ay, az), angle);
        let cam = WeakPerspective { scale: s, rotation: r, translation: [1.0, -2.0] };
        let x = cloud(seed);
        let y = depth_reflection(&x, &r);
        for (p, q) in cam.project(&x).iter().zip(cam.project(&y)) {
            prop_assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
        }
        let back = depth_reflection(&y, &r);
        for (p, q) in x.iter().zip(&back) {
            prop_assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-12));
        }
        let triple = |p: &[[f64; 3]; NUM_LANDMARKS]| {
            let v = |i: usize| Vector3::from(p[i]) - Vector3::from(p[0]);
            v(1).cross(&v(2)).dot(&v(3))
        };
        prop_assert!((triple(&x) + triple(&y)).abs() < 1e-12);
        let px = Pose3::new(x);
        let py = Pose3::new(y);
        for limb in 0..camloc_skeleton::NUM_LIMBS {
            prop_assert!((px.limb_length(limb) - py.limb_length(limb)).abs() < 1e-12);
        }
    }
}

#[test]
fn optimal_translation_centres_the_residual() {
    let r = rotation_about_axis(Vector3::new(0.2, 0.5, -0.4), 1.1);
    let cam = WeakPerspective {
        scale: 2.0,
        rotation: r,
        translation: [5.0, 7.0],
    };
    let x = cloud(0.3);
    let shifted = cam.project(&x).map(|p| [p[0] - 3.0, p[1] + 1.5]);
    let fixed = with_optimal_translation(&cam, &x, &shifted);
    assert!((fixed.translation[0] - 2.0).abs() < 1e-12);
    assert!((fixed.translation[1] - 8.5).abs() < 1e-12);
    assert!(fixed.squared_error(&x, &shifted).unwrap() < 1e-20);
}
