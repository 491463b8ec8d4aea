//! `camloc.Localizer`: the camera localizer over NumPy batches.

use std::path::PathBuf;

use camloc::keypoints::WeakScores;
use camloc::reconstruct::FrameRate;
use camloc::skeleton::{Landmark, NUM_LANDMARKS};
use camloc::store::Persist;
use camloc::{
    CameraHeight, CameraLocalizer, CamlocError, HEIGHT_SHARE_MAX_POSES, HeightShares, Localization,
    PartialPose2, PoseReconstructor, SequenceModel, default_basis,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;

use crate::arrays::{
    Output, PoseBatch, UnmaskedPoints, UnmaskedScores, landmark_flags, landmark_masks,
};
use crate::smooth::smoothed_columns;
use crate::warnings::{
    warn_if_every_pose_failed, warn_of_identity_jumps, warn_of_input_conventions, warn_of_stretch,
    warn_of_swapped_sides, warn_of_weak_scores,
};
use crate::{to_py_err, value_error};

/// Poses per parallel task: large enough that scheduling costs nothing next to the work.
const CHUNK: usize = 1024;

/// Poses localized between two looks at Python's signals (Ctrl-C): about 0.1 s on two cores.
const INTERRUPT_POSES: usize = 1 << 16;

// A trained camera localizer (the model embedded in camloc, or one loaded from a file): its
// docstring is camloc.pyi's (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/Localizer.txt"))]
#[pyclass(frozen, module = "camloc")]
pub(crate) struct Localizer {
    pub(crate) inner: CameraLocalizer,
    /// `camera_height="from-input"`: each call estimates the shares of the camera heights
    /// among its poses ([`for_poses`]) and localizes them under those shares.
    pub(crate) from_input: bool,
    /// The embedded basis, which fills in the torso of a pose that lacks one
    /// (`CameraLocalizer::localize_filled`); `None` when the build embedded no basis.
    filler: Option<PoseReconstructor>,
    /// Whether a call has compared its pixels for a stretch ([`warn_of_stretch`]): once per
    /// localizer, so that a loop over a video's chunks pays for it once.
    stretch_checked: std::sync::atomic::AtomicBool,
}

impl Localizer {
    /// `inner` under the camera height named `camera_height`, with the embedded basis.
    fn with_filler(inner: CameraLocalizer, camera_height: &str) -> PyResult<Self> {
        let (height, from_input) = parse_height(camera_height)?;
        let filler = default_basis().and_then(PoseReconstructor::new).ok();
        Ok(Localizer {
            inner: inner.with_camera_height(height),
            from_input,
            filler,
            stretch_checked: std::sync::atomic::AtomicBool::new(false),
        })
    }
}

/// What `Localizer.__reduce__` gives `pickle`: the function that rebuilds a localizer and its
/// arguments (the model file's bytes, the camera height).
type Reduced<'py> = (Bound<'py, PyAny>, (Vec<u8>, &'static str));

/// A localizer from the bytes of a model file, under the prior `camera_height`: how a pickled
/// [`Localizer`] is rebuilt (`Localizer.__reduce__`).
#[pyfunction]
#[pyo3(name = "_localizer_from_bytes")]
pub(crate) fn localizer_from_bytes(bytes: Vec<u8>, camera_height: &str) -> PyResult<Localizer> {
    let inner = CameraLocalizer::from_bytes_named(&bytes, "pickled Localizer")
        .map_err(|e| to_py_err(CamlocError::from(e)))?;
    Localizer::with_filler(inner, camera_height)
}

/// The prior a `camera_height` argument names, and whether it is `"from-input"` (then the
/// prior is `Any` until the shares of a call's poses are estimated).
pub(crate) fn parse_height(camera_height: &str) -> PyResult<(CameraHeight, bool)> {
    if camera_height == CameraHeight::FROM_INPUT {
        return Ok((CameraHeight::Any, true));
    }
    let height: CameraHeight = camera_height.parse().map_err(|_| {
        value_error(format!(
            "camera_height: expected \"from-input\", \"any\" or \"eye-level\", got \
             {camera_height:?}"
        ))
    })?;
    Ok((height, false))
}

/// `localizer` under the shares of the camera heights among the first poses of a call
/// (`leading`: [`PoseBatch::leading_poses`], of which the first `HEIGHT_SHARE_MAX_POSES` that
/// could be mapped are read; `camloc::CameraLocalizer::estimate_height_shares`: none that can
/// be localized leaves each pose on its own), as `camloc localize` estimates them from the
/// first records of its input; and the number of independent views the estimate counted
/// (`camloc::HeightEstimate::views`, the `camera_height_views` output).
pub(crate) fn for_poses(
    localizer: &CameraLocalizer,
    leading: &[Option<PartialPose2>],
) -> (CameraLocalizer, f64) {
    let poses: Vec<PartialPose2> = leading
        .iter()
        .take(HEIGHT_SHARE_MAX_POSES)
        .flatten()
        .copied()
        .collect();
    crate::pool::run(|| {
        let estimate = localizer.estimate_height_shares(&poses);
        (
            localizer
                .clone()
                .with_camera_height(estimate.camera_height()),
            estimate.reported_views(),
        )
    })
}

/// The `camera_height_shares` argument: the shares of the lower, middle and upper cameras
/// to localize under (three numbers, at least one > 0; normalised), as a call's
/// `camera_height_shares` output gives them, with the `camera_height_elevations_deg`
/// argument's mean elevations (three numbers, NaN for none, as that output gives them);
/// `None` when not given. They replace the estimate of `camera_height="from-input"`
/// (`from_input`): with another camera height they are a `ValueError` (a call had taken
/// them silently over `"any"`), and elevations without shares are one too.
pub(crate) fn given_shares(
    value: Option<&Bound<'_, PyAny>>,
    elevations: Option<&Bound<'_, PyAny>>,
    from_input: bool,
) -> PyResult<Option<HeightShares>> {
    let elevations = elevations.filter(|v| !v.is_none());
    let Some(value) = value.filter(|v| !v.is_none()) else {
        if elevations.is_some() {
            return Err(value_error(
                "camera_height_elevations_deg: only with camera_height_shares (the elevations \
                 of the heights the shares give)",
            ));
        }
        return Ok(None);
    };
    if !from_input {
        return Err(value_error(
            "camera_height_shares: only with camera_height=\"from-input\" (the shares replace \
             its estimate); this call's camera height is another",
        ));
    }
    let [lower, middle, upper] = three_numbers(value, "camera_height_shares", "")?;
    let shares = HeightShares::new(lower, middle, upper)
        .map_err(|e| value_error(format!("camera_height_shares: {e}")))?;
    let Some(elevations) = elevations else {
        return Ok(Some(shares));
    };
    let given = three_numbers(elevations, "camera_height_elevations_deg", "; NaN for none")?
        .map(|e| (!e.is_nan()).then_some(e));
    shares
        .with_elevations(given)
        .map(Some)
        .map_err(|e| value_error(format!("camera_height_elevations_deg: {e}")))
}

/// The three numbers (lower, middle, upper) of the argument `name`, as a call's output of
/// that name gives them (`note` added to the expectation): a `TypeError` for other than
/// numbers (a bool too), a `ValueError` for another count.
fn three_numbers(value: &Bound<'_, PyAny>, name: &str, note: &str) -> PyResult<[f64; 3]> {
    let expected = || {
        format!(
            "{name}: expected three numbers (lower, middle, upper{note}), as a call's {name} \
             output gives them"
        )
    };
    let items: Vec<Bound<'_, PyAny>> = value
        .try_iter()
        .and_then(|items| items.collect())
        .map_err(|_| pyo3::exceptions::PyTypeError::new_err(expected()))?;
    let mut numbers = Vec::with_capacity(items.len());
    for item in &items {
        if crate::number::is_bool(item)? {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "{}, not a bool",
                expected()
            )));
        }
        numbers.push(
            item.extract::<f64>()
                .map_err(|_| pyo3::exceptions::PyTypeError::new_err(expected()))?,
        );
    }
    numbers[..].try_into().map_err(|_| {
        value_error(format!(
            "{name}: expected three numbers (lower, middle, upper), got {}",
            numbers.len()
        ))
    })
}

/// The `camera_height_shares` and `camera_height_elevations_deg` outputs: how the call's
/// cameras divide among the three heights (low, middle, high rings) and the middle cameras'
/// mean elevation (`from-input`'s estimate, [`CameraHeight::reported`]), NaN when the
/// localizer used none (too few poses, `any`, `eye-level`) and for the heights without an
/// elevation, as `camloc localize --npz` writes them.
pub(crate) fn set_height_estimate<'py>(
    py: Python<'py>,
    out: &Output<'py>,
    localizer: Option<&CameraLocalizer>,
) -> PyResult<()> {
    let (shares, elevations) = localizer
        .map(CameraLocalizer::camera_height)
        .unwrap_or_default()
        .reported();
    out.set(
        "camera_height_shares",
        PyArray1::from_vec(py, shares.to_vec()),
    )?;
    out.set(
        "camera_height_elevations_deg",
        PyArray1::from_vec(py, elevations.to_vec()),
    )
}

/// A `camera_height` argument: `None`, or its text (`"from-input"`, `"any"` or `"eye-level"`,
/// checked where it is used), or a `TypeError` naming its type (pyo3's own said "cannot be
/// converted to 'PyString'").
pub(crate) fn camera_height_text(value: &Bound<'_, PyAny>) -> PyResult<Option<String>> {
    if value.is_none() {
        return Ok(None);
    }
    value.extract().map(Some).map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "camera_height must be a str (\"from-input\", \"any\" or \"eye-level\"), not {}",
            crate::number::type_name(value)
        ))
    })
}

#[pymethods]
impl Localizer {
    /// The default model embedded in this build, localizing under the prior `camera_height`
    /// (`"from-input"`, `"any"` or `"eye-level"`, as `camloc localize --camera-height`).
    #[new]
    #[pyo3(signature = (camera_height = None, **unexpected), text_signature = "(camera_height=\"from-input\")")]
    fn new(
        py: Python<'_>,
        camera_height: Option<&Bound<'_, PyAny>>,
        unexpected: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        // A model file given here (`Localizer(model=...)`, `Localizer("m.bin")`,
        // `Localizer(Path("m.bin"))`) is pointed to `Localizer.load`.
        const LOAD: &str = "a model file is read by camloc.Localizer.load(path)";
        if let Some((key, _)) = unexpected.and_then(|kw| kw.iter().next()) {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "Localizer() got an unexpected keyword argument {key}: {LOAD}"
            )));
        }
        let camera_height: Option<String> = match camera_height {
            Some(h) if h.hasattr("__fspath__")? => {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "Localizer() got a path as camera_height: {LOAD}"
                )));
            }
            Some(h) => camera_height_text(h)?,
            None => None,
        };
        let camera_height = camera_height.as_deref();
        if let Some(height) = camera_height.filter(|h| h.contains(['.', '/', '\\'])) {
            parse_height(height).map_err(|e| value_error(format!("{}: {LOAD}", e.value(py))))?;
        }
        Localizer::with_filler(
            CameraLocalizer::default_model().map_err(to_py_err)?,
            camera_height.unwrap_or(CameraHeight::FROM_INPUT),
        )
    }

    // Reads a model file written by `camloc train`, localizing under the prior `camera_height`.
    #[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/Localizer.load.txt"))]
    #[staticmethod]
    #[pyo3(signature = (path, camera_height = None), text_signature = "(path, camera_height=\"from-input\")")]
    fn load(
        path: PathBuf,
        #[pyo3(from_py_with = camera_height_text)] camera_height: Option<String>,
    ) -> PyResult<Self> {
        Localizer::with_filler(
            CameraLocalizer::load(&path).map_err(|e| to_py_err(e.into()))?,
            camera_height.as_deref().unwrap_or(CameraHeight::FROM_INPUT),
        )
    }

    /// How `pickle` and `copy` rebuild this localizer: [`localizer_from_bytes`] of its model
    /// file's bytes and its camera height (the embedded basis that fills in torsos comes back
    /// with it).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let rebuild = py.import("camloc")?.getattr("_localizer_from_bytes")?;
        let bytes = self
            .inner
            .to_bytes()
            .map_err(|e| to_py_err(CamlocError::from(e)))?;
        Ok((rebuild, (bytes, self.camera_height())))
    }

    // The prior over the camera's height this localizer applies.
    #[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/Localizer.camera_height.txt"))]
    #[getter]
    fn camera_height(&self) -> &'static str {
        if self.from_input {
            CameraHeight::FROM_INPUT
        } else {
            self.inner.camera_height().name()
        }
    }

    // The camera classes, one dict per label.
    #[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/Localizer.cameras.txt"))]
    #[getter]
    fn cameras<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let cameras = self
            .inner
            .cameras()
            .viewpoints()
            .iter()
            .map(|v| {
                let camera = PyDict::new(py);
                camera.set_item("label", v.label)?;
                camera.set_item("level", v.level.name())?;
                camera.set_item("side", v.side.name())?;
                camera.set_item("azimuth_deg", v.azimuth_deg)?;
                camera.set_item("elevation_deg", v.elevation_deg)?;
                let r = &v.rotation;
                let rows: Vec<f64> = (0..9).map(|k| r[(k / 3, k % 3)]).collect();
                camera.set_item("rotation", PyArray1::from_vec(py, rows).reshape([3, 3])?)?;
                Ok(camera)
            })
            .collect::<PyResult<Vec<_>>>()?;
        PyList::new(py, cameras)
    }

    // Localizes the camera of every pose.
    #[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/Localizer.localize.txt"))]
    #[pyo3(signature = (points, layout = Some("camloc15"), scores = None, min_score = 0.0, sequence = false, focal_px = None, principal_point = None, fps = 30.0, frames = None, camera_height_shares = None, camera_height_elevations_deg = None))]
    // Python's keyword arguments, as the stub names them.
    #[allow(clippy::too_many_arguments)]
    fn localize<'py>(
        &self,
        py: Python<'py>,
        points: UnmaskedPoints<'py>,
        layout: Option<&str>,
        scores: Option<UnmaskedScores<'py>>,
        #[pyo3(from_py_with = crate::number::min_score)] min_score: f64,
        #[pyo3(from_py_with = crate::number::sequence)] sequence: bool,
        focal_px: Option<Bound<'py, PyAny>>,
        principal_point: Option<Bound<'py, PyAny>>,
        #[pyo3(from_py_with = crate::number::fps)] fps: f64,
        frames: Option<Bound<'py, PyAny>>,
        camera_height_shares: Option<Bound<'py, PyAny>>,
        camera_height_elevations_deg: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let rate = crate::smooth::frame_rate(fps)?;
        let given = given_shares(
            camera_height_shares.as_ref(),
            camera_height_elevations_deg.as_ref(),
            self.from_input,
        )?;
        // With the camera's intrinsics each pose is localized as seen by the camera aimed at
        // it (a person near the edge of a wide-angle image).
        let aimed;
        let inner =
            match crate::intrinsics::intrinsics_arg(focal_px.as_ref(), principal_point.as_ref())? {
                Some(k) => {
                    if k.principal_point.is_none() {
                        crate::warnings::warn(
                            py,
                            "focal_px without principal_point changes no localization: the aim \
                         at the person needs where the optical axis meets the image"
                                .to_owned(),
                        )?;
                    }
                    aimed = (self.inner.clone())
                        .with_intrinsics(Some(k))
                        .map_err(|e| value_error(e.to_string()))?;
                    &aimed
                }
                None => &self.inner,
            };
        // Per pose: the probabilities and six other numbers out, a mapped pose for the
        // warnings.
        let k = self.inner.cameras().len();
        let output_bytes = (k + 6) * std::mem::size_of::<f64>()
            + std::mem::size_of::<Option<camloc::PartialPose2>>();
        let batch = PoseBatch::new(&points, layout, scores.as_deref(), min_score, output_bytes)?;
        // Mapped once for the warnings and the height estimate: a sequence's every pose.
        let leading = batch.leading_poses(if sequence {
            batch.len()
        } else {
            HEIGHT_SHARE_MAX_POSES
        });
        warn_of_input_conventions(py, &leading, inner.intrinsics())?;
        warn_of_weak_scores(py, batch.leading_weak_scores(WeakScores::SAMPLE_POSES))?;
        // Once per localizer that could compare its poses (a first chunk of people seen from
        // the front leaves it to the next).
        let checked = &self.stretch_checked;
        if !checked.load(std::sync::atomic::Ordering::Relaxed) && warn_of_stretch(py, &leading)? {
            checked.store(true, std::sync::atomic::Ordering::Relaxed);
        }
        // With `sequence`, the rows' video frame numbers (default: consecutive frames).
        let frame_numbers = crate::smooth::sequence_frames(frames.as_ref(), sequence, batch.len())?;
        let left_out = if sequence {
            warn_of_identity_jumps(
                py,
                leading.iter().map(|p| p.as_ref()),
                &frame_numbers,
                rate,
                "left out of the smoothing (their smoothed camera comes from the rows around \
                 them, and they have no smoothed viewpoint), as the command line does",
            )?
        } else {
            Vec::new()
        };
        let n = batch.len();
        // Shares given (another call's, over the whole video) replace this call's estimate.
        let estimated = match given {
            Some(shares) => Some((
                inner
                    .clone()
                    .with_camera_height(CameraHeight::Shares(shares)),
                f64::NAN,
            )),
            None => self.from_input.then(|| for_poses(inner, &leading)),
        };
        let views = estimated.as_ref().map_or(f64::NAN, |e| e.1);
        let (localizer, filler) = (
            estimated.as_ref().map_or(inner, |e| &e.0),
            self.filler.as_ref(),
        );
        let mut label = vec![0i64; n];
        let mut folded = vec![0i64; n];
        let mut probability = vec![f64::NAN; n];
        let mut probabilities = vec![f64::NAN; n * k];
        // Per pose: azimuth, elevation, uncertainty (degrees).
        let mut viewpoint = vec![f64::NAN; n * 3];
        // Per pose: its landmarks missing and derived (`landmark_masks`).
        let mut masks = vec![(0u16, 0u16); n];
        let mut errors: Vec<(usize, String)> = Vec::new();
        // Blocks of INTERRUPT_POSES, with a look at Python's signals (Ctrl-C) after each.
        for start in (0..n).step_by(INTERRUPT_POSES) {
            let end = (start + INTERRUPT_POSES).min(n);
            let block_errors: Vec<(usize, String)> = py.detach(|| {
                crate::pool::run(|| {
                    label[start..end]
                        .par_chunks_mut(CHUNK)
                        .zip(folded[start..end].par_chunks_mut(CHUNK))
                        .zip(probability[start..end].par_chunks_mut(CHUNK))
                        .zip(probabilities[start * k..end * k].par_chunks_mut(CHUNK * k))
                        .zip(viewpoint[start * 3..end * 3].par_chunks_mut(CHUNK * 3))
                        .zip(masks[start..end].par_chunks_mut(CHUNK))
                        .enumerate()
                        .flat_map_iter(
                            |(
                                c,
                                (((((label, folded), probability), probabilities), view), masks),
                            )| {
                                let mut errors = Vec::new();
                                for (j, row) in probabilities.chunks_exact_mut(k).enumerate() {
                                    let i = start + c * CHUNK + j;
                                    let mapped = batch.pose(i);
                                    masks[j] = landmark_masks(mapped.as_ref());
                                    let result = mapped.map_err(|e| e.to_string()).and_then(|m| {
                                        match filler {
                                            Some(f) => localizer
                                                .localize_filled(&m.pose, f.reconstructor()),
                                            None => localizer.localize_partial(&m.pose),
                                        }
                                        .map_err(|e| e.to_string())
                                    });
                                    match result {
                                        Ok(loc) => {
                                            // Missing as localized: a landmark far off the
                                            // others too (as the command line's JSON says).
                                            masks[j].0 = Landmark::mask_of(&loc.missing);
                                            (label[j], folded[j], probability[j]) = numbers(&loc);
                                            row.copy_from_slice(&loc.probabilities);
                                            view[3 * j..3 * j + 3].copy_from_slice(&angles(&loc));
                                        }
                                        Err(message) => errors.push((i, message)),
                                    }
                                }
                                errors
                            },
                        )
                        .collect()
                })
            });
            errors.extend(block_errors);
            py.check_signals()?;
        }
        // A sequence's limbs that a detector swapped left for right: swapped back and
        // localized again, as the command line does.
        let mut swapped_sides = None;
        if sequence {
            let read = leading.iter().map(|p| p.unwrap_or(PartialPose2::empty()));
            let (repaired, marks) =
                warn_of_swapped_sides(py, read.collect(), &frame_numbers, &left_out, rate)?;
            for (i, (pose, mark)) in repaired.iter().zip(&marks).enumerate() {
                if !mark.contains(&true) {
                    continue;
                }
                let result = match filler {
                    Some(f) => localizer.localize_filled(pose, f.reconstructor()),
                    None => localizer.localize_partial(pose),
                };
                errors.retain(|(row, _)| *row != i);
                match result {
                    Ok(loc) => {
                        (label[i], folded[i], probability[i]) = numbers(&loc);
                        probabilities[i * k..(i + 1) * k].copy_from_slice(&loc.probabilities);
                        viewpoint[3 * i..3 * i + 3].copy_from_slice(&angles(&loc));
                    }
                    Err(e) => errors.push((i, e.to_string())),
                }
            }
            errors.sort_by_key(|(row, _)| *row);
            swapped_sides = Some(marks);
        }
        let column =
            |c: usize| -> Vec<f64> { viewpoint.iter().skip(c).step_by(3).copied().collect() };
        let (azimuth, elevation) = (column(0), column(1));
        let smoothed = if sequence {
            Some(self.smoothed(
                &label,
                &probabilities,
                (&azimuth, &elevation),
                (&frame_numbers, &left_out),
                rate,
            )?)
        } else {
            None
        };
        let out = Output::new(py, n, batch.single);
        out.array("label", label, &[])?;
        out.array("folded_label", folded, &[])?;
        out.array("probability", probability, &[])?;
        out.array("probabilities", probabilities, &[k])?;
        out.array("azimuth_deg", azimuth, &[])?;
        out.array("elevation_deg", elevation, &[])?;
        out.array("uncertainty_deg", column(2), &[])?;
        let (missing, derived) = landmark_flags(&masks);
        out.array("missing", missing, &[NUM_LANDMARKS])?;
        out.array("derived", derived, &[NUM_LANDMARKS])?;
        set_height_estimate(py, &out, Some(localizer))?;
        out.set("camera_height_views", views)?;
        if let Some(marks) = swapped_sides {
            out.array("swapped_sides", marks.as_flattened().to_vec(), &[2])?;
        }
        if sequence {
            out.array("left_out_of_sequence", left_out.clone(), &[])?;
        }
        if let Some(Smoothed {
            label,
            probability,
            azimuth_deg,
            elevation_deg,
        }) = smoothed
        {
            out.array("smoothed_label", label, &[])?;
            out.array("smoothed_probability", probability, &[])?;
            out.array("smoothed_azimuth_deg", azimuth_deg, &[])?;
            out.array("smoothed_elevation_deg", elevation_deg, &[])?;
        }
        warn_if_every_pose_failed(py, n, &errors, min_score)?;
        out.errors(errors)?;
        Ok(out.into_dict())
    }

    fn __repr__(&self) -> String {
        format!(
            "camloc.Localizer(descriptor={:?}, cameras={}, camera_height={:?})",
            self.inner.descriptor().name(),
            self.inner.cameras().len(),
            self.camera_height()
        )
    }
}

/// The camera, folded camera (1-based numbers) and probability of a localization.
fn numbers(loc: &Localization) -> (i64, i64, f64) {
    (
        i64::from(loc.label.get()),
        i64::from(loc.folded_label.get()),
        loc.probability,
    )
}

/// The azimuth, elevation and uncertainty of a localization, degrees (NaN where it has none).
fn angles(loc: &Localization) -> [f64; 3] {
    [loc.azimuth_deg, loc.elevation_deg, loc.uncertainty_deg].map(|a| a.unwrap_or(f64::NAN))
}

/// A sequence's smoothed cameras and viewpoints, per row ([`Localizer::smoothed`]).
struct Smoothed {
    /// The smoothed camera, 0 for a person none of whose rows was localized.
    label: Vec<i64>,
    /// Its posterior probability (NaN without one).
    probability: Vec<f64>,
    /// The smoothed viewpoint, degrees (NaN for a row without a viewpoint).
    azimuth_deg: Vec<f64>,
    /// See `azimuth_deg`.
    elevation_deg: Vec<f64>,
}

impl Localizer {
    /// The smoothed values of a sequence (`localize(..., sequence=True)`): the rows are one
    /// person's frames in time order; each frame's camera smoothed by the hidden Markov model
    /// of `camloc localize --sequence` (`camloc::SequenceModel`, a frame that was not
    /// localized counting as a flat one) and its viewpoint by `camloc::smooth_viewpoints` over
    /// the rows' frame `numbers`; a row where `left_out` (missing entries: no) counts as not
    /// localized; `rate`: the rows' frames a second.
    fn smoothed(
        &self,
        label: &[i64],
        probabilities: &[f64],
        (azimuth, elevation): (&[f64], &[f64]),
        (numbers, left_out): (&[Option<u64>], &[bool]),
        rate: FrameRate,
    ) -> PyResult<Smoothed> {
        let n = label.len();
        let k = self.inner.cameras().len();
        let kept = |i: usize| !left_out.get(i).copied().unwrap_or(false);
        let frames: Vec<Option<&[f64]>> = (0..n)
            .map(|i| (label[i] > 0 && kept(i)).then(|| &probabilities[i * k..(i + 1) * k]))
            .collect();
        // A person none of whose frames was localized has no smoothed camera.
        let cameras = if frames.iter().any(Option::is_some) {
            SequenceModel::with_default_switch(self.inner.cameras())
                .smooth(&frames)
                .map_err(to_py_err)?
        } else {
            Vec::new()
        };
        let without = |column: &[f64]| -> Vec<f64> {
            (column.iter().enumerate())
                .map(|(i, &x)| if kept(i) { x } else { f64::NAN })
                .collect()
        };
        let (azimuth_deg, elevation_deg) =
            smoothed_columns(numbers, &without(azimuth), &without(elevation), rate);
        Ok(Smoothed {
            label: (0..n)
                .map(|i| cameras.get(i).map_or(0, |s| i64::from(s.label.get())))
                .collect(),
            probability: (0..n)
                .map(|i| cameras.get(i).map_or(f64::NAN, |s| s.probability))
                .collect(),
            azimuth_deg,
            elevation_deg,
        })
    }
}
