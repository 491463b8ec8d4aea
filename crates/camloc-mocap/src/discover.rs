//! Finding the motion files of a folder tree.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

use super::error::MocapError;
use super::{MocapClip, read_amc, read_asf, read_bvh, subject_and_clip};

/// A motion found by [`discover`]: a BVH file, or an AMC motion with its subject's ASF skeleton.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum MocapSource {
    /// A BVH file.
    Bvh {
        /// Path of the `.bvh` file.
        path: PathBuf,
    },
    /// An AMC motion and the ASF skeleton it animates.
    AsfAmc {
        /// Path of the subject's `.asf` skeleton.
        asf: PathBuf,
        /// Path of the `.amc` motion.
        amc: PathBuf,
    },
}

impl MocapSource {
    /// Reads and parses the motion (and, for AMC, its skeleton) into a clip.
    ///
    /// # Errors
    ///
    /// As [`read_bvh`], [`read_asf`] and [`read_amc`].
    pub fn read(&self) -> Result<MocapClip, MocapError> {
        match self {
            MocapSource::Bvh { path } => read_bvh(path),
            MocapSource::AsfAmc { asf, amc } => {
                if !asf.exists() {
                    return Err(MocapError::MissingSkeleton {
                        asf: asf.clone(),
                        amc: amc.clone(),
                    });
                }
                read_amc(amc, &read_asf(asf)?)
            }
        }
    }

    /// The motion file: the `.bvh` or the `.amc`.
    pub fn motion_path(&self) -> &Path {
        match self {
            MocapSource::Bvh { path } => path,
            MocapSource::AsfAmc { amc, .. } => amc,
        }
    }

    /// Subject id: the motion file's name up to its first `_` (`35` for `35_02.bvh`).
    pub fn subject(&self) -> String {
        subject_and_clip(&self.motion_path().to_string_lossy()).0
    }

    /// Clip id: the motion file's stem (`35_02` for `35_02.bvh`).
    pub fn clip(&self) -> String {
        subject_and_clip(&self.motion_path().to_string_lossy()).1
    }
}

/// Finds every motion under `dir`, recursively, sorted by motion path.
///
/// `.bvh` files are motions on their own; an `.amc` file `SS_CC.amc` is paired with the
/// skeleton `SS.asf` in the same folder (CMU naming; extensions compared ignoring ASCII
/// case). Symbolic links to files are followed, links to folders are not (no cycles). Nothing
/// is parsed: call [`MocapSource::read`].
///
/// # Errors
///
/// [`MocapError::Io`] when a folder cannot be listed. An `.amc` without its `.asf` is listed
/// all the same; [`MocapSource::read`] reports it as [`MocapError::MissingSkeleton`].
pub fn discover(dir: impl AsRef<Path>) -> Result<Vec<MocapSource>, MocapError> {
    let mut sources = Vec::new();
    let mut pending = vec![dir.as_ref().to_owned()];
    while let Some(dir) = pending.pop() {
        let io = |source| MocapError::Io {
            path: dir.clone(),
            source,
        };
        let mut skeletons: HashMap<String, PathBuf> = HashMap::new();
        let mut motions = Vec::new();
        for entry in fs::read_dir(&dir).map_err(io)? {
            let entry = entry.map_err(io)?;
            let path = entry.path();
            let file_type = entry.file_type().map_err(io)?;
            if file_type.is_dir() {
                pending.push(path);
                continue;
            }
            let is_file = file_type.is_file()
                || (file_type.is_symlink() && fs::metadata(&path).is_ok_and(|m| m.is_file()));
            if !is_file {
                continue;
            }
            let extension = path
                .extension()
                .map(|e| e.to_string_lossy().to_ascii_lowercase());
            match extension.as_deref() {
                Some("bvh") => sources.push(MocapSource::Bvh { path }),
                Some("amc") => motions.push(path),
                Some("asf") => {
                    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned());
                    skeletons.insert(stem.unwrap_or_default(), path);
                }
                _ => {}
            }
        }
        for amc in motions {
            let subject = subject_and_clip(&amc.to_string_lossy()).0;
            // Without its skeleton the motion is still listed: reading it reports the missing
            // `.asf`, so that callers skip this one file and keep the others.
            let asf = skeletons
                .get(&subject)
                .cloned()
                .unwrap_or_else(|| dir.join(format!("{subject}.asf")));
            sources.push(MocapSource::AsfAmc { asf, amc });
        }
    }
    sources.sort_by(|a, b| a.motion_path().cmp(b.motion_path()));
    Ok(sources)
}
