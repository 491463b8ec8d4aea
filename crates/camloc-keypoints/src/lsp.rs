//! LSP-14 CSV: header `image,joint,x,y,visible`, one row per joint.

use std::collections::HashMap;

use camloc_skeleton::{Landmark, PartialPose2};

use crate::error::{KeypointError, Location, MAX_QUOTED_CHARS, MAX_QUOTED_ITEMS};
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

/// One joint row, parsed (24 bytes: rows are held until the end of the input, since an image's
/// rows need not be contiguous).
struct Row {
    /// The image's index, in order of first appearance.
    image: u32,
    /// The joint's index in [`LSP_JOINTS`].
    slot: u8,
    visible: bool,
    point: [f64; 2],
}

/// One image: its name, the line of its first row, and the joints seen so far.
struct Image<'a> {
    name: &'a str,
    first_line: usize,
    seen: u16,
}

/// Reads LSP CSV text (BOM already removed, known not to be blank).
pub(crate) fn parse(
    text: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let mut records = Vec::new();
    read(text, file, options, &mut |r| {
        records.push(r);
        true
    })?;
    Ok(records)
}

/// Reads LSP CSV text (BOM already removed, known not to be blank) and gives the records, in
/// order of the images' first rows, to `emit` (which returns `false` to stop). Every row is
/// checked before the first record; memory is about 24 bytes per row and 70 per image.
pub(crate) fn read(
    text: &str,
    file: &str,
    options: &ReadOptions,
    emit: &mut dyn FnMut(KeypointRecord) -> bool,
) -> Result<(), KeypointError> {
    let mut lines = rows(text);
    let Some((header_line, header_text)) = lines.next() else {
        return Err(KeypointError::Empty {
            file: file.to_owned(),
        });
    };
    let header = parse_header(header_text, header_line, file)?;

    let mut images: Vec<Image> = Vec::new();
    let mut by_name: HashMap<&str, u32> = HashMap::new();
    let mut rows_read: Vec<Row> = Vec::new();
    let mut fields = Vec::with_capacity(header.width);
    for (line, row) in lines {
        fields.clear();
        // (One field past the header's width tells; the rest are only counted.)
        fields.extend(csv_fields(row).take(header.width + 1));
        if fields.len() != header.width {
            return Err(KeypointError::CsvFieldCount {
                file: file.to_owned(),
                line,
                expected: header.width,
                found: row.matches(',').count() + 1,
            });
        }
        let at = || Location::Line(line);
        let name = fields[header.image];
        if name.is_empty() {
            return Err(invalid(file, at(), "image", name, "a non-empty image name"));
        }
        let joint_name = fields[header.joint];
        let slot = joint_slot(joint_name).ok_or_else(|| KeypointError::UnknownJoint {
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
        let index = match by_name.get(name) {
            Some(&index) => index,
            None => {
                let index = u32::try_from(images.len()).map_err(|_| {
                    invalid(file, at(), "image", name, "one of at most 2^32 images")
                })?;
                images.push(Image {
                    name,
                    first_line: line,
                    seen: 0,
                });
                by_name.insert(name, index);
                index
            }
        };
        let image = &mut images[index as usize];
        if image.seen & (1 << slot) != 0 {
            return Err(KeypointError::DuplicateJoint {
                file: file.to_owned(),
                at: at(),
                first: Location::Line(first_row(text, &header, name, joint_name)),
                image: name.to_owned(),
                joint: joint_name.to_owned(),
            });
        }
        image.seen |= 1 << slot;
        rows_read.push(Row {
            image: index,
            slot,
            visible,
            point,
        });
    }
    drop(by_name);
    // The rows of each image together, images in order of first appearance.
    rows_read.sort_unstable_by_key(|r| r.image);
    for (image, joints) in images
        .iter()
        .zip(rows_read.chunk_by(|a, b| a.image == b.image))
    {
        if !emit(record(image, joints, file, options)) {
            break;
        }
    }
    Ok(())
}

/// The non-blank lines of `text` with their 1-based numbers, without line ends.
fn rows(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.split('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
        .filter(|(_, l)| !l.trim().is_empty())
}

/// The index of joint `name` in [`LSP_JOINTS`].
fn joint_slot(name: &str) -> Option<u8> {
    (0u8..)
        .zip(LSP_JOINTS)
        .find(|(_, (n, _))| *n == name)
        .map(|(i, _)| i)
}

/// The line of the first row of joint `joint` of image `image` (for the error on a second).
fn first_row(text: &str, header: &Header, image: &str, joint: &str) -> usize {
    rows(text)
        .skip(1)
        .find(|(_, row)| {
            let fields: Vec<&str> = csv_fields(row).collect();
            fields.get(header.image) == Some(&image) && fields.get(header.joint) == Some(&joint)
        })
        .map_or(0, |(line, _)| line)
}

/// Whether `joint` is an invisible joint without a position: a coordinate at or beyond the
/// image's top or left edge (`<= 0`). LSP-style files put the joints they did not annotate
/// there (in `lsp400_joints.csv` every invisible joint sits at `(0, -27.3)` or the like, all
/// of one image's at one point); taken as positions they would make a torso out of nothing.
/// Such a joint is missing even with [`Invisible::Use`] and gives no pelvis or neck.
fn is_placeholder(joint: &Row) -> bool {
    let placed = joint.point[0] > 0.0 && joint.point[1] > 0.0;
    !joint.visible && !placed
}

/// The record of `image` from its rows.
fn record(image: &Image, joints: &[Row], file: &str, options: &ReadOptions) -> KeypointRecord {
    let mut pose = PartialPose2::empty();
    let mut annotated = PartialPose2::empty();
    for joint in joints.iter().filter(|j| !is_placeholder(j)) {
        let landmark = LSP_JOINTS[usize::from(joint.slot)].1.index();
        if joint.visible || options.lsp.invisible == Invisible::Use {
            pose.points[landmark] = Some(joint.point);
        }
        annotated.points[landmark] = Some(joint.point);
    }
    // The torso is the unit of scale and LSP may annotate hidden joints too: a pelvis or neck
    // that the visible joints cannot give comes from the annotated (invisible, not placeholder)
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
}

/// Checks the header of the start of a longer LSP CSV input (`text`, after `lead_lines`
/// blank lines), which is read whole before it is parsed: a first line that does not name the
/// five columns is refused before the rest is read. A start without a whole line passes.
pub(crate) fn check_header_of_start(
    text: &str,
    lead_lines: u64,
    file: &str,
) -> Result<(), KeypointError> {
    let whole_lines = text.rfind('\n').map_or("", |end| &text[..end]);
    match rows(whole_lines).next() {
        Some((line, header)) => {
            let line = usize::try_from(lead_lines).map_or(usize::MAX, |l| l.saturating_add(line));
            parse_header(header, line, file).map(|_| ())
        }
        None => Ok(()),
    }
}

/// The comma-separated fields of a CSV line, white space trimmed and a field in double quotes
/// unquoted (`"im00001"`: spreadsheets and some writers quote text; no field of this format
/// holds a comma or a quote).
pub(crate) fn csv_fields(line: &str) -> impl Iterator<Item = &str> {
    line.split(',').map(|field| {
        let field = field.trim();
        field
            .strip_prefix('"')
            .and_then(|f| f.strip_suffix('"'))
            .unwrap_or(field)
    })
}

/// Finds the five columns in the header, in any order (names compared ignoring ASCII case).
/// The unknown or repeated names are kept up to [`MAX_QUOTED_ITEMS`] (the message shows no
/// more), and only counted beyond: a header of a hundred million empty names must not take
/// gigabytes.
fn parse_header(text: &str, line: usize, file: &str) -> Result<Header, KeypointError> {
    let mut found: [Option<usize>; 5] = [None; 5];
    let (mut extra, mut extra_count, mut width) = (Vec::new(), 0, 0);
    for (i, name) in csv_fields(text).enumerate() {
        width += 1;
        match COLUMNS.iter().position(|c| c.eq_ignore_ascii_case(name)) {
            Some(c) if found[c].is_none() => found[c] = Some(i),
            _ => {
                extra_count += 1;
                if extra.len() < MAX_QUOTED_ITEMS {
                    extra.push(name.to_owned());
                }
            }
        }
    }
    match found {
        [Some(image), Some(joint), Some(x), Some(y), Some(visible)] if extra_count == 0 => {
            Ok(Header {
                image,
                joint,
                x,
                y,
                visible,
                width,
            })
        }
        _ => Err(KeypointError::CsvHeader {
            file: file.to_owned(),
            line,
            // (As much as the message quotes, and one character to say there is more.)
            header: text.chars().take(MAX_QUOTED_CHARS + 1).collect(),
            missing: COLUMNS
                .iter()
                .zip(&found)
                .filter(|(_, f)| f.is_none())
                .map(|(c, _)| (*c).to_owned())
                .collect(),
            extra,
            extra_count,
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

    /// An invisible hip at the image's edge is a placeholder: no hip and no pelvis from it,
    /// with or without `Invisible::Use`; an invisible hip inside the image gives the pelvis.
    #[test]
    fn placeholder_joints_give_no_position_and_no_torso() {
        let text = "image,joint,x,y,visible\na,left_hip,10,20,1\na,right_hip,0,-27.3,0\n\
                    b,left_hip,10,20,1\nb,right_hip,30,20,0\n";
        for invisible in [Invisible::Missing, Invisible::Use] {
            let options = ReadOptions {
                lsp: crate::LspOptions { invisible },
                ..ReadOptions::default()
            };
            let records = parse(text, "t.csv", &options).unwrap();
            let (a, b) = (&records[0].pose, &records[1].pose);
            assert_eq!(a.points[Landmark::RightHip.index()], None);
            assert_eq!(a.points[Landmark::Pelvis.index()], None);
            assert_eq!(b.points[Landmark::Pelvis.index()], Some([20.0, 20.0]));
            let used = invisible == Invisible::Use;
            assert_eq!(b.points[Landmark::RightHip.index()].is_some(), used);
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
