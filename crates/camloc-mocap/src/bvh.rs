//! BVH (Biovision hierarchy) reader.

use std::collections::HashSet;
use std::path::Path;

use super::error::{MocapError, ParseProblem};
use super::rotation::{Axis, Rot3, add, y_up_to_z_up};
use super::text::{Lines, Source, decode};
use super::{CMU_UNIT_M, MocapClip, read_file, subject_and_clip};
use camloc_skeleton::{Landmark, NUM_LANDMARKS, Pose3};

/// Reads a BVH file; see [`parse_bvh`] for the conventions.
///
/// # Errors
///
/// [`MocapError::Io`] when the file cannot be read, otherwise as [`parse_bvh`].
pub fn read_bvh(path: impl AsRef<Path>) -> Result<MocapClip, MocapError> {
    read_bvh_with_unit(path, CMU_UNIT_M)
}

/// Reads a BVH file whose coordinates are in units of `metres_per_unit` metres (0.01 for the
/// centimetres [`write_bvh`](crate::write_bvh) writes by default); otherwise as [`read_bvh`].
///
/// # Errors
///
/// As [`read_bvh`].
pub fn read_bvh_with_unit(
    path: impl AsRef<Path>,
    metres_per_unit: f64,
) -> Result<MocapClip, MocapError> {
    let path = path.as_ref();
    parse_bvh_with_unit(
        &read_file(path)?,
        &path.display().to_string(),
        metres_per_unit,
    )
}

/// Parses BVH text (as `&str` or raw bytes) into a clip of 15-landmark poses.
///
/// `source_name` is the file name used in error messages and for the subject and clip ids
/// (`35_02.bvh` gives subject `35`, clip `35_02`).
///
/// # Format
///
/// * `HIERARCHY`, one `ROOT` with nested `JOINT` and `End Site` blocks, each with `OFFSET x y z`
///   and (except end sites) `CHANNELS n c1 .. cn`, then `MOTION`, `Frames: N`,
///   `Frame Time: t` and exactly `N` frame lines of one value per channel.
/// * LF or CRLF line ends, tabs or any whitespace; braces may share a line with other tokens.
///   Joint names are single tokens and must be unique.
/// * Channels may come in any order. The rotation channels of a joint compose in the order they
///   are listed: `Zrotation Xrotation Yrotation` is `R = Rz * Rx * Ry` (the BVH convention),
///   angles in degrees. Position channels, on the root or any other joint, give the joint's
///   translation from its parent in place of `OFFSET` (the common reading, e.g. Blender's importer);
///   a coordinate without a position channel keeps its `OFFSET` value.
/// * A joint's world position is `P_parent + R_parent * t`, its world rotation
///   `R_parent * R`.
///
/// # Landmarks
///
/// A landmark is the world position of a joint's origin. Two namings are recognised (joint
/// names compared ignoring ASCII case); a file containing `LeftUpLeg` or `RightUpLeg` uses the
/// second:
///
/// | landmark | CMU naming | MotionBuilder naming |
/// |---|---|---|
/// | pelvis | `Hips` | `Hips` |
/// | hip, knee, ankle | `LeftHip`, `LeftKnee`, `LeftAnkle` | `LeftUpLeg`, `LeftLeg`, `LeftFoot` |
/// | neck | `lowerneck` | `Neck` |
/// | head | `Head` | `Head` |
/// | shoulder, elbow, wrist | `LeftShoulder`, `LeftElbow`, `LeftWrist` | `LeftArm`, `LeftForeArm`, `LeftHand` |
///
/// (right side likewise). Coordinates are CMU units ([`CMU_UNIT_M`] metres; [`parse_bvh_with_unit`] takes another unit) in a y-up frame;
/// the poses are returned in metres, z up.
///
/// # Errors
///
/// [`MocapError::Parse`] with the line of the first problem: invalid UTF-8, an empty file,
/// unexpected tokens, malformed or non-finite numbers, unknown or repeated channels, repeated
/// joint names, a frame line with the wrong number of values, fewer or more frame lines than
/// `Frames:` declares, a non-positive `Frame Time`. [`MocapError::MissingLandmark`] when a
/// landmark joint is absent.
pub fn parse_bvh<B: AsRef<[u8]> + ?Sized>(
    input: &B,
    source_name: &str,
) -> Result<MocapClip, MocapError> {
    parse_bvh_with_unit(input, source_name, CMU_UNIT_M)
}

/// Parses BVH text whose coordinates are in units of `metres_per_unit` metres (0.01 for the
/// centimetres [`write_bvh`](crate::write_bvh) writes by default); otherwise as
/// [`parse_bvh`], which is this function with [`CMU_UNIT_M`].
///
/// # Errors
///
/// As [`parse_bvh`].
pub fn parse_bvh_with_unit<B: AsRef<[u8]> + ?Sized>(
    input: &B,
    source_name: &str,
    metres_per_unit: f64,
) -> Result<MocapClip, MocapError> {
    let source = Source { name: source_name };
    let text = decode(input.as_ref(), source)?;
    let mut tokens = Tokens::new(text);
    let hierarchy = parse_hierarchy(&mut tokens, source)?;
    let landmarks = locate_landmarks(&hierarchy.joints, source)?;
    let mut lines = tokens.into_motion_lines(source)?;
    let declared = header_value(&mut lines, source, "Frames")
        .and_then(|(line, value)| source.count(value, line, || "`Frames:`".to_owned()))?;
    let frame_time_s =
        header_value(&mut lines, source, "Frame Time").and_then(|(line, value)| {
            let t = source.number(value, line, || "`Frame Time:`".to_owned())?;
            if t > 0.0 {
                Ok(t)
            } else {
                Err(source.invalid(line, "`Frame Time:`".to_owned(), "must be positive"))
            }
        })?;
    // Never trust `declared` for the allocation: a frame line needs at least 2 bytes per
    // value, and beyond a few thousand frames the vector grows with the frames read (blank
    // lines count for no frame: a file of them had reserved 180 times its size).
    let max_frames = text.len() / (2 * hierarchy.channel_count);
    let capacity = declared.min(max_frames).min(RESERVED_FRAMES);
    let frames = parse_frames(
        lines,
        &hierarchy,
        &landmarks,
        (declared, capacity),
        metres_per_unit,
        source,
    )?;
    let (subject, clip) = subject_and_clip(source_name);
    Ok(MocapClip {
        subject,
        clip,
        frame_time_s,
        frames,
    })
}

/// A BVH channel: a translation or rotation along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Channel {
    Position(Axis),
    Rotation(Axis),
}

impl Channel {
    /// The channel named `token` (`Xposition` .. `Zrotation`, ignoring ASCII case).
    fn parse(token: &str) -> Option<Channel> {
        let (axis, kind) = token.split_at_checked(1)?;
        let axis = Axis::from_letter(axis.chars().next()?)?;
        if kind.eq_ignore_ascii_case("position") {
            Some(Channel::Position(axis))
        } else if kind.eq_ignore_ascii_case("rotation") {
            Some(Channel::Rotation(axis))
        } else {
            None
        }
    }

    /// The canonical channel name.
    fn name(self) -> &'static str {
        match self {
            Channel::Position(Axis::X) => "Xposition",
            Channel::Position(Axis::Y) => "Yposition",
            Channel::Position(Axis::Z) => "Zposition",
            Channel::Rotation(Axis::X) => "Xrotation",
            Channel::Rotation(Axis::Y) => "Yrotation",
            Channel::Rotation(Axis::Z) => "Zrotation",
        }
    }
}

/// One joint of the hierarchy; joints are stored parents first.
#[derive(Debug)]
struct Joint<'a> {
    name: &'a str,
    parent: Option<usize>,
    offset: [f64; 3],
    channels: Vec<Channel>,
    /// Index of this joint's first channel in a frame line.
    first_channel: usize,
}

/// The parsed `HIERARCHY` section.
#[derive(Debug)]
struct Hierarchy<'a> {
    joints: Vec<Joint<'a>>,
    channel_count: usize,
}

impl Hierarchy<'_> {
    /// Describes value `index` of frame `frame` (1-based) for error messages.
    fn describe_value(&self, index: usize, frame: usize) -> String {
        self.joints
            .iter()
            .find_map(|j| {
                let k = index.checked_sub(j.first_channel)?;
                let channel = j.channels.get(k)?;
                Some(format!(
                    "channel {} of joint {} in frame {frame}",
                    channel.name(),
                    j.name
                ))
            })
            .unwrap_or_else(|| format!("value {} of frame {frame}", index + 1))
    }
}

/// Whitespace-separated tokens with their line numbers; `{` and `}` are always tokens of
/// their own.
#[derive(Clone, Debug)]
struct Tokens<'a> {
    lines: Lines<'a>,
    rest: &'a str,
    line: usize,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str) -> Self {
        Tokens {
            lines: Lines::new(text),
            rest: "",
            line: 1,
        }
    }

    /// The next token and its line, `None` at the end of the text.
    fn next(&mut self) -> Option<(&'a str, usize)> {
        loop {
            let trimmed = self.rest.trim_start();
            if trimmed.is_empty() {
                let (number, line) = self.lines.next()?;
                self.line = number;
                self.rest = line;
                continue;
            }
            let end = if trimmed.starts_with(['{', '}']) {
                1
            } else {
                trimmed
                    .find(|c: char| c.is_whitespace() || c == '{' || c == '}')
                    .unwrap_or(trimmed.len())
            };
            let (token, rest) = trimmed.split_at(end);
            self.rest = rest;
            return Some((token, self.line));
        }
    }

    /// The next token, or an "unexpected end" error saying `expected`.
    fn require(
        &mut self,
        source: Source<'_>,
        expected: &str,
    ) -> Result<(&'a str, usize), MocapError> {
        self.next()
            .ok_or_else(|| source.unexpected_end(self.lines.number(), expected))
    }

    /// Consumes the keyword `word` or fails.
    fn keyword(&mut self, source: Source<'_>, word: &str) -> Result<usize, MocapError> {
        let (token, line) = self.require(source, word)?;
        if token == word {
            Ok(line)
        } else {
            Err(source.expected(line, word, token))
        }
    }

    /// A finite number; `what` describes it for errors.
    fn number(&mut self, source: Source<'_>, what: impl Fn() -> String) -> Result<f64, MocapError> {
        match self.next() {
            Some((token, line)) => source.number(token, line, what),
            None => {
                Err(source.unexpected_end(self.lines.number(), &format!("a number for {}", what())))
            }
        }
    }

    /// `OFFSET x y z`; `owner` names the joint or end site.
    fn offset(
        &mut self,
        source: Source<'_>,
        owner: &dyn Fn() -> String,
    ) -> Result<[f64; 3], MocapError> {
        self.keyword(source, "OFFSET")?;
        let mut v = [0.0; 3];
        for (c, axis) in v.iter_mut().zip(["x", "y", "z"]) {
            *c = self.number(source, || format!("OFFSET {axis} of {}", owner()))?;
        }
        Ok(v)
    }

    /// The lines after the `MOTION` keyword, which must end its line.
    fn into_motion_lines(mut self, source: Source<'_>) -> Result<Lines<'a>, MocapError> {
        let (token, line) = self.require(source, "MOTION")?;
        match token {
            "MOTION" => {}
            "ROOT" => {
                return Err(source.invalid(
                    line,
                    "second ROOT".to_owned(),
                    "only one skeleton per file is supported",
                ));
            }
            other => return Err(source.expected(line, "MOTION", other)),
        }
        match self.rest.split_whitespace().next() {
            None => Ok(self.lines),
            Some(extra) => Err(source.expected(line, "the end of the line after MOTION", extra)),
        }
    }
}

/// Parses `HIERARCHY` up to (not including) `MOTION`, without recursion.
fn parse_hierarchy<'a>(
    tokens: &mut Tokens<'a>,
    source: Source<'_>,
) -> Result<Hierarchy<'a>, MocapError> {
    tokens.keyword(source, "HIERARCHY")?;
    tokens.keyword(source, "ROOT")?;
    let mut hierarchy = Hierarchy {
        joints: Vec::new(),
        channel_count: 0,
    };
    let mut names = HashSet::new();
    parse_joint(tokens, source, None, &mut hierarchy, &mut names)?;
    let mut open = vec![0usize];
    while let Some(&current) = open.last() {
        const EXPECTED: &str = "JOINT, End Site or '}'";
        let (token, line) = tokens.require(source, EXPECTED)?;
        match token {
            "JOINT" => {
                open.push(parse_joint(
                    tokens,
                    source,
                    Some(current),
                    &mut hierarchy,
                    &mut names,
                )?);
            }
            "End" => {
                tokens.keyword(source, "Site")?;
                tokens.keyword(source, "{")?;
                let owner = hierarchy.joints.get(current).map_or("", |j| j.name);
                tokens.offset(source, &|| format!("the end site of joint {owner}"))?;
                tokens.keyword(source, "}")?;
            }
            "}" => {
                open.pop();
            }
            other => return Err(source.expected(line, EXPECTED, other)),
        }
    }
    if hierarchy.channel_count == 0 {
        return Err(source.invalid(tokens.line, "HIERARCHY".to_owned(), "no joint has CHANNELS"));
    }
    Ok(hierarchy)
}

/// Parses a joint's name, `{`, `OFFSET` and optional `CHANNELS`; returns its index.
fn parse_joint<'a>(
    tokens: &mut Tokens<'a>,
    source: Source<'_>,
    parent: Option<usize>,
    hierarchy: &mut Hierarchy<'a>,
    names: &mut HashSet<&'a str>,
) -> Result<usize, MocapError> {
    let (name, line) = tokens.require(source, "a joint name")?;
    if name == "{" || name == "}" {
        return Err(source.expected(line, "a joint name", name));
    }
    if !names.insert(name) {
        return Err(source.error(
            line,
            ParseProblem::Duplicate {
                what: format!("joint '{name}'"),
            },
        ));
    }
    tokens.keyword(source, "{")?;
    let offset = tokens.offset(source, &|| format!("joint {name}"))?;
    let mut channels = Vec::new();
    let after_offset = tokens.clone();
    match tokens.next() {
        Some(("CHANNELS", line)) => {
            let (token, count_line) = tokens.require(source, "the number of channels")?;
            let count = source.count(token, count_line, || format!("CHANNELS of joint {name}"))?;
            if count > 6 {
                return Err(source.invalid(
                    line,
                    format!("CHANNELS of joint {name}"),
                    "a joint has at most 6 channels",
                ));
            }
            for _ in 0..count {
                let (token, line) = tokens.require(source, "a channel name")?;
                let channel = Channel::parse(token).ok_or_else(|| {
                    source.error(
                        line,
                        ParseProblem::Unknown {
                            what: format!("channel '{token}' of joint {name}"),
                        },
                    )
                })?;
                if channels.contains(&channel) {
                    return Err(source.error(
                        line,
                        ParseProblem::Duplicate {
                            what: format!("channel {} of joint {name}", channel.name()),
                        },
                    ));
                }
                channels.push(channel);
            }
        }
        _ => *tokens = after_offset,
    }
    let first_channel = hierarchy.channel_count;
    hierarchy.channel_count += channels.len();
    hierarchy.joints.push(Joint {
        name,
        parent,
        offset,
        channels,
        first_channel,
    });
    Ok(hierarchy.joints.len() - 1)
}

/// Joint names of the landmarks in the CMU naming, in landmark order.
const CMU_NAMES: [&str; NUM_LANDMARKS] = [
    "Hips",
    "LeftHip",
    "LeftKnee",
    "LeftAnkle",
    "RightHip",
    "RightKnee",
    "RightAnkle",
    "lowerneck",
    "Head",
    "LeftShoulder",
    "LeftElbow",
    "LeftWrist",
    "RightShoulder",
    "RightElbow",
    "RightWrist",
];

/// Joint names of the landmarks in the MotionBuilder naming, in landmark order.
const MOTIONBUILDER_NAMES: [&str; NUM_LANDMARKS] = [
    "Hips",
    "LeftUpLeg",
    "LeftLeg",
    "LeftFoot",
    "RightUpLeg",
    "RightLeg",
    "RightFoot",
    "Neck",
    "Head",
    "LeftArm",
    "LeftForeArm",
    "LeftHand",
    "RightArm",
    "RightForeArm",
    "RightHand",
];

/// Index of the joint of each landmark.
fn locate_landmarks(
    joints: &[Joint<'_>],
    source: Source<'_>,
) -> Result<[usize; NUM_LANDMARKS], MocapError> {
    let find = |name: &str| {
        joints
            .iter()
            .position(|j| j.name.eq_ignore_ascii_case(name))
    };
    let (names, naming) = if find("LeftUpLeg").is_some() || find("RightUpLeg").is_some() {
        (&MOTIONBUILDER_NAMES, "MotionBuilder")
    } else {
        (&CMU_NAMES, "CMU")
    };
    let mut indices = [0; NUM_LANDMARKS];
    for ((index, name), landmark) in indices.iter_mut().zip(names).zip(Landmark::ALL) {
        *index = find(name).ok_or_else(|| MocapError::MissingLandmark {
            file: source.name.to_owned(),
            landmark,
            expected: format!("joint '{name}' ({naming} naming)"),
        })?;
    }
    Ok(indices)
}

/// Finds the next non-blank line `key: value` and returns its line number and value.
fn header_value<'a>(
    lines: &mut Lines<'a>,
    source: Source<'_>,
    key: &str,
) -> Result<(usize, &'a str), MocapError> {
    let expected = format!("`{key}: <value>`");
    let (number, line) = lines
        .find(|(_, l)| !l.trim().is_empty())
        .ok_or_else(|| source.unexpected_end(lines.number(), &expected))?;
    let mut value = line
        .trim()
        .strip_prefix(key)
        .and_then(|rest| rest.trim_start().strip_prefix(':'))
        .map(|rest| rest.split_whitespace())
        .ok_or_else(|| source.expected(number, &expected, line.trim()))?;
    match (value.next(), value.next()) {
        (Some(v), None) => Ok((number, v)),
        _ => Err(source.expected(number, &expected, line.trim())),
    }
}

/// The most frames reserved before any is read (a cgspeed clip has a few thousand).
const RESERVED_FRAMES: usize = 4096;

/// Parses the frame lines and runs forward kinematics on each.
fn parse_frames(
    mut lines: Lines<'_>,
    hierarchy: &Hierarchy<'_>,
    landmarks: &[usize; NUM_LANDMARKS],
    (declared, capacity): (usize, usize),
    metres_per_unit: f64,
    source: Source<'_>,
) -> Result<Vec<Pose3>, MocapError> {
    let n = hierarchy.channel_count;
    let mut frames = Vec::with_capacity(capacity);
    let mut values = vec![0.0; n];
    let mut kinematics = Kinematics::new(hierarchy.joints.len());
    for (number, line) in lines.by_ref() {
        if line.trim().is_empty() {
            continue;
        }
        if frames.len() == declared {
            return Err(source.error(number, ParseProblem::ExtraFrames { declared }));
        }
        let frame = frames.len() + 1;
        let mut found = 0;
        for token in line.split_ascii_whitespace() {
            if let Some(v) = values.get_mut(found) {
                *v = source.number(token, number, || hierarchy.describe_value(found, frame))?;
            }
            found += 1;
        }
        if found != n {
            return Err(source.error(
                number,
                ParseProblem::ValueCount {
                    what: format!("frame {frame}"),
                    expected: n,
                    found,
                },
            ));
        }
        let pose = kinematics.pose(&hierarchy.joints, &values, landmarks, metres_per_unit);
        frames.push(source.finite_pose(pose, number, frame)?);
    }
    if frames.len() < declared {
        return Err(source.error(
            lines.number(),
            ParseProblem::Truncated {
                declared,
                found: frames.len(),
            },
        ));
    }
    Ok(frames)
}

/// Reusable world rotations and positions of every joint.
struct Kinematics {
    rotations: Vec<Rot3>,
    positions: Vec<[f64; 3]>,
}

impl Kinematics {
    fn new(joints: usize) -> Self {
        Kinematics {
            rotations: vec![Rot3::IDENTITY; joints],
            positions: vec![[0.0; 3]; joints],
        }
    }

    /// Forward kinematics of one frame (`values` has one entry per channel).
    fn pose(
        &mut self,
        joints: &[Joint<'_>],
        values: &[f64],
        landmarks: &[usize; NUM_LANDMARKS],
        metres_per_unit: f64,
    ) -> Pose3 {
        for (j, joint) in joints.iter().enumerate() {
            let mut translation = joint.offset;
            let mut rotation = Rot3::IDENTITY;
            let channel_values = values.get(joint.first_channel..).unwrap_or_default();
            for (channel, &v) in joint.channels.iter().zip(channel_values) {
                match *channel {
                    Channel::Position(axis) => translation[axis.index()] = v,
                    Channel::Rotation(axis) => {
                        rotation = rotation.mul(&Rot3::about(axis, v.to_radians()));
                    }
                }
            }
            let parent = joint
                .parent
                .and_then(|p| Some((*self.rotations.get(p)?, *self.positions.get(p)?)));
            let (world_rotation, world_position) = match parent {
                Some((r, p)) => (r.mul(&rotation), add(p, r.apply(translation))),
                None => (rotation, translation),
            };
            if let (Some(r), Some(p)) = (self.rotations.get_mut(j), self.positions.get_mut(j)) {
                *r = world_rotation;
                *p = world_position;
            }
        }
        Pose3::new(landmarks.map(|j| {
            y_up_to_z_up(
                self.positions.get(j).copied().unwrap_or_default(),
                metres_per_unit,
            )
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_names_round_trip_ignoring_case() {
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            for c in [Channel::Position(axis), Channel::Rotation(axis)] {
                assert_eq!(Channel::parse(c.name()), Some(c));
                assert_eq!(Channel::parse(&c.name().to_uppercase()), Some(c));
            }
        }
        assert_eq!(Channel::parse("Wrotation"), None);
        assert_eq!(Channel::parse("X"), None);
        assert_eq!(Channel::parse("é"), None);
    }

    #[test]
    fn tokens_split_braces_and_track_lines() {
        let mut t = Tokens::new("ROOT Hips{\r\n\tOFFSET 1 2 3}\n");
        let got: Vec<_> = std::iter::from_fn(|| t.next()).collect();
        assert_eq!(
            got,
            vec![
                ("ROOT", 1),
                ("Hips", 1),
                ("{", 1),
                ("OFFSET", 2),
                ("1", 2),
                ("2", 2),
                ("3", 2),
                ("}", 2)
            ]
        );
    }
}
