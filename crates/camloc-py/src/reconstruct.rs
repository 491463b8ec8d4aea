//! `camloc.reconstruct`: 3D poses of a NumPy batch.

use std::path::PathBuf;
use std::sync::OnceLock;

use camloc::reconstruct::PoseBasis;
use camloc::store::Persist;
use camloc::{CameraLocalizer, CamlocError, ModeKind, PoseReconstructor};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::arrays::{ArrayArg, Output, PoseBatch};
use crate::localize::Localizer;
use crate::{to_py_err, value_error};

/// The reconstructor on the embedded basis with the embedded default model, made once.
fn default_reconstructor() -> PyResult<&'static PoseReconstructor> {
    static DEFAULT: OnceLock<Result<PoseReconstructor, String>> = OnceLock::new();
    DEFAULT
        .get_or_init(|| {
            let made = || -> Result<_, CamlocError> {
                Ok(PoseReconstructor::new(camloc::default_basis()?)?
                    .with_localizer(CameraLocalizer::default_model()?))
            };
            made().map_err(|e| e.to_string())
        })
        .as_ref()
        .map_err(|message| crate::CamlocError::new_err(message.clone()))
}

/// Reconstructs the 3D pose of every pose; see `camloc.pyi`.
#[pyfunction]
#[pyo3(signature = (points, layout = "camloc15", camera = "opt", scores = None, min_score = 0.0, localizer = None, basis = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn reconstruct<'py>(
    py: Python<'py>,
    points: ArrayArg<'py>,
    layout: &str,
    camera: &str,
    scores: Option<ArrayArg<'py>>,
    min_score: f64,
    localizer: Option<PyRef<'py, Localizer>>,
    basis: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let mode = ModeKind::ALL
        .into_iter()
        .find(|m| m.name() == camera && *m != ModeKind::Oracle)
        .ok_or_else(|| {
            value_error(format!(
                "unknown camera \"{camera}\" (expected one of: opt, classified, hybrid)"
            ))
        })?;
    let batch = PoseBatch::new(&points, layout, scores.as_ref(), min_score)?;
    let mut reconstructor = match basis {
        Some(path) => PoseBasis::load(&path)
            .map_err(CamlocError::from)
            .and_then(PoseReconstructor::new)
            .map_err(to_py_err)?
            .with_localizer(CameraLocalizer::default_model().map_err(to_py_err)?),
        None => default_reconstructor()?.clone(),
    };
    if let Some(localizer) = localizer {
        reconstructor = reconstructor.with_localizer(localizer.inner.clone());
    }
    let reconstructor = reconstructor
        .with_mode(mode)
        .map_err(|e| value_error(e.to_string()))?;
    let n = batch.len();
    let results = py.detach(|| {
        (0..n)
            .into_par_iter()
            .with_max_len(8)
            .map(|i| {
                let mapped = batch.pose(i).map_err(|e| e.to_string())?;
                reconstructor
                    .reconstruct(&mapped.pose)
                    .map_err(|e| e.to_string())
            })
            .collect::<Vec<_>>()
    });
    let mut points3d = vec![f64::NAN; n * 45];
    let mut rotation = vec![f64::NAN; n * 9];
    let mut scale = vec![f64::NAN; n];
    let mut translation = vec![f64::NAN; n * 2];
    let mut projection_error = vec![f64::NAN; n];
    let mut label = vec![0i64; n];
    let mut errors = Vec::new();
    for (i, result) in results.into_iter().enumerate() {
        let r = match result {
            Ok(r) => r,
            Err(message) => {
                errors.push((i, message));
                continue;
            }
        };
        let rec = &r.reconstruction;
        for (out, p) in points3d[i * 45..(i + 1) * 45]
            .chunks_exact_mut(3)
            .zip(&rec.pose.points)
        {
            out.copy_from_slice(p);
        }
        for (k, out) in rotation[i * 9..(i + 1) * 9].iter_mut().enumerate() {
            *out = rec.camera.rotation[(k / 3, k % 3)];
        }
        scale[i] = rec.camera.scale;
        translation[i * 2..(i + 1) * 2].copy_from_slice(&rec.camera.translation);
        projection_error[i] = rec.projection_error;
        label[i] = r
            .localization
            .as_ref()
            .map_or(0, |l| i64::from(l.label.get()));
    }
    let out = Output::new(py, n, batch.single);
    out.array("points3d", points3d, &[15, 3])?;
    out.array("rotation", rotation, &[3, 3])?;
    out.array("scale", scale, &[])?;
    out.array("translation", translation, &[2])?;
    out.array("projection_error", projection_error, &[])?;
    out.array("label", label, &[])?;
    out.errors(errors)?;
    out.set("camera", mode.name())?;
    Ok(out.into_dict())
}
