//! The frames of one person: each frame's hypotheses, the depths chosen consistently over
//! time, the shared bone lengths, and the refinement with those lengths and smoothness
//! ([`Reconstructor::reconstruct_sequence`]).

use camloc_skeleton::{Pose2, Pose3};
use nalgebra::Vector3;
use rayon::prelude::*;

use super::hypotheses::{Candidate, Ranked, Reconstruction};
use super::mode::CameraMode;
use super::reconstructor::Reconstructor;
use super::refined::LiftedDepths;
use crate::Refinement;
use crate::refine::{LengthInput, RefinedFrame, refine};
use crate::viterbi::cheapest_path;
use crate::{BoneLengths, Given, ReconstructError};

/// The reconstruction of one person's frames.
#[derive(Debug)]
pub struct SequenceReconstruction {
    /// Per frame, in the order given: its reconstruction, or why it has none.
    pub frames: Vec<Result<Reconstruction, ReconstructError>>,
    /// The person's bone lengths, which every reconstructed frame has: the given ones, or
    /// those estimated from all frames (metres; size from the length prior).
    pub lengths: BoneLengths,
}

/// The Viterbi cost of a joint-limit violation: one unit per this many radians.
const VIOLATION_UNIT_RAD: f64 = 0.2;

impl Reconstructor {
    /// Reconstructs the frames of one person, in time order: each frame's pursuit
    /// hypotheses (with its own [`CameraMode`]); then, with
    /// [`Refinement::consistent_depth`](crate::Refinement::consistent_depth), the hypothesis
    /// of every frame on the path that minimises the frames' reprojection errors and
    /// joint-limit violations plus the camera-oriented motion between consecutive frames
    /// (Viterbi), else each frame's preferred one; then one refinement of all frames with
    /// shared bone lengths (given, or unknowns under the length prior) and the smoothness of
    /// [`Refinement::smoothness`](crate::Refinement::smoothness). Unknown lengths are
    /// estimated by a first refinement without the smoothness (which, holding each bone's
    /// direction near its neighbours', biased them: mean length error 7.0% -> 6.8% under
    /// `jittered`, 5.1% -> 4.7% under `rig` in docs/RESULTS.md), and the poses are then
    /// refined with the smoothness and those lengths; with the joint-angle limits on, frames
    /// whose refined pose has a limb that a flip of its bones' depths takes into the limits
    /// are then refined again from the flips (kept if the frames end further within the
    /// limits). A frame whose pursuit
    /// fails (a degenerate pose) is reported and left out: it breaks the Viterbi path, and
    /// its neighbours become consecutive in the smoothness.
    ///
    /// # Errors
    /// [`ReconstructError::InvalidConfig`] for invalid intrinsics;
    /// [`ReconstructError::Numerical`] when the estimated lengths leave the plausible range.
    /// Errors of single frames are in [`SequenceReconstruction::frames`].
    pub fn reconstruct_sequence(
        &self,
        frames: &[(Pose2, CameraMode)],
        given: &Given,
    ) -> Result<SequenceReconstruction, ReconstructError> {
        self.reconstruct_sequence_lifted(frames, &[], given)
    }

    /// [`reconstruct_sequence`](Self::reconstruct_sequence) with, per frame, the landmarks'
    /// depths the refinement starts from where `depths` has them (`depths[t]` for frame `t`;
    /// missing or `None` entries: the pursuit's pose, as
    /// [`reconstruct_lifted`](Self::reconstruct_lifted) does). Unknown lengths come from the
    /// first refinement of those starts, lifted where lifted: from the pursuit's poses, whose
    /// basis places the neck and pelvis as the mocap does, they were 12% off for people whose
    /// landmarks are placed as detectors place them (the neck at the mid-shoulder point, the
    /// pelvis at the mid-hip point: 11.7% -> 4.4% mean length error on validation subjects),
    /// at the cost of 6.4% -> 7.8% for rescaled mocap people under `jittered`
    /// (docs/RESULTS.md).
    ///
    /// # Errors
    /// As [`reconstruct_sequence`](Self::reconstruct_sequence).
    pub fn reconstruct_sequence_lifted(
        &self,
        frames: &[(Pose2, CameraMode)],
        depths: &[Option<LiftedDepths>],
        given: &Given,
    ) -> Result<SequenceReconstruction, ReconstructError> {
        self.reconstruct_sequence_imputed(frames, depths, &[], given)
    }

    /// [`reconstruct_sequence_lifted`](Self::reconstruct_sequence_lifted) of frames whose
    /// landmarks with bit `i` set in `imputed[t]` (frame `t`; missing entries: none) were
    /// filled in, not observed: the refinements leave them out of their reprojection error,
    /// as [`reconstruct_imputed`](Self::reconstruct_imputed) does.
    ///
    /// # Errors
    /// As [`reconstruct_sequence`](Self::reconstruct_sequence).
    pub fn reconstruct_sequence_imputed(
        &self,
        frames: &[(Pose2, CameraMode)],
        depths: &[Option<LiftedDepths>],
        imputed: &[u16],
        given: &Given,
    ) -> Result<SequenceReconstruction, ReconstructError> {
        if let Some(intrinsics) = &given.intrinsics {
            intrinsics.check()?;
        }
        let ranked: Vec<Result<Ranked, ReconstructError>> = frames
            .par_iter()
            .with_max_len(8)
            .map(|(pose, mode)| {
                if let Some(intrinsics) = &given.intrinsics {
                    intrinsics.check_pose(pose)?;
                }
                self.ranked(pose, mode)
            })
            .collect();
        let choice = self.choose(&ranked);
        // Every frame's result; the successful ones are filled in at the end.
        let mut out: Vec<Result<Reconstruction, ReconstructError>> =
            Vec::with_capacity(frames.len());
        let mut chosen: Vec<(usize, Ranked, Candidate)> = Vec::new();
        for (t, (r, h)) in ranked.into_iter().zip(choice).enumerate() {
            match r {
                Ok(mut r) if h < r.candidates.len() => {
                    let candidate = r.candidates.swap_remove(h);
                    chosen.push((t, r, candidate));
                    out.push(Err(ReconstructError::Numerical("no hypothesis was solved")));
                }
                Ok(_) => out.push(Err(ReconstructError::Numerical("no hypothesis was solved"))),
                Err(e) => out.push(Err(e)),
            }
        }
        let (refined, lengths): (Vec<Option<RefinedFrame>>, BoneLengths) = if self.refines(given) {
            let lifted_of = |t: usize| depths.get(t).and_then(Option::as_ref);
            let imputed_of = |t: usize| imputed.get(t).copied().unwrap_or(0);
            // A frame started from its lifted depths is their reading, whichever of the
            // pursuit's depth readings the path chose (`lifted_starts`).
            for (t, _, c) in &mut chosen {
                c.reflected &= lifted_of(*t).is_none();
            }
            let inputs: Vec<_> = chosen
                .iter()
                .map(|(t, r, c)| self.refine_frame(&r.obs, c, given, lifted_of(*t), imputed_of(*t)))
                .collect();
            let settings = &self.config.refinement;
            let (refined, lengths) = if given.lengths.is_none() && settings.smoothness > 0.0 {
                // The lengths from a first refinement without the smoothness (see
                // reconstruct_sequence), then the poses with them and the smoothness.
                let plain = Refinement {
                    smoothness: 0.0,
                    ..*settings
                };
                let (_, lengths) = refine(&inputs, self.length_input(given), &plain, true)?;
                let (refined, _) = refine(&inputs, LengthInput::Given(lengths), settings, true)?;
                (refined, lengths)
            } else {
                refine(&inputs, self.length_input(given), settings, true)?
            };
            let refined = self.refine_again_within_limits(
                inputs,
                refined,
                LengthInput::Given(lengths),
                true,
            )?;
            (refined.into_iter().map(Some).collect(), lengths)
        } else {
            let poses: Vec<Pose3> = chosen
                .iter()
                .map(|(_, _, c)| Pose3 {
                    points: c.fit.points,
                })
                .collect();
            (
                chosen.iter().map(|_| None).collect(),
                self.unrefined_lengths(given, &poses)?,
            )
        };
        for ((t, r, candidate), refined) in chosen.into_iter().zip(refined) {
            out[t] = Ok(self.reconstruction(&r.obs, candidate, refined, given, r.iterations));
        }
        Ok(SequenceReconstruction {
            frames: out,
            lengths,
        })
    }

    /// The hypothesis of each frame (0 for a failed frame): the Viterbi path when depths are
    /// chosen consistently, else each frame's preferred one.
    fn choose(&self, ranked: &[Result<Ranked, ReconstructError>]) -> Vec<usize> {
        let settings = &self.config.refinement;
        if !settings.consistent_depth {
            return vec![0; ranked.len()];
        }
        let image = 0.5 / (settings.image_sigma * settings.image_sigma);
        let costs = per_hypothesis(ranked, |c| {
            c.fit.error * image + c.violation / VIOLATION_UNIT_RAD
        });
        // Camera-oriented landmarks of every hypothesis.
        let seen = per_hypothesis(ranked, |c| {
            c.fit
                .points
                .map(|p| c.fit.camera.rotation * Vector3::from(p))
        });
        let motion = 0.5 / (settings.motion_m * settings.motion_m);
        // A failed frame breaks the path, so that a transition is always from the frame
        // before.
        cheapest_path(&costs, |t, from, to| {
            let (a, b) = (&seen[t - 1][from], &seen[t][to]);
            motion
                * a.iter()
                    .zip(b)
                    .map(|(x, y)| (x - y).norm_squared())
                    .sum::<f64>()
        })
    }
}

/// `f` of every hypothesis of every frame (none for a failed frame).
fn per_hypothesis<T>(
    ranked: &[Result<Ranked, ReconstructError>],
    f: impl Fn(&Candidate) -> T,
) -> Vec<Vec<T>> {
    ranked
        .iter()
        .map(|r| {
            r.as_ref()
                .map_or_else(|_| Vec::new(), |r| r.candidates.iter().map(&f).collect())
        })
        .collect()
}
