//! From the pursuit's poses and cameras to refined ones: the starting states, the solve, the
//! results.

use camloc_geometry::WeakPerspective;
use camloc_skeleton::{NUM_LANDMARKS, NUM_LIMBS, Pose3};
use nalgebra::Vector3;

use super::Refinement;
use super::kinematics::{directions_of, to_pose};
use super::problem::{FrameData, FrameState, Projection, Weights};
use super::solve::{KappaUnknown, LengthUnknowns, Problem, SharedState};
use crate::length_prior::LimbMatrix;
use crate::{BoneLengths, ReconstructError};

/// One frame to refine: the 2D, the pursuit's answer, the camera model (all in the frame's
/// normalised image units).
pub(crate) struct RefineFrame {
    /// The 2D landmarks.
    pub(crate) observed: [[f64; 2]; NUM_LANDMARKS],
    /// The pose the refinement starts from (metres, body frame): the pursuit's, or the
    /// lifted one (`lifted`).
    pub(crate) pose: Pose3,
    /// The pursuit's weak-perspective camera.
    pub(crate) camera: WeakPerspective,
    /// Known intrinsics: `(focal, principal point)`.
    pub(crate) intrinsics: Option<(f64, [f64; 2])>,
    /// Whether `pose` is the lifted one (the 2D at a depth lifter's depths), not the
    /// pursuit's.
    pub(crate) lifted: bool,
    /// Bit `i` set when landmark `i` of `observed` was filled in rather than observed.
    pub(crate) imputed: u16,
}

/// One refined frame (normalised image units).
pub(crate) struct RefinedFrame {
    /// The pose with the refined lengths (metres, body frame, pelvis at the origin).
    pub(crate) pose: Pose3,
    /// The weak-perspective camera; with intrinsics or an estimated distance, the perspective
    /// camera's weak approximation at the pelvis.
    pub(crate) camera: WeakPerspective,
    /// The perspective camera (given intrinsics, or an estimated distance): its focal
    /// length, translation `T` (metres) and principal point.
    pub(crate) perspective: Option<(f64, [f64; 3], [f64; 2])>,
    /// Sum of squared reprojection errors.
    pub(crate) squared_error: f64,
}

/// The bone lengths of a refinement: given, or unknowns under the length prior.
pub(crate) enum LengthInput<'a> {
    /// Fixed lengths.
    Given(BoneLengths),
    /// Unknowns: the prior's whitening matrix and mean log lengths (the start).
    Estimated {
        whitening: &'a LimbMatrix,
        mean_log: [f64; NUM_LIMBS],
    },
}

/// The starting state of `frame` for the bone `lengths` and the anchors (the pursuit's bone
/// directions): the pursuit's rotation, its scale corrected for the change of size, the
/// least-squares translation.
fn start(frame: &RefineFrame, lengths: &[f64; NUM_LIMBS]) -> (FrameData, FrameState) {
    let anchors = directions_of(&frame.pose, Vector3::z());
    let pursuit_size: f64 = (0..NUM_LIMBS)
        .map(|b| frame.pose.limb_length(b).powi(2))
        .sum();
    let size: f64 = lengths.iter().map(|l| l * l).sum();
    let scale = frame.camera.scale * (pursuit_size / size).sqrt();
    let mut state = FrameState {
        rotation: frame.camera.rotation,
        camera: [scale.max(f64::MIN_POSITIVE).ln(), 0.0, 0.0],
        directions: anchors,
    };
    let points = state.points(lengths);
    let n = NUM_LANDMARKS as f64;
    let mean3 = points.iter().sum::<Vector3<f64>>() / n;
    let seen = frame.camera.rotation * mean3 * scale;
    let mean2: [f64; 2] =
        std::array::from_fn(|k| frame.observed.iter().map(|u| u[k]).sum::<f64>() / n);
    let t = [mean2[0] - seen.x, mean2[1] - seen.y];
    let projection = match frame.intrinsics {
        None => {
            state.camera = [state.camera[0], t[0], t[1]];
            Projection::OnAxis
        }
        Some((focal, principal)) => {
            let depth = focal / scale;
            state.camera = [
                (t[0] - principal[0]) * depth / focal,
                (t[1] - principal[1]) * depth / focal,
                depth,
            ];
            Projection::Perspective { focal, principal }
        }
    };
    let data = FrameData {
        observed: frame.observed,
        anchors,
        projection,
        imputed: frame.imputed,
    };
    (data, state)
}

/// The deviation of the bone directions from their anchors for `frames`:
/// [`Refinement::lifted_direction_sigma`] for single frames started from a lifted pose without
/// intrinsics or with a camera [`Refinement::weak_perspective_from_m`] or farther, else
/// [`Refinement::direction_sigma`].
fn direction_sigma(frames: &[RefineFrame], settings: &Refinement, sequence: bool) -> f64 {
    let weak = |f: &RefineFrame| {
        f.intrinsics
            .is_none_or(|(focal, _)| focal / f.camera.scale >= settings.weak_perspective_from_m)
    };
    if !sequence && frames.iter().all(|f| f.lifted && weak(f)) {
        settings.lifted_direction_sigma
    } else {
        settings.direction_sigma
    }
}

/// Refines `frames` (one person: their lengths are shared) with `settings`; `sequence` turns
/// on the smoothness between consecutive frames and, for unknown lengths, the sequence's
/// tighter length prior ([`Refinement::sequence_prior`]). Returns the refined frames, in
/// order, and the lengths.
///
/// # Errors
/// [`ReconstructError::Numerical`] when the estimated lengths leave the plausible range
/// ([`BoneLengths::from_array`]).
pub(crate) fn refine(
    frames: &[RefineFrame],
    lengths: LengthInput,
    settings: &Refinement,
    sequence: bool,
) -> Result<(Vec<RefinedFrame>, BoneLengths), ReconstructError> {
    let given = match &lengths {
        LengthInput::Given(given) => Some(*given),
        LengthInput::Estimated { .. } => None,
    };
    // A sequence's length prior, tightened (see `Refinement::sequence_prior` and
    // `Refinement::length_evidence_frames`).
    let tightened: Option<LimbMatrix> = match (&lengths, sequence) {
        (LengthInput::Estimated { whitening, .. }, true) => {
            let n = frames.len() as f64;
            let factor = settings
                .sequence_prior
                .min(n.sqrt())
                .max(1.0)
                .max(settings.sequence_prior * (n / settings.length_evidence_frames).sqrt());
            Some(*whitening * factor)
        }
        _ => None,
    };
    let (log_lengths, unknowns) = match lengths {
        LengthInput::Given(given) => (given.as_array().map(f64::ln), None),
        LengthInput::Estimated {
            whitening,
            mean_log,
        } => (
            mean_log,
            Some(LengthUnknowns {
                whitening: tightened.as_ref().unwrap_or(whitening),
                mean_log,
            }),
        ),
    };
    let initial = log_lengths.map(f64::exp);
    let (data, mut states): (Vec<FrameData>, Vec<FrameState>) =
        frames.iter().map(|f| start(f, &initial)).unzip();
    // Without intrinsics the camera's distance is an unknown under its prior.
    let kappa = settings
        .distance
        .filter(|_| frames.iter().all(|f| f.intrinsics.is_none()))
        .map(|prior| KappaUnknown {
            mean: prior.mean_per_m,
            weight: 1.0 / prior.sigma_per_m,
        });
    let mut shared = SharedState {
        log_lengths,
        kappa: kappa.as_ref().map_or(0.0, |k| k.mean),
    };
    let problem = Problem {
        frames: &data,
        weights: Weights {
            image: 1.0 / settings.image_sigma,
            huber: settings.huber,
            direction: 1.0 / direction_sigma(frames, settings, sequence),
            smooth: if sequence && settings.smoothness > 0.0 {
                1.0 / (settings.smoothness * settings.frame_rate.deviation_factor())
            } else {
                0.0
            },
            hidden_smooth: settings.hidden_smoothness,
            head_limit: settings.head_tilt_limit_rad,
            head: 1.0 / settings.head_tilt_sigma_rad,
        },
        lengths: unknowns,
        kappa,
        iterations: settings.iterations,
        smoothing_frames: settings.frame_rate.step(),
    };
    problem.solve(&mut states, &mut shared);
    // Given lengths stay exactly as given (not through their logarithms).
    let lengths = match given {
        Some(given) => given,
        None => BoneLengths::from_array(shared.log_lengths.map(f64::exp)).map_err(|_| {
            ReconstructError::Numerical(if sequence {
                "the estimated bone lengths are implausible (give the bone lengths, or \
                 reconstruct the frames one by one)"
            } else {
                "the estimated bone lengths are implausible (give the bone lengths)"
            })
        })?,
    };
    let metres = lengths.as_array();
    let refined = data
        .iter()
        .zip(&states)
        .map(|(d, s)| finish(d, s, &metres, shared.kappa))
        .collect();
    Ok((refined, lengths))
}

/// The refined frame of `state` (inverse distance `kappa` for the on-axis camera).
fn finish(
    data: &FrameData,
    state: &FrameState,
    lengths: &[f64; NUM_LIMBS],
    kappa: f64,
) -> RefinedFrame {
    let points = state.points(lengths);
    // Over the landmarks seen: a filled-in one's own fill is no measurement (a simulated
    // user's occluded walk: 27.7 px median with them, the seen ones within 1-4 px).
    let squared_error = state
        .project(data.projection, kappa, &points)
        .map_or(f64::INFINITY, |p| {
            p.iter()
                .zip(&data.observed)
                .enumerate()
                .filter(|&(j, _)| data.imputed & (1 << j) == 0)
                .map(|(_, (a, b))| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2))
                .sum()
        });
    let (camera, perspective) = match data.projection {
        Projection::OnAxis => {
            let scale = state.camera[0].exp();
            let translation = [state.camera[1], state.camera[2]];
            // At a finite distance, the pinhole camera with the pelvis on its optical axis.
            let perspective =
                (kappa > 0.0).then(|| (scale / kappa, [0.0, 0.0, 1.0 / kappa], translation));
            (
                WeakPerspective {
                    scale,
                    rotation: state.rotation,
                    translation,
                },
                perspective,
            )
        }
        Projection::Perspective { focal, principal } => {
            let t = state.camera;
            (
                WeakPerspective {
                    scale: focal / t[2],
                    rotation: state.rotation,
                    translation: [
                        focal * t[0] / t[2] + principal[0],
                        focal * t[1] / t[2] + principal[1],
                    ],
                },
                Some((focal, t, principal)),
            )
        }
    };
    RefinedFrame {
        pose: to_pose(&points),
        camera,
        perspective,
        squared_error,
    }
}
