//! NumPy input: a batch of raw poses in a joint layout, checked for shape, mapped pose by pose
//! by [`pose_from_array`]; and the conversion of outputs back to NumPy.

use std::borrow::Cow;
use std::marker::PhantomData;

use camloc::PartialPose2;
use camloc::keypoints::{
    ArrayPoseError, Layout, MappedPose, ReadOptions, WeakScores, pose_from_array,
};
use camloc::skeleton::{Landmark, NUM_LANDMARKS};
use numpy::{AllowTypeChange, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::Borrowed;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::value_error;

/// Most joints of any layout (MediaPipe's 33), for the stack buffer that joins points and
/// scores: read from the layouts, so that a new one cannot outgrow it.
const MAX_JOINTS: usize = {
    let mut most = 0;
    let mut i = 0;
    while i < Layout::ALL.len() {
        if Layout::ALL[i].joint_count() > most {
            most = Layout::ALL[i].joint_count();
        }
        i += 1;
    }
    most
};

/// Points as given (any array-like of numbers, converted to float64 by NumPy when needed).
pub(crate) type ArrayArg<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// An array argument whose masked entries (`numpy.ma.MaskedArray`) are filled as its `K`
/// says ([`FILL_MASKED`]): not given, as the mask says (NumPy's conversion would read the
/// values under the mask); any other array-like as [`ArrayArg`].
pub(crate) struct Unmasked<'py, K: MaskedKind = Numbers>(ArrayArg<'py>, PhantomData<K>);

/// How [`Unmasked`] fills masked entries: the `kind` of [`FILL_MASKED`].
pub(crate) trait MaskedKind {
    /// `numbers`, `points` or `scores`.
    const KIND: &'static str;
}

/// Masked entries are NaN.
pub(crate) struct Numbers;

/// Points: a joint with a masked coordinate is missing (NaN), a masked score 0.
pub(crate) struct Points;

/// Scores: a masked one is 0 (the joint not seen, hence missing).
pub(crate) struct Scores;

impl MaskedKind for Numbers {
    const KIND: &'static str = "numbers";
}

impl MaskedKind for Points {
    const KIND: &'static str = "points";
}

impl MaskedKind for Scores {
    const KIND: &'static str = "scores";
}

/// Points whose masked joints are missing and masked scores 0.
pub(crate) type UnmaskedPoints<'py> = Unmasked<'py, Points>;

/// Scores whose masked entries are 0.
pub(crate) type UnmaskedScores<'py> = Unmasked<'py, Scores>;

impl<'py, K: MaskedKind> std::ops::Deref for Unmasked<'py, K> {
    type Target = ArrayArg<'py>;

    fn deref(&self) -> &ArrayArg<'py> {
        &self.0
    }
}

/// How a masked array's masked entries are filled, by kind: `points` (`(..., 2)` or
/// `(..., 3)` with scores: a joint with a masked coordinate is missing, NaN, and a masked
/// score is 0), `scores` (0, not seen) or `numbers` (NaN).
const FILL_MASKED: &std::ffi::CStr = cr#"
import numpy as np

def filled(array, kind):
    array = np.ma.asarray(array, dtype=np.float64)
    mask = np.ma.getmaskarray(array)
    out = np.ma.filled(array, 0.0 if kind == "scores" else np.nan)
    if kind == "points" and out.ndim >= 1 and out.shape[-1] in (2, 3):
        gone = mask[..., 0] | mask[..., 1]
        out[..., 0][gone] = np.nan
        out[..., 1][gone] = np.nan
        if out.shape[-1] == 3:
            out[..., 2][mask[..., 2]] = 0.0
    return out
"#;

/// [`FILL_MASKED`]'s function, compiled once.
static FILL_MASKED_FN: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

impl<'a, 'py, K: MaskedKind> FromPyObject<'a, 'py> for Unmasked<'py, K> {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let py = ob.py();
        // One look at the dtype NumPy gives the argument.
        if let Some(dtype) = numpy_dtype(&ob)? {
            refuse_complex_dtype(&dtype)?;
            refuse_text_or_flags(&dtype, K::KIND)?;
        }
        let ma = py.import("numpy.ma")?;
        let masked_array = ma.getattr("MaskedArray")?;
        // A list or tuple of masked arrays (one per pose) keeps its masks too.
        let masked = ob.is_instance(&masked_array)?
            || (ob.is_instance_of::<PyList>() || ob.is_instance_of::<PyTuple>())
                && ob.try_iter()?.any(|item| {
                    item.is_ok_and(|item| item.is_instance(&masked_array).unwrap_or(false))
                });
        let array = if masked {
            let fill = FILL_MASKED_FN.get_or_try_init(py, || {
                PyModule::from_code(py, FILL_MASKED, c"camloc_masked.py", c"camloc_masked")?
                    .getattr("filled")
                    .map(Bound::unbind)
            })?;
            fill.bind(py).call1((ob, K::KIND))?.extract()?
        } else {
            ob.extract()
                .map_err(|e: PyErr| missing_value_hint(py, e, K::KIND))?
        };
        Ok(Unmasked(array, PhantomData))
    }
}

/// `error` of converting an argument of `kind` to float64, with what to do when a pandas
/// missing value (`pd.NA`, which NumPy cannot make a float) caused it: pandas' nullable
/// columns (`Float64`, `Int64`) hold those where a plain float column holds NaN.
fn missing_value_hint(py: Python<'_>, error: PyErr, kind: &str) -> PyErr {
    if error.is_instance_of::<pyo3::exceptions::PyTypeError>(py)
        && error.to_string().contains("NAType")
    {
        return pyo3::exceptions::PyTypeError::new_err(format!(
            "{kind}: pandas' missing value pd.NA is not a number: convert with \
             .to_numpy(dtype=float, na_value=np.nan), NaN marking a missing joint"
        ));
    }
    error
}

/// A `TypeError` for a NumPy array or scalar of complex numbers, or a list or tuple of them,
/// whose conversion to float64 would drop the imaginary parts with only a `ComplexWarning` (a
/// list of Python complex numbers is refused by the conversion itself).
pub(crate) fn refuse_complex(ob: &Bound<'_, PyAny>) -> PyResult<()> {
    match numpy_dtype(ob)? {
        Some(dtype) => refuse_complex_dtype(&dtype),
        None => Ok(()),
    }
}

/// The NumPy dtype of `ob`: its own, or for a list or tuple (of arrays, one per pose) that of
/// its elements as NumPy would read them; `None` without one (a ragged list: the conversion
/// says what is wrong).
fn numpy_dtype<'py>(ob: &Bound<'py, PyAny>) -> PyResult<Option<Bound<'py, PyAny>>> {
    let array = if ob.is_instance_of::<PyList>() || ob.is_instance_of::<PyTuple>() {
        match ob.py().import("numpy")?.call_method1("asarray", (ob,)) {
            Ok(array) => array,
            Err(_) => return Ok(None),
        }
    } else {
        ob.clone()
    };
    Ok(array.getattr("dtype").ok())
}

/// A `TypeError` for an argument of `kind` whose `dtype` is text (NumPy would parse `"12.5"`
/// as a number without a word), dates, durations or records (converted to numbers without a
/// word, and every pose failing) or, for `points`, booleans (every pose would fail). Scores
/// may be booleans (visibility flags).
fn refuse_text_or_flags(dtype: &Bound<'_, PyAny>, kind: &str) -> PyResult<()> {
    let code: String = dtype.getattr("kind")?.extract()?;
    let what = match code.as_str() {
        "U" | "S" => "text",
        "M" => "dates",
        "m" => "durations",
        "V" => "records",
        "b" if kind == "points" => "booleans",
        _ => return Ok(()),
    };
    Err(pyo3::exceptions::PyTypeError::new_err(format!(
        "{kind}: an array of {what} ({}): expected numbers",
        dtype.str()?
    )))
}

/// [`refuse_complex`] of a NumPy `dtype`.
fn refuse_complex_dtype(dtype: &Bound<'_, PyAny>) -> PyResult<()> {
    if dtype
        .getattr("kind")
        .is_ok_and(|kind| kind.eq("c").unwrap_or(false))
    {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "an array of complex numbers ({}): expected real ones (the imaginary parts would be dropped)",
            dtype.str()?
        )));
    }
    Ok(())
}

/// The numbers of an array in C order, borrowed when the array is C-contiguous (`as_slice`
/// alone also accepts Fortran order, whose memory order is not C's); a copy this process
/// cannot allocate (a broadcast view of 10^9 poses is a few bytes in NumPy) is a
/// `MemoryError`, not an abort of the interpreter.
pub(crate) fn c_order<'a>(array: &'a ArrayArg<'_>) -> PyResult<Cow<'a, [f64]>> {
    match array.as_slice() {
        Ok(slice) if array.is_c_contiguous() => Ok(Cow::Borrowed(slice)),
        _ => {
            let mut copy = Vec::new();
            copy.try_reserve_exact(array.len()).map_err(|_| {
                too_large(array.len(), std::mem::size_of::<f64>(), "numbers copied")
            })?;
            copy.extend(array.as_array().iter().copied());
            Ok(Cow::Owned(copy))
        }
    }
}

/// Refuses with a `MemoryError`, before any work, a call on `items` poses or frames (`what`)
/// whose outputs and working copies take about `bytes_per_item` each and that this process
/// cannot allocate (it would otherwise abort the interpreter when the allocation fails
/// midway).
pub(crate) fn ensure_memory(items: usize, bytes_per_item: usize, what: &str) -> PyResult<()> {
    let mut probe: Vec<u8> = Vec::new();
    items
        .checked_mul(bytes_per_item)
        .and_then(|bytes| probe.try_reserve_exact(bytes).ok())
        .ok_or_else(|| too_large(items, bytes_per_item, what))
}

/// The `MemoryError` of [`ensure_memory`] and [`c_order`].
fn too_large(items: usize, bytes_per_item: usize, what: &str) -> PyErr {
    let gib = items as f64 * bytes_per_item as f64 / f64::from(1u32 << 30);
    pyo3::exceptions::PyMemoryError::new_err(format!(
        "{items} {what} need about {gib:.1} GiB, which cannot be allocated; give fewer per call"
    ))
}

/// The message of points of `shape` whose joint count is not `layout`'s: columns that are a
/// layout's x, y (and score) flattened (a table of one pose a row) are named so, with the
/// reshape that makes them poses; another joint count names the layouts that have it.
fn joint_count_error(shape: &[usize], layout: Layout) -> String {
    let joints = layout.joint_count();
    let (j, c) = (shape[shape.len() - 2], shape[shape.len() - 1]);
    let found = format!(
        "points have {j} joints per pose but layout {layout} has {joints} (shape {shape:?})"
    );
    if shape.len() == 2 && (c == 2 * joints || c == 3 * joints) {
        let channels = c / joints;
        return format!(
            "{found}: {c} columns look like one pose a row, the {joints} joints' {} flattened: \
             give points.reshape(-1, {joints}, {channels})",
            if channels == 2 { "x, y" } else { "x, y, score" }
        );
    }
    let named: Vec<&str> = Layout::ALL
        .iter()
        .filter(|l| l.joint_count() == j)
        .map(|l| l.name())
        .collect();
    if named.is_empty() {
        return found;
    }
    let choices: Vec<String> = named.iter().map(|n| format!("layout=\"{n}\"")).collect();
    format!("{found}: for {j} joints give {}", choices.join(" or "))
}

/// A checked batch of raw poses: N poses of J joints (the layout's count) with C = 2 (x, y)
/// or 3 (x, y, score) channels, and optional separate scores (N × J). Read-only and `Sync`, so
/// poses are mapped on any thread without the GIL.
pub(crate) struct PoseBatch<'a> {
    values: Cow<'a, [f64]>,
    scores: Option<Cow<'a, [f64]>>,
    layout: Layout,
    channels: usize,
    poses: usize,
    options: ReadOptions,
    /// `true` when one pose (J, C) was given rather than a batch (N, J, C).
    pub single: bool,
}

impl<'a> PoseBatch<'a> {
    /// Checks `points` ((N, J, C) or (J, C)), `scores` ((N, J) or (J,), only with C = 2), the
    /// layout name (none: `camloc15`, the functions' default) and `min_score`; every problem
    /// is a `ValueError` saying what was expected. `output_bytes` is what the caller's outputs
    /// take per pose ([`ensure_memory`]).
    pub(crate) fn new(
        points: &'a ArrayArg<'_>,
        layout: Option<&str>,
        scores: Option<&'a ArrayArg<'_>>,
        min_score: f64,
        output_bytes: usize,
    ) -> PyResult<Self> {
        let layout: Layout = layout
            .unwrap_or("camloc15")
            .parse()
            .map_err(|e| value_error(format!("{e}")))?;
        let joints = layout.joint_count();
        // An empty list (a frame without detections) is no poses, as an (0, J, 2) array.
        let empty = [0, joints, 2];
        let shape = if points.shape() == [0] {
            &empty[..]
        } else {
            points.shape()
        };
        let (poses, single) = match shape.len() {
            3 => (shape[0], false),
            2 => (1, true),
            _ => {
                // (None and plain numbers become arrays without a dimension.)
                let got = match shape.len() {
                    0 => "a single value, not an array of points".to_owned(),
                    _ => format!("shape {shape:?}"),
                };
                return Err(value_error(format!(
                    "points must have shape (N, J, 2) or one pose (J, 2), got {got}"
                )));
            }
        };
        let (j, channels) = (shape[shape.len() - 2], shape[shape.len() - 1]);
        if j != joints {
            return Err(value_error(joint_count_error(shape, layout)));
        }
        if !(channels == 2 || channels == 3) {
            // MediaPipe's landmarks as arrays are (x, y, z, visibility).
            let hint = match (layout, channels) {
                (Layout::Mediapipe33, 4) => {
                    ": MediaPipe's (x, y, z, visibility) are points[..., :2] with \
                     scores=points[..., 3]"
                }
                _ => "",
            };
            return Err(value_error(format!(
                "points must have 2 channels (x, y) or 3 (x, y, score) per joint, got {channels} \
                 (shape {shape:?}){hint}"
            )));
        }
        if !(min_score.is_finite() && min_score >= 0.0) {
            return Err(value_error(format!(
                "min_score must be a finite number >= 0, got {min_score}"
            )));
        }
        // A threshold without scores had been ignored without a word (a simulated user's
        // flickering detector joints kept as seen).
        if min_score > 0.0 && scores.is_none() && channels == 2 {
            return Err(value_error(format!(
                "min_score {min_score} needs scores: give scores (N, J) or points with a third \
                 (score) channel"
            )));
        }
        if let Some(scores) = scores {
            let expected: &[usize] = if single { &shape[..1] } else { &shape[..2] };
            if channels == 3 {
                return Err(value_error(
                    "scores given twice: points have a third (score) channel and scores is set",
                ));
            }
            if scores.shape() != expected {
                return Err(value_error(format!(
                    "scores must have shape {expected:?} (one per joint of points {shape:?}), got {:?}",
                    scores.shape()
                )));
            }
        }
        let options = ReadOptions {
            min_score,
            ..ReadOptions::default()
        };
        ensure_memory(poses, output_bytes, "poses")?;
        Ok(PoseBatch {
            values: c_order(points)?,
            scores: scores.map(c_order).transpose()?,
            layout,
            channels,
            poses,
            options,
            single,
        })
    }

    /// Number of poses N.
    pub(crate) fn len(&self) -> usize {
        self.poses
    }

    /// The first `count` poses (all, if fewer) mapped to the 15 landmarks, `None` where a
    /// pose cannot be: what the height estimate and the warnings read.
    pub(crate) fn leading_poses(&self, count: usize) -> Vec<Option<PartialPose2>> {
        (0..self.len().min(count))
            .map(|i| self.pose(i).ok().map(|m| m.pose))
            .collect()
    }

    /// The landmarks of the first `count` poses scored below [`WeakScores::THRESHOLD`] and
    /// kept at a `min_score` of 0 ([`WeakScores`]); `None` when the poses have no scores or
    /// `min_score` is not 0.
    pub(crate) fn leading_weak_scores(&self, count: usize) -> Option<WeakScores> {
        if self.options.min_score != 0.0 || (self.scores.is_none() && self.channels == 2) {
            return None;
        }
        let strong = ReadOptions {
            min_score: WeakScores::THRESHOLD,
            ..self.options
        };
        let mut counts = WeakScores::default();
        for i in 0..self.len().min(count) {
            if let (Ok(read), Ok(kept)) = (self.pose(i), self.pose_with(i, &strong)) {
                counts.add(&read.pose, &read.derived, &kept.pose);
            }
        }
        Some(counts)
    }

    /// Pose `i` mapped to the 15 landmarks (NaN coordinates = missing joint).
    pub(crate) fn pose(&self, i: usize) -> Result<MappedPose, ArrayPoseError> {
        self.pose_with(i, &self.options)
    }

    /// Pose `i` mapped to the 15 landmarks with `options` (its `min_score`).
    fn pose_with(&self, i: usize, options: &ReadOptions) -> Result<MappedPose, ArrayPoseError> {
        let joints = self.layout.joint_count();
        let values = &self.values[i * joints * self.channels..(i + 1) * joints * self.channels];
        match &self.scores {
            None => pose_from_array(self.layout, values, self.channels, options),
            Some(scores) => {
                let scores = &scores[i * joints..(i + 1) * joints];
                let mut joined = [0.0; 3 * MAX_JOINTS];
                for ((out, xy), s) in joined
                    .chunks_exact_mut(3)
                    .zip(values.chunks_exact(2))
                    .zip(scores)
                {
                    out.copy_from_slice(&[xy[0], xy[1], *s]);
                }
                pose_from_array(self.layout, &joined[..3 * joints], 3, options)
                    .map_err(of_separate_scores)
            }
        }
    }
}

/// `error` of a pose whose scores were given on their own: a score out of range is not the
/// third channel of the points (its message does not say so).
fn of_separate_scores(error: ArrayPoseError) -> ArrayPoseError {
    match error {
        ArrayPoseError::ScoreOutOfRange { joint, score, .. } => ArrayPoseError::ScoreOutOfRange {
            joint,
            score,
            separate: true,
        },
        other => other,
    }
}

/// The landmark masks of a pose as read, bit `i` for landmark `i` (camloc15 order): those
/// missing and those derived rather than read (a pelvis from the hips, a COCO head from the
/// face points); a pose that cannot be read is every landmark missing.
pub(crate) fn landmark_masks(mapped: Result<&MappedPose, &ArrayPoseError>) -> (u16, u16) {
    match mapped {
        Ok(m) => (m.pose.missing_mask(), Landmark::mask_of(&m.derived)),
        Err(_) => ((1 << NUM_LANDMARKS) - 1, 0),
    }
}

/// The `(N, 15)` flag arrays of per-pose [`landmark_masks`], as `camloc localize --npz`
/// writes `missing` and `derived`.
pub(crate) fn landmark_flags(masks: &[(u16, u16)]) -> (Vec<bool>, Vec<bool>) {
    let bits = |mask: u16| (0..NUM_LANDMARKS).map(move |j| mask & (1 << j) != 0);
    (
        masks.iter().flat_map(|&(m, _)| bits(m)).collect(),
        masks.iter().flat_map(|&(_, d)| bits(d)).collect(),
    )
}

/// Output arrays of a batch: each value is stored with shape `(N, *rest)`, or `rest` alone
/// for a single pose; per-pose errors become a list (or one value for a single pose).
pub(crate) struct Output<'py> {
    dict: Bound<'py, PyDict>,
    poses: usize,
    single: bool,
}

impl<'py> Output<'py> {
    /// An empty output for `poses` poses (`single`: one pose given without the batch axis).
    pub(crate) fn new(py: Python<'py>, poses: usize, single: bool) -> Self {
        Output {
            dict: PyDict::new(py),
            poses,
            single,
        }
    }

    /// Stores `data` (N × prod(rest) values in C order) under `key` with shape (N, *rest).
    pub(crate) fn array<T: numpy::Element>(
        &self,
        key: &str,
        data: Vec<T>,
        rest: &[usize],
    ) -> PyResult<()> {
        let py = self.dict.py();
        let mut shape = Vec::with_capacity(rest.len() + 1);
        if !self.single {
            shape.push(self.poses);
        }
        shape.extend_from_slice(rest);
        let array = numpy::PyArray1::from_vec(py, data).reshape(shape)?;
        let array: Bound<'py, PyArrayDyn<T>> = array;
        self.dict.set_item(key, array)
    }

    /// Stores per-pose errors under `error`: a list with `None` where the pose is fine (one value
    /// for a single pose). `errors` holds (pose index, message).
    pub(crate) fn errors(&self, errors: Vec<(usize, String)>) -> PyResult<()> {
        let py = self.dict.py();
        let mut messages: Vec<Option<String>> = vec![None; self.poses];
        for (i, message) in errors {
            messages[i] = Some(message);
        }
        if self.single {
            return self.dict.set_item("error", messages.pop().flatten());
        }
        self.dict.set_item("error", PyList::new(py, messages)?)
    }

    /// Stores any Python value under `key`.
    pub(crate) fn set(&self, key: &str, value: impl IntoPyObject<'py>) -> PyResult<()> {
        self.dict.set_item(key, value)
    }

    /// The finished dict.
    pub(crate) fn into_dict(self) -> Bound<'py, PyDict> {
        self.dict
    }
}
