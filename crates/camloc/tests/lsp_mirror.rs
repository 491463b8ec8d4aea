//! The default model on real photos (LSP, skipped without ../shared/data): a mirrored photo
//! is seen from the mirrored side and the mirrored continuous viewpoint.

use camloc::keypoints::{ReadOptions, read_keypoints};
use camloc::{CameraLocalizer, MIN_PRESENT_FOR_FILL, PartialPose2, PoseReconstructor};

/// A horizontally mirrored photo with left/right labels swapped is seen from the mirrored side:
/// the default model is mirror-symmetric (trained on mirror image pairs,
/// `mirror_training_gives_a_mirror_symmetric_model` in localizer.rs), so every pose but a tie
/// between two cameras must agree; its viewpoint heads are fitted on the mirror images too,
/// so the continuous viewpoint of a mirrored pose with a torso is the mirrored viewpoint
/// (azimuth `a` -> `-a`, the same elevation).
#[test]
fn mirrored_lsp_poses_get_the_mirrored_side() {
    let Some(file) = camloc::skeleton::data::data_path_or_skip(
        "lsp/lsp400_joints.csv",
        "camloc::mirrored_lsp_poses_get_the_mirrored_side",
    ) else {
        return;
    };
    let localizer = CameraLocalizer::default_model().unwrap();
    let filler = PoseReconstructor::new(camloc::default_basis().unwrap()).unwrap();
    let records = read_keypoints(&file, None, &ReadOptions::default()).unwrap();
    assert_eq!(records.len(), 400);
    // Poses without a torso from their visible joints (the file's invisible joints have no
    // position: docs/keypoints.md) are localized with it filled in, given enough landmarks.
    let with_torso = records.iter().filter(|r| r.require_torso().is_ok()).count();
    let fillable = records
        .iter()
        .filter(|r| {
            r.require_torso().is_err()
                && r.pose.points.iter().flatten().count() >= MIN_PRESENT_FOR_FILL
        })
        .count();
    let localize = |pose: &PartialPose2| localizer.localize_filled(pose, filler.reconstructor());
    // [with a torso, filled in]: poses localized, and of those seen from the mirrored side.
    let (mut ok, mut consistent) = ([0usize; 2], [0usize; 2]);
    // Poses with a torso: the largest viewpoint mismatch (degrees) and those over 0.01 deg.
    let (mut worst_deg, mut mismatched) = (0.0f64, 0usize);
    for r in &records {
        let filled = usize::from(r.require_torso().is_err());
        if let (Ok(a), Ok(b)) = (localize(&r.pose), localize(&r.pose.mirrored())) {
            ok[filled] += 1;
            consistent[filled] += usize::from(b.side == a.side.mirrored());
            if filled == 0 {
                let (az_a, az_b) = (a.azimuth_deg.unwrap(), b.azimuth_deg.unwrap());
                let azimuth = ((az_a + az_b) % 360.0 + 540.0) % 360.0 - 180.0;
                let elevation = a.elevation_deg.unwrap() - b.elevation_deg.unwrap();
                let mismatch = azimuth.abs().max(elevation.abs());
                worst_deg = worst_deg.max(mismatch);
                mismatched += usize::from(mismatch > 0.01);
            }
        }
    }
    eprintln!(
        "LSP mirror check: {} of {} poses with a torso, {} of {} with it filled in; \
         viewpoint of the mirrored pose off by more than 0.01 deg in {mismatched} poses with a \
         torso (at most {worst_deg:.3} deg)",
        consistent[0], ok[0], consistent[1], ok[1]
    );
    assert_eq!(
        mismatched, 0,
        "mirrored poses with a torso whose viewpoint is not the mirrored one (up to \
         {worst_deg:.2} deg)"
    );
    assert!(
        ok[0] == with_torso && with_torso >= 240,
        "{} of the {with_torso} LSP poses with a torso localized",
        ok[0]
    );
    assert!(
        ok[1] == fillable && fillable >= 100,
        "{} of the {fillable} LSP poses whose torso can be filled in localized",
        ok[1]
    );
    // A filled-in torso comes from the basis (fitted to people as recorded, not mirrored)
    // and the search may settle on another camera where two are about equally probable.
    for (what, (consistent, ok), least) in [
        ("with a torso", (consistent[0], ok[0]), 0.99),
        ("filled in", (consistent[1], ok[1]), 0.85),
    ] {
        let share = consistent as f64 / ok as f64;
        assert!(
            share >= least,
            "{what}: mirrored side in {:.1}% of poses",
            100.0 * share
        );
    }
}
