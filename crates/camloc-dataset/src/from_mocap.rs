//! Reading folders of motion capture into canonical pose sequences.

use std::path::PathBuf;

use camloc_mocap::{self as mocap, MocapIndex, MocapSource};

use crate::{ClipInfo, DatasetError, PoseSequence};

/// What [`load_mocap_folders`] read and skipped.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MocapSummary {
    /// Files (BVH, or AMC with its ASF) read successfully.
    pub files_read: usize,
    /// Files skipped, with the reason (one warning each).
    pub skipped: Vec<String>,
    /// Frames read, before striding.
    pub frames: usize,
    /// Frames dropped because they could not be canonicalised (degenerate hips/shoulders).
    pub degenerate_frames: usize,
}

/// Walks each folder for `.bvh` files and `.amc` files with their subject's `.asf`, reads them,
/// and canonicalises every frame (docs/conventions.md section 1). A file that fails to read is
/// skipped with a warning (passed to `warn` and recorded in the summary); the others are still
/// used.
/// `progress(done, total, name)` is called after each file.
///
/// Sequences are sorted by subject and clip name, so the result does not depend on the order
/// the file system lists files in.
///
/// # Errors
/// [`DatasetError::Invalid`] when a folder cannot be listed or no file at all could be read.
pub fn load_mocap_folders(
    folders: &[PathBuf],
    warn: &mut dyn FnMut(&str),
    progress: &mut dyn FnMut(usize, usize, &str),
) -> Result<(Vec<PoseSequence>, MocapSummary), DatasetError> {
    let mut sources: Vec<MocapSource> = Vec::new();
    for folder in folders {
        sources.extend(
            mocap::discover(folder)
                .map_err(|e| DatasetError::Invalid(format!("{}: {e}", folder.display())))?,
        );
    }
    let mut summary = MocapSummary::default();
    let mut sequences = Vec::with_capacity(sources.len());
    let total = sources.len();
    for (i, source) in sources.iter().enumerate() {
        let name = source.motion_path().display().to_string();
        match source.read() {
            Ok(clip) => {
                summary.files_read += 1;
                summary.frames += clip.frames.len();
                let mut frames = Vec::with_capacity(clip.frames.len());
                for (f, pose) in clip.frames.iter().enumerate() {
                    match mocap::canonicalise(pose) {
                        Ok(p) => frames.push((f as u32, p)),
                        Err(_) => summary.degenerate_frames += 1,
                    }
                }
                sequences.push(PoseSequence {
                    clip: ClipInfo::new(clip.subject, clip.clip),
                    frames,
                });
            }
            Err(e) => {
                let message = format!("skipping {name}: {e}");
                warn(&message);
                summary.skipped.push(message);
            }
        }
        progress(i + 1, total, &name);
    }
    if sequences.is_empty() {
        let where_ = folders
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ");
        return Err(DatasetError::Invalid(format!(
            "no readable motion capture (.bvh, or .amc with its .asf) under {where_}"
        )));
    }
    sequences.sort_by(|a, b| {
        natural_key(&a.clip.subject)
            .cmp(&natural_key(&b.clip.subject))
            .then_with(|| a.clip.name.cmp(&b.clip.name))
    });
    Ok((sequences, summary))
}

/// Sort key that orders numeric ids numerically ("2" < "10") and others after, as text.
fn natural_key(id: &str) -> (u8, u64, &str) {
    match id.parse::<u64>() {
        Ok(n) => (0, n, id),
        Err(_) => (1, 0, id),
    }
}

/// Sets the category of every sequence's clip from `index` ([`MocapIndex::category`]).
/// Returns one message per subject none of whose clips the index describes (neither trial
/// nor subject description found), whose clips are [`MotionCategory::Other`](crate::MotionCategory::Other).
pub fn assign_categories(sequences: &mut [PoseSequence], index: &MocapIndex) -> Vec<String> {
    let mut unknown: Vec<String> = Vec::new();
    for seq in sequences.iter_mut() {
        let (category, _) = index.category(&seq.clip.subject, &seq.clip.name);
        seq.clip.category = category;
        let described = index.trial_description(&seq.clip.name).is_some()
            || index.subject_description(&seq.clip.subject).is_some();
        if !described && !unknown.contains(&seq.clip.subject) {
            unknown.push(seq.clip.subject.clone());
        }
    }
    unknown
        .into_iter()
        .map(|s| format!("subject {s} is not in the CMU index: its clips are category 'other'"))
        .collect()
}
