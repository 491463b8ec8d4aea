//! Poses with missing landmarks: the held-out single poses of the proportions test with
//! random landmarks taken away, reconstructed as `camloc reconstruct` does (the missing ones
//! filled in from the basis seen by the localized camera); PA-MPJPE against the same poses
//! complete.

use std::fmt::Write;

use camloc::reconstruct::{PoseBasis, align_similarity, mpjpe_after_similarity};
use camloc::skeleton::NUM_LANDMARKS;
use camloc::{
    CameraLocalizer, DepthLifter, Landmark, ModeKind, PartialPose2, Pose3, PoseReconstructor,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::people::Frames;
use super::views::Studio;
use super::{Skeletons, film_all};

/// What is taken away from each pose.
const TAKEN: [Taken; 7] = [
    Taken::Random(0),
    Taken::Random(1),
    Taken::Random(2),
    Taken::Random(3),
    Taken::Random(5),
    Taken::PelvisAndHip,
    Taken::NeckAndShoulder,
];

/// Landmarks taken away from a pose.
#[derive(Clone, Copy)]
enum Taken {
    /// This many at random, any but the pelvis and neck.
    Random(usize),
    /// The pelvis and one hip (left or right at random): no torso for the descriptor.
    PelvisAndHip,
    /// The neck and one shoulder (left or right at random).
    NeckAndShoulder,
}

impl Taken {
    /// The table's `missing` cell.
    fn name(self) -> String {
        match self {
            Taken::Random(k) => k.to_string(),
            Taken::PelvisAndHip => "pelvis, one hip".into(),
            Taken::NeckAndShoulder => "neck, one shoulder".into(),
        }
    }

    /// Takes the landmarks away from `pose`; returns their indices.
    fn apply(self, pose: &mut PartialPose2, rng: &mut ChaCha8Rng) -> Vec<usize> {
        let (end, left, right) = match self {
            Taken::Random(k) => return drop_landmarks(pose, k, rng),
            Taken::PelvisAndHip => (Landmark::Pelvis, Landmark::LeftHip, Landmark::RightHip),
            Taken::NeckAndShoulder => (
                Landmark::Neck,
                Landmark::LeftShoulder,
                Landmark::RightShoulder,
            ),
        };
        let side = if rng.random_bool(0.5) { left } else { right };
        let taken = vec![end.index(), side.index()];
        for &j in &taken {
            pose.points[j] = None;
        }
        taken
    }
}

/// The section: per camera protocol and number of missing landmarks, the PA-MPJPE of all
/// 15 landmarks and of the missing ones (after the alignment of all 15), and the poses that
/// failed.
pub(super) fn section(
    basis: &PoseBasis,
    (localizer, lifter): (&CameraLocalizer, Option<&DepthLifter>),
    singles: &[Frames],
    seed: u64,
) -> Result<String, String> {
    let reconstructor = hybrid_reconstructor(basis, (localizer, lifter))?;
    let mut md = format!(
        "\nMissing landmarks: the rescaled single poses with k landmarks taken away at random \
         (any but the pelvis and neck, the same draw for every protocol), or the pelvis and one \
         hip, or the neck and one shoulder (no torso for the localizer's descriptor: filled in \
         from camera hypotheses, `CameraLocalizer::localize_filled`), reconstructed as \
         `camloc reconstruct` does (`hybrid`{}; the missing landmarks filled in from the pose \
         basis seen by the localized camera, docs/conventions.md section 6). PA-MPJPE (mm) \
         of all 15 landmarks, and of the missing ones alone after the same alignment:\n\n| \
         protocol | missing | poses | PA-MPJPE | missing landmarks | failed |\n|---|---|---|---|---|---|\n",
        if lifter.is_some() { ", lifter" } else { "" }
    );
    for studio in [Studio::Jittered, Studio::Rig] {
        let filmed = film_all(singles, studio, Skeletons::Random, seed)?;
        for taken in TAKEN {
            eprintln!(
                "proportions: missing landmarks, {}, {}",
                studio.name(),
                taken.name()
            );
            let results: Vec<Option<(f64, f64)>> = filmed
                .par_iter()
                .enumerate()
                .flat_map_iter(|(i, item)| {
                    let salt = match taken {
                        Taken::Random(k) => k as u64,
                        Taken::PelvisAndHip => 101,
                        Taken::NeckAndShoulder => 102,
                    };
                    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (i as u64 * 7919 + salt));
                    item.views
                        .iter()
                        .zip(&item.truth)
                        .map(|(view, truth)| {
                            let mut pose = PartialPose2::from(view.pose2);
                            let dropped = taken.apply(&mut pose, &mut rng);
                            let r = reconstructor.reconstruct(&pose).ok()?;
                            errors_of(&r.reconstruction.pose, truth, &dropped)
                        })
                        .collect::<Vec<_>>()
                })
                .collect();
            let solved: Vec<(f64, f64)> = results.iter().flatten().copied().collect();
            let n = solved.len().max(1) as f64;
            let all = solved.iter().map(|r| r.0).sum::<f64>() / n;
            let missing = if matches!(taken, Taken::Random(0)) {
                "-".to_string()
            } else {
                format!("{:.1}", solved.iter().map(|r| r.1).sum::<f64>() / n)
            };
            let _ = writeln!(
                md,
                "| `{}` | {} | {} | {all:.1} | {missing} | {} |",
                studio.name(),
                taken.name(),
                results.len(),
                results.len() - solved.len()
            );
        }
    }
    Ok(md)
}

/// `camloc reconstruct`'s reconstructor: `hybrid` with `localizer` (and `lifter`).
pub(super) fn hybrid_reconstructor(
    basis: &PoseBasis,
    (localizer, lifter): (&CameraLocalizer, Option<&DepthLifter>),
) -> Result<PoseReconstructor, String> {
    let mut reconstructor = PoseReconstructor::new(basis.clone())
        .map_err(|e| e.to_string())?
        .with_localizer(localizer.clone());
    if let Some(lifter) = lifter {
        reconstructor = reconstructor.with_lifter(lifter.clone());
    }
    reconstructor
        .with_mode(ModeKind::Hybrid)
        .map_err(|e| e.to_string())
}

/// The PA-MPJPE (mm) of all 15 landmarks of `estimate` against `truth`, and the mean error
/// of the `dropped` ones after the same alignment (0 without any); `None` when the alignment
/// fails or the error is not finite.
pub(super) fn errors_of(estimate: &Pose3, truth: &Pose3, dropped: &[usize]) -> Option<(f64, f64)> {
    let all = mpjpe_after_similarity(estimate, truth);
    let aligned = align_similarity(estimate, truth)?;
    let missing = dropped
        .iter()
        .map(|&j| {
            let d: f64 = (0..3)
                .map(|a| (aligned.points[j][a] - truth.points[j][a]).powi(2))
                .sum();
            1000.0 * d.sqrt()
        })
        .sum::<f64>()
        / dropped.len().max(1) as f64;
    all.is_finite().then_some((all, missing))
}

/// Takes `k` random landmarks other than the pelvis and neck away from `pose`; returns their
/// indices.
pub(super) fn drop_landmarks(
    pose: &mut PartialPose2,
    k: usize,
    rng: &mut ChaCha8Rng,
) -> Vec<usize> {
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
