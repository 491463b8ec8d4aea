//! Python bindings of camloc, importable as `camloc`: NumPy arrays in, dicts of NumPy arrays out.
//!
//! Thin over the Rust crates: joint layouts come from [`camloc::keypoints::pose_from_array`],
//! localization from [`camloc::CameraLocalizer`], reconstruction from [`camloc::PoseReconstructor`],
//! files from [`camloc::keypoints::read_keypoints`], smoothed viewpoints from
//! [`camloc::smooth_viewpoints`], BVH from [`camloc::mocap::write_bvh`] and
//! [`camloc::mocap::read_bvh_with_unit`]. This crate only converts arrays, releases
//! the GIL around batch work and runs batches on rayon's thread pool. The Python API is
//! documented in `camloc.pyi` beside this crate's Cargo.toml.

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyOSError, PyUserWarning, PyValueError};
use pyo3::prelude::*;

mod arrays;
mod bvh;
mod defaults;
mod intrinsics;
mod localize;
mod number;
mod pool;
mod read;
mod reconstruct;
mod smooth;
mod warnings;

create_exception!(
    camloc,
    CamlocError,
    PyException,
    "An error reported by camloc's Rust library (unreadable or malformed file, unusable model, ...); the message is the library's."
);

create_exception!(
    camloc,
    CamlocWarning,
    PyUserWarning,
    "The warnings camloc gives (a UserWarning): filter them with warnings.simplefilter(\"ignore\", camloc.CamlocWarning)."
);

/// The Python exception for a camloc error: `OSError` when a file could not be opened or read,
/// `ValueError` for a layout the file's format does not take, [`CamlocError`] otherwise, with
/// the library's message.
pub(crate) fn to_py_err(error: camloc::CamlocError) -> PyErr {
    use camloc::CamlocError as E;
    use camloc::keypoints::KeypointError;
    use camloc::store::StoreError;
    match &error {
        E::Keypoints(KeypointError::Io { .. }) | E::Store(StoreError::Io { .. }) => {
            PyOSError::new_err(error.to_string())
        }
        // An option the file cannot take.
        E::Keypoints(KeypointError::LayoutNotUsed { .. }) => value_error(error.to_string()),
        _ => CamlocError::new_err(error.to_string()),
    }
}

/// A `ValueError` with `message`.
pub(crate) fn value_error(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

// The `camloc` module: its docstring is camloc.pyi's (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/module.txt"))]
#[pymodule]
#[pyo3(name = "camloc")]
fn camloc_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    pool::note_importing_process();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("CamlocError", m.py().get_type::<CamlocError>())?;
    m.add("CamlocWarning", m.py().get_type::<CamlocWarning>())?;
    m.add(
        "LAYOUTS",
        camloc::keypoints::Layout::ALL.map(|l| l.name()).to_vec(),
    )?;
    m.add(
        "FORMATS",
        camloc::keypoints::KeypointFormat::ALL
            .map(|f| f.name())
            .to_vec(),
    )?;
    m.add(
        "LANDMARKS",
        camloc::Landmark::ALL.map(|l| l.name()).to_vec(),
    )?;
    m.add("BONE_KEYS", camloc::reconstruct::BONE_KEYS.to_vec())?;
    m.add_class::<localize::Localizer>()?;
    m.add_function(wrap_pyfunction!(localize::localizer_from_bytes, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct::reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(reconstruct::bone_lengths_json_text, m)?)?;
    m.add_function(wrap_pyfunction!(read::read_keypoints, m)?)?;
    m.add_function(wrap_pyfunction!(bvh::to_bvh, m)?)?;
    m.add_function(wrap_pyfunction!(bvh::read_bvh, m)?)?;
    m.add_function(wrap_pyfunction!(smooth::smooth_viewpoints, m)?)?;
    Ok(())
}
