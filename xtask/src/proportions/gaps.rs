//! Landmarks missing over consecutive frames: the held-out windows of the proportions test
//! with two random landmarks each missing in one gap of a few frames, reconstructed as
//! `camloc reconstruct --sequence` does, with the short gaps filled in from the frames around
//! them (`PoseReconstructor::with_gap_fill`) and without (each frame's fill from the basis);
//! PA-MPJPE of the frames of the gaps against the same frames complete.

use std::fmt::Write;

use camloc::reconstruct::PoseBasis;
use camloc::{CameraLocalizer, DepthLifter, GAP_FILL_S, PartialPose2};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::missing::{drop_landmarks, errors_of, hybrid_reconstructor};
use super::people::Frames;
use super::views::Studio;
use super::{Skeletons, film_all};

/// The gaps' lengths, frames (at about 30 frames a second).
const GAP_FRAMES: [usize; 6] = [2, 5, 10, 20, 30, 40];

/// Landmarks missing in each window, each over one gap.
const GAP_LANDMARKS: usize = 2;

/// The longest gaps filled in from the frames around them, seconds: off, the default, and
/// longer.
const FILL_SECONDS: [f64; 3] = [0.0, GAP_FILL_S, 1.0];

/// The section: per protocol, gap length and longest gap filled, the PA-MPJPE of the gaps'
/// frames (all 15 landmarks, and the missing ones after the same alignment) and the frames
/// that failed.
pub(super) fn section(
    basis: &PoseBasis,
    models: (&CameraLocalizer, Option<&DepthLifter>),
    windows: &[Frames],
    seed: u64,
) -> Result<String, String> {
    let reconstructor = hybrid_reconstructor(basis, models)?;
    let mut md = format!(
        "\nLandmarks missing over consecutive frames: in each window, {GAP_LANDMARKS} random \
         landmarks (any but the pelvis and neck) each missing over one gap of g frames inside \
         the window (the same draw for every setting), reconstructed as `camloc reconstruct \
         --sequence` does (`hybrid`{}), with gaps up to the given time filled in from the frames \
         around them (`PoseReconstructor::with_gap_fill`; 0: each frame's missing landmarks \
         filled in from the pose basis, as a single pose's; the default {GAP_FILL_S} s). \
         PA-MPJPE (mm) over the frames of the gaps, of all 15 landmarks and of the missing \
         ones alone after the same alignment:\n\n| protocol | gap | longest gap filled | \
         frames | PA-MPJPE | missing landmarks | failed |\n|---|---|---|---|---|---|---|\n",
        if models.1.is_some() { ", lifter" } else { "" }
    );
    for studio in [Studio::Jittered, Studio::Rig] {
        let filmed = film_all(windows, studio, Skeletons::Random, seed)?;
        for gap in GAP_FRAMES {
            // Per window: its poses with the gaps, and per frame the landmarks taken away.
            let drawn: Vec<(Vec<PartialPose2>, Vec<Vec<usize>>)> = filmed
                .iter()
                .enumerate()
                .map(|(i, item)| {
                    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (i as u64 * 7919 + gap as u64));
                    let mut poses: Vec<PartialPose2> = item
                        .views
                        .iter()
                        .map(|v| PartialPose2::from(v.pose2))
                        .collect();
                    let mut taken = vec![Vec::new(); poses.len()];
                    let mut probe = poses[0];
                    let chosen = drop_landmarks(&mut probe, GAP_LANDMARKS, &mut rng);
                    for j in chosen {
                        // Inside the window: a frame with the landmark on each side.
                        let last_start = poses.len().saturating_sub(gap + 1).max(1);
                        let start = rng.random_range(1..=last_start);
                        for t in start..(start + gap).min(poses.len()) {
                            poses[t].points[j] = None;
                            taken[t].push(j);
                        }
                    }
                    (poses, taken)
                })
                .collect();
            for seconds in FILL_SECONDS {
                eprintln!(
                    "proportions: gaps of {gap} frames, {}, filled up to {seconds} s",
                    studio.name()
                );
                let filling = reconstructor
                    .clone()
                    .with_gap_fill(seconds)
                    .map_err(|e| e.to_string())?;
                let results: Vec<Option<(f64, f64)>> = filmed
                    .par_iter()
                    .zip(&drawn)
                    .flat_map_iter(|(item, (poses, taken))| {
                        let frames = filling.reconstruct_sequence(poses).ok().map(|s| s.frames);
                        (0..poses.len())
                            .filter(|&t| !taken[t].is_empty())
                            .map(|t| {
                                let r = frames.as_ref()?.get(t)?.as_ref().ok()?;
                                errors_of(&r.reconstruction.pose, &item.truth[t], &taken[t])
                            })
                            .collect::<Vec<_>>()
                    })
                    .collect();
                let solved: Vec<(f64, f64)> = results.iter().flatten().copied().collect();
                let n = solved.len().max(1) as f64;
                let _ = writeln!(
                    md,
                    "| `{}` | {gap} | {seconds} s | {} | {:.1} | {:.1} | {} |",
                    studio.name(),
                    results.len(),
                    solved.iter().map(|r| r.0).sum::<f64>() / n,
                    solved.iter().map(|r| r.1).sum::<f64>() / n,
                    results.len() - solved.len()
                );
            }
        }
    }
    Ok(md)
}
