//! Joint rotations of the BVH skeleton ([`JOINTS`]) from the landmarks of one frame, with the
//! twist and the Euler angles chosen to stay close to the previous frame's.

use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS};

use super::bvh_skeleton::{JOINTS, JointRole};
use super::rotation::{Rot3, cross, dot, sub, unit};

/// Swing angle (radians) of a bone from its rest direction, relative to its parent, from
/// which its twist starts to follow the previous frame's instead of the smallest rotation
/// (120 degrees); it follows the previous frame alone from [`TWIST_FOLLOWS_FULLY`].
const TWIST_FOLLOWS_FROM: f64 = 120.0 * std::f64::consts::PI / 180.0;
/// See [`TWIST_FOLLOWS_FROM`] (170 degrees).
const TWIST_FOLLOWS_FULLY: f64 = 170.0 * std::f64::consts::PI / 180.0;

/// Share of a lateral line's length that must lie across the up axis for it to set a body
/// frame (about 0.06 degrees off the axis).
const MIN_LATERAL_SHARE: f64 = 1e-3;

/// Solves frame after frame, remembering the previous frame's rotations and angles.
pub(crate) struct Solver {
    /// Per joint, its rotation relative to its parent in the previous frame.
    previous_local: Vec<Option<Rot3>>,
    /// Per joint, its Euler angles (radians) in the previous frame.
    previous_angles: Vec<Option<[f64; 3]>>,
    /// Per joint, the x axis of its world frame in the previous frame.
    previous_x: Vec<Option<[f64; 3]>>,
}

impl Solver {
    /// A solver before the first frame.
    pub(crate) fn new() -> Solver {
        Solver {
            previous_local: vec![None; JOINTS.len()],
            previous_angles: vec![None; JOINTS.len()],
            previous_x: vec![None; JOINTS.len()],
        }
    }

    /// The Euler angles (radians, each joint's channel order) of every joint of [`JOINTS`]
    /// for one frame, `points` being the landmarks in the file frame. Every limb must have a
    /// direction (checked by the caller).
    pub(crate) fn frame(&mut self, points: &[[f64; 3]; NUM_LANDMARKS]) -> Vec<[f64; 3]> {
        let at = |l: Landmark| points[l.index()];
        let line = |(a, b): (Landmark, Landmark)| sub(at(b), at(a));
        let mut world = Vec::with_capacity(JOINTS.len());
        let mut angles = Vec::with_capacity(JOINTS.len());
        for (j, joint) in JOINTS.iter().enumerate() {
            let parent = joint
                .parent
                .and_then(|p| world.get(p).copied())
                .unwrap_or(Rot3::IDENTITY);
            let local = match joint.role {
                JointRole::Body {
                    up,
                    lateral,
                    fallback,
                } => {
                    let frame = body_frame(
                        line(up),
                        &[
                            Some(line(lateral)),
                            Some(line(fallback)),
                            self.previous_x[j],
                        ],
                    );
                    self.previous_x[j] = Some([frame.0[0][0], frame.0[1][0], frame.0[2][0]]);
                    parent.transpose().mul(&frame)
                }
                JointRole::Bone { limb } => {
                    let direction = unit(line(LIMBS[limb])).unwrap_or(joint.rest);
                    let in_parent = parent.transpose().apply(direction);
                    bone_rotation(joint.rest, in_parent, self.previous_local[j].as_ref())
                }
                JointRole::Leaf => Rot3::IDENTITY,
            };
            let a = joint.order.decompose(&local, self.previous_angles[j]);
            self.previous_angles[j] = Some(a);
            self.previous_local[j] = Some(local);
            world.push(parent.mul(&local));
            angles.push(a);
        }
        angles
    }
}

/// The frame whose y axis is `up` (not zero) and whose x axis is the part across `up` of the
/// first of `laterals` that has one; z completes it (x cross y, forward for a body whose left
/// is x). With none, x is the smallest turn of the file's x axis.
fn body_frame(up: [f64; 3], laterals: &[Option<[f64; 3]>]) -> Rot3 {
    let y = unit(up).unwrap_or([0.0, 1.0, 0.0]);
    let across = laterals.iter().flatten().find_map(|&v| {
        let along = dot(v, y);
        let perpendicular = sub(v, y.map(|c| c * along));
        let share = perpendicular.iter().map(|c| c * c).sum::<f64>().sqrt()
            / v.iter().map(|c| c * c).sum::<f64>().sqrt();
        (share > MIN_LATERAL_SHARE)
            .then(|| unit(perpendicular))
            .flatten()
    });
    let x = across.unwrap_or_else(|| Rot3::swing([0.0, 1.0, 0.0], y).apply([1.0, 0.0, 0.0]));
    Rot3::from_columns(x, y, cross(x, y))
}

/// The rotation, relative to the parent, that turns `rest` onto `direction` (unit vectors in
/// the parent's frame): the smallest such rotation, its twist about `rest` blended towards
/// the one closest to `previous` as the bone nears the direction opposite to `rest`, where
/// the smallest rotation is ill-defined.
fn bone_rotation(rest: [f64; 3], direction: [f64; 3], previous: Option<&Rot3>) -> Rot3 {
    let swing = Rot3::swing(rest, direction);
    let angle = dot(rest, direction).clamp(-1.0, 1.0).acos();
    let follow =
        ((angle - TWIST_FOLLOWS_FROM) / (TWIST_FOLLOWS_FULLY - TWIST_FOLLOWS_FROM)).clamp(0.0, 1.0);
    let Some(previous) = previous.filter(|_| follow > 0.0) else {
        return swing;
    };
    // Maximise (1 - w) tr(Rot(t)) + w tr(P^T S Rot(t)) over the twist t, with
    // tr(M Rot(t)) = cos t (tr M - a.Ma) + sin t tr(M [a]x) + a.Ma.
    let w = follow * follow * (3.0 - 2.0 * follow);
    let m = previous.transpose().mul(&swing);
    let ma = m.apply(rest);
    let skew = Rot3([
        [0.0, -rest[2], rest[1]],
        [rest[2], 0.0, -rest[0]],
        [-rest[1], rest[0], 0.0],
    ]);
    let cos_weight = (1.0 - w) * 2.0 + w * (m.trace() - dot(rest, ma));
    let sin_weight = w * m.mul(&skew).trace();
    swing.mul(&Rot3::about_unit(rest, sin_weight.atan2(cos_weight)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angle_between(a: &Rot3, b: &Rot3) -> f64 {
        ((a.transpose().mul(b).trace() - 1.0) / 2.0)
            .clamp(-1.0, 1.0)
            .acos()
    }

    #[test]
    fn a_bone_through_its_opposite_direction_turns_smoothly() {
        // A forearm-like bone along +x swept through -x (and beyond) in small steps: the
        // smallest rotation flips its twist by a half turn near -x; the chosen one may not.
        let rest = [1.0, 0.0, 0.0];
        let mut previous: Option<Rot3> = None;
        for step in 0..=180 {
            let t = (60.0 + step as f64).to_radians();
            // Tilted a little out of the xy plane so that the path misses -x itself.
            let direction = unit([t.cos(), t.sin(), 0.02]).unwrap_or(rest);
            let r = bone_rotation(rest, direction, previous.as_ref());
            let got = r.apply(rest);
            for k in 0..3 {
                assert!((got[k] - direction[k]).abs() < 1e-12);
            }
            if let Some(p) = previous {
                let turn = angle_between(&p, &r).to_degrees();
                assert!(turn < 3.0, "step {step}: turned {turn} deg in one step");
            }
            previous = Some(r);
        }
    }

    #[test]
    fn body_frames_are_rotations_along_up_and_fall_back_on_later_lines() {
        let up = [0.1, 2.0, -0.3];
        for laterals in [
            vec![Some([1.0, 0.2, 0.1])],
            vec![Some(up), Some([0.0, 0.0, -1.0])],
            vec![Some([0.0; 3]), None],
        ] {
            let f = body_frame(up, &laterals);
            let y = unit(up).unwrap_or_default();
            for (row, y) in f.0.iter().zip(y) {
                assert!((row[1] - y).abs() < 1e-12);
            }
            let ftf = f.transpose().mul(&f);
            assert!(angle_between(&ftf, &Rot3::IDENTITY) < 1e-9);
            let det = dot(
                [f.0[0][0], f.0[1][0], f.0[2][0]],
                cross(
                    [f.0[0][1], f.0[1][1], f.0[2][1]],
                    [f.0[0][2], f.0[1][2], f.0[2][2]],
                ),
            );
            assert!((det - 1.0).abs() < 1e-12);
        }
    }
}
