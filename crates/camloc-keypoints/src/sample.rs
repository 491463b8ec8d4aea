//! The first poses of a file or folder read again ([`sample_records`]), for checks made
//! before the input is read for good: a bounded read that skips what cannot be read.

use std::path::Path;

use crate::{KeypointFormat, KeypointRecord, ReadOptions, keypoint_files, open_path};

/// The bytes of each text file [`sample_records`] reads at most (a large file with few poses,
/// or much else before them, is not read whole again).
pub const SAMPLE_MAX_BYTES: u64 = 64 << 20;

/// The first `count` records of the file or folder at `path` (a folder's files as
/// [`keypoint_files`] lists them, `recursive` as it takes it), read with `format` and
/// `options` but at most [`SAMPLE_MAX_BYTES`] of each text file; poses and files that cannot
/// be read are left out. `None` unless `path` is a regular file or a folder (standard input
/// or a named pipe cannot be read again).
pub fn sample_records(
    path: &Path,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
    recursive: bool,
    count: usize,
) -> Option<Vec<KeypointRecord>> {
    let meta = std::fs::metadata(path).ok()?;
    let files = if meta.is_file() {
        vec![path.to_owned()]
    } else if meta.is_dir() {
        keypoint_files(path, recursive).ok()?
    } else {
        return None;
    };
    let options = ReadOptions {
        max_bytes: options.max_bytes.min(SAMPLE_MAX_BYTES),
        ..*options
    };
    Some(
        files
            .iter()
            .filter(|f| std::fs::metadata(f).is_ok_and(|m| m.is_file()))
            .filter_map(|f| open_path(f, format, &options, false).ok())
            .flatten()
            .filter_map(Result::ok)
            .take(count)
            .collect(),
    )
}
