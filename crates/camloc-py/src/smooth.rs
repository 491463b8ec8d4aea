//! `camloc.smooth_viewpoints`: one person's per-frame viewpoints smoothed over time, as
//! `camloc localize --sequence` smooths them ([`camloc::smooth_viewpoints`]); and the time
//! arguments of the sequence calls: `fps` ([`frame_rate`]) and `frames` ([`frame_numbers`],
//! [`sequence_frames`]).

use camloc::reconstruct::FrameRate;
use numpy::{PyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::arrays::{Unmasked, c_order, ensure_memory};
use crate::value_error;

/// Azimuths and elevations, degrees, one per frame.
type Degrees<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

// Smooths one person's viewpoints over the frames of a video: its docstring is camloc.pyi's
// (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/smooth_viewpoints.txt"))]
#[pyfunction]
#[pyo3(signature = (azimuth_deg, elevation_deg, frames = None, fps = 30.0))]
pub(crate) fn smooth_viewpoints<'py>(
    py: Python<'py>,
    azimuth_deg: Unmasked<'py>,
    elevation_deg: Unmasked<'py>,
    frames: Option<Unmasked<'py>>,
    #[pyo3(from_py_with = crate::number::fps)] fps: f64,
) -> PyResult<Degrees<'py>> {
    let rate = frame_rate(fps)?;
    for (name, array) in [
        ("azimuth_deg", &azimuth_deg),
        ("elevation_deg", &elevation_deg),
    ]
    .into_iter()
    .chain(frames.as_ref().map(|f| ("frames", f)))
    {
        if array.ndim() != 1 {
            return Err(value_error(format!(
                "{name} must be one-dimensional (one number per frame), got shape {:?}",
                array.shape()
            )));
        }
    }
    // Per frame: its number, viewpoint given and smoothed (with the library's working copies).
    ensure_memory(
        azimuth_deg.len(),
        16 * std::mem::size_of::<f64>(),
        "viewpoints",
    )?;
    let (azimuth, elevation) = (c_order(&azimuth_deg)?, c_order(&elevation_deg)?);
    if let Some(e) = elevation.iter().find(|e| e.abs() > 90.0) {
        return Err(value_error(format!(
            "elevation_deg must lie in [-90, 90] (NaN: no viewpoint), got {e}"
        )));
    }
    let n = azimuth.len();
    if elevation.len() != n {
        return Err(value_error(format!(
            "azimuth_deg and elevation_deg must have the same length, got {n} and {}",
            elevation.len()
        )));
    }
    let frames = frame_numbers(frames.as_ref(), n, "viewpoint", Order::Increasing)?.map_or_else(
        || vec![None; n],
        |numbers| numbers.into_iter().map(Some).collect(),
    );
    smoothed_arrays(py, &frames, &azimuth, &elevation, rate)
}

/// The `fps` argument as a frame rate (`ValueError` unless finite and > 0).
pub(crate) fn frame_rate(fps: f64) -> PyResult<FrameRate> {
    FrameRate::new(fps).map_err(|e| value_error(format!("fps: {e}")))
}

/// How the `frames` argument's numbers must follow each other ([`frame_numbers`]).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    /// Each greater than the one before (one number per frame).
    Increasing,
    /// None smaller than the one before (several rows of one frame: an untracked
    /// detector's people).
    NotDecreasing,
}

/// The `frames` argument (one number per row, `n` rows, each a `row` in messages): the video
/// frame numbers, whole numbers from 0 to 2^53 in `order`; `None` when not given or all -1
/// (`read_keypoints`' frames of an input without frame numbers). `ValueError` for a
/// wrong length, a number that is not such a whole number, or numbers out of order.
pub(crate) fn frame_numbers(
    frames: Option<&Unmasked<'_>>,
    n: usize,
    row: &str,
    order: Order,
) -> PyResult<Option<Vec<u64>>> {
    let Some(given) = frames else {
        return Ok(None);
    };
    if given.ndim() != 1 {
        return Err(value_error(format!(
            "frames must be one-dimensional (one number per {row}), got shape {:?}",
            given.shape()
        )));
    }
    let given = c_order(given)?;
    if given.len() != n {
        return Err(value_error(format!(
            "frames must have one number per {row} ({n}), got {}",
            given.len()
        )));
    }
    if given.iter().all(|&f| f == -1.0) {
        return Ok(None);
    }
    let numbers = given
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            (f.is_finite() && f >= 0.0 && f.fract() == 0.0 && f <= 2f64.powi(53))
                .then_some(f as u64)
                .ok_or_else(|| {
                    let masked = if f.is_nan() { " (masked?)" } else { "" };
                    value_error(format!(
                        "frames must be whole numbers from 0 to 2^53, got {f}{masked} at {k}"
                    ))
                })
        })
        .collect::<PyResult<Vec<u64>>>()?;
    let out_of_order = |w: &[u64]| match order {
        Order::Increasing => w[1] <= w[0],
        Order::NotDecreasing => w[1] < w[0],
    };
    if let Some(k) = numbers.windows(2).position(out_of_order) {
        let must = match order {
            Order::Increasing => "increase",
            Order::NotDecreasing => "not decrease (rows in time order)",
        };
        return Err(value_error(format!(
            "frames must {must}, got {} then {} at {}",
            numbers[k],
            numbers[k + 1],
            k + 1
        )));
    }
    Ok(Some(numbers))
}

/// The video frame numbers of the `n` rows of a `sequence` call (`reconstruct`,
/// `Localizer.localize`): `frames` as [`frame_numbers`] reads them (several rows of one frame
/// allowed), else consecutive frames; none without `sequence`. `ValueError` for `frames`
/// without `sequence`, `TypeError` for booleans, text or float16 (NumPy would read them as
/// numbers).
pub(crate) fn sequence_frames(
    frames: Option<&Bound<'_, PyAny>>,
    sequence: bool,
    n: usize,
) -> PyResult<Vec<Option<u64>>> {
    if frames.is_some() && !sequence {
        return Err(value_error(
            "frames is for sequence=True (the rows' video frame numbers); single poses have \
             no time"
                .to_owned(),
        ));
    }
    if !sequence {
        return Ok(Vec::new());
    }
    let frames = match frames {
        Some(given) => {
            let dtype = given
                .py()
                .import("numpy")?
                .call_method1("asarray", (given,))?
                .getattr("dtype")?;
            let kind: String = dtype.getattr("kind")?.extract()?;
            let bytes: usize = dtype.getattr("itemsize")?.extract()?;
            if !matches!(kind.as_str(), "i" | "u" | "f") {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "frames must be frame numbers (integers), got an array of NumPy kind \
                     {kind:?}"
                )));
            }
            // float16 holds whole numbers exactly only up to 2048 (frames beyond merge).
            if kind == "f" && bytes < 4 {
                return Err(pyo3::exceptions::PyTypeError::new_err(
                    "frames must be frame numbers (integers): float16 cannot hold frame \
                     numbers above 2048"
                        .to_owned(),
                ));
            }
            Some(given.extract::<Unmasked<'_>>()?)
        }
        None => None,
    };
    let numbers = frame_numbers(frames.as_ref(), n, "row", Order::NotDecreasing)?;
    Ok(match numbers {
        Some(numbers) => numbers.into_iter().map(Some).collect(),
        None => (0..n as u64).map(Some).collect(),
    })
}

/// Most frame numbers a sequence of `n` rows is placed in the world over
/// (`PoseReconstructor::place_on_timeline`): 100 per row and 1,000 more, and at most 100,000
/// more than the rows (the memory of the frames the person is missing from); rows spread
/// wider are placed as consecutive frames.
pub(crate) fn timeline_max_slots(n: usize) -> usize {
    n.saturating_mul(100)
        .saturating_add(1_000)
        .min(n.saturating_add(100_000))
}

/// [`smoothed_columns`] as NumPy arrays.
fn smoothed_arrays<'py>(
    py: Python<'py>,
    frames: &[Option<u64>],
    azimuth: &[f64],
    elevation: &[f64],
    rate: FrameRate,
) -> PyResult<Degrees<'py>> {
    let (azimuth, elevation) = smoothed_columns(frames, azimuth, elevation, rate);
    Ok((
        PyArray1::from_vec(py, azimuth),
        PyArray1::from_vec(py, elevation),
    ))
}

/// [`camloc::smooth_viewpoints`] of per-frame `azimuth` and `elevation` (degrees; a frame with
/// a non-finite one has no viewpoint) at frame numbers `frames`, as azimuth and elevation
/// columns, NaN where a frame has no smoothed viewpoint; `rate`: the frames a second.
pub(crate) fn smoothed_columns(
    frames: &[Option<u64>],
    azimuth: &[f64],
    elevation: &[f64],
    rate: FrameRate,
) -> (Vec<f64>, Vec<f64>) {
    let viewpoints: Vec<Option<(f64, f64)>> = azimuth
        .iter()
        .zip(elevation)
        .map(|(&a, &e)| (a.is_finite() && e.is_finite()).then_some((a, e)))
        .collect();
    camloc::smooth_viewpoints(frames, &viewpoints, rate)
        .into_iter()
        .map(|v| v.unwrap_or((f64::NAN, f64::NAN)))
        .unzip()
}
