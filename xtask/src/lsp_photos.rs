//! The report's section on the LSP photos: where the embedded default model puts their
//! cameras (a pose without a torso with it filled in), and whether a mirrored photo is seen
//! from the mirrored side.

use std::fmt::Write;
use std::path::Path;

use camloc::keypoints::{ReadOptions, read_keypoints};
use camloc::{
    CameraLocalizer, MIN_PRESENT_FOR_FILL, PartialPose2, PoseReconstructor, default_basis,
};
use rayon::prelude::*;

/// Distribution of predicted viewpoints on the LSP photos, with the embedded default model.
pub fn section(md: &mut String, lsp: Option<&Path>) -> Result<(), String> {
    let path = lsp
        .map(Path::to_path_buf)
        .unwrap_or_else(|| camloc::skeleton::data::data_folder().join("lsp/lsp400_joints.csv"));
    let _ = writeln!(md, "## Real photos: 400 LSP poses\n");
    let (localizer, filler) = match (CameraLocalizer::default_model(), default_basis()) {
        (Ok(l), Ok(b)) => (l, PoseReconstructor::new(b).map_err(|e| e.to_string())?),
        (Err(e), _) | (_, Err(e)) => {
            let _ = writeln!(md, "Not measured: {e}.\n");
            return Ok(());
        }
    };
    let records =
        read_keypoints(&path, None, &ReadOptions::default()).map_err(|e| e.to_string())?;
    let localize = |pose: &PartialPose2| localizer.localize_filled(pose, filler.reconstructor());
    let found: Vec<_> = records
        .par_iter()
        .map(|r| (localize(&r.pose), localize(&r.pose.mirrored())))
        .collect();
    let cameras = localizer.cameras();
    let mut counts = vec![0usize; cameras.len()];
    // [with a torso, without one]: poses, localized, seen from the mirrored side when mirrored.
    let (mut poses, mut ok, mut consistent) = ([0usize; 2], [0usize; 2], [0usize; 2]);
    let mut missing = 0usize;
    for (r, (a, b)) in records.iter().zip(&found) {
        let group = usize::from(r.require_torso().is_err());
        poses[group] += 1;
        if let Ok(a) = a {
            ok[group] += 1;
            counts[a.label.index()] += 1;
            missing += usize::from(!a.missing.is_empty());
            if let Ok(b) = b {
                consistent[group] += usize::from(b.side == a.side.mirrored());
            }
        }
    }
    let no_torso = poses[1];
    let localized = ok[0] + ok[1];
    let _ = writeln!(
        md,
        "`{}` read with the default options (joints marked invisible are missing; {no_torso} \
         poses have no pelvis or neck that their visible joints give: the file's invisible \
         joints are placeholders without a position, docs/keypoints.md), localized with the \
         default model embedded in the binary (`cargo xtask train-default`) under its own \
         priors (`--camera-height any`); the missing landmarks filled in from the embedded \
         basis, `CameraLocalizer::localize_filled`, docs/conventions.md section 6, when at \
         least {MIN_PRESENT_FOR_FILL} landmarks are present: {missing} of the localized poses \
         have at least one missing, {} of the {no_torso} without a torso. \
         {localized} of {} poses localized. There is no ground truth camera for these photos: \
         this is a sanity check of how the predictions spread over the sphere.\n",
        path.file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        ok[1],
        records.len()
    );
    let _ = writeln!(
        md,
        "| camera | level | side | poses | share |\n|---|---|---|---|---|"
    );
    for (v, n) in cameras.viewpoints().iter().zip(&counts) {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {n} | {:.1}% |",
            v.label_text(),
            v.level.name(),
            v.side.name(),
            100.0 * *n as f64 / localized.max(1) as f64
        );
    }
    let level_share = |level: camloc::Level| {
        let n: usize = cameras
            .viewpoints()
            .iter()
            .zip(&counts)
            .filter(|(v, _)| v.level == level)
            .map(|(_, n)| n)
            .sum();
        100.0 * n as f64 / localized.max(1) as f64
    };
    let _ = writeln!(
        md,
        "\nBy level: lower {:.1}%, middle {:.1}%, upper {:.1}%.",
        level_share(camloc::Level::Lower),
        level_share(camloc::Level::Middle),
        level_share(camloc::Level::Upper)
    );
    let share = |g: usize| 100.0 * consistent[g] as f64 / ok[g].max(1) as f64;
    let _ = writeln!(
        md,
        "\nMirror check: each pose mirrored horizontally with left/right labels swapped is \
         localized on the mirrored side (left <-> right, front and back unchanged) in {} of \
         the {} poses with a torso ({:.1}%) and in {} of the {} with the torso filled in \
         ({:.1}%; each fill is the mean of the pose's and of the mirror image of its mirror \
         image's, as the basis, fitted to people as recorded, is not mirror-symmetric).\n",
        consistent[0],
        ok[0],
        share(0),
        consistent[1],
        ok[1],
        share(1)
    );
    Ok(())
}
