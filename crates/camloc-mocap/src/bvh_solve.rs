//! Joint rotations of the BVH skeleton ([`JOINTS`]) from the landmarks of one frame, with the
//! twist and the Euler angles chosen to stay close to the previous frame's.

use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS};

use super::bvh_skeleton::{Hinge, JOINTS, JointRole};
use super::rotation::{Rot3, cross, dot, sub, unit};

/// Swing angle (radians) of a bone from its rest direction, relative to its parent, from
/// which its twist starts to follow the previous frame's instead of the smallest rotation
/// (120 degrees); it follows the previous frame alone from [`TWIST_FOLLOWS_FULLY`].
const TWIST_FOLLOWS_FROM: f64 = 120.0 * std::f64::consts::PI / 180.0;
/// See [`TWIST_FOLLOWS_FROM`] (170 degrees).
const TWIST_FOLLOWS_FULLY: f64 = 170.0 * std::f64::consts::PI / 180.0;

/// Bend (radians) of a knee below which its plane is too uncertain to set the twist of the
/// thigh above it (20 degrees); the knee sets it fully from [`HINGE_SETS_FULLY`] (a walk's
/// knee, 5-20 degrees bent in stance, keeps the thigh's smallest rotation there: the plane of
/// a knee bent 10-30 degrees, set from 10, turned the thigh by up to 19 degrees a frame under
/// 3 px of detector noise, against 10 before).
const HINGE_SETS_FROM: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// See [`HINGE_SETS_FROM`] (45 degrees).
const HINGE_SETS_FULLY: f64 = 45.0 * std::f64::consts::PI / 180.0;

/// Angle (radians) between a hinge's axis and the opposite of its natural axis within which
/// the limb below is taken as bent the wrong way (45 degrees: an overstretched knee), and
/// left untwisted.
const HINGE_AWAY_FROM: f64 = 45.0 * std::f64::consts::PI / 180.0;
/// Cosine span over which the twist fades in beyond [`HINGE_AWAY_FROM`] (0.4: from 135 to
/// about 108 degrees from the natural axis).
const HINGE_SWITCH_FADE: f64 = 0.4;
/// Twist (radians) of a thigh from its natural frame that a knee's hinge may set as it is
/// (40 degrees, about a hip's own range of rotation); see [`held_twist`].
const HINGE_TWIST_FREE: f64 = 40.0 * std::f64::consts::PI / 180.0;
/// The most twist (radians) a knee's hinge sets (65 degrees: the thigh's `Z Y X` angles lock
/// at 90).
const HINGE_TWIST_MAX: f64 = 65.0 * std::f64::consts::PI / 180.0;

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
                JointRole::Bone { limb, hinge } => {
                    let direction = unit(line(LIMBS[limb])).unwrap_or(joint.rest);
                    let in_parent = parent.transpose().apply(direction);
                    let turned =
                        bone_rotation(joint.rest, in_parent, self.previous_local[j].as_ref());
                    match hinge.and_then(|h| unit(line(LIMBS[h.limb])).map(|below| (h, below))) {
                        Some((hinge, below)) => {
                            let below = parent.transpose().apply(below);
                            hinged_rotation(turned, joint.rest, hinge, in_parent, below)
                        }
                        None => turned,
                    }
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
    let w = smoothstep(follow);
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

/// The rotation, relative to the parent, of a bone carrying a hinge: `turned` (its
/// [`bone_rotation`], which takes `rest` onto the bone's `direction`) twisted about the bone
/// so that the limb below the hinge (`below`; both unit vectors in the parent's frame) bends
/// towards `hinge.bends` in the bone's frame: the knee then turns about one axis of the
/// bone's frame, `rest x bends`, and the bone below needs no twist of its own (its smallest
/// rotation). The twist is measured from the bone's natural frame (the one whose hinge axis
/// is the rest axis, across the bone) and held within about [`HINGE_TWIST_MAX`] of it, where
/// the thigh's Euler angles stay clear of gimbal lock (a knee bent sideways is then left
/// partly so). It fades out as the bend nears straight ([`HINGE_SETS_FROM`]: its plane is
/// noise) and as the hinge's axis nears the opposite of the natural one
/// ([`HINGE_AWAY_FROM`]: a knee bent the wrong way, not one to be twisted round by a half
/// turn), so the rotation is continuous in the limbs' directions.
fn hinged_rotation(
    turned: Rot3,
    rest: [f64; 3],
    hinge: Hinge,
    direction: [f64; 3],
    below: [f64; 3],
) -> Rot3 {
    let axis_at_rest = cross(rest, hinge.bends);
    let bend = dot(direction, below).clamp(-1.0, 1.0).acos();
    let set = ((bend - HINGE_SETS_FROM) / (HINGE_SETS_FULLY - HINGE_SETS_FROM)).clamp(0.0, 1.0);
    let natural = unit(sub(
        axis_at_rest,
        direction.map(|c| c * dot(direction, axis_at_rest)),
    ));
    let (Some(axis), Some(natural)) = (unit(cross(direction, below)), natural) else {
        return turned;
    };
    // The twist about the bone from the natural axis to the hinge's.
    let twist = dot(direction, cross(natural, axis)).atan2(dot(natural, axis));
    let toward = ((twist.cos() + HINGE_AWAY_FROM.cos()) / HINGE_SWITCH_FADE).clamp(0.0, 1.0);
    let weight = smoothstep(set) * smoothstep(toward);
    if weight == 0.0 {
        return turned;
    }
    let held = Rot3::about_unit(direction, held_twist(twist)).apply(natural);
    // The rotation taking `rest` to `direction` and the rest axis to `held`; relative to
    // `turned` (which also takes `rest` to `direction`) it is a twist about `rest`.
    let target = Rot3::from_columns(direction, held, cross(direction, held))
        .mul(&Rot3::from_columns(rest, axis_at_rest, cross(rest, axis_at_rest)).transpose());
    let seen = turned.transpose().mul(&target).apply(axis_at_rest);
    let to_target = dot(rest, cross(axis_at_rest, seen)).atan2(dot(axis_at_rest, seen));
    turned.mul(&Rot3::about_unit(rest, weight * to_target))
}

/// `twist` (radians) as it is up to [`HINGE_TWIST_FREE`], then bent smoothly towards
/// [`HINGE_TWIST_MAX`], which it never passes.
fn held_twist(twist: f64) -> f64 {
    let beyond = twist.abs() - HINGE_TWIST_FREE;
    if beyond <= 0.0 {
        return twist;
    }
    let room = HINGE_TWIST_MAX - HINGE_TWIST_FREE;
    (HINGE_TWIST_FREE + room * (beyond / room).tanh()).copysign(twist)
}

/// `3t^2 - 2t^3` of `t` in [0, 1]: from 0 to 1 with a flat start and end.
fn smoothstep(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
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
    fn a_bone_above_a_hinge_is_twisted_so_that_the_hinge_bends_about_one_axis() {
        // A thigh along -y at rest whose shin bends back (-z) in its frame.
        let rest = [0.0, -1.0, 0.0];
        let hinge = Hinge {
            limb: 2,
            bends: [0.0, 0.0, -1.0],
        };
        // The thigh raised forward (a squat) or not, the knee bent back or turned in or out by
        // up to 40 deg: the knee bends about the thigh frame's x.
        for (thigh_deg, bend_deg, turned_deg) in [
            (0.0_f64, 90.0_f64, 0.0_f64),
            (90.0, 140.0, 0.0),
            (90.0, 140.0, 40.0),
            (0.0, 60.0, -40.0),
        ] {
            let raise = Rot3::about_unit([1.0, 0.0, 0.0], -thigh_deg.to_radians());
            let direction = raise.apply(rest);
            let knee = Rot3::about_unit(rest, turned_deg.to_radians())
                .mul(&Rot3::about_unit([1.0, 0.0, 0.0], bend_deg.to_radians()));
            let below = raise.mul(&knee).apply(rest);
            let turned = bone_rotation(rest, direction, None);
            let r = hinged_rotation(turned, rest, hinge, direction, below);
            let along = r.apply(rest);
            let seen = r.transpose().apply(below);
            for k in 0..3 {
                assert!((along[k] - direction[k]).abs() < 1e-12);
            }
            assert!(
                seen[0].abs() < 1e-12,
                "{thigh_deg} {bend_deg} {turned_deg}: {seen:?}"
            );
            assert!(seen[2] < 0.0, "{seen:?}");
        }
        // Turned out by 90 deg (a knee bent sideways): the thigh twists by 64 deg, no more.
        let below = Rot3::about_unit(rest, std::f64::consts::FRAC_PI_2)
            .mul(&Rot3::about_unit([1.0, 0.0, 0.0], 1.0))
            .apply(rest);
        let r = hinged_rotation(Rot3::IDENTITY, rest, hinge, rest, below);
        let twist = dot(rest, cross([1.0, 0.0, 0.0], r.apply([1.0, 0.0, 0.0])))
            .atan2(r.apply([1.0, 0.0, 0.0])[0]);
        assert!(
            (twist.abs().to_degrees() - 64.0).abs() < 1.0,
            "{}",
            twist.to_degrees()
        );
        // Bent the wrong way (the axis opposite the rest one), or nearly straight: untwisted.
        let forward = Rot3::about_unit([1.0, 0.0, 0.0], -0.8).apply(rest);
        let straight = unit([0.05, -1.0, 0.0]).unwrap_or(rest);
        for below in [forward, straight] {
            let r = hinged_rotation(Rot3::IDENTITY, rest, hinge, rest, below);
            assert!(angle_between(&r, &Rot3::IDENTITY) < 1e-12);
        }
        // Bent 60 deg and turned all round the thigh: the rotation never jumps, also where the
        // twist fades out near the wrong way.
        let at = |deg: f64| {
            let below = Rot3::about_unit(rest, deg.to_radians()).apply([
                0.0,
                -60f64.to_radians().cos(),
                -60f64.to_radians().sin(),
            ]);
            hinged_rotation(Rot3::IDENTITY, rest, hinge, rest, below)
        };
        for step in 0..720 {
            let (a, b) = (
                at(-180.0 + 0.5 * step as f64),
                at(-179.5 + 0.5 * step as f64),
            );
            assert!(angle_between(&a, &b) < 0.1, "step {step}");
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
