//! Writing output files: a temporary file beside the target, then a rename that never
//! clobbers unless asked to.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::StoreError;

/// Writes `bytes` to `path` so that `path` is either untouched or complete: the bytes go to a
/// temporary file (`tempfile::NamedTempFile`) in `path`'s folder, flushed to disk, which is
/// then renamed onto `path`.
///
/// What is at `path` decides what happens:
///
/// | at `path` | `overwrite = false` | `overwrite = true` (`--force`) |
/// |---|---|---|
/// | nothing | written | written |
/// | a regular file | [`StoreError::Exists`] | replaced |
/// | a symbolic link (to anything, or dangling) | [`StoreError::Symlink`] | the *link* is replaced by the new regular file; its target is neither followed nor written |
/// | a directory, device, FIFO or socket | [`StoreError::NotRegular`] | [`StoreError::NotRegular`] as well |
///
/// Without `overwrite` the final rename is a no-clobber one (`persist_noclobber`, an atomic
/// link-or-rename-if-absent of the operating system), so a file that appears at `path`
/// while the bytes are written is not replaced either: there is no check-then-rename race.
/// With `overwrite`, a special file created at `path` between the check and the rename
/// would be replaced by the new file (the rename cannot be made conditional on the kind of
/// file it replaces).
///
/// # Errors
/// As in the table, and [`StoreError::Io`] for operating-system failures (the temporary file
/// is removed).
pub fn write_new(path: &Path, bytes: &[u8], overwrite: bool) -> Result<(), StoreError> {
    let io = |source| StoreError::Io {
        path: path.to_path_buf(),
        source,
    };
    match fs::symlink_metadata(path) {
        Ok(meta) => {
            let kind = meta.file_type();
            if kind.is_symlink() {
                if !overwrite {
                    return Err(StoreError::Symlink {
                        path: path.to_path_buf(),
                    });
                }
            } else if !kind.is_file() {
                return Err(StoreError::NotRegular {
                    path: path.to_path_buf(),
                    kind: describe(&kind),
                });
            } else if !overwrite {
                return Err(StoreError::Exists {
                    path: path.to_path_buf(),
                });
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(io(e)),
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let prefix = format!(
        ".{}.",
        path.file_name()
            .map_or_else(|| "output".into(), |n| n.to_string_lossy())
    );
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    // An ordinary output file (0666 less the umask, as `File::create` makes), not the
    // owner-only mode temporary files get by default.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let mut tmp = builder.tempfile_in(&dir).map_err(io)?;
    tmp.write_all(bytes).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    let persisted = if overwrite {
        tmp.persist(path)
    } else {
        tmp.persist_noclobber(path)
    };
    // On failure the temporary file is dropped with the error, which deletes it.
    persisted.map(|_| ()).map_err(|e| {
        if e.error.kind() == std::io::ErrorKind::AlreadyExists {
            StoreError::Exists {
                path: path.to_path_buf(),
            }
        } else {
            io(e.error)
        }
    })
}

/// Human name of a non-regular, non-link file type.
fn describe(kind: &fs::FileType) -> &'static str {
    if kind.is_dir() {
        return "directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_char_device() {
            return "character device";
        }
        if kind.is_block_device() {
            return "block device";
        }
        if kind.is_fifo() {
            return "FIFO";
        }
        if kind.is_socket() {
            return "socket";
        }
    }
    "special file"
}
