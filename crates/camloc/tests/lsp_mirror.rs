//! The default model on real photos (LSP, skipped without ../shared/data): a mirrored photo
//! is seen from the mirrored side.

use camloc::CameraLocalizer;
use camloc::keypoints::{ReadOptions, read_keypoints};

/// A horizontally mirrored photo with left/right labels swapped is seen from the mirrored side:
/// the default model is mirror-symmetric (trained on mirror image pairs,
/// `mirror_training_gives_a_mirror_symmetric_model` in localizer.rs), so every pose but a tie
/// between two cameras must agree.
#[test]
fn mirrored_lsp_poses_get_the_mirrored_side() {
    let Some(file) = camloc::skeleton::data::data_path_or_skip(
        "lsp/lsp400_joints.csv",
        "camloc::mirrored_lsp_poses_get_the_mirrored_side",
    ) else {
        return;
    };
    let localizer = CameraLocalizer::default_model().unwrap();
    let records = read_keypoints(&file, None, &ReadOptions::default()).unwrap();
    assert_eq!(records.len(), 400);
    // Poses without a torso from their visible joints cannot be localized (the file's
    // invisible joints have no position: docs/keypoints.md).
    let with_torso = records.iter().filter(|r| r.require_torso().is_ok()).count();
    let (mut ok, mut consistent) = (0usize, 0usize);
    for r in &records {
        if let (Ok(a), Ok(b)) = (
            localizer.localize_partial(&r.pose),
            localizer.localize_partial(&r.pose.mirrored()),
        ) {
            ok += 1;
            consistent += usize::from(b.side == a.side.mirrored());
        }
    }
    let share = consistent as f64 / ok as f64;
    eprintln!(
        "LSP mirror check: {consistent} of {ok} poses ({:.1}%)",
        100.0 * share
    );
    assert!(
        ok == with_torso && with_torso >= 240,
        "{ok} of the {with_torso} LSP poses with a torso localized"
    );
    assert!(
        share >= 0.99,
        "mirrored side in {:.1}% of poses",
        100.0 * share
    );
}
