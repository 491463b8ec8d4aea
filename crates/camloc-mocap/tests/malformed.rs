//! Malformed inputs, made by editing the fixtures: every error kind, with the right line.

use std::path::Path;

use camloc_mocap::{
    AsfSkeleton, MocapClip, MocapError, ParseProblem, parse_amc, parse_asf, parse_bvh,
};
use camloc_skeleton::Landmark;

fn fixture_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/mocap")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

/// A fixture as lines (terminators dropped) and the terminator it uses.
struct Lines {
    lines: Vec<String>,
    ending: &'static str,
}

impl Lines {
    fn of(name: &str) -> Self {
        let text = fixture_text(name);
        let ending = if text.contains("\r\n") { "\r\n" } else { "\n" };
        Lines {
            lines: text.split(ending).map(str::to_owned).collect(),
            ending,
        }
    }

    /// 1-based number of the first line containing `needle`.
    fn find(&self, needle: &str) -> usize {
        1 + self
            .lines
            .iter()
            .position(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("no line contains {needle:?}"))
    }

    /// Replaces line `number` (1-based).
    fn set(&mut self, number: usize, line: &str) -> &mut Self {
        self.lines[number - 1] = line.to_owned();
        self
    }

    /// Replaces the first occurrence of `from` in line `number`.
    fn edit(&mut self, number: usize, from: &str, to: &str) -> &mut Self {
        let line = self.lines[number - 1].replacen(from, to, 1);
        self.set(number, &line)
    }

    fn remove(&mut self, number: usize) -> &mut Self {
        self.lines.remove(number - 1);
        self
    }

    fn text(&self) -> String {
        self.lines.join(self.ending)
    }
}

/// Asserts that `result` is a parse error at `line` whose problem satisfies `check`.
#[track_caller]
fn assert_parse_error<T: std::fmt::Debug>(
    result: Result<T, MocapError>,
    line: usize,
    check: impl FnOnce(&ParseProblem) -> bool,
) -> MocapError {
    let err = result.expect_err("expected an error");
    assert_eq!(err.line(), Some(line), "wrong line in: {err}");
    assert!(check(err.problem().unwrap()), "wrong problem: {err}");
    err
}

fn bvh(lines: &Lines) -> Result<MocapClip, MocapError> {
    parse_bvh(&lines.text(), "walk.bvh")
}

/// Line numbers of the two frame lines of 98_01.bvh.
fn frame_lines(lines: &Lines) -> (usize, usize) {
    let first = lines.find("Frame Time") + 1;
    (first, first + 1)
}

#[test]
fn bvh_empty_and_non_utf8() {
    for empty in ["", " \r\n\t\r\n"] {
        assert_parse_error(parse_bvh(empty, "e.bvh"), 1, |p| *p == ParseProblem::Empty);
    }
    let mut bytes = fixture_text("98_01.bvh").into_bytes();
    let end_of_fourth_line = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(3)
        .unwrap()
        .0;
    bytes[end_of_fourth_line + 2] = 0xff;
    assert_parse_error(parse_bvh(&bytes, "walk.bvh"), 5, |p| {
        *p == ParseProblem::NotUtf8
    });
}

#[test]
fn bvh_bad_frame_value_names_channel_joint_and_frame() {
    let mut lines = Lines::of("98_01.bvh");
    let (first, _) = frame_lines(&lines);
    let mut values: Vec<String> = lines.lines[first - 1]
        .split('\t')
        .map(str::to_owned)
        .collect();
    values[9] = "abc".into(); // LeftKnee's first channel, Zrotation.
    lines.set(first, &values.join("\t"));
    let err = assert_parse_error(bvh(&lines), first, |p| {
        matches!(p, ParseProblem::NotANumber { .. })
    });
    assert_eq!(
        err.to_string(),
        format!(
            "walk.bvh:{first}: expected a number for channel Zrotation of joint LeftKnee in \
             frame 1, found 'abc'"
        )
    );
    values[9] = "nan".into();
    lines.set(first, &values.join("\t"));
    assert_parse_error(bvh(&lines), first, |p| {
        matches!(p, ParseProblem::NotFinite { .. })
    });
}

#[test]
fn bvh_frame_count_must_match_the_header() {
    let mut lines = Lines::of("98_01.bvh");
    let (_, second) = frame_lines(&lines);
    let second_frame = lines.lines[second - 1].clone();
    // One frame line fewer than `Frames: 2`: reported on the line after the last frame.
    let mut truncated = Lines::of("98_01.bvh");
    truncated.remove(second);
    assert_parse_error(bvh(&truncated), second, |p| {
        *p == ParseProblem::Truncated {
            declared: 2,
            found: 1,
        }
    });
    // One more.
    let mut extra = Lines::of("98_01.bvh");
    extra.set(second + 1, &second_frame);
    assert_parse_error(bvh(&extra), second + 1, |p| {
        *p == ParseProblem::ExtraFrames { declared: 2 }
    });
    // A frame line with one value missing.
    let shorter = second_frame
        .trim_end()
        .rsplit_once(' ')
        .unwrap()
        .0
        .to_owned();
    lines.set(second, &shorter);
    assert_parse_error(bvh(&lines), second, |p| {
        *p == ParseProblem::ValueCount {
            what: "frame 2".into(),
            expected: 51,
            found: 50,
        }
    });
    // An absurd declared count is neither trusted for allocation nor accepted.
    let mut absurd = Lines::of("98_01.bvh");
    let header = absurd.find("Frames:");
    absurd.set(header, "Frames: 1000000000");
    assert_parse_error(bvh(&absurd), second + 1, |p| {
        *p == ParseProblem::Truncated {
            declared: 1_000_000_000,
            found: 2,
        }
    });
    absurd.set(header, "Frames: 99999999999999999999999999");
    assert_parse_error(bvh(&absurd), header, |p| {
        matches!(p, ParseProblem::NotANumber { .. })
    });
}

#[test]
fn bvh_overflowing_positions_are_an_error() {
    let mut lines = Lines::of("98_01.bvh");
    let (first, _) = frame_lines(&lines);
    let hip_offset = lines.find("JOINT LeftHip") + 2;
    lines.set(hip_offset, "OFFSET 1.7e308 0 0");
    lines.edit(first, "0", "1.7e308");
    assert_parse_error(
        bvh(&lines),
        first,
        |p| matches!(p, ParseProblem::Invalid { what, .. } if what == "frame 1"),
    );
}

#[test]
fn bvh_header_values() {
    let mut lines = Lines::of("98_01.bvh");
    let time = lines.find("Frame Time");
    lines.set(time, "Frame Time: 0");
    assert_parse_error(bvh(&lines), time, |p| {
        matches!(p, ParseProblem::Invalid { .. })
    });
    lines.set(time, "Frame Time: fast");
    assert_parse_error(bvh(&lines), time, |p| {
        matches!(p, ParseProblem::NotANumber { .. })
    });
    lines.set(time, "Frame Rate: 120");
    assert_parse_error(bvh(&lines), time, |p| {
        matches!(p, ParseProblem::Expected { .. })
    });
}

#[test]
fn bvh_missing_landmark_joint_is_named() {
    let mut lines = Lines::of("98_01.bvh");
    let knee = lines.find("JOINT LeftKnee");
    lines.edit(knee, "LeftKnee", "LeftKnie");
    match bvh(&lines) {
        Err(MocapError::MissingLandmark {
            landmark, expected, ..
        }) => {
            assert_eq!(landmark, Landmark::LeftKnee);
            assert!(expected.contains("'LeftKnee'"), "{expected}");
        }
        other => panic!("expected MissingLandmark, got {other:?}"),
    }
}

#[test]
fn bvh_hierarchy_errors_point_at_the_offending_line() {
    let base = Lines::of("98_01.bvh");
    let knee_channels = base.find("JOINT LeftKnee") + 3;

    let mut unknown = Lines::of("98_01.bvh");
    unknown.edit(knee_channels, "Xrotation", "Wrotation");
    assert_parse_error(
        bvh(&unknown),
        knee_channels,
        |p| matches!(p, ParseProblem::Unknown { what } if what.contains("Wrotation")),
    );

    let mut repeated = Lines::of("98_01.bvh");
    repeated.edit(knee_channels, "Xrotation", "Zrotation");
    assert_parse_error(bvh(&repeated), knee_channels, |p| {
        matches!(p, ParseProblem::Duplicate { .. })
    });

    let mut too_many = Lines::of("98_01.bvh");
    too_many.edit(knee_channels, "CHANNELS 3", "CHANNELS 7");
    assert_parse_error(bvh(&too_many), knee_channels, |p| {
        matches!(p, ParseProblem::Invalid { .. })
    });

    let mut duplicate = Lines::of("98_01.bvh");
    let right_knee = base.find("JOINT RightKnee");
    duplicate.edit(right_knee, "RightKnee", "LeftKnee");
    assert_parse_error(
        bvh(&duplicate),
        right_knee,
        |p| matches!(p, ParseProblem::Duplicate { what } if what == "joint 'LeftKnee'"),
    );

    let mut misspelt = Lines::of("98_01.bvh");
    let offset = base.find("JOINT LeftKnee") + 2;
    misspelt.edit(offset, "OFFSET", "OFFST");
    assert_parse_error(bvh(&misspelt), offset, |p| {
        *p == ParseProblem::Expected {
            expected: "OFFSET".into(),
            found: "OFFST".into(),
        }
    });

    let mut bad_offset = Lines::of("98_01.bvh");
    bad_offset.edit(offset, "-8", "-8x");
    assert_parse_error(
        bvh(&bad_offset),
        offset,
        |p| matches!(p, ParseProblem::NotANumber { what, .. } if what == "OFFSET y of joint LeftKnee"),
    );

    let mut second_root = Lines::of("98_01.bvh");
    let motion = base.find("MOTION");
    second_root.set(motion, "ROOT Other");
    assert_parse_error(bvh(&second_root), motion, |p| {
        matches!(p, ParseProblem::Invalid { .. })
    });
}

#[test]
fn bvh_cut_short_reports_the_end_of_the_file() {
    let lines = Lines::of("98_01.bvh");
    let chest = lines.find("JOINT Chest");
    let cut = Lines {
        lines: lines.lines[..chest].to_vec(),
        ending: lines.ending,
    };
    assert_parse_error(bvh(&cut), chest, |p| {
        matches!(p, ParseProblem::UnexpectedEnd { .. })
    });
}

#[test]
fn bvh_deep_nesting_does_not_overflow_the_stack() {
    let depth = 200_000;
    let mut text = String::from("HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n");
    for i in 0..depth {
        text.push_str(&format!("JOINT j{i} {{ OFFSET 0 1 0\n"));
    }
    let err = parse_bvh(&text, "deep.bvh").unwrap_err();
    assert!(
        matches!(err.problem(), Some(ParseProblem::UnexpectedEnd { .. })),
        "{err}"
    );
}

fn asf(lines: &Lines) -> Result<AsfSkeleton, MocapError> {
    parse_asf(&lines.text(), "tiny.asf")
}

#[test]
fn asf_unit_root_and_bone_errors() {
    let base = Lines::of("99.asf");

    let mut angle = Lines::of("99.asf");
    let line = base.find("angle deg");
    angle.edit(line, "deg", "grad");
    assert_parse_error(asf(&angle), line, |p| {
        matches!(p, ParseProblem::Expected { .. })
    });

    let mut no_order = Lines::of("99.asf");
    no_order.remove(base.find("order TX"));
    let last = no_order.lines.len();
    assert_parse_error(asf(&no_order), last, |p| {
        matches!(p, ParseProblem::UnexpectedEnd { .. })
    });

    let mut translation_dof = Lines::of("99.asf");
    let dof = base.find("dof rx ry rz");
    translation_dof.edit(dof, "rx", "tx");
    assert_parse_error(asf(&translation_dof), dof, |p| {
        matches!(p, ParseProblem::Invalid { .. })
    });

    let mut length = Lines::of("99.asf");
    let line = base.find("length 8");
    length.edit(line, "8", "eight");
    assert_parse_error(asf(&length), line, |p| {
        matches!(p, ParseProblem::NotANumber { .. })
    });

    let mut direction = Lines::of("99.asf");
    let line = base.find("direction 0 -1 0");
    direction.set(line, "direction 0 0 0");
    assert_parse_error(asf(&direction), line, |p| {
        matches!(p, ParseProblem::Invalid { .. })
    });

    let mut short = Lines::of("99.asf");
    short.set(line, "direction 0 -1");
    assert_parse_error(asf(&short), line, |p| {
        matches!(
            p,
            ParseProblem::ValueCount {
                expected: 3,
                found: 2,
                ..
            }
        )
    });

    let mut unclosed = Lines::of("99.asf");
    let end = base.find("name lfemur") + 8; // the `end` after dof and three limits lines
    assert_eq!(base.lines[end - 1].trim(), "end");
    unclosed.remove(end);
    assert_parse_error(asf(&unclosed), end, |p| {
        matches!(p, ParseProblem::Expected { .. })
    });
}

#[test]
fn asf_name_and_hierarchy_errors() {
    let base = Lines::of("99.asf");

    let mut duplicate = Lines::of("99.asf");
    let rfemur = base.find("name rfemur");
    duplicate.edit(rfemur, "rfemur", "lfemur");
    // Reported at the `begin` of the second block (`begin`, `id`, `name`).
    assert_parse_error(
        asf(&duplicate),
        rfemur - 2,
        |p| matches!(p, ParseProblem::Duplicate { what } if what == "bone 'lfemur'"),
    );

    let mut unknown = Lines::of("99.asf");
    let line = base.find("rfemur rtibia");
    unknown.edit(line, "rtibia", "rtibiaa");
    assert_parse_error(
        asf(&unknown),
        line,
        |p| matches!(p, ParseProblem::Unknown { what } if what.contains("rtibiaa")),
    );

    let mut twice = Lines::of("99.asf");
    twice.edit(line, "rtibia", "ltibia");
    assert_parse_error(asf(&twice), line, |p| {
        matches!(p, ParseProblem::Duplicate { .. })
    });

    let mut unattached = Lines::of("99.asf");
    unattached.remove(base.find("rhumerus rradius"));
    assert_parse_error(
        asf(&unattached),
        base.find("name rradius") - 2,
        |p| matches!(p, ParseProblem::Invalid { what, .. } if what == "bone 'rradius'"),
    );

    let renamed = fixture_text("99.asf").replace("lradius", "lforearm");
    match parse_asf(&renamed, "tiny.asf") {
        Err(MocapError::MissingLandmark { landmark, .. }) => {
            assert_eq!(landmark, Landmark::LeftWrist);
        }
        other => panic!("expected MissingLandmark, got {other:?}"),
    }
}

fn amc(lines: &Lines) -> Result<MocapClip, MocapError> {
    let skeleton = parse_asf(&fixture_text("99.asf"), "99.asf").unwrap();
    parse_amc(&lines.text(), "99_01.amc", &skeleton)
}

#[test]
fn amc_bone_line_errors() {
    let base = Lines::of("99_01.amc");
    let frame_two = base.find("root 2 16") - 1;
    let tibia = frame_two
        + base.lines[frame_two..]
            .iter()
            .position(|l| l.starts_with("ltibia"))
            .unwrap()
        + 1;

    let mut unknown = Lines::of("99_01.amc");
    unknown.edit(tibia, "ltibia", "ltibai");
    assert_parse_error(amc(&unknown), tibia, |p| {
        matches!(p, ParseProblem::Unknown { .. })
    });

    let mut twice = Lines::of("99_01.amc");
    twice.set(tibia + 1, "ltibia 5");
    assert_parse_error(amc(&twice), tibia + 1, |p| {
        matches!(p, ParseProblem::Duplicate { .. })
    });

    let mut missing = Lines::of("99_01.amc");
    missing.remove(tibia);
    assert_parse_error(
        amc(&missing),
        frame_two,
        |p| matches!(p, ParseProblem::Invalid { reason, .. } if reason.contains("ltibia")),
    );

    let mut count = Lines::of("99_01.amc");
    count.set(tibia, "ltibia 90 0");
    assert_parse_error(amc(&count), tibia, |p| {
        matches!(
            p,
            ParseProblem::ValueCount {
                expected: 1,
                found: 2,
                ..
            }
        )
    });

    let mut infinite = Lines::of("99_01.amc");
    infinite.set(tibia, "ltibia 1e999");
    assert_parse_error(amc(&infinite), tibia, |p| {
        matches!(p, ParseProblem::NotFinite { .. })
    });
}

#[test]
fn amc_frame_number_errors() {
    let base = Lines::of("99_01.amc");
    let frame_two = base.find("root 2 16") - 1;

    let mut skipped = Lines::of("99_01.amc");
    skipped.set(frame_two, "3");
    assert_parse_error(amc(&skipped), frame_two, |p| {
        matches!(p, ParseProblem::Invalid { .. })
    });

    let mut headless = Lines::of("99_01.amc");
    let first = base.find(":DEGREES") + 1;
    headless.remove(first);
    assert_parse_error(
        amc(&headless),
        first,
        |p| matches!(p, ParseProblem::Expected { expected, .. } if expected == "a frame number"),
    );

    let mut late_keyword = Lines::of("99_01.amc");
    late_keyword.set(frame_two, ":RADIANS");
    assert_parse_error(amc(&late_keyword), frame_two, |p| {
        matches!(p, ParseProblem::Expected { .. })
    });
}

/// A token of the file is quoted short and escaped: a 100,000-character token and terminal
/// control characters had gone whole and raw into the message.
#[test]
fn bvh_tokens_are_quoted_short_and_escaped() {
    let long = format!("HIERARCHY\nROOT Hips {{\n{}\n}}\n", "X".repeat(100_000));
    let message = parse_bvh(&long, "long.bvh").unwrap_err().to_string();
    assert!(message.len() < 400, "{} characters", message.len());
    assert!(message.contains('…'), "{message}");
    let control = "\u{1b}[31mHIERARCHY\u{7}\n";
    let message = parse_bvh(control, "esc.bvh").unwrap_err().to_string();
    assert!(!message.contains(['\u{1b}', '\u{7}']), "{message:?}");
}
