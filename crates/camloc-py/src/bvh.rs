//! `camloc.to_bvh` and `camloc.read_bvh`: 3D poses to BVH text, and a BVH file's 15 landmarks.

use std::path::PathBuf;

use camloc::Pose3;
use camloc::mocap::{
    BVH_UNIT_RANGE_M, BvhOptions, BvhWriteError, CMU_UNIT_M, read_bvh_with_unit, write_person_bvh,
};
use camloc::reconstruct::BoneLengths;
use camloc::skeleton::NUM_LIMBS;
use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{ArrayArg, Output, Unmasked, c_order, ensure_memory};
use crate::reconstruct::bone_lengths;
use crate::value_error;

/// A BVH file's unit, metres per unit, within `camloc::mocap::BVH_UNIT_RANGE_M`, or a
/// `ValueError`.
fn unit(unit_m: f64) -> PyResult<f64> {
    let (smallest, largest) = BVH_UNIT_RANGE_M;
    if (smallest..=largest).contains(&unit_m) {
        Ok(unit_m)
    } else {
        Err(value_error(format!(
            "unit_m must be from {smallest:e} to {largest:e} metres per unit, got {unit_m:?}"
        )))
    }
}

/// The frames of `points3d` ((N, 15, 3) or (15, 3) metres): `None` for an all-NaN frame (a
/// pose `reconstruct` could not reconstruct).
fn frames(points3d: &ArrayArg<'_>) -> PyResult<Vec<Option<Pose3>>> {
    let shape = points3d.shape();
    let ok = match shape.len() {
        3 => shape[1..] == [15, 3],
        2 => shape == [15, 3],
        _ => false,
    };
    if !ok {
        return Err(value_error(format!(
            "points3d must have shape (N, 15, 3) or (15, 3), got {shape:?}"
        )));
    }
    // Per frame: the pose, and its line of the BVH text (31 joints' channels, about 1 kB).
    ensure_memory(
        shape[0],
        std::mem::size_of::<Option<Pose3>>() + 1024,
        "frames",
    )?;
    let values = c_order(points3d)?;
    let mut out = Vec::with_capacity(values.len() / 45);
    for (n, chunk) in values.chunks_exact(45).enumerate() {
        if chunk.iter().all(|v| v.is_nan()) {
            out.push(None);
            continue;
        }
        if !chunk.iter().all(|v| v.is_finite()) {
            return Err(value_error(format!(
                "points3d[{n}] has a NaN or infinite coordinate (a frame is either complete or all NaN)"
            )));
        }
        out.push(Some(Pose3::new(std::array::from_fn(|i| {
            std::array::from_fn(|k| chunk[3 * i + k])
        }))));
    }
    Ok(out)
}

// The 3D poses as BVH text: its docstring is camloc.pyi's (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/to_bvh.txt"))]
#[pyfunction]
#[pyo3(signature = (points3d, fps = 30.0, limb_lengths = None, unit_m = 0.01))]
pub(crate) fn to_bvh(
    points3d: Unmasked<'_>,
    #[pyo3(from_py_with = crate::number::fps)] fps: f64,
    limb_lengths: Option<Bound<'_, PyAny>>,
    #[pyo3(from_py_with = crate::number::unit_m)] unit_m: f64,
) -> PyResult<String> {
    let unit_m = unit(unit_m)?;
    let frames = frames(&points3d)?;
    let lengths: Option<[f64; NUM_LIMBS]> = limb_lengths
        .map(|given| bone_lengths(&given, "limb_lengths").map(|l| l.as_array()))
        .transpose()?;
    // Lengths taken from the frames are held to the range given ones are (points in
    // millimetres made limbs of 100 m).
    if lengths.is_none() {
        let poses: Vec<Pose3> = frames.iter().flatten().copied().collect();
        if !poses.is_empty() {
            BoneLengths::mean_of(&poses).map_err(|e| {
                value_error(format!(
                    "points3d: the frames' mean limb lengths: {e} (points3d must be in metres)"
                ))
            })?;
        }
    }
    let options = BvhOptions {
        frame_time_s: 1.0 / fps,
        metres_per_unit: unit_m,
    };
    write_person_bvh(&frames, lengths.as_ref(), &options).map_err(|e| match e {
        BvhWriteError::NoFrames => value_error("points3d has no frame that is not all NaN"),
        other => value_error(other.to_string()),
    })
}

// A BVH file's 15 landmarks: its docstring is camloc.pyi's (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/read_bvh.txt"))]
#[pyfunction]
// The default shown as the number it is (CMU_UNIT_M, the CMU files' inch / 0.45).
#[pyo3(signature = (path, unit_m = CMU_UNIT_M), text_signature = "(path, unit_m=0.05644444444444444)")]
pub(crate) fn read_bvh<'py>(
    py: Python<'py>,
    path: PathBuf,
    #[pyo3(from_py_with = crate::number::unit_m)] unit_m: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let unit_m = unit(unit_m)?;
    let clip = read_bvh_with_unit(&path, unit_m).map_err(|e| match e {
        camloc::mocap::MocapError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => crate::CamlocError::new_err(other.to_string()),
    })?;
    let n = clip.frames.len();
    let points: Vec<f64> = clip
        .frames
        .iter()
        .flat_map(|p| p.points.iter().flatten().copied())
        .collect();
    let out = Output::new(py, n, false);
    out.array("points3d", points, &[15, 3])?;
    out.set("frame_time_s", clip.frame_time_s)?;
    Ok(out.into_dict())
}
