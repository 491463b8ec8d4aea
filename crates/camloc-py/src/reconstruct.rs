//! `camloc.reconstruct`: 3D poses of a NumPy batch.

use std::collections::HashMap;
use std::path::PathBuf;

use camloc::keypoints::WeakScores;
use camloc::reconstruct::{BONE_KEYS, BoneLengths, PoseBasis};
use camloc::skeleton::{NUM_LANDMARKS, NUM_LIMBS};
use camloc::store::Persist;
use camloc::{
    CameraHeight, CameraLocalizer, CamlocError, DepthLifter, HEIGHT_SHARE_MAX_POSES, ModeKind,
    Pose3, PoseReconstruction, PoseReconstructor,
};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyMapping};
use rayon::prelude::*;

use crate::arrays::{Output, PoseBatch, UnmaskedPoints, UnmaskedScores};
use crate::intrinsics::intrinsics_arg;
use crate::localize::{Localizer, for_poses, given_shares, parse_height, set_height_estimate};
use crate::smooth::{sequence_frames, timeline_max_slots};
use crate::warnings::{
    warn_if_every_pose_failed, warn_of_identity_jumps, warn_of_input_conventions, warn_of_stretch,
    warn_of_swapped_sides, warn_of_weak_scores,
};
use crate::{to_py_err, value_error};

/// Poses reconstructed between two looks at Python's signals (Ctrl-C): about half a second of
/// the default `hybrid` on two cores.
const INTERRUPT_POSES: usize = 1024;

/// Most rows `reconstruct(sequence=True)` takes by default (`sequence_max_rows`), as `camloc
/// reconstruct --sequence-max-poses`: a person's frames take 12-15 KB each while solved.
const SEQUENCE_MAX_ROWS: usize = 200_000;

/// A bone lengths argument named `name` (`reconstruct`'s `bone_lengths`, `to_bvh`'s
/// `limb_lengths`): a mapping of the 14 JSON keys, 14 numbers in the library's limb order
/// (`BONE_KEYS`), or the path of a bone lengths JSON file.
pub(crate) fn bone_lengths(value: &Bound<'_, PyAny>, name: &str) -> PyResult<BoneLengths> {
    // (The library's messages begin with what the argument's name already says.)
    let invalid = |e: camloc::reconstruct::BoneLengthError| {
        let message = e.to_string();
        value_error(format!(
            "{name}: {}",
            message.strip_prefix("bone lengths: ").unwrap_or(&message)
        ))
    };
    if let Ok(mapping) = value.cast::<PyMapping>() {
        let given: HashMap<String, Bound<'_, PyAny>> = mapping.extract()?;
        let mut named: HashMap<String, f64> = HashMap::with_capacity(given.len());
        for (key, value) in given {
            if crate::number::is_bool(&value)? {
                return Err(bool_length(name));
            }
            let number = value.extract::<f64>().map_err(|_| {
                value_error(format!(
                    "{name}: {key:?} must be a number of metres, got {}",
                    value
                        .get_type()
                        .name()
                        .map_or_else(|_| "?".to_owned(), |n| n.to_string())
                ))
            })?;
            named.insert(key, number);
        }
        if let Some(unknown) = named.keys().find(|k| !BONE_KEYS.contains(&k.as_str())) {
            return Err(value_error(format!(
                "{name}: unknown key {unknown:?} (expected the 14 keys of BONE_KEYS)"
            )));
        }
        let missing: Vec<String> = BONE_KEYS
            .iter()
            .filter(|k| !named.contains_key(**k))
            .map(|k| format!("{k:?}"))
            .collect();
        if !missing.is_empty() {
            return Err(value_error(format!(
                "{name}: missing key(s) {} (all 14 are needed)",
                missing.join(", ")
            )));
        }
        return BoneLengths::given(BONE_KEYS.map(|k| named[k])).map_err(invalid);
    }
    if value.is_instance_of::<pyo3::types::PyBytes>()
        || value.is_instance_of::<pyo3::types::PyByteArray>()
        || value.is_instance_of::<pyo3::types::PyMemoryView>()
    {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "{name}: bytes are neither a path nor lengths; give a str or pathlib.Path, a \
             mapping of BONE_KEYS or 14 numbers"
        )));
    }
    if let Ok(path) = value.extract::<PathBuf>() {
        return BoneLengths::read_json(&path).map_err(invalid);
    }
    let numbers: Vec<f64> = value.extract().map_err(|_| {
        value_error(format!(
            "{name}: expected a mapping of BONE_KEYS, 14 numbers or a file path"
        ))
    })?;
    // (A bool converts to 1.0: 14 of them would be a person of 1 m limbs.)
    for item in value.try_iter()? {
        if crate::number::is_bool(&item?)? {
            return Err(bool_length(name));
        }
    }
    let lengths: [f64; NUM_LIMBS] = numbers
        .try_into()
        .map_err(|v: Vec<f64>| value_error(format!("{name}: {} numbers, expected 14", v.len())))?;
    BoneLengths::given(lengths).map_err(invalid)
}

/// The `TypeError` of a bool given as a length of the argument `name`.
fn bool_length(name: &str) -> PyErr {
    pyo3::exceptions::PyTypeError::new_err(format!(
        "{name}: a length must be a number of metres, not a bool"
    ))
}

// A bone lengths argument as the JSON file `bone_lengths=PATH` and `camloc reconstruct
// --bone-lengths` read: its docstring is camloc.pyi's (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/bone_lengths_json.txt"))]
#[pyfunction]
#[pyo3(name = "bone_lengths_json")]
pub(crate) fn bone_lengths_json_text(lengths: Bound<'_, PyAny>) -> PyResult<String> {
    Ok(bone_lengths(&lengths, "lengths")?.to_json_string())
}

/// `reconstruct`'s `lifter`: whether to use the embedded depth lifter, or a lifter file.
pub(crate) enum LifterArg {
    Use(bool),
    File(PathBuf),
}

impl<'a, 'py> FromPyObject<'a, 'py> for LifterArg {
    type Error = PyErr;

    /// A bool (`None`: the default, the embedded lifter), or a path (`str` or `os.PathLike`);
    /// else a `TypeError` naming the argument.
    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if ob.is_none() {
            return Ok(LifterArg::Use(true));
        }
        if crate::number::is_bool(&ob)? {
            return ob.is_truthy().map(LifterArg::Use);
        }
        ob.extract::<PathBuf>().map(LifterArg::File).map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(format!(
                "lifter: expected True, False or a lifter file's path, got {}",
                crate::number::type_name(&ob)
            ))
        })
    }
}

// Reconstructs the 3D pose of every pose: its docstring is camloc.pyi's (build.rs).
#[doc = include_str!(concat!(env!("OUT_DIR"), "/doc/reconstruct.txt"))]
#[pyfunction]
#[pyo3(signature = (points, layout = Some("camloc15"), camera = None, scores = None, min_score = 0.0, localizer = None, basis = None, bone_lengths = None, focal_px = None, principal_point = None, sequence = false, camera_height = None, lifter = LifterArg::Use(true), person_height = None, fps = 30.0, frames = None, sequence_max_rows = SEQUENCE_MAX_ROWS, camera_height_shares = None, camera_height_elevations_deg = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn reconstruct<'py>(
    py: Python<'py>,
    points: UnmaskedPoints<'py>,
    layout: Option<&str>,
    camera: Option<&str>,
    scores: Option<UnmaskedScores<'py>>,
    #[pyo3(from_py_with = crate::number::min_score)] min_score: f64,
    localizer: Option<PyRef<'py, Localizer>>,
    basis: Option<PathBuf>,
    bone_lengths: Option<Bound<'py, PyAny>>,
    focal_px: Option<Bound<'py, PyAny>>,
    principal_point: Option<Bound<'py, PyAny>>,
    #[pyo3(from_py_with = crate::number::sequence)] sequence: bool,
    #[pyo3(from_py_with = crate::localize::camera_height_text)] camera_height: Option<String>,
    lifter: LifterArg,
    #[pyo3(from_py_with = crate::number::person_height)] person_height: Option<f64>,
    #[pyo3(from_py_with = crate::number::fps)] fps: f64,
    frames: Option<Bound<'py, PyAny>>,
    #[pyo3(from_py_with = crate::number::sequence_max_rows)] sequence_max_rows: usize,
    camera_height_shares: Option<Bound<'py, PyAny>>,
    camera_height_elevations_deg: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    // The command line's default.
    let camera = camera.unwrap_or("hybrid");
    let mode = ModeKind::ALL
        .into_iter()
        .find(|m| m.name().eq_ignore_ascii_case(camera.trim()) && *m != ModeKind::Oracle)
        .ok_or_else(|| {
            value_error(format!(
                "unknown camera \"{camera}\" (expected one of: opt, classified, hybrid)"
            ))
        })?;
    // Per pose: the 79 numbers and 15 flags out, the reconstruction, its place in the world
    // and the mapped pose.
    let output_bytes = 79 * std::mem::size_of::<f64>()
        + NUM_LANDMARKS
        + std::mem::size_of::<Result<PoseReconstruction, String>>()
        + std::mem::size_of::<Option<Pose3>>()
        + std::mem::size_of::<camloc::PartialPose2>();
    let batch = PoseBatch::new(&points, layout, scores.as_deref(), min_score, output_bytes)?;
    // Mapped once for the warning and the height estimate.
    let leading = batch.leading_poses(HEIGHT_SHARE_MAX_POSES);
    let intrinsics = intrinsics_arg(focal_px.as_ref(), principal_point.as_ref())?;
    warn_of_input_conventions(py, &leading, intrinsics)?;
    warn_of_weak_scores(py, batch.leading_weak_scores(WeakScores::SAMPLE_POSES))?;
    warn_of_stretch(py, &leading)?;
    let mut reconstructor = match basis {
        Some(path) => PoseBasis::load(&path)
            .map_err(CamlocError::from)
            .and_then(PoseReconstructor::new)
            .map_err(to_py_err)?
            .with_localizer(CameraLocalizer::default_model().map_err(to_py_err)?)
            .with_lifter(DepthLifter::default_lifter().map_err(to_py_err)?),
        None => crate::defaults::default_reconstructor()?.clone(),
    };
    // The embedded lifter serves a localizer of Table 1's cameras (the embedded model, or one
    // trained with `camloc train`), as `camloc reconstruct --model` has it; another
    // reconstructs without.
    let mut from_input = true;
    if let Some(localizer) = localizer {
        from_input = localizer.from_input;
        reconstructor = reconstructor.with_localizer(localizer.inner.clone());
        if !DepthLifter::serves(localizer.inner.cameras()) {
            reconstructor = reconstructor.without_lifter();
        }
    }
    match lifter {
        LifterArg::Use(true) => {}
        LifterArg::Use(false) => reconstructor = reconstructor.without_lifter(),
        // A lifter file replaces the embedded one, as `camloc reconstruct --lifter FILE`.
        LifterArg::File(path) => {
            let file = DepthLifter::load(&path)
                .map_err(CamlocError::from)
                .map_err(to_py_err)?;
            reconstructor = reconstructor.with_lifter(file);
        }
    }
    // A camera height given here replaces the localizer's own (the lifter stays).
    if let Some(name) = camera_height.as_deref() {
        let height;
        (height, from_input) = parse_height(name)?;
        if let Some(localizer) = reconstructor.localizer().cloned() {
            reconstructor = reconstructor.with_localizer(localizer.with_camera_height(height));
        }
    }
    // Before the estimate, which sees the poses aimed as they are localized.
    if let Some(intrinsics) = intrinsics {
        reconstructor = reconstructor
            .with_intrinsics(intrinsics)
            .map_err(|e| value_error(e.to_string()))?;
    }
    // Shares given (another call's, over the whole video) replace this call's estimate.
    if let Some(shares) = given_shares(
        camera_height_shares.as_ref(),
        camera_height_elevations_deg.as_ref(),
        from_input,
    )? && let Some(localizer) = reconstructor.localizer().cloned()
    {
        reconstructor = reconstructor
            .with_localizer(localizer.with_camera_height(CameraHeight::Shares(shares)));
        from_input = false;
    }
    // `opt` localizes no complete pose: no estimate, as `camloc reconstruct --camera opt`.
    let mut views = f64::NAN;
    if from_input
        && mode != ModeKind::Opt
        && let Some(localizer) = reconstructor.localizer()
    {
        let (estimated, counted) = for_poses(localizer, &leading);
        views = counted;
        reconstructor = reconstructor.with_localizer(estimated);
    }
    let mut reconstructor = reconstructor
        .with_mode(mode)
        .map_err(|e| value_error(e.to_string()))?;
    if let Some(value) = &bone_lengths {
        reconstructor = reconstructor.with_bone_lengths(self::bone_lengths(value, "bone_lengths")?);
    }
    if let Some(height_m) = person_height {
        reconstructor = reconstructor
            .with_person_height(height_m)
            .map_err(|e| value_error(e.to_string()))?;
    }
    reconstructor = reconstructor
        .with_frame_rate(fps)
        .map_err(|e| value_error(e.to_string()))?;
    let n = batch.len();
    if sequence && n > sequence_max_rows {
        return Err(value_error(format!(
            "{n} rows for sequence=True, more than sequence_max_rows ({sequence_max_rows}): a \
             person's frames take 12-15 KB each while they are solved together (100,000: \
             1.2 GB); give parts of the video apart (split at a gap), or raise \
             sequence_max_rows if the memory is there"
        )));
    }
    // With `sequence`, the rows' video frame numbers (default: consecutive frames).
    let numbers: Vec<Option<u64>> = sequence_frames(frames.as_ref(), sequence, n)?;
    // With `sequence`: per row, whether its legs and its arms were swapped back.
    let mut swapped_sides: Option<Vec<[bool; 2]>> = None;
    let (results, person_lengths, left_out) = if sequence {
        // A row that cannot be read (a pose refused for its layout, a half-missing joint) is
        // a frame without landmarks in the sequence, and its error in its place, as the
        // command line and `Localizer.localize(sequence=True)` have it.
        let read: Vec<Result<camloc::PartialPose2, String>> = (0..n)
            .map(|i| batch.pose(i).map(|m| m.pose).map_err(|e| e.to_string()))
            .collect();
        let poses: Vec<camloc::PartialPose2> = read
            .iter()
            .map(|r| r.as_ref().map_or(camloc::PartialPose2::empty(), |p| *p))
            .collect();
        let rate = reconstructor.frame_rate();
        let left_out = warn_of_identity_jumps(
            py,
            poses.iter().map(Some),
            &numbers,
            rate,
            "reconstructed on their own, left out of the sequence (its lengths, smoothness \
             and world placement), as the command line does",
        )?;
        // The limbs swapped in the rows kept (another person's are not judged).
        let (poses, marks) = warn_of_swapped_sides(py, poses, &numbers, &left_out, rate)?;
        swapped_sides = Some(marks);
        let solved = py
            .detach(|| {
                crate::pool::run(|| {
                    reconstructor.reconstruct_sequence_at_frames(&numbers, &poses, &left_out)
                })
            })
            .map_err(to_py_err)?;
        if let Some(said) = solved.lengths_fit.and_then(|fit| fit.warning()) {
            crate::warnings::warn(py, format!("bone_lengths: {said}"))?;
        }
        let frames: Vec<Result<PoseReconstruction, String>> = solved
            .frames
            .into_iter()
            .zip(read)
            .map(|(f, read)| read.and_then(|_| f.map_err(|e| e.to_string())))
            .collect();
        // Lengths estimated from no frame are the prior's, not the person's: NaN, as the
        // command line writes no lengths for such a person.
        let estimated_from_frames = frames
            .iter()
            .zip(&left_out)
            .any(|(f, &left)| f.is_ok() && !left);
        let lengths = if estimated_from_frames || bone_lengths.is_some() {
            solved.lengths.as_array()
        } else {
            [f64::NAN; NUM_LIMBS]
        };
        (frames, Some(lengths), left_out)
    } else {
        let mut frames = Vec::with_capacity(n);
        for start in (0..n).step_by(INTERRUPT_POSES) {
            let block = start..(start + INTERRUPT_POSES).min(n);
            frames.extend(py.detach(|| {
                crate::pool::run(|| {
                    block
                        .into_par_iter()
                        .with_max_len(8)
                        .map(|i| {
                            let mapped = batch.pose(i).map_err(|e| e.to_string())?;
                            reconstructor
                                .reconstruct(&mapped.pose)
                                .map_err(|e| e.to_string())
                        })
                        .collect::<Vec<_>>()
                })
            }));
            // Ctrl-C (a KeyboardInterrupt) between blocks, not only at the end.
            py.check_signals()?;
        }
        (frames, None, Vec::new())
    };
    let mut points3d = vec![f64::NAN; n * 45];
    let mut rotation = vec![f64::NAN; n * 9];
    let mut scale = vec![f64::NAN; n];
    let mut translation = vec![f64::NAN; n * 2];
    let mut projection_error = vec![f64::NAN; n];
    let mut outside_limits = vec![f64::NAN; n];
    let mut reflected = vec![false; n];
    let mut label = vec![0i64; n];
    let mut probability = vec![f64::NAN; n];
    let mut azimuth = vec![f64::NAN; n];
    let mut elevation = vec![f64::NAN; n];
    let mut lengths = vec![f64::NAN; n * NUM_LIMBS];
    let mut translation_m = vec![f64::NAN; n * 3];
    let mut focal_px = vec![f64::NAN; n];
    let mut principal_point = vec![f64::NAN; n * 2];
    let mut imputed = vec![false; n * NUM_LANDMARKS];
    // With `sequence`, the frames placed where a camera standing still saw them (as
    // `camloc reconstruct --sequence --bvh` animates them).
    let world: Option<Vec<Option<Pose3>>> = sequence.then(|| {
        // The left-out rows are not placed: time passes over them, as over a missing frame.
        let found: Vec<_> = results
            .iter()
            .zip(&left_out)
            .map(|(r, &left)| r.as_ref().ok().filter(|_| !left))
            .collect();
        reconstructor.place_on_timeline(&numbers, &found, timeline_max_slots(n))
    });
    // Rows reconstructed one by one with landmarks filled in, not seen, counted, and a
    // sequence's landmarks filled in in many of its rows named (the command line warns alike).
    if !sequence {
        let mut count = camloc::FilledCount::default();
        for r in results.iter().flatten() {
            count.add(&r.imputed);
        }
        if let Some(said) = count.summary() {
            crate::warnings::warn(
                py,
                format!(
                    "imputed: {said}: their 3D is the pose basis's guess; check them before \
                     using their joints (sequence=True fills a video's short gaps from the \
                     rows around)"
                ),
            )?;
        }
    } else {
        if let Some(often) =
            camloc::often_filled_frames(&results, &numbers, reconstructor.frame_rate())
        {
            crate::warnings::warn(
                py,
                format!(
                    "imputed: landmarks filled in, not seen (their 3D is a guess, from the pose basis \
                     or the rows around a short gap), \
                     of the {} reconstructed rows: {}",
                    often.frames,
                    often.summary(bone_lengths.is_some())
                ),
            )?;
        }
    }
    let mut limits = camloc::LimitCount::default();
    for r in results.iter().flatten() {
        limits.add(r.reconstruction.outside_limits_rad);
    }
    if let Some(said) = limits.summary() {
        crate::warnings::warn(
            py,
            format!("{said} (the result's outside_limits_rad; layout= names the layout)"),
        )?;
    }
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
        points3d[i * 45..(i + 1) * 45].copy_from_slice(rec.pose.points.as_flattened());
        for (k, out) in rotation[i * 9..(i + 1) * 9].iter_mut().enumerate() {
            *out = rec.camera.rotation[(k / 3, k % 3)];
        }
        scale[i] = rec.camera.scale;
        translation[i * 2..(i + 1) * 2].copy_from_slice(&rec.camera.translation);
        projection_error[i] = rec.projection_error;
        outside_limits[i] = rec.outside_limits_rad;
        reflected[i] = rec.reflected;
        if let Ok(l) = BoneLengths::of_pose(&rec.pose) {
            lengths[i * NUM_LIMBS..(i + 1) * NUM_LIMBS].copy_from_slice(&l.as_array());
        }
        if let Some(p) = &rec.perspective {
            translation_m[i * 3..(i + 1) * 3].copy_from_slice(&p.translation);
            focal_px[i] = p.focal_px;
            principal_point[i * 2..(i + 1) * 2].copy_from_slice(&p.principal_point);
        }
        for l in &r.imputed {
            imputed[i * NUM_LANDMARKS + l.index()] = true;
        }
        if let Some(l) = &r.localization {
            label[i] = i64::from(l.label.get());
            probability[i] = l.probability;
            azimuth[i] = l.azimuth_deg.unwrap_or(f64::NAN);
            elevation[i] = l.elevation_deg.unwrap_or(f64::NAN);
        }
    }
    let out = Output::new(py, n, batch.single);
    out.array("points3d", points3d, &[15, 3])?;
    out.array("rotation", rotation, &[3, 3])?;
    out.array("scale", scale, &[])?;
    out.array("translation", translation, &[2])?;
    out.array("projection_error", projection_error, &[])?;
    out.array("outside_limits_rad", outside_limits, &[])?;
    out.array("reflected", reflected, &[])?;
    out.array("label", label, &[])?;
    out.array("probability", probability, &[])?;
    out.array("azimuth_deg", azimuth, &[])?;
    out.array("elevation_deg", elevation, &[])?;
    out.array("bone_lengths", lengths, &[NUM_LIMBS])?;
    out.array("translation_m", translation_m, &[3])?;
    out.array("focal_px", focal_px, &[])?;
    out.array("principal_point", principal_point, &[2])?;
    out.array("imputed", imputed, &[NUM_LANDMARKS])?;
    if let Some(marks) = swapped_sides {
        out.array("swapped_sides", marks.as_flattened().to_vec(), &[2])?;
    }
    if sequence {
        out.array("left_out_of_sequence", left_out.clone(), &[])?;
    }
    if let Some(world) = world {
        if let Some(below) = camloc::below_floor(&world) {
            crate::warnings::warn(
                py,
                format!(
                    "world_points3d: the feet go {:.0} cm below the floor in {} row(s) (first \
                     at {}): {}",
                    100.0 * below.deepest_m,
                    below.frames,
                    crate::warnings::row_name(&numbers, below.first),
                    camloc::BELOW_FLOOR_CAUSES
                ),
            )?;
        }
        let mut placed = vec![f64::NAN; n * 45];
        for (out, pose) in placed.chunks_exact_mut(45).zip(&world) {
            if let Some(pose) = pose {
                out.copy_from_slice(pose.points.as_flattened());
            }
        }
        out.array("world_points3d", placed, &[15, 3])?;
    }
    if let Some(l) = person_lengths {
        let array = numpy::PyArray1::from_vec(py, l.to_vec());
        out.set("person_bone_lengths", array)?;
    }
    warn_if_every_pose_failed(py, n, &errors, min_score)?;
    out.errors(errors)?;
    out.set("camera", mode.name())?;
    // The rate the call solved at, for `to_bvh(r["world_points3d"], r["fps"], ...)`.
    out.set("fps", fps)?;
    set_height_estimate(py, &out, reconstructor.localizer())?;
    out.set("camera_height_views", views)?;
    Ok(out.into_dict())
}
