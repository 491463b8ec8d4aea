//! The joints of the BVH files camloc writes ([`write_bvh`](super::write_bvh)): names, tree,
//! rest pose and channel orders.

use camloc_skeleton::{Landmark, NUM_LIMBS};

use super::euler::EulerOrder;
use super::rotation::Axis;

/// What a joint's rotation does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JointRole {
    /// It takes the frame of the body part (its `up` bone and the line from the right to the
    /// left landmark of `lateral`, or of `fallback` where that runs along `up`).
    Body {
        /// The bone the frame's y axis follows.
        up: (Landmark, Landmark),
        /// The right and left landmarks whose line is the frame's x axis.
        lateral: (Landmark, Landmark),
        /// The line used when `lateral` is parallel to `up`.
        fallback: (Landmark, Landmark),
    },
    /// It turns the joint's rest axis onto limb `limb` (an index into `LIMBS`).
    Bone {
        /// The limb.
        limb: usize,
    },
    /// It has no landmark below it: its rotation is its parent's.
    Leaf,
}

/// One joint of the written skeleton.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointSpec {
    /// The joint's name in the file.
    pub(crate) name: &'static str,
    /// Index of the parent in [`JOINTS`] (parents come first).
    pub(crate) parent: Option<usize>,
    /// What its rotation does.
    pub(crate) role: JointRole,
    /// The direction, in the joint's own frame, of the bone to its children (of its end site
    /// for a leaf) in the rest pose.
    pub(crate) rest: [f64; 3],
    /// The limb whose length places this joint along its parent's `rest` axis; `None` for a
    /// joint at its parent's origin.
    pub(crate) offset_limb: Option<usize>,
    /// Its rotation channels, the bone's own axis in the middle (gimbal lock only at a twist
    /// of a quarter turn).
    pub(crate) order: EulerOrder,
}

const UP: [f64; 3] = [0.0, 1.0, 0.0];
const DOWN: [f64; 3] = [0.0, -1.0, 0.0];
const LEFT: [f64; 3] = [1.0, 0.0, 0.0];
const RIGHT: [f64; 3] = [-1.0, 0.0, 0.0];
const FORWARD: [f64; 3] = [0.0, 0.0, 1.0];

/// Channel order of the root: yaw about the vertical first, so that pitch (the middle) is
/// the angle that rarely reaches a quarter turn.
const YAW_PITCH_ROLL: EulerOrder = EulerOrder([Axis::Y, Axis::X, Axis::Z]);
/// Channel order of the bones along y (legs, spine, neck).
const ALONG_Y: EulerOrder = EulerOrder([Axis::Z, Axis::Y, Axis::X]);
/// Channel order of the bones along x (hip offsets, collars, arms).
const ALONG_X: EulerOrder = EulerOrder([Axis::Z, Axis::X, Axis::Y]);

/// Length of the end sites (drawing only), metres: the feet forward, the head up, the hands
/// along the forearm.
const FOOT_M: f64 = 0.12;
const HEAD_END_M: f64 = 0.10;
const HAND_M: f64 = 0.08;

/// Limb indices into `LIMBS`.
mod limb {
    pub(super) const L_HIP: usize = 0;
    pub(super) const L_THIGH: usize = 1;
    pub(super) const L_SHIN: usize = 2;
    pub(super) const R_HIP: usize = 3;
    pub(super) const R_THIGH: usize = 4;
    pub(super) const R_SHIN: usize = 5;
    pub(super) const TORSO: usize = 6;
    pub(super) const HEAD: usize = 7;
    pub(super) const L_COLLAR: usize = 8;
    pub(super) const L_UPPER_ARM: usize = 9;
    pub(super) const L_FOREARM: usize = 10;
    pub(super) const R_COLLAR: usize = 11;
    pub(super) const R_UPPER_ARM: usize = 12;
    pub(super) const R_FOREARM: usize = 13;
}

const fn bone(
    name: &'static str,
    parent: usize,
    limb: usize,
    rest: [f64; 3],
    offset_limb: Option<usize>,
    order: EulerOrder,
) -> JointSpec {
    JointSpec {
        name,
        parent: Some(parent),
        role: JointRole::Bone { limb },
        rest,
        offset_limb,
        order,
    }
}

const fn leaf(name: &'static str, parent: usize, rest: [f64; 3], offset_limb: usize) -> JointSpec {
    JointSpec {
        name,
        parent: Some(parent),
        role: JointRole::Leaf,
        rest,
        offset_limb: Some(offset_limb),
        order: ALONG_Y,
    }
}

use Landmark as L;

/// The hips, spine and neck frames: up along the torso (the head for the neck), x along the
/// hip line for the hips and along the shoulder line above.
const HIPS: JointRole = JointRole::Body {
    up: (L::Pelvis, L::Neck),
    lateral: (L::RightHip, L::LeftHip),
    fallback: (L::RightShoulder, L::LeftShoulder),
};
const SPINE: JointRole = JointRole::Body {
    up: (L::Pelvis, L::Neck),
    lateral: (L::RightShoulder, L::LeftShoulder),
    fallback: (L::RightHip, L::LeftHip),
};
const NECK: JointRole = JointRole::Body {
    up: (L::Neck, L::Head),
    lateral: (L::RightShoulder, L::LeftShoulder),
    fallback: (L::RightHip, L::LeftHip),
};

/// The joints in file order (parents first). Landmark joints: `Hips` (pelvis), `LeftUpLeg`,
/// `LeftLeg`, `LeftFoot` (hip, knee, ankle), `Neck`, `Head`, `LeftArm`, `LeftForeArm`,
/// `LeftHand` (shoulder, elbow, wrist), right likewise.
pub(crate) const JOINTS: [JointSpec; 20] = [
    JointSpec {
        name: "Hips",
        parent: None,
        role: HIPS,
        rest: UP,
        offset_limb: None,
        order: YAW_PITCH_ROLL,
    },
    bone("LHipJoint", 0, limb::L_HIP, LEFT, None, ALONG_X),
    bone(
        "LeftUpLeg",
        1,
        limb::L_THIGH,
        DOWN,
        Some(limb::L_HIP),
        ALONG_Y,
    ),
    bone(
        "LeftLeg",
        2,
        limb::L_SHIN,
        DOWN,
        Some(limb::L_THIGH),
        ALONG_Y,
    ),
    leaf("LeftFoot", 3, FORWARD, limb::L_SHIN),
    bone("RHipJoint", 0, limb::R_HIP, RIGHT, None, ALONG_X),
    bone(
        "RightUpLeg",
        5,
        limb::R_THIGH,
        DOWN,
        Some(limb::R_HIP),
        ALONG_Y,
    ),
    bone(
        "RightLeg",
        6,
        limb::R_SHIN,
        DOWN,
        Some(limb::R_THIGH),
        ALONG_Y,
    ),
    leaf("RightFoot", 7, FORWARD, limb::R_SHIN),
    JointSpec {
        name: "Spine",
        parent: Some(0),
        role: SPINE,
        rest: UP,
        offset_limb: None,
        order: ALONG_Y,
    },
    JointSpec {
        name: "Neck",
        parent: Some(9),
        role: NECK,
        rest: UP,
        offset_limb: Some(limb::TORSO),
        order: ALONG_Y,
    },
    leaf("Head", 10, UP, limb::HEAD),
    bone("LeftShoulder", 10, limb::L_COLLAR, LEFT, None, ALONG_X),
    bone(
        "LeftArm",
        12,
        limb::L_UPPER_ARM,
        LEFT,
        Some(limb::L_COLLAR),
        ALONG_X,
    ),
    bone(
        "LeftForeArm",
        13,
        limb::L_FOREARM,
        LEFT,
        Some(limb::L_UPPER_ARM),
        ALONG_X,
    ),
    leaf("LeftHand", 14, LEFT, limb::L_FOREARM),
    bone("RightShoulder", 10, limb::R_COLLAR, RIGHT, None, ALONG_X),
    bone(
        "RightArm",
        16,
        limb::R_UPPER_ARM,
        RIGHT,
        Some(limb::R_COLLAR),
        ALONG_X,
    ),
    bone(
        "RightForeArm",
        17,
        limb::R_FOREARM,
        RIGHT,
        Some(limb::R_UPPER_ARM),
        ALONG_X,
    ),
    leaf("RightHand", 18, RIGHT, limb::R_FOREARM),
];

/// The `OFFSET` of joint `j` for limb lengths in file units.
pub(crate) fn joint_offset(j: usize, lengths: &[f64; NUM_LIMBS]) -> [f64; 3] {
    let joint = &JOINTS[j];
    match (joint.parent, joint.offset_limb) {
        (Some(p), Some(limb)) => JOINTS[p].rest.map(|c| c * lengths[limb]),
        _ => [0.0; 3],
    }
}

/// The `End Site` offset of leaf joint `j`, in file units.
pub(crate) fn end_site_offset(j: usize, metres_per_unit: f64) -> [f64; 3] {
    let joint = &JOINTS[j];
    let metres = if joint.rest == FORWARD {
        FOOT_M
    } else if joint.rest == UP {
        HEAD_END_M
    } else {
        HAND_M
    };
    joint.rest.map(|c| c * metres / metres_per_unit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::LIMBS;

    #[test]
    fn every_limb_is_one_bone_between_the_joints_of_its_landmarks() {
        // Each limb is turned by exactly one joint, and placed by exactly one offset.
        for k in 0..NUM_LIMBS {
            let turning = JOINTS
                .iter()
                .filter(|j| j.role == JointRole::Bone { limb: k })
                .count();
            let body = matches!(k, limb::TORSO | limb::HEAD);
            assert_eq!(turning, usize::from(!body), "limb {k}");
            assert_eq!(
                JOINTS.iter().filter(|j| j.offset_limb == Some(k)).count(),
                1,
                "limb {k}"
            );
        }
        for (j, joint) in JOINTS.iter().enumerate() {
            assert!(joint.parent.is_none_or(|p| p < j), "{}", joint.name);
            if let JointRole::Bone { limb } = joint.role {
                // The joint sits at the limb's parent landmark: its own offset limb ends there.
                let parent_landmark = LIMBS[limb].0;
                let placed_at = |j: usize| {
                    JOINTS[j]
                        .offset_limb
                        .map_or(Landmark::Pelvis, |l| LIMBS[l].1)
                };
                let at = match joint.offset_limb {
                    Some(l) => LIMBS[l].1,
                    None => placed_at(joint.parent.unwrap_or(0)),
                };
                assert_eq!(at, parent_landmark, "{}", joint.name);
            }
        }
    }
}
