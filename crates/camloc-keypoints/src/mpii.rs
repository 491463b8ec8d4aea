//! MPII Human Pose annotations in their common JSON form (the conversion of the MATLAB release
//! used by HRNet and MMPose: `mpii_train.json`, `mpii_val.json`): a list of
//! `{"image": "015601864.jpg", "joints": [[x, y] × 16], "joints_vis": [0 or 1 × 16], ...}`.

use serde::de::SeqAccess;

use crate::ReadOptions;
use crate::emit::{self, Sink, TopLevel};
use crate::error::{KeypointError, Location};
use crate::json::{
    self, Json, array, index_path, key_path, number_array, numbers, object, required,
};
use crate::layout::MPII16;
use crate::record::{KeypointRecord, from_joints};

/// MPII JSON annotations: a list of annotations, read one at a time.
pub(crate) struct Annotations;

impl TopLevel for Annotations {
    const EXPECTED: &'static str = "a list of MPII annotations";

    fn list<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        let (file, options) = (sink.file, sink.options);
        emit::entries(seq, sink, |entry, i| {
            annotation(&entry, i, file, options).map(Some)
        })
    }
}

/// The `i`-th annotation.
fn annotation(
    entry: &Json,
    i: usize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let path = index_path("", i);
    let fields = object(entry, "an annotation object", file, &path)?;
    let image = match required(fields, "image", file, &path)? {
        Json::String(image) => image,
        other => {
            return Err(json::wrong_type(
                file,
                &key_path(&path, "image"),
                "a string",
                other,
            ));
        }
    };
    let joints_path = key_path(&path, "joints");
    let joints = array(
        required(fields, "joints", file, &path)?,
        "a list of 16 [x, y]",
        file,
        &joints_path,
    )?;
    let vis_path = key_path(&path, "joints_vis");
    let vis = numbers(
        required(fields, "joints_vis", file, &path)?,
        "a list of 16 flags",
        file,
        &vis_path,
    )?;
    for (found, at, items, what) in [
        (joints.len(), &joints_path, "joints", "MPII [x, y]"),
        (vis.len(), &vis_path, "flags", "MPII joints_vis"),
    ] {
        if found != MPII16.len() {
            return Err(KeypointError::WrongLength {
                file: file.to_owned(),
                at: Location::Path(at.clone()),
                expected: MPII16.len(),
                found,
                items,
                what,
            });
        }
    }
    let mut points = Vec::with_capacity(MPII16.len());
    for (k, (joint, &flag)) in joints.iter().zip(&vis).enumerate() {
        let xy = number_array::<2>(joint, "[x, y]", file, &index_path(&joints_path, k))?;
        if flag != 0.0 && flag != 1.0 {
            return Err(KeypointError::InvalidValue {
                file: file.to_owned(),
                at: Location::Path(index_path(&vis_path, k)),
                field: "joints_vis",
                text: flag.to_string(),
                expected: "0 or 1",
            });
        }
        points.push((flag == 1.0).then_some(xy));
    }
    Ok(from_joints(
        &MPII16,
        points,
        format!("{image}/{i}"),
        file,
        &path,
        options,
    ))
}
