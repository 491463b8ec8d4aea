//! Folders of keypoint files (video frames, one file each): listed in natural order and read
//! one file at a time, each file's result reported on its own.

use std::cmp::Ordering;
use std::path::{Path, PathBuf};

use crate::error::KeypointError;
use crate::record::KeypointRecord;
use crate::{KeypointFormat, KeypointStream, ReadOptions, open_keypoints};

/// Extensions of the files a folder is read for (any case).
const EXTENSIONS: [&str; 3] = ["json", "csv", "npy"];

/// Extension of YOLO pose text files, read in a folder that has none of [`EXTENSIONS`] (a
/// folder of notes beside JSON frames is not read for them).
const YOLO_EXTENSION: &str = "txt";

/// The file of class names that YOLO datasets and labelling tools keep beside their label
/// files (any case), not read.
const YOLO_CLASSES: &str = "classes.txt";

/// Whether `dir` holds a folder that [`keypoint_files`] reads only when recursive (a name not
/// starting with `.`, not a link): said with an input that has no poses of its own.
pub fn has_subfolders(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries.flatten().any(|e| {
            !e.file_name().to_string_lossy().starts_with('.')
                && e.file_type().is_ok_and(|t| t.is_dir())
        })
    })
}

/// The keypoint files (`.json`, `.csv`, `.npy`, any case; `.txt` but `classes.txt` when there is
/// none of those) in `dir`, in natural order of their paths (digit runs compare as numbers:
/// `frame_2` before `frame_10`), files of sub-folders too when `recursive`. Names starting with `.`
/// are skipped, and symbolic links to folders are not followed (no cycles). Entries with these
/// extensions that are not regular files (a dangling link, a link to a device, a FIFO) are listed
/// too: [`open_folder_file`] refuses them, so that they are reported rather than skipped in
/// silence.
pub fn keypoint_files(dir: &Path, recursive: bool) -> Result<Vec<PathBuf>, KeypointError> {
    let (mut files, mut texts) = (Vec::new(), Vec::new());
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let io = |source| KeypointError::Io {
            file: dir.display().to_string(),
            source,
        };
        for entry in std::fs::read_dir(&dir).map_err(io)? {
            let entry = entry.map_err(io)?;
            let path = entry.path();
            if entry.file_name().to_string_lossy().starts_with('.') {
                continue;
            }
            let kind = entry.file_type().map_err(io)?;
            if kind.is_dir() {
                if recursive {
                    pending.push(path);
                }
            } else if !path.is_dir() {
                let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
                if EXTENSIONS.iter().any(|x| x.eq_ignore_ascii_case(extension)) {
                    files.push(path);
                } else if YOLO_EXTENSION.eq_ignore_ascii_case(extension)
                    && !entry
                        .file_name()
                        .to_string_lossy()
                        .eq_ignore_ascii_case(YOLO_CLASSES)
                {
                    texts.push(path);
                }
            }
        }
    }
    if files.is_empty() {
        files = texts;
    }
    files.sort_by(|a, b| natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
    Ok(files)
}

/// Compares two strings with runs of ASCII digits compared as numbers.
fn natural_cmp(a: &str, b: &str) -> Ordering {
    let (mut a, mut b) = (a, b);
    loop {
        let digits = |s: &str| s.len() - s.trim_start_matches(|c: char| c.is_ascii_digit()).len();
        match (a.chars().next(), b.chars().next()) {
            (None, None) => return Ordering::Equal,
            (None, Some(_)) => return Ordering::Less,
            (Some(_), None) => return Ordering::Greater,
            (Some(x), Some(y)) if x.is_ascii_digit() && y.is_ascii_digit() => {
                let (da, db) = (digits(a), digits(b));
                let (na, nb) = (
                    a[..da].trim_start_matches('0'),
                    b[..db].trim_start_matches('0'),
                );
                let order = na
                    .len()
                    .cmp(&nb.len())
                    .then_with(|| na.cmp(nb))
                    .then(da.cmp(&db));
                if order != Ordering::Equal {
                    return order;
                }
                (a, b) = (&a[da..], &b[db..]);
            }
            (Some(x), Some(y)) => {
                if x != y {
                    return x.cmp(&y);
                }
                (a, b) = (&a[x.len_utf8()..], &b[y.len_utf8()..]);
            }
        }
    }
}

/// The files of a folder, read one at a time: each item is a file and its records or its
/// error, so one bad file is reported and the others are still read. Made by [`read_folder`].
/// Each file is read whole; to stream large `.npy` arrays of a folder, open each of
/// [`keypoint_files`] with [`open_keypoints`](crate::open_keypoints).
pub struct FolderRecords {
    files: std::vec::IntoIter<PathBuf>,
    format: Option<KeypointFormat>,
    options: ReadOptions,
}

impl FolderRecords {
    /// The files not read yet.
    pub fn remaining(&self) -> &[PathBuf] {
        self.files.as_slice()
    }

    /// The files not read yet, each opened as a stream ([`open_folder_file`]) instead of
    /// read whole: for a caller that keeps a refused pose's place and reads on
    /// ([`KeypointError::refused_pose`]), as the command line does.
    pub fn streams(self) -> impl Iterator<Item = (PathBuf, Result<KeypointStream, KeypointError>)> {
        let (format, options) = (self.format, self.options);
        self.files.map(move |path| {
            let stream = open_folder_file(&path, format, &options);
            (path, stream)
        })
    }
}

impl Iterator for FolderRecords {
    type Item = (PathBuf, Result<Vec<KeypointRecord>, KeypointError>);

    fn next(&mut self) -> Option<Self::Item> {
        let path = self.files.next()?;
        let records = open_folder_file(&path, self.format, &self.options)
            .and_then(|records| records.collect());
        Some((path, records))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.files.size_hint()
    }
}

/// Opens the file `path` of a folder listing ([`keypoint_files`]) with
/// [`open_keypoints`](crate::open_keypoints), unless it is not a regular file once links are
/// followed: a dangling link, a FIFO (which would wait for a writer) or a device (`/dev/zero`
/// never ends) is [`KeypointError::NotRegular`] instead.
pub fn open_folder_file(
    path: &Path,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<KeypointStream, KeypointError> {
    let kind = match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => return open_keypoints(path, format, options),
        Ok(meta) => camloc_store::file_type_name(&meta.file_type()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => "dangling symbolic link",
        Err(source) => {
            return Err(KeypointError::Io {
                file: path.display().to_string(),
                source,
            });
        }
    };
    Err(KeypointError::NotRegular {
        file: path.display().to_string(),
        kind,
    })
}

/// Reads the keypoint files of `dir` ([`keypoint_files`]) in order, each with
/// [`open_folder_file`]; `format: None` detects each file's format. Only listing the folder can
/// fail here; each file's error comes with it from the iterator. OpenPose files get their
/// frame index from their names ([`frame_index`](crate::frame_index)).
pub fn read_folder(
    dir: impl AsRef<Path>,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
    recursive: bool,
) -> Result<FolderRecords, KeypointError> {
    options.check_min_score(&dir.as_ref().display().to_string())?;
    Ok(FolderRecords {
        files: keypoint_files(dir.as_ref(), recursive)?.into_iter(),
        format,
        options: *options,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn natural_order_compares_numbers() {
        let mut names = vec![
            "f_10.json",
            "f_2.json",
            "f_1.json",
            "f_02.json",
            "e.json",
            "f_.json",
        ];
        names.sort_by(|a, b| natural_cmp(a, b));
        assert_eq!(
            names,
            [
                "e.json",
                "f_.json",
                "f_1.json",
                "f_2.json",
                "f_02.json",
                "f_10.json"
            ]
        );
        assert_eq!(natural_cmp("a9", "a10"), Ordering::Less);
        assert_eq!(natural_cmp("é2", "é10"), Ordering::Less);
    }
}
