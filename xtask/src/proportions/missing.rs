//! Poses with missing landmarks: the held-out single poses of the proportions test with
//! random landmarks taken away, reconstructed as `camloc reconstruct` does (the missing ones
//! filled in from the basis seen by the localized camera); PA-MPJPE against the same poses
//! complete.

use std::fmt::Write;

use camloc::reconstruct::{PoseBasis, align_similarity, mpjpe_after_similarity};
use camloc::skeleton::NUM_LANDMARKS;
use camloc::{CameraLocalizer, DepthLifter, Landmark, ModeKind, PartialPose2, PoseReconstructor};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::people::Frames;
use super::views::Studio;
use super::{Skeletons, film_all};

/// Numbers of landmarks taken away from each pose.
const MISSING_COUNTS: [usize; 5] = [0, 1, 2, 3, 5];

/// The section: per camera protocol and number of missing landmarks, the PA-MPJPE of all
/// 15 landmarks and of the missing ones (after the alignment of all 15), and the poses that
/// failed.
pub(super) fn section(
    basis: &PoseBasis,
    (localizer, lifter): (&CameraLocalizer, Option<&DepthLifter>),
    singles: &[Frames],
    seed: u64,
) -> Result<String, String> {
    let mut reconstructor = PoseReconstructor::new(basis.clone())
        .map_err(|e| e.to_string())?
        .with_localizer(localizer.clone());
    if let Some(lifter) = lifter {
        reconstructor = reconstructor.with_lifter(lifter.clone());
    }
    let reconstructor = reconstructor
        .with_mode(ModeKind::Hybrid)
        .map_err(|e| e.to_string())?;
    let mut md = format!(
        "\nMissing landmarks: the rescaled single poses with k landmarks taken away at random \
         (any but the pelvis and neck, the same draw for every protocol), reconstructed as \
         `camloc reconstruct` does (`hybrid`{}; the missing landmarks filled in from the pose \
         basis seen by the localized camera, docs/conventions.md section 6). PA-MPJPE (mm) \
         of all 15 landmarks, and of the missing ones alone after the same alignment:\n\n| \
         protocol | missing | poses | PA-MPJPE | missing landmarks | failed |\n|---|---|---|---|---|---|\n",
        if lifter.is_some() { ", lifter" } else { "" }
    );
    for studio in [Studio::Jittered, Studio::Rig] {
        let filmed = film_all(singles, studio, Skeletons::Random, seed)?;
        for k in MISSING_COUNTS {
            eprintln!("proportions: missing landmarks, {} k = {k}", studio.name());
            let results: Vec<Option<(f64, f64)>> = filmed
                .par_iter()
                .enumerate()
                .flat_map_iter(|(i, item)| {
                    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (i as u64 * 7919 + k as u64));
                    item.views
                        .iter()
                        .zip(&item.truth)
                        .map(|(view, truth)| {
                            let mut pose = PartialPose2::from(view.pose2);
                            let dropped = drop_landmarks(&mut pose, k, &mut rng);
                            let r = reconstructor.reconstruct(&pose).ok()?;
                            let estimate = &r.reconstruction.pose;
                            let all = mpjpe_after_similarity(estimate, truth);
                            let aligned = align_similarity(estimate, truth)?;
                            let missing = dropped
                                .iter()
                                .map(|&j| {
                                    let d: f64 = (0..3)
                                        .map(|a| {
                                            (aligned.points[j][a] - truth.points[j][a]).powi(2)
                                        })
                                        .sum();
                                    1000.0 * d.sqrt()
                                })
                                .sum::<f64>()
                                / dropped.len().max(1) as f64;
                            all.is_finite().then_some((all, missing))
                        })
                        .collect::<Vec<_>>()
                })
                .collect();
            let solved: Vec<(f64, f64)> = results.iter().flatten().copied().collect();
            let n = solved.len().max(1) as f64;
            let all = solved.iter().map(|r| r.0).sum::<f64>() / n;
            let missing = if k == 0 {
                "-".to_string()
            } else {
                format!("{:.1}", solved.iter().map(|r| r.1).sum::<f64>() / n)
            };
            let _ = writeln!(
                md,
                "| `{}` | {k} | {} | {all:.1} | {missing} | {} |",
                studio.name(),
                results.len(),
                results.len() - solved.len()
            );
        }
    }
    Ok(md)
}

/// Takes `k` random landmarks other than the pelvis and neck away from `pose`; returns their
/// indices.
fn drop_landmarks(pose: &mut PartialPose2, k: usize, rng: &mut ChaCha8Rng) -> Vec<usize> {
    let mut candidates: Vec<usize> = (0..NUM_LANDMARKS)
        .filter(|&i| i != Landmark::Pelvis.index() && i != Landmark::Neck.index())
        .collect();
    (0..k)
        .map(|_| {
            let j = candidates.swap_remove(rng.random_range(0..candidates.len()));
            pose.points[j] = None;
            j
        })
        .collect()
}
