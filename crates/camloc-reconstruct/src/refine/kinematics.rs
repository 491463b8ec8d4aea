//! The skeleton as bone directions and lengths: forward kinematics from the pelvis, the limbs
//! on each landmark's path, tangent bases of a direction.

use camloc_skeleton::{LIMBS, NUM_LANDMARKS, NUM_LIMBS, Pose3};
use nalgebra::Vector3;

/// Most limbs between the pelvis and a landmark (the wrists: torso, collar, upper arm,
/// forearm).
pub(super) const MAX_CHAIN: usize = 4;

/// The limbs on the path from the pelvis to each landmark, by landmark index, from the
/// pelvis outwards: `(limbs, count)`.
pub(super) fn chains() -> [([usize; MAX_CHAIN], usize); NUM_LANDMARKS] {
    let mut out = [([0; MAX_CHAIN], 0); NUM_LANDMARKS];
    // LIMBS lists every parent before its children: a child's chain is its parent's plus
    // the limb itself.
    for (b, (parent, child)) in LIMBS.iter().enumerate() {
        let (mut chain, n) = out[parent.index()];
        if n < MAX_CHAIN {
            chain[n] = b;
            out[child.index()] = (chain, n + 1);
        }
    }
    out
}

/// The landmarks of the skeleton with limb `lengths` (metres) along unit `directions`, the
/// pelvis at the origin.
pub(super) fn forward(
    lengths: &[f64; NUM_LIMBS],
    directions: &[Vector3<f64>; NUM_LIMBS],
) -> [Vector3<f64>; NUM_LANDMARKS] {
    let mut points = [Vector3::zeros(); NUM_LANDMARKS];
    for (b, (parent, child)) in LIMBS.iter().enumerate() {
        points[child.index()] = points[parent.index()] + directions[b] * lengths[b];
    }
    points
}

/// The unit direction of each limb of `pose`; `fallback` where a limb has no length.
pub(super) fn directions_of(pose: &Pose3, fallback: Vector3<f64>) -> [Vector3<f64>; NUM_LIMBS] {
    std::array::from_fn(|b| {
        let (parent, child) = LIMBS[b];
        (Vector3::from(pose.get(child)) - Vector3::from(pose.get(parent)))
            .try_normalize(1e-12)
            .unwrap_or(fallback)
    })
}

/// Two unit vectors orthogonal to the unit `d` and to each other (`e2 = d x e1`).
pub(super) fn tangent_basis(d: &Vector3<f64>) -> [Vector3<f64>; 2] {
    // The axis least aligned with d keeps the cross product well away from zero.
    let axis = if d.x.abs() <= d.y.abs() && d.x.abs() <= d.z.abs() {
        Vector3::x()
    } else if d.y.abs() <= d.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let e1 = d.cross(&axis).normalize();
    [e1, d.cross(&e1)]
}

/// `d` turned by `step[0] e1 + step[1] e2` in its tangent plane and normalised.
pub(super) fn moved(d: &Vector3<f64>, step: [f64; 2]) -> Vector3<f64> {
    let [e1, e2] = tangent_basis(d);
    (d + e1 * step[0] + e2 * step[1])
        .try_normalize(1e-12)
        .unwrap_or(*d)
}

/// The pose of the landmarks `points` (metres).
pub(super) fn to_pose(points: &[Vector3<f64>; NUM_LANDMARKS]) -> Pose3 {
    Pose3::new(points.map(Into::into))
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::Landmark;

    #[test]
    fn chains_run_from_the_pelvis() {
        let c = chains();
        assert_eq!(c[Landmark::Pelvis.index()].1, 0);
        assert_eq!(c[Landmark::LeftKnee.index()], ([0, 1, 0, 0], 2));
        assert_eq!(c[Landmark::RightWrist.index()], ([6, 11, 12, 13], 4));
    }

    #[test]
    fn forward_kinematics_rebuilds_a_pose() {
        let mut pose = Pose3::new([[0.0; 3]; NUM_LANDMARKS]);
        for (i, p) in pose.points.iter_mut().enumerate().skip(1) {
            let t = i as f64;
            *p = [(t * 0.7).sin() * 0.4, (t * 1.3).cos() * 0.3, t * 0.05 - 0.3];
        }
        let lengths = std::array::from_fn(|b| pose.limb_length(b));
        let rebuilt = to_pose(&forward(&lengths, &directions_of(&pose, Vector3::z())));
        for (a, b) in rebuilt.points.iter().zip(&pose.points) {
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-12));
        }
        for d in [Vector3::x(), Vector3::new(0.3, -0.2, 0.9).normalize()] {
            let [e1, e2] = tangent_basis(&d);
            assert!(e1.dot(&d).abs() < 1e-12 && e2.dot(&d).abs() < 1e-12);
            assert!(e1.dot(&e2).abs() < 1e-12 && (e2.norm() - 1.0).abs() < 1e-12);
            assert!((moved(&d, [0.1, -0.2]).norm() - 1.0).abs() < 1e-12);
        }
    }
}
