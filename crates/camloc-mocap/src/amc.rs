//! CMU AMC (Acclaim motion capture) reader.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

use super::asf::AsfSkeleton;
use super::error::{MocapError, ParseProblem};
use super::rotation::Rot3;
use super::text::{Lines, Source, decode};
use super::{CMU_FRAME_TIME_S, MocapClip, read_file, subject_and_clip};
use camloc_skeleton::Pose3;

/// Reads an AMC motion of `skeleton`; see [`parse_amc`].
///
/// # Errors
///
/// [`MocapError::Io`] when the file cannot be read, otherwise as [`parse_amc`].
pub fn read_amc(path: impl AsRef<Path>, skeleton: &AsfSkeleton) -> Result<MocapClip, MocapError> {
    let path = path.as_ref();
    parse_amc(&read_file(path)?, &path.display().to_string(), skeleton)
}

/// Parses AMC text (as `&str` or raw bytes) into a clip of 15-landmark poses of `skeleton`
/// (forward kinematics as described in [`parse_asf`](super::parse_asf)).
///
/// `source_name` is the file name used in error messages and for the subject and clip ids
/// (`16_01.amc` gives subject `16`, clip `16_01`). AMC files do not store a frame rate: the
/// clip gets the CMU rate, [`CMU_FRAME_TIME_S`].
///
/// # Format
///
/// Header lines (`#` comments, `:FULLY-SPECIFIED`, `:DEGREES` or `:RADIANS`; without either of
/// the last two, angles are in the skeleton's `:units angle`), then frames: a line holding the
/// frame number (consecutive), followed by one line `bone v1 v2 ...` for the root and for every
/// bone with dofs, values in the order of the skeleton's root `order` and bone `dof`. Bones may
/// come in any order within a frame.
///
/// # Errors
///
/// [`MocapError::Parse`] with the line of the first problem: invalid UTF-8, an empty file,
/// unknown bones, a bone listed twice in a frame or missing from it, a wrong number of values,
/// malformed or non-finite numbers, non-consecutive frame numbers, bone lines before the first
/// frame number.
pub fn parse_amc<B: AsRef<[u8]> + ?Sized>(
    input: &B,
    source_name: &str,
    skeleton: &AsfSkeleton,
) -> Result<MocapClip, MocapError> {
    let source = Source { name: source_name };
    let text = decode(input.as_ref(), source)?;
    let mut reader = Reader::new(skeleton, source);
    for (number, line) in Lines::new(text) {
        let content = line.split('#').next().unwrap_or_default();
        let mut tokens = content.split_ascii_whitespace();
        let Some(first) = tokens.next() else { continue };
        if let Some(keyword) = first.strip_prefix(':') {
            reader.keyword(keyword, number)?;
        } else if first.bytes().all(|b| b.is_ascii_digit()) {
            if let Some(extra) = tokens.next() {
                return Err(source.expected(
                    number,
                    "the end of the line after a frame number",
                    extra,
                ));
            }
            let frame_number = source.count(first, number, || "the frame number".to_owned())?;
            reader.start_frame(frame_number, number)?;
        } else {
            reader.bone_line(first, tokens, number)?;
        }
    }
    reader.finish_frame()?;
    let (subject, clip) = subject_and_clip(source_name);
    Ok(MocapClip {
        subject,
        clip,
        frame_time_s: CMU_FRAME_TIME_S,
        frames: reader.frames,
    })
}

/// State of an AMC file being read.
struct Reader<'s> {
    skeleton: &'s AsfSkeleton,
    source: Source<'s>,
    /// AMC line names and the ranges of their values, as [`AsfSkeleton::motion_slots`].
    slots: Vec<(&'s str, Range<usize>)>,
    lookup: HashMap<&'s str, usize>,
    radians_per_unit: f64,
    /// The current frame's values, laid out as `slots`.
    values: Vec<f64>,
    /// `seen[slot]` is the 1-based index of the last frame that listed the slot.
    seen: Vec<usize>,
    /// Number and line of the frame being read.
    current: Option<(usize, usize)>,
    frames: Vec<Pose3>,
    scratch: Vec<(Rot3, [f64; 3])>,
}

impl<'s> Reader<'s> {
    fn new(skeleton: &'s AsfSkeleton, source: Source<'s>) -> Self {
        let slots: Vec<_> = skeleton.motion_slots().collect();
        let lookup = slots
            .iter()
            .enumerate()
            .map(|(i, (name, _))| (*name, i))
            .collect();
        Reader {
            skeleton,
            source,
            seen: vec![0; slots.len()],
            slots,
            lookup,
            radians_per_unit: skeleton.radians_per_angle_unit(),
            values: vec![0.0; skeleton.value_count()],
            current: None,
            frames: Vec::new(),
            scratch: Vec::new(),
        }
    }

    /// A `:keyword` line, allowed only in the header.
    fn keyword(&mut self, keyword: &str, line: usize) -> Result<(), MocapError> {
        if self.current.is_some() {
            return Err(self.source.expected(
                line,
                "a bone line or a frame number",
                &format!(":{keyword}"),
            ));
        }
        if keyword.eq_ignore_ascii_case("DEGREES") {
            self.radians_per_unit = 1f64.to_radians();
        } else if keyword.eq_ignore_ascii_case("RADIANS") {
            self.radians_per_unit = 1.0;
        }
        Ok(())
    }

    /// A frame-number line: completes the previous frame and starts frame `frame_number`.
    fn start_frame(&mut self, frame_number: usize, line: usize) -> Result<(), MocapError> {
        if let Some((previous, _)) = self.current {
            self.finish_frame()?;
            if previous.checked_add(1) != Some(frame_number) {
                return Err(self.source.invalid(
                    line,
                    format!("frame number {frame_number}"),
                    &format!("expected {}", previous.saturating_add(1)),
                ));
            }
        }
        self.current = Some((frame_number, line));
        Ok(())
    }

    /// A line `bone v1 v2 ...` of the current frame.
    fn bone_line<'t>(
        &mut self,
        name: &str,
        tokens: impl Iterator<Item = &'t str>,
        line: usize,
    ) -> Result<(), MocapError> {
        let source = self.source;
        let Some((frame_number, _)) = self.current else {
            return Err(source.expected(line, "a frame number", name));
        };
        let slot = *self.lookup.get(name).ok_or_else(|| {
            source.error(
                line,
                ParseProblem::Unknown {
                    what: format!("bone '{name}'"),
                },
            )
        })?;
        let count = self.frames.len() + 1;
        if let Some(seen) = self.seen.get_mut(slot) {
            if *seen == count {
                return Err(source.error(
                    line,
                    ParseProblem::Duplicate {
                        what: format!("bone '{name}' in frame {frame_number}"),
                    },
                ));
            }
            *seen = count;
        }
        let range = self
            .slots
            .get(slot)
            .map(|(_, r)| r.clone())
            .unwrap_or_default();
        let expected = range.len();
        let targets = self.values.get_mut(range).unwrap_or_default();
        let mut found = 0;
        for token in tokens {
            if let Some(v) = targets.get_mut(found) {
                *v = source.number(token, line, || {
                    format!("value {} of '{name}' in frame {frame_number}", found + 1)
                })?;
            }
            found += 1;
        }
        if found != expected {
            return Err(source.error(
                line,
                ParseProblem::ValueCount {
                    what: format!("'{name}' in frame {frame_number}"),
                    expected,
                    found,
                },
            ));
        }
        Ok(())
    }

    /// Checks that the current frame listed every bone with dofs and adds its pose.
    fn finish_frame(&mut self) -> Result<(), MocapError> {
        let Some((frame_number, frame_line)) = self.current else {
            return Ok(());
        };
        let count = self.frames.len() + 1;
        let missing = self
            .slots
            .iter()
            .zip(&self.seen)
            .find(|((_, range), seen)| !range.is_empty() && **seen != count);
        if let Some(((name, _), _)) = missing {
            return Err(self.source.invalid(
                frame_line,
                format!("frame {frame_number}"),
                &format!("no line for '{name}'"),
            ));
        }
        let pose = self
            .skeleton
            .pose(&self.values, self.radians_per_unit, &mut self.scratch);
        self.frames
            .push(self.source.finite_pose(pose, frame_line, frame_number)?);
        Ok(())
    }
}
