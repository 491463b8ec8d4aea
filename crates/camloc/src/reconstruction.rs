//! 3D reconstruction with the localized camera (paper section 8.2).

use camloc_dataset::Dataset;
use camloc_reconstruct::{
    BoneLengths, CameraMode, EvalReport, EvalSample, FrameRate, Given, Intrinsics, LiftedDepths,
    MAX_HEIGHT_M, MIN_HEIGHT_M, ModeKind, Pipeline, PoseBasis, ReconstructConfig, ReconstructError,
    Reconstruction, Reconstructor,
};
use camloc_skeleton::{Landmark, PartialPose2, Pose2};
use camloc_store::Persist;
use camloc_store::Validate;

use crate::rows::sample_pose;
use crate::{
    CameraLocalizer, CamlocError, DepthLifter, LengthsFit, Localization, MIN_PRESENT_FOR_FILL,
};

mod gap_fill;
mod landmark_smoothing;
mod runs;

pub use gap_fill::{GAP_FILL_S, fill_short_gaps};
pub use landmark_smoothing::{LANDMARK_SMOOTHING_S, smooth_landmarks};
pub use runs::SEQUENCE_BREAK_FRAMES;

/// A reconstructed pose and the camera localization it used (none for `opt`).
#[derive(Clone, Debug)]
pub struct PoseReconstruction {
    /// The reconstruction: 3D pose (metres, canonical body frame), weak-perspective camera,
    /// reprojection error. The preferred hypothesis.
    pub reconstruction: Reconstruction,
    /// The other hypotheses asked for ([`PoseReconstructor::reconstruct_hypotheses`]), in
    /// order of preference (e.g. the depth mirror of `reconstruction`); empty from
    /// [`PoseReconstructor::reconstruct`].
    pub alternatives: Vec<Reconstruction>,
    /// The camera localization, when the mode used one.
    pub localization: Option<Localization>,
    /// The landmarks that were missing in the input, in index order: their 2D was filled in
    /// from the pose basis seen by the localized camera before the reconstruction
    /// ([`Reconstructor::impute`]), or in a sequence from the frames around a short gap
    /// ([`PoseReconstructor::with_gap_fill`]), so their 3D is a guess, not a measurement.
    pub imputed: Vec<Landmark>,
}

/// The default basis embedded in this build (16 principal components and 256 cluster
/// centres of the CMU poses of every subject, selected by pose; `cargo xtask train-default`).
///
/// # Errors
/// [`CamlocError::NoDefault`] when the build embedded none; decoding errors otherwise.
pub fn default_basis() -> Result<PoseBasis, CamlocError> {
    let bytes = include_bytes!(concat!(env!("OUT_DIR"), "/default-basis.bin"));
    if bytes.is_empty() {
        return Err(CamlocError::NoDefault("basis"));
    }
    Ok(PoseBasis::from_bytes_named(
        bytes,
        "embedded default basis",
    )?)
}

/// Why `height_m` is not a person's standing height in metres
/// ([`MIN_HEIGHT_M`]..=[`MAX_HEIGHT_M`]), for [`PoseReconstructor::with_person_height`] and the
/// command line's `--person-height`; `None` when it is one. A value that would be one in
/// centimetres is named in metres.
pub fn person_height_problem(height_m: f64) -> Option<String> {
    if (MIN_HEIGHT_M..=MAX_HEIGHT_M).contains(&height_m) {
        return None;
    }
    let shown = if height_m != 0.0 && (height_m.abs() >= 1e6 || height_m.abs() < 1e-3) {
        format!("{height_m:e}")
    } else {
        height_m.to_string()
    };
    let hint = if (100.0 * MIN_HEIGHT_M..=100.0 * MAX_HEIGHT_M).contains(&height_m) {
        format!(": {height_m} cm is {} m", height_m / 100.0)
    } else {
        String::new()
    };
    Some(format!(
        "{shown} m is not a person's standing height (in metres, {MIN_HEIGHT_M} to \
         {MAX_HEIGHT_M}{hint})"
    ))
}

/// 3D reconstruction of 2D poses: a pose basis, the pursuit settings, the camera mode, and
/// (for the `classified` and `hybrid` modes) the camera localizer that classifies the camera.
///
/// ```
/// use camloc::{PoseReconstructor, CameraLocalizer, ModeKind};
/// # fn main() -> Result<(), camloc::CamlocError> {
/// let reconstructor = PoseReconstructor::new(camloc::default_basis()?)?
///     .with_localizer(CameraLocalizer::default_model()?)
///     .with_mode(ModeKind::Classified)?;
/// assert_eq!(reconstructor.mode(), ModeKind::Classified);
/// # Ok(()) }
/// ```
#[derive(Clone, Debug)]
pub struct PoseReconstructor {
    reconstructor: Reconstructor,
    mode: ModeKind,
    localizer: Option<CameraLocalizer>,
    /// The depth lifter the refinement starts from (with a localization: `classified` and
    /// `hybrid`).
    lifter: Option<DepthLifter>,
    given: Given,
    /// The person's standing height, metres, that estimated lengths are scaled to
    /// ([`with_person_height`](PoseReconstructor::with_person_height)).
    height_m: Option<f64>,
    /// Sequences: the longest gap (seconds) of a landmark filled in from the frames around it
    /// ([`with_gap_fill`](PoseReconstructor::with_gap_fill)).
    gap_fill_s: f64,
}

/// The reconstruction of one person's frames ([`PoseReconstructor::reconstruct_sequence`]).
#[derive(Debug)]
pub struct PoseSequenceReconstruction {
    /// Per frame, in the order given: its reconstruction (no alternatives), or why it has
    /// none.
    pub frames: Vec<Result<PoseReconstruction, CamlocError>>,
    /// The person's bone lengths, which every reconstructed frame has (metres): the given
    /// ones, or those estimated from all the frames. When no frame could be reconstructed
    /// (or none was given) nothing was estimated, and they are the length prior's own: look
    /// at `frames` before using them.
    pub lengths: BoneLengths,
    /// With bone lengths given, how well they fit the frames against lengths estimated from
    /// them ([`LengthsFit::warning`]); `None` without given lengths or a frame both solved.
    pub lengths_fit: Option<LengthsFit>,
}

impl PoseReconstructor {
    /// A reconstructor on `basis` with the default pursuit settings, the `opt` camera mode and
    /// no localizer.
    ///
    /// # Errors
    /// [`CamlocError::Reconstruct`] if the basis is unusable.
    pub fn new(basis: PoseBasis) -> Result<PoseReconstructor, CamlocError> {
        Self::with_config(basis, ReconstructConfig::default())
    }

    /// A reconstructor on `basis` with the pursuit settings `config`, the `opt` camera mode
    /// and no localizer.
    ///
    /// # Errors
    /// [`CamlocError::Reconstruct`] if the basis or the settings are unusable.
    pub fn with_config(
        basis: PoseBasis,
        config: ReconstructConfig,
    ) -> Result<PoseReconstructor, CamlocError> {
        let reconstructor =
            Reconstructor::new(basis, config).map_err(|source| CamlocError::Reconstruct {
                context: "basis".into(),
                source,
            })?;
        Ok(PoseReconstructor {
            reconstructor,
            mode: ModeKind::Opt,
            localizer: None,
            lifter: None,
            given: Given::default(),
            height_m: None,
            gap_fill_s: GAP_FILL_S,
        })
    }

    /// Reconstructs with the person's own bone lengths `lengths` (metres): every
    /// reconstruction then has exactly these (docs/conventions.md section 6). They give the
    /// size: a height given before ([`with_person_height`](Self::with_person_height)) is dropped.
    pub fn with_bone_lengths(mut self, lengths: BoneLengths) -> PoseReconstructor {
        self.given.lengths = Some(lengths);
        self.height_m = None;
        self
    }

    /// Reconstructs a person `height_m` metres tall standing (soles to the top of the head):
    /// the estimated lengths keep their proportions, and each answer (a single pose, or a
    /// sequence with its one set of lengths) is scaled with its camera so that
    /// [`BoneLengths::standing_height_m`] of its lengths is `height_m`; the image is
    /// unchanged ([`Reconstruction::resize`]). Without it, the size is the length prior's
    /// (about 1.7 m): one camera cannot tell a size.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for a height that is not a number from
    /// [`MIN_HEIGHT_M`] to [`MAX_HEIGHT_M`], or when bone lengths were given (they give the
    /// size already).
    pub fn with_person_height(mut self, height_m: f64) -> Result<PoseReconstructor, CamlocError> {
        if let Some(detail) = person_height_problem(height_m) {
            return Err(CamlocError::InvalidOption {
                name: "person height",
                detail,
            });
        }
        if self.given.lengths.is_some() {
            return Err(CamlocError::InvalidOption {
                name: "person height",
                detail: "the bone lengths given already give the size".into(),
            });
        }
        self.height_m = Some(height_m);
        Ok(self)
    }

    /// Reconstructs sequences filmed at `hz` frames a second (30 by default): above 30 their
    /// smoothness and their placement in the world keep their windows in time
    /// ([`FrameRate`]: without it a 120 frames a second video came out with 16 times the
    /// accelerations of the same motion at 30); single poses do not depend on it.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] unless `hz` is finite and > 0.
    pub fn with_frame_rate(mut self, hz: f64) -> Result<PoseReconstructor, CamlocError> {
        let rate = FrameRate::new(hz).map_err(|e| CamlocError::InvalidOption {
            name: "frame rate",
            detail: e.to_string(),
        })?;
        self.reconstructor = self.reconstructor.with_frame_rate(rate);
        Ok(self)
    }

    /// The frames a second of the sequences it reconstructs
    /// ([`with_frame_rate`](Self::with_frame_rate)).
    pub fn frame_rate(&self) -> FrameRate {
        self.reconstructor.config().refinement.frame_rate
    }

    /// Sequences: landmarks missing for at most `seconds` in a row between frames that have
    /// them are filled in from those frames ([`fill_short_gaps`]; [`GAP_FILL_S`] by default;
    /// 0 turns it off) before the frames are localized and solved, as seen landmarks; each
    /// frame's [`PoseReconstruction::imputed`] still names them. Longer gaps are filled in
    /// per frame from the pose basis, as a single pose's.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] unless `seconds` is finite and >= 0.
    pub fn with_gap_fill(mut self, seconds: f64) -> Result<PoseReconstructor, CamlocError> {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(CamlocError::InvalidOption {
                name: "gap fill",
                detail: format!("{seconds:?} s: give a number of seconds >= 0"),
            });
        }
        self.gap_fill_s = seconds;
        Ok(self)
    }

    /// The standing height the estimated lengths are scaled to, metres, if one was given.
    pub fn person_height_m(&self) -> Option<f64> {
        self.height_m
    }

    /// Reconstructs with a known camera: a final full-perspective refinement with these
    /// intrinsics (pixels, in the input's image coordinates; without a principal point, the
    /// centre of the bounding box of each pose's given landmarks, not those filled in), and
    /// the localizer aiming each pose
    /// ([`CameraLocalizer::with_intrinsics`]: a simulated user's views at f = 500 px with the
    /// pelvis 500 px off-centre, labels 58.8% -> 78.5%, PA-MPJPE 37 -> 36 mm against the
    /// refinement alone).
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for a focal length that is not finite and positive or
    /// a principal point that is not finite.
    pub fn with_intrinsics(
        mut self,
        intrinsics: Intrinsics,
    ) -> Result<PoseReconstructor, CamlocError> {
        crate::localizer::check_intrinsics(&intrinsics)?;
        self.given.intrinsics = Some(intrinsics);
        if let Some(localizer) = &mut self.localizer {
            localizer.intrinsics = Some(intrinsics);
        }
        Ok(self)
    }

    /// What the reconstructions are given: bone lengths and intrinsics.
    pub fn given(&self) -> &Given {
        &self.given
    }

    /// Uses `localizer` to classify the camera (needed by the `classified` and `hybrid` modes
    /// and by [`PoseReconstructor::evaluate`]), aiming its poses with this reconstructor's
    /// intrinsics when they were given ([`with_intrinsics`](Self::with_intrinsics)).
    pub fn with_localizer(mut self, mut localizer: CameraLocalizer) -> PoseReconstructor {
        // Known intrinsics (checked when given) aim its poses too; else it keeps its own.
        if let Some(k) = self.given.intrinsics {
            localizer.intrinsics = Some(k);
        }
        self.localizer = Some(localizer);
        self
    }

    /// Starts the refinement of every reconstruction that has a localization (the
    /// `classified` and `hybrid` modes) from the depths `lifter` predicts for the classified
    /// camera instead of the pursuit's pose (docs/conventions.md section 6): the bone
    /// directions the refinement holds the pose near are then the lifted ones. The lifter's
    /// classes must be the localizer's cameras.
    pub fn with_lifter(mut self, lifter: DepthLifter) -> PoseReconstructor {
        self.lifter = Some(lifter);
        self
    }

    /// The reconstructor without a depth lifter (the pursuit's pose starts every refinement).
    pub fn without_lifter(mut self) -> PoseReconstructor {
        self.lifter = None;
        self
    }

    /// The depth lifter, if one was given.
    pub fn lifter(&self) -> Option<&DepthLifter> {
        self.lifter.as_ref()
    }

    /// Sets the camera mode: [`ModeKind::Opt`] (the default: Procrustes camera, the fastest),
    /// [`ModeKind::Classified`] (the rotation of the classified camera, the paper's section
    /// 8.2) or [`ModeKind::Hybrid`] (the camera of the localized viewpoint,
    /// [`Localization::viewpoint_rotation`], refined by Procrustes: the lowest 3D error on
    /// held-out subjects, about twice the time of `opt`; docs/RESULTS.md).
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for [`ModeKind::Oracle`] (it needs the true camera,
    /// which only an evaluation has), and for `classified` or `hybrid` without a localizer.
    pub fn with_mode(mut self, mode: ModeKind) -> Result<PoseReconstructor, CamlocError> {
        let detail = match mode {
            ModeKind::Oracle => Some("oracle needs the true camera: it exists only in evaluation"),
            ModeKind::Classified | ModeKind::Hybrid if self.localizer.is_none() => {
                Some("this mode classifies the camera: give a localizer first (with_localizer)")
            }
            _ => None,
        };
        if let Some(detail) = detail {
            return Err(CamlocError::InvalidOption {
                name: "camera mode",
                detail: format!("{}: {detail}", mode.name()),
            });
        }
        self.mode = mode;
        Ok(self)
    }

    /// The camera mode.
    pub fn mode(&self) -> ModeKind {
        self.mode
    }

    /// Most hypotheses [`reconstruct_hypotheses`](Self::reconstruct_hypotheses) can keep: 2
    /// per solve (as found and depth-reflected); `hybrid` without a lifter solves twice (4),
    /// every other mode once (2).
    pub fn most_hypotheses(&self) -> usize {
        if self.mode == ModeKind::Hybrid && self.lifter().is_none() {
            4
        } else {
            2
        }
    }

    /// The camera localizer, if one was given.
    pub fn localizer(&self) -> Option<&CameraLocalizer> {
        self.localizer.as_ref()
    }

    /// The underlying pursuit (basis and settings).
    pub fn reconstructor(&self) -> &Reconstructor {
        &self.reconstructor
    }

    /// Reconstructs one 2D pose (image coordinates) with the camera mode: a 3D pose in metres
    /// in the canonical body frame, its weak-perspective camera, and the localization used
    /// (none for `opt`). Missing landmarks are first filled in from the pose basis seen by
    /// the localized camera ([`PoseReconstruction::imputed`]; this needs a localizer in every
    /// mode), then, with a localization (`classified`, `hybrid`), again from the first
    /// reconstruction's reprojection for a second solve (docs/conventions.md section 6). What
    /// may be missing is any landmark, provided at least
    /// [`MIN_PRESENT_FOR_FILL`](crate::MIN_PRESENT_FOR_FILL) (8) landmarks are present, the
    /// rule [`CameraLocalizer::localize_filled`] applies to a pose whose torso is incomplete:
    /// with fewer, most of the 3D pose would be the basis's guess.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] when landmarks are missing and there is no localizer;
    /// [`CamlocError::Feature`] when localization finds no torso and too few landmarks to
    /// fill one in, for
    /// a pose whose scale localization refuses too (`Descriptor::check_scale` of the
    /// localizer's descriptor, or of the default one); localization errors for `classified`
    /// and `hybrid`; [`CamlocError::Reconstruct`] for a degenerate pose, and for an incomplete
    /// pose with fewer than [`MIN_PRESENT_FOR_FILL`](crate::MIN_PRESENT_FOR_FILL) landmarks
    /// ([`ReconstructError::TooFewLandmarks`]).
    pub fn reconstruct(&self, pose: &PartialPose2) -> Result<PoseReconstruction, CamlocError> {
        self.reconstruct_hypotheses(pose, 1)
    }

    /// Reconstructs one 2D pose like [`PoseReconstructor::reconstruct`], keeping up to `max`
    /// hypotheses (at least one): where the 2D fits two poses about equally (the mirror in
    /// depth), the one the joint-angle prior likes comes first and the other is in
    /// [`PoseReconstruction::alternatives`], each with its reprojection error and limit
    /// violation. Hypotheses: 2 per solve (as found and depth-reflected), and `hybrid` runs
    /// two solves.
    ///
    /// # Errors
    /// As [`PoseReconstructor::reconstruct`].
    pub fn reconstruct_hypotheses(
        &self,
        pose: &PartialPose2,
        max: usize,
    ) -> Result<PoseReconstruction, CamlocError> {
        // A landmark far off the others is read as missing, and filled in as missing ones.
        let (pose, _) = crate::without_far_off_landmarks(pose);
        self.reconstruct_prepared(&pose, self.prepare(&pose, None)?, max)
    }

    /// [`reconstruct_hypotheses`](Self::reconstruct_hypotheses) of `pose` from what
    /// [`prepare`](Self::prepare) made of it.
    fn reconstruct_prepared(
        &self,
        pose: &PartialPose2,
        prepared: Prepared,
        max: usize,
    ) -> Result<PoseReconstruction, CamlocError> {
        let Prepared {
            complete,
            localization,
            mode,
            depths,
            imputed,
        } = prepared;
        let mask = pose.missing_mask();
        let solve = |pose: &Pose2, depths: Option<&LiftedDepths>| {
            self.reconstructor
                .reconstruct_imputed(pose, mask, &mode, max, &self.given, depths)
                .map_err(pose_error)
        };
        let mut hypotheses = solve(&complete, depths.as_ref())?;
        // With a localized camera, filled-in landmarks are filled in again from the first
        // reconstruction's reprojection and the pose solved once more (validation subjects,
        // `hybrid`: 0.4-1.6 mm lower PA-MPJPE with 1-5 landmarks missing, docs/RESULTS.md;
        // `opt`, whose camera is found again, turned one example pose 194 mm away).
        let again = mask != 0 && localization.is_some();
        if let Some(first) = hypotheses.first().filter(|_| again) {
            let projected = first.reprojection();
            let mut refilled = complete;
            for l in &imputed {
                refilled.points[l.index()] = projected[l.index()];
            }
            // (A single pose: its placement read from it, as `prepare` read it.)
            let depths = self.lifted_depths(&refilled, localization.as_ref(), None)?;
            hypotheses = solve(&refilled, depths.as_ref())?;
        }
        // A camera that sees landmarks behind it (its reprojection error is not finite: a
        // landmark misplaced, a very close wide-angle view) makes no answer.
        hypotheses.retain(|h| h.projection_error.is_finite());
        if hypotheses.is_empty() {
            return Err(pose_error(ReconstructError::BehindFittedCamera));
        }
        if let Some((azimuth, elevation)) =
            self.levelling_viewpoint(&localization, depths.is_some())
        {
            for h in &mut hypotheses {
                h.level_to_viewpoint(azimuth, elevation);
            }
        }
        if let Some(height_m) = self.height_m {
            for h in &mut hypotheses {
                h.resize_to_height(height_m)
                    .map_err(|e| pose_error(ReconstructError::from(e)))?;
            }
        }
        let mut hypotheses = hypotheses.into_iter();
        let reconstruction = hypotheses
            .next()
            .ok_or_else(|| pose_error(ReconstructError::Numerical("no hypothesis was solved")))?;
        Ok(PoseReconstruction {
            reconstruction,
            alternatives: hypotheses.collect(),
            localization,
            imputed,
        })
    }

    /// Reconstructs the frames of one person, in time order, with one set of bone lengths
    /// (the given ones, or estimated from all frames), the depth of each frame chosen
    /// consistently over time and temporal smoothness
    /// ([`Reconstructor::reconstruct_sequence`]); missing landmarks are filled in as
    /// [`PoseReconstructor::reconstruct`] fills them. A frame that cannot be reconstructed
    /// (no torso and too few landmarks, a degenerate pose, a failed localization) gets its error
    /// and the others are still reconstructed; the frames before and after a few such frames
    /// in a row are not tied to each other over time (see
    /// [`reconstruct_sequence_with_breaks`](Self::reconstruct_sequence_with_breaks)).
    ///
    /// # Errors
    /// [`CamlocError::Reconstruct`] when the estimated lengths leave the plausible range;
    /// errors of single frames are in [`PoseSequenceReconstruction::frames`].
    pub fn reconstruct_sequence(
        &self,
        poses: &[PartialPose2],
    ) -> Result<PoseSequenceReconstruction, CamlocError> {
        self.reconstruct_sequence_with_breaks(poses, &[])
    }

    /// The depths the lifter predicts for `complete` seen by the camera of `localization`,
    /// mirror-symmetric ([`DepthLifter::mirror_symmetric_depths`]; none without a lifter or a
    /// localization), with the weight `placement` of the skeleton's own placement of the
    /// pelvis and the neck (a sequence's; none: read from `complete`).
    fn lifted_depths(
        &self,
        complete: &Pose2,
        localization: Option<&Localization>,
        placement: Option<f64>,
    ) -> Result<Option<LiftedDepths>, CamlocError> {
        let (Some(l), Some(lifter), Some(localizer)) =
            (localization, &self.lifter, &self.localizer)
        else {
            return Ok(None);
        };
        let cameras = localizer.cameras();
        if lifter.n_classes() != cameras.len() {
            return Err(CamlocError::InvalidOption {
                name: "depth lifter",
                detail: format!(
                    "it has {} camera classes, the localizer {} cameras",
                    lifter.n_classes(),
                    cameras.len()
                ),
            });
        }
        Ok(Some(lifter.mirror_symmetric_placed_depths(
            complete, cameras, l.label, placement,
        )?))
    }

    /// What a reconstruction of `pose` needs ([`Prepared`]), its depths lifted with the weight
    /// `placement` of the skeleton's own placement (a sequence's; none: the pose's own).
    fn prepare(
        &self,
        pose: &PartialPose2,
        placement: Option<f64>,
    ) -> Result<Prepared, CamlocError> {
        let imputed: Vec<Landmark> = pose.missing().collect();
        // A pose with missing landmarks is localized with them filled in from the basis
        // (`localize_filled`), and filled in again, mirror-symmetrically, with that camera.
        let (complete, partial_localization) = match pose.complete() {
            Some(complete) => (complete, None),
            None => {
                let Some(localizer) = &self.localizer else {
                    let missing: Vec<&str> = imputed.iter().map(|l| l.name()).collect();
                    return Err(CamlocError::InvalidOption {
                        name: "input pose",
                        detail: format!(
                            "missing landmarks ({}) are filled in with the localized camera: \
                             give a localizer",
                            missing.join(", ")
                        ),
                    });
                };
                // (A pose without a torso and with too few landmarks is refused here, naming
                // the torso's missing landmark; one with a torso, below.)
                let localization = localizer.localize_filled(pose, &self.reconstructor)?;
                let present = pose.points.iter().flatten().count();
                if present < MIN_PRESENT_FOR_FILL {
                    return Err(pose_error(ReconstructError::TooFewLandmarks {
                        present,
                        needed: MIN_PRESENT_FOR_FILL,
                    }));
                }
                let rotation = localization.viewpoint_rotation();
                let (complete, _) =
                    crate::filled::mirror_symmetric_fill(&self.reconstructor, pose, &rotation)
                        .map_err(pose_error)?;
                (complete, Some(localization))
            }
        };
        // The scale check of localization (the localizer's descriptor, or the default one), so
        // that a pose localize refuses (a pelvis at 1e8 beside a body 100 px tall) is refused
        // here too rather than answered with a plausible pose.
        let descriptor = self.localizer.as_ref().map(|l| *l.descriptor());
        descriptor
            .unwrap_or_default()
            .check_scale(&complete)
            .map_err(|source| CamlocError::Feature {
                context: "input pose".into(),
                source,
            })?;
        let localization = match (self.mode, &self.localizer, partial_localization) {
            (ModeKind::Opt, _, _) => None,
            (_, _, Some(localization)) => Some(localization),
            (_, Some(localizer), None) => Some(localizer.localize(&complete)?),
            (mode, None, None) => {
                return Err(CamlocError::InvalidOption {
                    name: "camera mode",
                    detail: format!("{} needs a localizer", mode.name()),
                });
            }
        };
        let depths = self.lifted_depths(&complete, localization.as_ref(), placement)?;
        let mode = match (&localization, self.mode) {
            (Some(l), ModeKind::Hybrid) => hybrid_camera(l, depths.is_some()),
            (Some(l), _) => CameraMode::Classified(l.rotation),
            (None, _) => CameraMode::Opt,
        };
        Ok(Prepared {
            complete,
            localization,
            mode,
            depths,
            imputed,
        })
    }

    /// Reconstructs every complete sample of `dataset` with every camera mode (`opt`,
    /// `classified` with the localizer's prediction, `oracle` with the true rotation,
    /// `hybrid`) and reports 3D error after similarity alignment and projection error per
    /// mode. The reconstructor's own mode does not matter here.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] without a localizer; [`CamlocError::Dataset`] for an
    /// invalid sample label or clip index; localization errors naming the sample.
    pub fn evaluate(&self, dataset: &Dataset) -> Result<EvalReport, CamlocError> {
        let samples = self.evaluation_samples(dataset)?;
        Ok(camloc_reconstruct::evaluate(
            &samples,
            &self.reconstructor,
            &ModeKind::ALL,
        ))
    }

    /// [`evaluate`](Self::evaluate), and this reconstructor's own
    /// [`reconstruct`](Self::reconstruct) (its mode, lifter, given or estimated bone lengths, intrinsics) run on every complete
    /// sample and measured as the modes are ([`EvalReport::pipeline`], named `reconstruct: `
    /// and its [`pipeline_name`](Self::pipeline_name)): what `camloc reconstruct` gives, which
    /// none of the pursuit's bare modes is.
    ///
    /// # Errors
    /// As [`evaluate`](Self::evaluate).
    pub fn evaluate_with_own_pipeline(&self, dataset: &Dataset) -> Result<EvalReport, CamlocError> {
        let samples = self.evaluation_samples(dataset)?;
        let run = |pose: &Pose2| {
            self.reconstruct(&PartialPose2::from(*pose))
                .ok()
                .map(|r| r.reconstruction)
        };
        let pipeline = Pipeline {
            name: format!("reconstruct: {}", self.pipeline_name()),
            mode: self.mode,
            run: &run,
        };
        Ok(camloc_reconstruct::evaluate_with_pipeline(
            &samples,
            &self.reconstructor,
            &ModeKind::ALL,
            Some(&pipeline),
        ))
    }

    /// What [`reconstruct`](Self::reconstruct) does, in a few words: the camera mode, `+
    /// lifter` with a depth lifter, `+ lengths` with given bone lengths (e.g. `"hybrid +
    /// lifter"`), `+ focal` with intrinsics.
    pub fn pipeline_name(&self) -> String {
        let mut name = self.mode.name().to_string();
        if self.lifter.is_some() && self.mode != ModeKind::Opt {
            name.push_str(" + lifter");
        }
        if self.given.lengths.is_some() {
            name.push_str(" + lengths");
        }
        if self.given.intrinsics.is_some() {
            name.push_str(" + focal");
        }
        name
    }

    /// The complete samples of `dataset` as [`evaluation_samples`] gives them with this
    /// reconstructor's localizer.
    fn evaluation_samples(&self, dataset: &Dataset) -> Result<Vec<EvalSample>, CamlocError> {
        let Some(localizer) = &self.localizer else {
            return Err(CamlocError::InvalidOption {
                name: "localizer",
                detail: "evaluating the classified and hybrid modes needs a localizer".into(),
            });
        };
        evaluation_samples(dataset, localizer)
    }
}

impl PoseReconstructor {
    /// The viewpoint (azimuth, elevation, degrees) a `hybrid` reconstruction started from
    /// lifted depths (`lifted`) is levelled to ([`Reconstruction::level_to_viewpoint`]: its
    /// elevation, when the reconstruction's camera is on the viewpoint's side): the
    /// localization's continuous viewpoint. On validation subjects this took the
    /// pelvis-centred error without rotation alignment from 98.7 to 92.0 mm (`jittered`),
    /// 100.5 to 87.9 mm (`rig`) and 103.4 to 92.0 mm (the labs' skeletons), the torso's lean
    /// error from 8.8 to 7.6, 7.0 and 6.7 deg; from the pursuit's pose it did not help (100.3
    /// to 103.6 mm `jittered`; docs/RESULTS.md).
    fn levelling_viewpoint(
        &self,
        localization: &Option<Localization>,
        lifted: bool,
    ) -> Option<(f64, f64)> {
        if self.mode != ModeKind::Hybrid || !lifted {
            return None;
        }
        let l = localization.as_ref()?;
        Some((l.azimuth_deg?, l.elevation_deg?))
    }
}

/// The camera the `hybrid` mode solves with for a pose localized as `localization`: the
/// rotation of its continuous viewpoint refined by Procrustes, or, when the refinement starts
/// from `lifted` depths, that rotation held (one pursuit instead of two). With lifted depths
/// the pose's shape is the refinement's whatever the pursuit's camera (within 8e-5 m after a
/// similarity alignment over 1,060 poses), and the Procrustes camera only turned it: held at
/// the continuous viewpoint, the pelvis-centred error without rotation alignment fell from
/// 93.9 to 88.1 mm (`jittered`) and from 88.3 to 81.2 mm (`rig`) on validation subjects, in
/// about half the time (docs/RESULTS.md).
pub fn hybrid_camera(localization: &Localization, lifted: bool) -> CameraMode {
    if lifted {
        CameraMode::Classified(localization.viewpoint_rotation())
    } else {
        CameraMode::Hybrid(localization.viewpoint_rotation())
    }
}

/// What a reconstruction of one pose needs ([`PoseReconstructor::prepare`]).
struct Prepared {
    /// The 2D pose, missing landmarks filled in (after the scale check of localization).
    complete: Pose2,
    /// The localization (none for `opt`).
    localization: Option<Localization>,
    /// The camera mode.
    mode: CameraMode,
    /// The lifted depths (with a lifter and a localization).
    depths: Option<LiftedDepths>,
    /// The landmarks that were filled in.
    imputed: Vec<Landmark>,
}

/// A reconstruction error of the input pose.
fn pose_error(source: ReconstructError) -> CamlocError {
    CamlocError::Reconstruct {
        context: "input pose".into(),
        source,
    }
}

/// The complete samples of `dataset` (no missing landmark), in order, as reconstruction
/// evaluation samples: 2D landmarks, true 3D pose and rotation, and the rotation of the
/// camera `localizer` classifies each one as.
///
/// # Errors
/// [`CamlocError::Dataset`] for an invalid dataset; localization errors naming the sample.
pub fn evaluation_samples(
    dataset: &Dataset,
    localizer: &CameraLocalizer,
) -> Result<Vec<EvalSample>, CamlocError> {
    dataset.validate()?;
    let poses: Vec<PartialPose2> = dataset.samples.iter().map(sample_pose).collect();
    let labels = localizer.predict_labels(&poses)?;
    Ok(dataset
        .samples
        .iter()
        .zip(&labels)
        .filter(|(s, _)| s.missing_mask == 0)
        .map(|(s, label)| EvalSample {
            pose2: s.landmarks,
            truth: s.pose3,
            true_rotation: s.rotation,
            classified_rotation: localizer.cameras().get(label.get()).map(|v| v.rotation),
        })
        .collect())
}
