//! The motion capture the xtask commands share: read, categorised, projected into datasets,
//! split by subject, and selected as basis poses.

use std::path::PathBuf;

use camloc_dataset::{
    Dataset, GenerateConfig, MocapIndex, MocapSummary, PoseSequence, assign_categories, generate,
    load_mocap_folders,
};

use crate::progress::Progress;

/// Reads the motion capture under `folders` (default: the CMU data beside the workspace)
/// into canonical pose sequences, with progress and one warning per skipped file on stderr.
/// Returns the sequences, what was read, and the number of warnings.
pub fn load_sequences(
    folders: &[PathBuf],
) -> Result<(Vec<PoseSequence>, MocapSummary, usize), String> {
    let folders = if folders.is_empty() {
        vec![camloc::skeleton::data::data_folder().join("cmu")]
    } else {
        folders.to_vec()
    };
    let mut warnings = 0usize;
    let mut reading = Progress::new("reading mocap");
    let (sequences, summary) = load_mocap_folders(
        &folders,
        &mut |w| {
            warnings += 1;
            eprintln!("warning: {w}");
        },
        &mut |done, total, name| reading.tick(done, total, name),
    )
    .map_err(|e| e.to_string())?;
    Ok((sequences, summary, warnings))
}

/// Sets every sequence's motion category from the CMU index at `index` (default:
/// `cmu-mocap-index-text.txt` in the first of `folders`, or in the default CMU folder), with
/// a warning on stderr for a missing default index or subjects it does not describe. Returns
/// the number of warnings; an index given that cannot be read is an error.
pub fn categorise(
    sequences: &mut [PoseSequence],
    folders: &[PathBuf],
    index: Option<&PathBuf>,
) -> Result<usize, String> {
    let path = index.cloned().unwrap_or_else(|| {
        folders
            .first()
            .cloned()
            .unwrap_or_else(|| camloc::skeleton::data::data_folder().join("cmu"))
            .join("cmu-mocap-index-text.txt")
    });
    let index = match MocapIndex::load(&path) {
        Ok(index) => index,
        Err(e) if index.is_some() => return Err(format!("--index: {e}")),
        Err(e) => {
            eprintln!("warning: no motion categories (every clip is 'other'): {e}");
            return Ok(1);
        }
    };
    let warnings = assign_categories(sequences, &index);
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    Ok(warnings.len())
}

/// Generates a dataset from loaded sequences, with progress on stderr.
pub fn project(sequences: &[PoseSequence], config: &GenerateConfig) -> Result<Dataset, String> {
    let projecting = std::sync::Mutex::new(Progress::new("projecting clips"));
    generate(sequences, config, &|done, total| {
        if let Ok(mut p) = projecting.lock() {
            p.tick(done, total, "");
        }
    })
    .map_err(|e| e.to_string())
}

/// The canonical 3D poses of `sequences` selected by pose at `min_pose_distance_mm`
/// (millimetres of maximum per-joint distance), with their subjects.
pub fn basis_poses(
    sequences: &[PoseSequence],
    min_pose_distance_mm: f64,
) -> Vec<(camloc::Pose3, String)> {
    let mut out = Vec::new();
    for s in sequences {
        let poses: Vec<&camloc::Pose3> = s.frames.iter().map(|(_, p)| p).collect();
        for k in camloc::dataset::select_by_pose(&poses, min_pose_distance_mm) {
            out.push((*poses[k], s.clip.subject.clone()));
        }
    }
    out
}

/// The clips of `mocap` with their motion categories, split into (training, test) by
/// subject: the test clips are those of `test_subjects`.
pub fn load_split(
    mocap: &[PathBuf],
    test_subjects: &[String],
) -> Result<(Vec<PoseSequence>, Vec<PoseSequence>), String> {
    let (mut sequences, _, _) = load_sequences(mocap)?;
    categorise(&mut sequences, mocap, None)?;
    Ok(sequences
        .into_iter()
        .partition(|s| !test_subjects.contains(&s.clip.subject)))
}
