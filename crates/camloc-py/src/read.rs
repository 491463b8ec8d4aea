//! `camloc.read_keypoints`: a keypoint file or folder as NumPy arrays.

use std::path::PathBuf;

use camloc::keypoints::{
    ImageSize, Invisible, KeypointError, KeypointFormat, KeypointRecord, KeypointStream, Layout,
    ReadOptions, WeakScores, open_keypoints, read_folder,
};
use camloc::reconstruct::FrameRate;
use camloc::{CamlocError, ImageSizeCheck, Landmark};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::arrays::Output;
use crate::{to_py_err, value_error};

/// `image_size` as given: `(W, H)` in pixels (a tuple, list or array), or the text `"W,H"`.
#[derive(FromPyObject)]
pub(crate) enum ImageSizeArg {
    Text(String),
    /// Bytes (not read as numbers): refused.
    Bytes(Py<pyo3::types::PyBytes>),
    Numbers(Vec<f64>),
    /// Anything else: refused with its type's name.
    Other(Py<PyAny>),
}

/// The `TypeError` of an `image_size` of type `given`.
fn image_size_type(given: &str) -> PyErr {
    pyo3::exceptions::PyTypeError::new_err(format!(
        "image_size: (width, height) in pixels, as a tuple, list or array of two numbers, or \
         the text \"W,H\"; got {given}"
    ))
}

/// The reader options from the Python arguments; bad values are `ValueError`s.
fn read_options(
    layout: Option<&str>,
    min_score: f64,
    image_size: Option<ImageSizeArg>,
    lsp_invisible: &str,
    derive_torso: bool,
) -> PyResult<ReadOptions> {
    let layout = layout
        .map(str::parse::<Layout>)
        .transpose()
        .map_err(|e| value_error(e.to_string()))?;
    if !(min_score.is_finite() && min_score >= 0.0) {
        return Err(value_error(format!(
            "min_score must be a finite number >= 0, got {min_score}"
        )));
    }
    let image_size = match image_size {
        None => None,
        Some(ImageSizeArg::Text(text)) => Some(text),
        Some(ImageSizeArg::Bytes(given)) => {
            let length = Python::attach(|py| given.bind(py).as_bytes().len());
            return Err(image_size_type(&format!(
                "{length} bytes (give the text as a str)"
            )));
        }
        Some(ImageSizeArg::Other(given)) => {
            let name = Python::attach(|py| {
                given
                    .bind(py)
                    .get_type()
                    .name()
                    .map_or_else(|_| "?".to_owned(), |n| n.to_string())
            });
            return Err(image_size_type(&name));
        }
        Some(ImageSizeArg::Numbers(numbers)) => match numbers[..] {
            [w, h] => Some(format!("{w},{h}")),
            _ => {
                return Err(value_error(format!(
                    "image_size: two numbers (width, height) in pixels, got {}",
                    numbers.len()
                )));
            }
        },
    }
    .map(|text| text.parse::<ImageSize>())
    .transpose()
    .map_err(|e| value_error(e.to_string()))?;
    let invisible = match lsp_invisible {
        "missing" => Invisible::Missing,
        "use" => Invisible::Use,
        other => {
            return Err(value_error(format!(
                "lsp_invisible must be \"missing\" or \"use\", got \"{other}\""
            )));
        }
    };
    let mut options = ReadOptions {
        derive_torso,
        min_score,
        image_size,
        layout,
        ..ReadOptions::default()
    };
    options.lsp.invisible = invisible;
    Ok(options)
}

// Reads a keypoint file, or every keypoint file of a folder: its docstring is camloc.pyi's
// (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/read_keypoints.txt"))]
#[pyfunction]
#[pyo3(signature = (path, format = None, layout = None, min_score = 0.0, image_size = None, lsp_invisible = "missing", derive_torso = true, recursive = false, max_input_bytes = ReadOptions::DEFAULT_MAX_BYTES))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn read_keypoints<'py>(
    py: Python<'py>,
    path: PathBuf,
    format: Option<&str>,
    layout: Option<&str>,
    #[pyo3(from_py_with = crate::number::min_score)] min_score: f64,
    image_size: Option<ImageSizeArg>,
    lsp_invisible: &str,
    #[pyo3(from_py_with = crate::number::derive_torso)] derive_torso: bool,
    #[pyo3(from_py_with = crate::number::recursive)] recursive: bool,
    #[pyo3(from_py_with = crate::number::max_input_bytes)] max_input_bytes: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let format = format
        .map(str::parse::<KeypointFormat>)
        .transpose()
        .map_err(|e| value_error(e.to_string()))?;
    let mut options = read_options(layout, min_score, image_size, lsp_invisible, derive_torso)?;
    if max_input_bytes == 0 {
        return Err(value_error(
            "max_input_bytes: at least 1 byte (the default: 1 GiB)".to_owned(),
        ));
    }
    options.max_bytes = max_input_bytes;
    // The poses read (a refused pose kept in its place without landmarks, its error in
    // `pose_errors`); of a folder, each file that failed and its message, the files read.
    let mut pose_errors = Vec::new();
    let (records, file_errors, read_files) = py
        .detach(|| {
            crate::pool::run(|| -> Result<_, CamlocError> {
                if !path.is_dir() {
                    let stream = open_keypoints(&path, format, &options)?;
                    return Ok((records_of(stream, &mut pose_errors)?, Vec::new(), 1));
                }
                let mut records = Vec::new();
                let mut file_errors = Vec::new();
                let mut first_error = None;
                let mut read_files = 0;
                for (file, stream) in read_folder(&path, format, &options, recursive)?.streams() {
                    match stream.and_then(|s| records_of(s, &mut pose_errors)) {
                        Ok(mut read) => {
                            records.append(&mut read);
                            read_files += 1;
                        }
                        Err(e) => {
                            file_errors.push((file.display().to_string(), e.to_string()));
                            first_error.get_or_insert(e);
                        }
                    }
                }
                // A folder without a pose read and with a file that could not be read (the
                // others, if any, empty: OpenPose's frames without people): the first file's
                // error, as reading that file alone gives it (a layout the format does not
                // take fails every file alike).
                match first_error {
                    Some(e) if records.is_empty() => Err(e.into()),
                    _ => Ok((records, file_errors, read_files)),
                }
            })
        })
        .map_err(to_py_err)?;
    if let Some((source, message)) = pose_errors.first() {
        crate::warnings::warn(
            py,
            format!(
                "{} pose(s) could not be read and are rows without landmarks (pose_errors); \
                 the first, {source}: {message}",
                pose_errors.len()
            ),
        )?;
    }
    if let Some((file, message)) = file_errors.first() {
        crate::warnings::warn(
            py,
            format!(
                "{} of the {} files could not be read and are left out (file_errors); the \
                 first, {file}: {message}",
                file_errors.len(),
                file_errors.len() + read_files
            ),
        )?;
    }
    // The command line refuses such an input ("no poses in ..."); here the arrays are empty.
    if records.is_empty() {
        let hint = if !recursive && camloc::keypoints::has_subfolders(&path) {
            " (its sub-folders are read with recursive=True)"
        } else {
            ""
        };
        crate::warnings::warn(
            py,
            format!(
                "no poses in {}{hint}: the arrays are empty",
                camloc::store::quoted_path(&path)
            ),
        )?;
    }
    if min_score == 0.0 {
        // The poses read already are those at 0: only the reading at the threshold is new.
        let counts =
            py.detach(|| WeakScores::against(&records, &path, format, &options, recursive));
        crate::warnings::warn_of_weak_scores(py, counts)?;
    }
    if let Some(size) = options.image_size {
        let poses =
            py.detach(|| ImageSizeCheck::normalised_poses(&path, format, &options, recursive));
        // The embedded models are loaded only for an input the size scales.
        if let Some(poses) = poses {
            let reconstructor = crate::defaults::default_reconstructor()?;
            let check = py.detach(|| ImageSizeCheck::measure(reconstructor, &poses, size));
            crate::warnings::warn_of_swapped_image_size(py, check)?;
        }
    }
    // Every pose empty under a threshold: the threshold on another scale than the scores? (A
    // simulated user's min_score=30 for scores of 0-1 had given all-NaN points without a word.)
    if min_score > 0.0 && !records.is_empty() && records.iter().all(|r| r.pose.present_mask() == 0)
    {
        crate::warnings::warn(
            py,
            format!(
                "none of the {} poses has a landmark at min_score {min_score}: is it on the \
                 scale of the scores (0-1 for most detectors)?",
                records.len()
            ),
        )?;
    }
    let mut records = records;
    // Untracked people followed as the command line's `--sequence` does (30 frames a second).
    let followed = camloc::follow_records(&mut records, path.is_dir(), FrameRate::default());
    for warning in followed.warnings() {
        crate::warnings::warn(py, warning)?;
    }
    records_dict(py, &records, file_errors, pose_errors)
}

/// The records of `stream`: a pose the reader refused ([`KeypointError::refused_pose`]: a
/// 17-joint pose whose first joints contradict its layout, a `.npy` row no pose holds) kept
/// in its place without landmarks and its source and message added to `pose_errors`, as the
/// command line reads on past it; any other error ends the reading.
fn records_of(
    stream: KeypointStream,
    pose_errors: &mut Vec<(String, String)>,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let mut records = Vec::new();
    for item in stream {
        match item {
            Ok(record) => records.push(record),
            Err(e) => match KeypointRecord::of_refused_pose(&e) {
                Some((record, _)) => {
                    pose_errors.push((record.source.clone(), e.to_string()));
                    records.push(record);
                }
                None => return Err(e),
            },
        }
    }
    Ok(records)
}

/// The records as arrays: points (N, 15, 2) with NaN for missing landmarks, derived (N, 15),
/// frames and persons (N,) with -1 for none, ids and sources as lists of str.
fn records_dict<'py>(
    py: Python<'py>,
    records: &[KeypointRecord],
    file_errors: Vec<(String, String)>,
    pose_errors: Vec<(String, String)>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = records.len();
    let mut points = Vec::with_capacity(n * 30);
    let mut derived = Vec::with_capacity(n * 15);
    for record in records {
        for (point, landmark) in record.pose.points.iter().zip(Landmark::ALL) {
            points.extend_from_slice(&point.unwrap_or([f64::NAN; 2]));
            derived.push(record.is_derived(landmark));
        }
    }
    let index = |v: Option<u64>| v.and_then(|v| i64::try_from(v).ok()).unwrap_or(-1);
    let out = Output::new(py, n, false);
    out.array("points", points, &[15, 2])?;
    out.array("derived", derived, &[15])?;
    out.array(
        "frames",
        records.iter().map(|r| index(r.frame)).collect(),
        &[],
    )?;
    out.array(
        "persons",
        records.iter().map(|r| index(r.person)).collect(),
        &[],
    )?;
    out.set("ids", PyList::new(py, records.iter().map(|r| &r.id))?)?;
    out.set(
        "sources",
        PyList::new(py, records.iter().map(|r| &r.source))?,
    )?;
    out.set("file_errors", PyList::new(py, file_errors)?)?;
    out.set("pose_errors", PyList::new(py, pose_errors)?)?;
    Ok(out.into_dict())
}
