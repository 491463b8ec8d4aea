//! LSP-14 CSV: header `image,joint,x,y,visible`, one row per joint.

use std::collections::HashMap;

use camloc_skeleton::{Landmark, PartialPose2};

use crate::error::{KeypointError, Location};
use crate::record::{KeypointRecord, finish};
use crate::torso::derive_torso;
use crate::{Invisible, ReadOptions};

/// The 14 LSP joints and the camloc landmark each one becomes (`head_top` is read as the head;
/// the pelvis is not in LSP and is derived from the hips).
pub const LSP_JOINTS: [(&str, Landmark); 14] = [
    ("head_top", Landmark::Head),
    ("neck", Landmark::Neck),
    ("left_shoulder", Landmark::LeftShoulder),
    ("left_elbow", Landmark::LeftElbow),
    ("left_wrist", Landmark::LeftWrist),
    ("right_shoulder", Landmark::RightShoulder),
    ("right_elbow", Landmark::RightElbow),
    ("right_wrist", Landmark::RightWrist),
    ("left_hip", Landmark::LeftHip),
    ("left_knee", Landmark::LeftKnee),
    ("left_ankle", Landmark::LeftAnkle),
    ("right_hip", Landmark::RightHip),
    ("right_knee", Landmark::RightKnee),
    ("right_ankle", Landmark::RightAnkle),
];

/// The CSV columns, in the order of the field indices kept by [`Header`].
const COLUMNS: [&str; 5] = ["image", "joint", "x", "y", "visible"];

/// Position of each of [`COLUMNS`] in a row, and the number of fields a row must have.
struct Header {
    image: usize,
    joint: usize,
    x: usize,
    y: usize,
    visible: usize,
    width: usize,
}

/// One joint of one image.
#[derive(Clone, Copy)]
struct Joint {
    point: [f64; 2],
    visible: bool,
    line: usize,
}

/// The rows of one image.
struct Image<'a> {
    name: &'a str,
    first_line: usize,
    joints: [Option<Joint>; 14],
}

/// Reads LSP CSV text (BOM already removed, known not to be blank).
pub(crate) fn parse(
    text: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let mut lines = text
        .split('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((header_line, header_text)) = lines.next() else {
        return Err(KeypointError::Empty {
            file: file.to_owned(),
        });
    };
    let header = parse_header(header_text, header_line, file)?;

    let mut images: Vec<Image> = Vec::new();
    let mut by_name: HashMap<&str, usize> = HashMap::new();
    let mut fields = Vec::with_capacity(header.width);
    for (line, row) in lines {
        fields.clear();
        fields.extend(row.split(',').map(str::trim));
        if fields.len() != header.width {
            return Err(KeypointError::CsvFieldCount {
                file: file.to_owned(),
                line,
                expected: header.width,
                found: fields.len(),
            });
        }
        let at = || Location::Line(line);
        let name = fields[header.image];
        if name.is_empty() {
            return Err(invalid(file, at(), "image", name, "a non-empty image name"));
        }
        let joint_name = fields[header.joint];
        let slot = LSP_JOINTS
            .iter()
            .position(|(n, _)| *n == joint_name)
            .ok_or_else(|| KeypointError::UnknownJoint {
                file: file.to_owned(),
                at: at(),
                name: joint_name.to_owned(),
                expected: LSP_JOINTS.map(|(n, _)| n).join(", "),
            })?;
        let point = [
            coordinate(fields[header.x], "x", file, line)?,
            coordinate(fields[header.y], "y", file, line)?,
        ];
        let visible = match fields[header.visible] {
            "1" => true,
            "0" => false,
            other => return Err(invalid(file, at(), "visible", other, "0 or 1")),
        };

        let index = *by_name.entry(name).or_insert_with(|| {
            images.push(Image {
                name,
                first_line: line,
                joints: [None; 14],
            });
            images.len() - 1
        });
        let image = &mut images[index];
        if let Some(first) = image.joints[slot] {
            return Err(KeypointError::DuplicateJoint {
                file: file.to_owned(),
                at: at(),
                first: Location::Line(first.line),
                image: name.to_owned(),
                joint: joint_name.to_owned(),
            });
        }
        image.joints[slot] = Some(Joint {
            point,
            visible,
            line,
        });
    }

    Ok(images
        .into_iter()
        .map(|image| {
            let mut pose = PartialPose2::empty();
            let mut annotated = PartialPose2::empty();
            for ((_, landmark), joint) in LSP_JOINTS.iter().zip(&image.joints) {
                let kept = joint.filter(|j| j.visible || options.lsp.invisible == Invisible::Use);
                pose.points[landmark.index()] = kept.map(|j| j.point);
                annotated.points[landmark.index()] = joint.map(|j| j.point);
            }
            // The torso is the unit of scale and LSP annotates hidden joints too: a pelvis or
            // neck that the visible joints cannot give comes from the annotated (invisible)
            // hips, shoulders or neck, and is recorded as derived.
            let mut derived = Vec::new();
            if options.derive_torso {
                derive_torso(&mut annotated);
                let mut visible_only = pose;
                derive_torso(&mut visible_only);
                for torso in [Landmark::Pelvis, Landmark::Neck] {
                    let t = torso.index();
                    if visible_only.points[t].is_none() && annotated.points[t].is_some() {
                        pose.points[t] = annotated.points[t];
                        derived.push(torso);
                    }
                }
            }
            let source = format!("{file}: {}", Location::Line(image.first_line));
            finish(image.name.to_owned(), pose, derived, source, options)
        })
        .collect())
}

/// Finds the five columns in the header, in any order (names compared ignoring ASCII case).
fn parse_header(text: &str, line: usize, file: &str) -> Result<Header, KeypointError> {
    let names: Vec<&str> = text.split(',').map(str::trim).collect();
    let mut found: [Option<usize>; 5] = [None; 5];
    let mut extra = Vec::new();
    for (i, name) in names.iter().enumerate() {
        match COLUMNS.iter().position(|c| c.eq_ignore_ascii_case(name)) {
            Some(c) if found[c].is_none() => found[c] = Some(i),
            _ => extra.push((*name).to_owned()),
        }
    }
    match found {
        [Some(image), Some(joint), Some(x), Some(y), Some(visible)] if extra.is_empty() => {
            Ok(Header {
                image,
                joint,
                x,
                y,
                visible,
                width: names.len(),
            })
        }
        _ => Err(KeypointError::CsvHeader {
            file: file.to_owned(),
            line,
            header: text.to_owned(),
            missing: COLUMNS
                .iter()
                .zip(&found)
                .filter(|(_, f)| f.is_none())
                .map(|(c, _)| (*c).to_owned())
                .collect(),
            extra,
        }),
    }
}

/// A finite coordinate from a CSV field.
fn coordinate(
    text: &str,
    field: &'static str,
    file: &str,
    line: usize,
) -> Result<f64, KeypointError> {
    let value: f64 = text
        .parse()
        .map_err(|_| invalid(file, Location::Line(line), field, text, "a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(KeypointError::NonFinite {
            file: file.to_owned(),
            at: Location::Line(line),
            field,
            text: text.to_owned(),
        })
    }
}

/// A [`KeypointError::InvalidValue`].
fn invalid(
    file: &str,
    at: Location,
    field: &'static str,
    text: &str,
    expected: &'static str,
) -> KeypointError {
    KeypointError::InvalidValue {
        file: file.to_owned(),
        at,
        field,
        text: text.to_owned(),
        expected,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_landmark_but_the_pelvis_has_exactly_one_lsp_joint() {
        for l in Landmark::ALL {
            let n = LSP_JOINTS.iter().filter(|(_, m)| *m == l).count();
            assert_eq!(n, usize::from(l != Landmark::Pelvis), "{l:?}");
        }
    }

    #[test]
    fn columns_may_come_in_any_order_and_case() {
        let text = "Visible, X ,y,JOINT,image\n1,3.5,4.5,neck,a\n";
        let records = parse(text, "t.csv", &ReadOptions::default()).unwrap();
        assert_eq!(records.len(), 1);
        assert_eq!(
            records[0].pose.points[Landmark::Neck.index()],
            Some([3.5, 4.5])
        );
    }

    #[test]
    fn repeated_column_is_reported() {
        let err = parse(
            "image,joint,x,x,y,visible\n",
            "t.csv",
            &ReadOptions::default(),
        )
        .unwrap_err();
        assert!(
            matches!(&err, KeypointError::CsvHeader { extra, missing, .. } if extra == &["x"] && missing.is_empty())
        );
    }
}
