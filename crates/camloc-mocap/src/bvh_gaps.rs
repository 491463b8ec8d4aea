//! Frames missing from one person's animation ([`fill_missing_frames`]): between two poses
//! they are turned from one to the other, before the first and after the last they hold it.

use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, Pose3};

/// `frames` with each missing frame (`None`) filled: between two poses, the pose
/// [`between`] them at its place in time; before the first pose and after the last, that
/// pose. `None` when there is no pose at all.
pub(crate) fn fill_missing_frames(frames: &[Option<Pose3>]) -> Option<Vec<Pose3>> {
    let first = *frames.iter().flatten().next()?;
    let mut filled = Vec::with_capacity(frames.len());
    // The last pose seen and its frame.
    let mut last: Option<(usize, Pose3)> = None;
    for (t, frame) in frames.iter().enumerate() {
        let Some(pose) = frame else { continue };
        if let Some((s, before)) = last {
            for gap in s + 1..t {
                let f = (gap - s) as f64 / (t - s) as f64;
                filled.push(between(&before, pose, f));
            }
        } else {
            filled.extend(std::iter::repeat_n(first, t));
        }
        filled.push(*pose);
        last = Some((t, *pose));
    }
    if let Some((s, pose)) = last {
        filled.extend(std::iter::repeat_n(pose, frames.len() - 1 - s));
    }
    Some(filled)
}

/// The pose the share `f` (0..=1) of the way from `a` to `b`: the pelvis moved along the
/// straight line, each limb's direction turned along the great circle and its length
/// changed in proportion (a limb pointing the opposite way switches at half way).
pub(crate) fn between(a: &Pose3, b: &Pose3, f: f64) -> Pose3 {
    let lerp = |p: [f64; 3], q: [f64; 3], f: f64| -> [f64; 3] {
        std::array::from_fn(|k| p[k] + (q[k] - p[k]) * f)
    };
    let mut points = [[0.0; 3]; NUM_LANDMARKS];
    let pelvis = Landmark::Pelvis.index();
    points[pelvis] = lerp(a.points[pelvis], b.points[pelvis], f);
    for &(parent, child) in &LIMBS {
        let limb = |p: &Pose3| -> ([f64; 3], f64) {
            let d: [f64; 3] =
                std::array::from_fn(|k| p.points[child.index()][k] - p.points[parent.index()][k]);
            let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if length > 0.0 {
                (d.map(|c| c / length), length)
            } else {
                ([0.0; 3], 0.0)
            }
        };
        let ((u, la), (v, lb)) = (limb(a), limb(b));
        let cos = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]).clamp(-1.0, 1.0);
        let angle = cos.acos();
        // Too close to one direction or to opposite ones for a great circle: switch half way.
        let direction = if angle < 1e-9 || std::f64::consts::PI - angle < 1e-6 || la * lb == 0.0 {
            if f < 0.5 { u } else { v }
        } else {
            let (wa, wb) = (
                ((1.0 - f) * angle).sin() / angle.sin(),
                (f * angle).sin() / angle.sin(),
            );
            std::array::from_fn(|k| wa * u[k] + wb * v[k])
        };
        let length = la + (lb - la) * f;
        let from = points[parent.index()];
        points[child.index()] = std::array::from_fn(|k| from[k] + direction[k] * length);
    }
    Pose3 { points }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pose whose limbs all point along `direction` from the pelvis at `pelvis`, each
    /// 0.3 m long.
    fn pointing(pelvis: [f64; 3], direction: [f64; 3]) -> Pose3 {
        let mut points = [pelvis; NUM_LANDMARKS];
        for &(parent, child) in &LIMBS {
            let from = points[parent.index()];
            points[child.index()] = std::array::from_fn(|k| from[k] + 0.3 * direction[k]);
        }
        Pose3 { points }
    }

    #[test]
    fn missing_frames_are_turned_between_poses_and_hold_at_the_ends() {
        let a = pointing([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let b = pointing([0.4, 0.0, 1.0], [0.0, 1.0, 0.0]);
        let filled =
            fill_missing_frames(&[None, Some(a), None, None, None, Some(b), None]).unwrap();
        assert_eq!(filled.len(), 7);
        assert_eq!((filled[0], filled[1], filled[5], filled[6]), (a, a, b, b));
        // Half way: the pelvis half way, each limb turned by 45 deg and as long.
        let half = filled[3];
        let pelvis = half.get(Landmark::Pelvis);
        assert!((pelvis[0] - 0.2).abs() < 1e-12);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        for (k, &(parent, child)) in LIMBS.iter().enumerate() {
            let (p, c) = (half.get(parent), half.get(child));
            let d = [c[0] - p[0], c[1] - p[1], c[2] - p[2]];
            assert!((half.limb_length(k) - 0.3).abs() < 1e-12);
            assert!((d[0] - 0.3 * s).abs() < 1e-12 && (d[1] - 0.3 * s).abs() < 1e-12);
        }
        assert_eq!(fill_missing_frames(&[None, None]), None);
    }

    #[test]
    fn a_limb_turned_the_opposite_way_switches_half_way() {
        let a = pointing([0.0; 3], [1.0, 0.0, 0.0]);
        let b = pointing([0.0; 3], [-1.0, 0.0, 0.0]);
        assert_eq!(between(&a, &b, 0.25), a);
        assert_eq!(between(&a, &b, 0.75), b);
    }
}
