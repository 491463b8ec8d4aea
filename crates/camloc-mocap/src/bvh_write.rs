//! BVH writer: the 15 landmarks of a sequence of 3D poses as a skeleton animation that 3D
//! packages (Blender, MotionBuilder) import, and that [`parse_bvh_with_unit`] reads back.
//!
//! [`parse_bvh_with_unit`]: super::parse_bvh_with_unit

use std::fmt::Write;

use camloc_skeleton::{LIMB_NAMES, LIMBS, Landmark, NUM_LIMBS, Pose3, mean_limb_lengths};
use thiserror::Error;

use super::bvh_gaps::fill_missing_frames;
use super::bvh_skeleton::{JOINTS, JointRole, end_site_offset, joint_offset};
use super::bvh_solve::Solver;
use super::rotation::z_up_to_y_up;

/// Metres per file unit of centimetre BVH files (MotionBuilder's unit, and most BVH files').
pub const BVH_CENTIMETRE: f64 = 0.01;

/// How [`write_bvh`] writes a file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BvhOptions {
    /// Time between frames, seconds (`Frame Time:`); `1 / fps`.
    pub frame_time_s: f64,
    /// Metres per file unit ([`BVH_CENTIMETRE`] by default; BVH files carry no unit, so a
    /// reader must be told it: `parse_bvh_with_unit`, Blender's import scale 0.01).
    pub metres_per_unit: f64,
}

impl BvhOptions {
    /// `fps` frames per second, centimetres.
    pub fn at_fps(fps: f64) -> BvhOptions {
        BvhOptions {
            frame_time_s: 1.0 / fps,
            metres_per_unit: BVH_CENTIMETRE,
        }
    }
}

/// The frame times, seconds, a BVH file is written with: `Frame Time:` is written to 9
/// decimals, so a shorter one would read back as 0 (a frame rate of a million a second), and
/// a longer one (an hour a frame) is no animation.
pub const BVH_FRAME_TIME_RANGE_S: (f64, f64) = (1e-6, 3600.0);

/// The file units, metres per unit, a BVH file is written in: from a micrometre to a
/// kilometre (a smaller one made every coordinate infinite, a file camloc's reader refused).
pub const BVH_UNIT_RANGE_M: (f64, f64) = (1e-6, 1e3);

/// Why [`write_bvh`] cannot write a sequence.
#[derive(Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum BvhWriteError {
    /// There is no frame to write.
    #[error("BVH: no frames to write")]
    NoFrames,
    /// A limb length is not a positive finite number of metres.
    #[error("BVH: the length of limb {} is {value} m, not a positive finite number", LIMB_NAMES[*limb])]
    LimbLength {
        /// Index into `LIMBS`.
        limb: usize,
        /// The length given.
        value: f64,
    },
    /// The unit is outside [`BVH_UNIT_RANGE_M`], or the frame time outside
    /// [`BVH_FRAME_TIME_RANGE_S`].
    #[error("BVH: {what} is {value:e}, not a positive finite number in range")]
    Option {
        /// `frame time` or `metres per unit`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A frame has a non-finite coordinate, or a limb without direction (its two landmarks
    /// at one point).
    #[error("BVH: frame {frame}: {problem}")]
    Frame {
        /// 1-based frame number.
        frame: usize,
        /// What is wrong with it.
        problem: String,
    },
}

/// Writes `frames` (3D poses in metres, z-up world frame) as BVH text.
///
/// # Skeleton
///
/// One `ROOT Hips` at the pelvis with position and rotation channels, and joints in the
/// MotionBuilder naming that [`parse_bvh`](super::parse_bvh) recognises (`LeftUpLeg`,
/// `LeftLeg`, `LeftFoot`, `Neck`, `Head`, `LeftArm`, `LeftForeArm`, `LeftHand`, right side
/// likewise), whose origins are the 15 landmarks, plus joints at a landmark with no offset
/// that turn one bone of a landmark with several (`LHipJoint`, `RHipJoint` and `Spine` at the
/// pelvis, `LeftShoulder` and `RightShoulder` at the neck). Bone lengths are `limb_lengths`
/// (metres, `LIMBS` order), the rest pose a T-pose facing +z in the y-up file frame. The
/// ankles, wrists and head end in an `End Site` (for drawing only).
///
/// # Motion
///
/// Per frame, the root position is the pelvis; each bone's rotation turns its rest direction
/// onto the frame's limb direction, so that forward kinematics gives
/// `pose.with_limb_lengths(limb_lengths)`: the frame itself when its limbs have those lengths.
/// The rotation about a bone's own axis (twist), which landmarks cannot tell, is chosen to
/// stay smooth over time: the hips, the spine and the neck take the body's facing (hip and
/// shoulder lines), every other bone the smallest rotation from its parent, and where that
/// is ill-defined (a bone turned nearly opposite to its rest direction) the rotation closest
/// to the previous frame's. Euler angles (per joint, the bone's own axis in the middle of the
/// channel order) are chosen nearest the previous frame's, so channels have no jumps of a
/// full turn.
///
/// Coordinates are written in file units (`options.metres_per_unit`), y up (a world point
/// `(x, y, z)` is `(x, z, -y)` in the file), angles in degrees, six decimals.
///
/// # Errors
///
/// [`BvhWriteError`] for no frames, a limb length or option that is not a positive finite
/// number, a frame with a non-finite coordinate or a limb of zero length.
pub fn write_bvh(
    frames: &[Pose3],
    limb_lengths: &[f64; NUM_LIMBS],
    options: &BvhOptions,
) -> Result<String, BvhWriteError> {
    if frames.is_empty() {
        return Err(BvhWriteError::NoFrames);
    }
    for (limb, &value) in limb_lengths.iter().enumerate() {
        if !(value > 0.0 && value.is_finite()) {
            return Err(BvhWriteError::LimbLength { limb, value });
        }
    }
    let (shortest, longest) = BVH_FRAME_TIME_RANGE_S;
    for (what, value, in_range) in [
        (
            "the frame time (s)",
            options.frame_time_s,
            (shortest..=longest).contains(&options.frame_time_s),
        ),
        (
            "metres per unit",
            options.metres_per_unit,
            (BVH_UNIT_RANGE_M.0..=BVH_UNIT_RANGE_M.1).contains(&options.metres_per_unit),
        ),
    ] {
        if !(value > 0.0 && value.is_finite() && in_range) {
            return Err(BvhWriteError::Option { what, value });
        }
    }
    let unit = options.metres_per_unit;
    let lengths = limb_lengths.map(|l| l / unit);
    let mut text = hierarchy(&lengths, unit);
    let _ = writeln!(text, "MOTION");
    let _ = writeln!(text, "Frames: {}", frames.len());
    let _ = writeln!(text, "Frame Time: {:.9}", options.frame_time_s);
    let mut solver = Solver::new();
    let mut line = String::new();
    for (n, pose) in frames.iter().enumerate() {
        let frame = n + 1;
        if !pose.is_finite() {
            return Err(BvhWriteError::Frame {
                frame,
                problem: "a coordinate is not finite".to_owned(),
            });
        }
        if let Some(limb) = (0..NUM_LIMBS).find(|&k| !(pose.limb_length(k) > 0.0)) {
            let (a, b) = LIMBS[limb];
            return Err(BvhWriteError::Frame {
                frame,
                problem: format!(
                    "limb {} has no direction ({} and {} at one point)",
                    LIMB_NAMES[limb],
                    a.name(),
                    b.name()
                ),
            });
        }
        let points = pose.points.map(|p| z_up_to_y_up(p, unit));
        line.clear();
        let root = points[Landmark::Pelvis.index()];
        let _ = write!(line, "{:.6} {:.6} {:.6}", root[0], root[1], root[2]);
        for angles in solver.frame(&points) {
            for a in angles {
                let _ = write!(line, " {:.6}", a.to_degrees());
            }
        }
        let _ = writeln!(text, "{line}");
    }
    Ok(text)
}

/// Writes one person's animation: `frames` (metres, z-up world frame, in time order) as
/// [`write_bvh`] does, where a frame may be missing (`None`: a pose that could not be
/// reconstructed, or a video frame the person is missing from), so that the file keeps the
/// frames' timing: a missing frame between two poses is turned from one to the other (the
/// pelvis along a straight line, each limb's direction along the great circle); those before
/// the first pose and after the last hold it.
///
/// The bone lengths are `limb_lengths` (metres, `LIMBS` order) when given: the person's own
/// lengths where the caller knows them. Without them, the mean length of each limb over the
/// person's poses ([`mean_limb_lengths`]).
///
/// # Errors
///
/// As [`write_bvh`]; [`BvhWriteError::NoFrames`] also when every frame is missing.
pub fn write_person_bvh(
    frames: &[Option<Pose3>],
    limb_lengths: Option<&[f64; NUM_LIMBS]>,
    options: &BvhOptions,
) -> Result<String, BvhWriteError> {
    let filled = fill_missing_frames(frames).ok_or(BvhWriteError::NoFrames)?;
    let lengths = match limb_lengths {
        Some(given) => *given,
        None => {
            let poses: Vec<Pose3> = frames.iter().flatten().copied().collect();
            mean_limb_lengths(&poses).ok_or(BvhWriteError::NoFrames)?
        }
    };
    write_bvh(&filled, &lengths, options)
}

/// The `HIERARCHY` section for limb lengths in file units.
fn hierarchy(lengths: &[f64; NUM_LIMBS], metres_per_unit: f64) -> String {
    let mut text = String::from("HIERARCHY\n");
    let mut open: Vec<usize> = Vec::new();
    let close_to = |text: &mut String, open: &mut Vec<usize>, parent: Option<usize>| {
        while open.last().copied() != parent && !open.is_empty() {
            open.pop();
            let _ = writeln!(text, "{}}}", "\t".repeat(open.len()));
        }
    };
    for (j, joint) in JOINTS.iter().enumerate() {
        close_to(&mut text, &mut open, joint.parent);
        let indent = "\t".repeat(open.len());
        let keyword = if joint.parent.is_none() {
            "ROOT"
        } else {
            "JOINT"
        };
        let o = joint_offset(j, lengths);
        let _ = writeln!(text, "{indent}{keyword} {}", joint.name);
        let _ = writeln!(text, "{indent}{{");
        let _ = writeln!(text, "{indent}\tOFFSET {:.6} {:.6} {:.6}", o[0], o[1], o[2]);
        let position = if joint.parent.is_none() {
            "6 Xposition Yposition Zposition"
        } else {
            "3"
        };
        let order = joint.order.0.map(|a| match a.index() {
            0 => "Xrotation",
            1 => "Yrotation",
            _ => "Zrotation",
        });
        let _ = writeln!(text, "{indent}\tCHANNELS {position} {}", order.join(" "));
        if joint.role == JointRole::Leaf {
            let e = end_site_offset(j, metres_per_unit);
            let _ = writeln!(text, "{indent}\tEnd Site");
            let _ = writeln!(text, "{indent}\t{{");
            let _ = writeln!(
                text,
                "{indent}\t\tOFFSET {:.6} {:.6} {:.6}",
                e[0], e[1], e[2]
            );
            let _ = writeln!(text, "{indent}\t}}");
        }
        open.push(j);
    }
    close_to(&mut text, &mut open, None);
    text
}
