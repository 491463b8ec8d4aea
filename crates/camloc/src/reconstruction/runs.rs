//! One person's frames as runs without a gap ([`PoseReconstructor::reconstruct_sequence_with_breaks`]):
//! the depths' consistency and the smoothness tie a frame only to frames of its own run, the
//! bone lengths are shared by all.

use camloc_reconstruct::{
    BoneLengths, CameraMode, Given, LiftedDepths, ReconstructError, Reconstruction,
};
use camloc_skeleton::{PartialPose2, Pose2};

use super::gap_fill::fill_short_gaps;
use super::landmark_smoothing::smooth_landmarks;
use super::{
    PoseReconstruction, PoseReconstructor, PoseSequenceReconstruction, Prepared, pose_error,
};
use crate::sequence::number_or_position;
use crate::torso_placement::sequence_own_placement_weight;
use crate::{CamlocError, LengthsFit, Viewpoint, smooth_viewpoints, viewpoint_half_window};

/// The runs of one person's frames (positions), each frame's solve (`None` where none) and
/// the person's lengths.
type SolvedRuns = (
    Vec<Vec<usize>>,
    Vec<Option<Result<Reconstruction, ReconstructError>>>,
    BoneLengths,
);

/// The fewest frames in a row, missing or not reconstructed, that split one person's frames
/// into runs solved apart (fewer: the frames on each side stay neighbours, as they nearly
/// are; a detector that misses every other frame keeps its smoothness), at 30 frames a
/// second; [`FrameRate::step`](camloc_reconstruct::FrameRate::step) times as many at the
/// reconstructor's faster rate ([`PoseReconstructor::with_frame_rate`]).
pub const SEQUENCE_BREAK_FRAMES: usize = 3;

impl PoseReconstructor {
    /// [`SEQUENCE_BREAK_FRAMES`] at this reconstructor's frame rate: the fewest frames in a
    /// row, missing or not reconstructed, that split a person's frames into runs.
    pub fn sequence_break_frames(&self) -> usize {
        SEQUENCE_BREAK_FRAMES * self.frame_rate().step()
    }

    /// One person's poses at their video frame `numbers` (in time order; `None` where
    /// unknown: the position) reconstructed as `camloc reconstruct --sequence` does: the frames kept in the
    /// sequence (not `left_out[t]`) by
    /// [`reconstruct_sequence_with_breaks`](Self::reconstruct_sequence_with_breaks), a frame
    /// after more than [`sequence_break_frames`](Self::sequence_break_frames) frame numbers
    /// since the last kept one starting a new run; the left-out frames each on its own, as
    /// [`reconstruct`](Self::reconstruct) does. The left-out frames count for no time of
    /// their own: an untracked detector's other people, rows of the same frames as the
    /// person's, had split a crowd's sequence into runs of a frame or two (three or more of
    /// them in a row counted as missing frames), changing the person's 3D by up to 19 cm.
    ///
    /// # Errors
    /// As [`reconstruct_sequence`](Self::reconstruct_sequence).
    pub fn reconstruct_sequence_at_frames(
        &self,
        numbers: &[Option<u64>],
        poses: &[PartialPose2],
        left_out: &[bool],
    ) -> Result<PoseSequenceReconstruction, CamlocError> {
        let left = |t: usize| left_out.get(t).copied().unwrap_or(false);
        let kept: Vec<usize> = (0..poses.len()).filter(|&t| !left(t)).collect();
        let mut breaks = vec![false; kept.len()];
        for (k, pair) in kept.windows(2).enumerate() {
            let (a, b) = (
                number_or_position(numbers, pair[0]),
                number_or_position(numbers, pair[1]),
            );
            breaks[k + 1] = b.saturating_sub(a) > self.sequence_break_frames() as u64;
        }
        let kept_poses: Vec<PartialPose2> = kept.iter().map(|&t| poses[t]).collect();
        let kept_numbers: Vec<u64> = kept
            .iter()
            .map(|&t| number_or_position(numbers, t))
            .collect();
        let solved = self.solve_sequence(&kept_poses, Some(&kept_numbers), &breaks)?;
        let mut in_sequence = solved.frames.into_iter();
        let frames = (0..poses.len())
            .map(|t| match left(t) {
                true => self.reconstruct(&poses[t]),
                false => in_sequence
                    .next()
                    .unwrap_or(Err(CamlocError::NothingDetected)),
            })
            .collect();
        Ok(PoseSequenceReconstruction {
            frames,
            lengths: solved.lengths,
            lengths_fit: solved.lengths_fit,
        })
    }

    /// [`reconstruct_sequence`](Self::reconstruct_sequence) of frames where `breaks[t]` says
    /// that frame `t` follows at least [`SEQUENCE_BREAK_FRAMES`] frames the person is missing
    /// from (a gap in the video; missing entries: no gap). The frames are solved in runs that
    /// end at such a gap and at [`SEQUENCE_BREAK_FRAMES`] or more frames in a row that cannot
    /// be reconstructed: the choice of depths over time and the smoothness tie a frame only to
    /// the frames of its run (across a gap of 28 frames in a user's walk, the frames at its
    /// ends had turned 17 and 35 deg to meet each other). The bone lengths are the given ones,
    /// or estimated from all frames together (which solves them once more). Every frame is the
    /// person's: frames left out of the sequence (a tracker's second pose of a frame, another
    /// person's detection) are [`reconstruct_sequence_at_frames`](Self::reconstruct_sequence_at_frames)'s.
    ///
    /// # Errors
    /// As [`reconstruct_sequence`](Self::reconstruct_sequence).
    pub fn reconstruct_sequence_with_breaks(
        &self,
        poses: &[PartialPose2],
        breaks: &[bool],
    ) -> Result<PoseSequenceReconstruction, CamlocError> {
        self.solve_sequence(poses, None, breaks)
    }

    /// [`reconstruct_sequence_with_breaks`](Self::reconstruct_sequence_with_breaks) of frames
    /// numbered `frames` in the video (none: consecutive), which time the smoothing of the
    /// landmarks ([`smooth_landmarks`]).
    fn solve_sequence(
        &self,
        poses: &[PartialPose2],
        frames: Option<&[u64]>,
        breaks: &[bool],
    ) -> Result<PoseSequenceReconstruction, CamlocError> {
        // A landmark far off the others is read as missing, and filled in as missing ones;
        // the others are smoothed over time within each run (a detector's noise).
        let cleaned: Vec<PartialPose2> = poses
            .iter()
            .map(|p| crate::without_far_off_landmarks(p).0)
            .collect();
        let mut smoothed = self.smoothed_and_filled(&cleaned, frames, breaks);
        let mut prepared = self.prepare_all(&smoothed, &cleaned);
        let (mut runs, mut solved, mut lengths) =
            self.solve_runs(&smoothed, &prepared, breaks, &self.given)?;
        // A frame whose fitted camera sees landmarks behind it (a landmark misplaced, a very
        // close wide-angle view) fails, and the others are smoothed and solved again without
        // it: it had pulled the person's lengths and smoothness (a simulated user's wrist 1000
        // px off in one frame of 120, before such landmarks were read as missing, moved every
        // other frame by 8 cm).
        let behind: Vec<usize> = (0..smoothed.len())
            .filter(|&t| matches!(&solved[t], Some(Ok(r)) if !r.projection_error.is_finite()))
            .collect();
        if !behind.is_empty() {
            let mut kept = cleaned;
            for &t in &behind {
                kept[t] = PartialPose2::empty();
            }
            smoothed = self.smoothed_and_filled(&kept, frames, breaks);
            prepared = self.prepare_all(&smoothed, &kept);
            for &t in &behind {
                prepared[t] = Err(pose_error(ReconstructError::BehindFittedCamera));
            }
            (runs, solved, lengths) = self.solve_runs(&smoothed, &prepared, breaks, &self.given)?;
        }
        // Given lengths against lengths estimated from the same frames (one solve more).
        let lengths_fit = self.given.lengths.and_then(|_| {
            let free = Given {
                lengths: None,
                ..self.given
            };
            let (_, estimated, _) = self.solve_runs(&smoothed, &prepared, breaks, &free).ok()?;
            let error = |r: &Option<Result<Reconstruction, ReconstructError>>| match r {
                Some(Ok(r)) => Some(r.projection_error),
                _ => None,
            };
            LengthsFit::of(
                solved
                    .iter()
                    .zip(&estimated)
                    .map(|(g, e)| error(g).zip(error(e))),
            )
        });
        // A height given scales the estimated lengths and every frame solved with them alike.
        let size = match self.height_m {
            Some(height_m) => height_m / lengths.standing_height_m(),
            None => 1.0,
        };
        let lengths = lengths.scaled(size).map_err(|e| CamlocError::Reconstruct {
            context: "sequence".into(),
            source: e.into(),
        })?;
        let viewpoints = self.levelling_viewpoints(&prepared, &runs);
        let frames = prepared
            .into_iter()
            .zip(solved)
            .zip(viewpoints)
            .map(|((p, solved), viewpoint)| {
                let Prepared {
                    localization,
                    imputed,
                    ..
                } = p?;
                let mut reconstruction = solved
                    .unwrap_or(Err(ReconstructError::Numerical("no hypothesis was solved")))
                    .and_then(|r| {
                        // As a single pose's: landmarks behind the fitted camera.
                        if r.projection_error.is_finite() {
                            Ok(r)
                        } else {
                            Err(ReconstructError::BehindFittedCamera)
                        }
                    })
                    .map_err(pose_error)?;
                if let Some((azimuth, elevation)) = viewpoint {
                    reconstruction.level_to_viewpoint(azimuth, elevation);
                }
                if self.height_m.is_some() {
                    reconstruction.resize(size);
                }
                Ok(PoseReconstruction {
                    reconstruction,
                    alternatives: Vec::new(),
                    localization,
                    imputed,
                })
            })
            .collect();
        Ok(PoseSequenceReconstruction {
            frames,
            lengths,
            lengths_fit,
        })
    }

    /// `poses` smoothed over time ([`smooth_landmarks`]), then their short gaps filled in
    /// from the frames around them ([`fill_short_gaps`]).
    fn smoothed_and_filled(
        &self,
        poses: &[PartialPose2],
        frames: Option<&[u64]>,
        breaks: &[bool],
    ) -> Vec<PartialPose2> {
        let rate = self.frame_rate();
        let smoothed = smooth_landmarks(poses, frames, breaks, rate);
        fill_short_gaps(&smoothed, frames, breaks, rate, self.gap_fill_s)
    }

    /// Every frame of `smoothed` prepared, all lifted with one placement of the pelvis and the
    /// neck (`sequence_own_placement_weight`: a person keeps one, which some views hide; across
    /// breaks too, as the bone lengths); each frame's `imputed` the landmarks missing in
    /// `input` (the frames before the short gaps were filled in).
    fn prepare_all(
        &self,
        smoothed: &[PartialPose2],
        input: &[PartialPose2],
    ) -> Vec<Result<Prepared, CamlocError>> {
        let placement = sequence_own_placement_weight(smoothed);
        smoothed
            .iter()
            .zip(input)
            .map(|(p, seen)| {
                let mut prepared = self.prepare(p, placement)?;
                prepared.imputed = seen.missing().collect();
                Ok(prepared)
            })
            .collect()
    }

    /// The runs of `prepared` frames (split at `breaks` and at frames not prepared, as [`reconstruct_sequence_with_breaks`](Self::reconstruct_sequence_with_breaks)
    /// says), each frame's solve (`None` where none) and the person's lengths.
    fn solve_runs(
        &self,
        poses: &[PartialPose2],
        prepared: &[Result<Prepared, CamlocError>],
        breaks: &[bool],
        given: &Given,
    ) -> Result<SolvedRuns, CamlocError> {
        // Runs of frames that were prepared, split at gaps and at as many frames in a row
        // that were not.
        let mut runs: Vec<Vec<usize>> = Vec::new();
        let mut failed_in_a_row = 0;
        for (t, p) in prepared.iter().enumerate() {
            if p.is_err() {
                failed_in_a_row += 1;
                continue;
            }
            let gap = failed_in_a_row >= self.sequence_break_frames()
                || breaks.get(t).copied().unwrap_or(false);
            failed_in_a_row = 0;
            match runs.last_mut() {
                Some(run) if !gap => run.push(t),
                _ => runs.push(vec![t]),
            }
        }
        let solve = |frames: &[usize], given: &Given| {
            let ready: Vec<&Prepared> = frames
                .iter()
                .filter_map(|&t| prepared[t].as_ref().ok())
                .collect();
            let inputs: Vec<(Pose2, CameraMode)> =
                ready.iter().map(|p| (p.complete, p.mode)).collect();
            let depths: Vec<Option<LiftedDepths>> = ready.iter().map(|p| p.depths).collect();
            let imputed: Vec<u16> = frames.iter().map(|&t| poses[t].missing_mask()).collect();
            self.reconstructor
                .reconstruct_sequence_imputed(&inputs, &depths, &imputed, given)
                .map_err(|source| CamlocError::Reconstruct {
                    context: "sequence".into(),
                    source,
                })
        };
        let all: Vec<usize> = runs.iter().flatten().copied().collect();
        let mut solved: Vec<Option<Result<Reconstruction, ReconstructError>>> =
            (0..poses.len()).map(|_| None).collect();
        let lengths = if runs.len() <= 1 {
            let whole = solve(&all, given)?;
            for (&t, frame) in all.iter().zip(whole.frames) {
                solved[t] = Some(frame);
            }
            whole.lengths
        } else {
            let lengths = match given.lengths {
                Some(lengths) => lengths,
                None => solve(&all, given)?.lengths,
            };
            let given = Given {
                lengths: Some(lengths),
                ..*given
            };
            for run in &runs {
                for (&t, frame) in run.iter().zip(solve(run, &given)?.frames) {
                    solved[t] = Some(frame);
                }
            }
            lengths
        };
        Ok((runs, solved, lengths))
    }

    /// Per frame, the viewpoint its reconstruction is levelled to (as a single pose's,
    /// [`PoseReconstructor::levelling_viewpoint`]), the localizations' viewpoints smoothed over
    /// the frames of its run ([`smooth_viewpoints`]; the frames of `runs` counted as
    /// consecutive, as the solve takes them): on validation subjects' sequences, the
    /// pelvis-centred error without rotation alignment went from 90.2 to 86.2 mm with each
    /// frame's own elevation and to 83.7 mm with the smoothed one (`jittered`; `rig` 89.3 to
    /// 77.9 and 76.5 mm).
    fn levelling_viewpoints(
        &self,
        prepared: &[Result<Prepared, CamlocError>],
        runs: &[Vec<usize>],
    ) -> Vec<Option<Viewpoint>> {
        let mut members: Vec<usize> = Vec::new();
        let mut numbers: Vec<Option<u64>> = Vec::new();
        let mut viewpoints: Vec<Option<Viewpoint>> = Vec::new();
        // Each run starts beyond the smoothing's reach of the one before.
        let mut number = 0;
        for run in runs {
            for &t in run {
                let viewpoint = prepared[t]
                    .as_ref()
                    .ok()
                    .and_then(|p| self.levelling_viewpoint(&p.localization, p.depths.is_some()));
                members.push(t);
                numbers.push(Some(number));
                viewpoints.push(viewpoint);
                number += 1;
            }
            number += 2 * viewpoint_half_window(self.frame_rate()) + 1;
        }
        let mut smoothed = vec![None; prepared.len()];
        for (t, v) in
            members
                .into_iter()
                .zip(smooth_viewpoints(&numbers, &viewpoints, self.frame_rate()))
        {
            smoothed[t] = v;
        }
        smoothed
    }
}
