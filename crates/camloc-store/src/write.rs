//! Writing output files: temporary files beside their targets, then renames that never
//! clobber unless asked to. One file ([`write_new`]) or several, all or nothing
//! ([`StagedFiles`]), under one rule for what may be at a target ([`check_target`]).

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::TempPath;

use crate::StoreError;
use crate::unfinished::{Listed, moving, placed};

/// Checks what is at `path` against the one rule for output targets:
///
/// | at `path` | `overwrite = false` | `overwrite = true` (`--force`) |
/// |---|---|---|
/// | nothing | may be written | may be written |
/// | a regular file | [`StoreError::Exists`] | may be replaced |
/// | a symbolic link (to anything, or dangling) | [`StoreError::Symlink`] | the *link* may be replaced by a new regular file; its target is neither followed nor written |
/// | a directory, device, FIFO or socket | [`StoreError::NotRegular`] | [`StoreError::NotRegular`] as well |
///
/// [`write_new`] and [`StagedFiles::commit`] apply it before moving anything into place;
/// callers may apply it earlier too, to refuse a run before doing its work.
///
/// # Errors
/// As in the table, and [`StoreError::Io`] when `path`'s metadata cannot be read for
/// another reason than its absence.
pub fn check_target(path: &Path, overwrite: bool) -> Result<(), StoreError> {
    let meta = match fs::symlink_metadata(path) {
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_error(path, e)),
    };
    let kind = meta.file_type();
    let path = path.to_path_buf();
    if !kind.is_symlink() && !kind.is_file() {
        Err(StoreError::NotRegular {
            path,
            kind: file_type_name(&kind),
        })
    } else if overwrite {
        Ok(())
    } else if kind.is_symlink() {
        Err(StoreError::Symlink { path })
    } else {
        Err(StoreError::Exists { path })
    }
}

/// Writes `bytes` to `path` so that `path` is either untouched or complete: the bytes go to a
/// temporary file (`tempfile::NamedTempFile`) in `path`'s folder, flushed to disk, which is
/// then renamed onto `path` (the one-file case of [`StagedFiles`], replacing an existing file
/// in a single rename).
///
/// What is at `path` decides what happens, by [`check_target`]. Without `overwrite` the final
/// rename is a no-clobber one (`persist_noclobber`, an atomic link-or-rename-if-absent of the
/// operating system), so a file that appears at `path` while the bytes are written is not
/// replaced either: there is no check-then-rename race. With `overwrite`, a special file
/// created at `path` between the check and the rename would be replaced by the new file (the
/// rename cannot be made conditional on the kind of file it replaces).
///
/// # Errors
/// As [`check_target`], and [`StoreError::Io`] for operating-system failures (the temporary
/// file is removed).
pub fn write_new(path: &Path, bytes: &[u8], overwrite: bool) -> Result<(), StoreError> {
    check_target(path, overwrite)?;
    let (tmp, _listed) = temporary(path, Flush::Now, |w| w.write_all(bytes))?;
    let _moving = moving();
    persist(tmp, path, overwrite)?;
    placed();
    Ok(())
}

/// An anonymous scratch file in `target`'s folder (opened for reading and writing, deleted by
/// the operating system when closed), for data an output is later made from.
///
/// # Errors
/// [`StoreError::Io`] (naming `target`) when it cannot be made.
pub fn scratch_beside(target: &Path) -> Result<File, StoreError> {
    tempfile::tempfile_in(folder(target)).map_err(|e| io_error(target, e))
}

/// The output files of one run, all or nothing. Each is written at once to a temporary file
/// (`tempfile::NamedTempFile`) beside its target, and closed (only its name is kept, so that
/// thousands of staged files hold no open file descriptor); [`StagedFiles::commit`] moves them all into
/// place, and on any failure removes what it moved and puts back what it replaced. Dropped
/// without a commit (or after a failed one), it removes its temporaries.
///
/// Targets follow [`check_target`]. Without `overwrite` each file is moved with a no-clobber
/// rename (`persist_noclobber`), so a file that appears at a target during the run is never
/// replaced (the commit fails and is rolled back instead). With `overwrite` an existing target
/// is first moved aside (and removed once every file is in place).
#[derive(Debug)]
pub struct StagedFiles {
    overwrite: bool,
    files: Vec<(TempPath, Listed, PathBuf)>,
}

impl StagedFiles {
    /// No files yet; `overwrite` allows replacing existing targets (`--force`).
    pub fn new(overwrite: bool) -> StagedFiles {
        StagedFiles {
            overwrite,
            files: Vec::new(),
        }
    }

    /// Stages `bytes` as the future content of `target`; returns the file's number for
    /// [`StagedFiles::retarget`].
    ///
    /// # Errors
    /// [`StoreError::Io`] (naming `target`) when the temporary cannot be written.
    pub fn add(&mut self, target: &Path, bytes: &[u8]) -> Result<usize, StoreError> {
        self.add_with(target, |w| w.write_all(bytes))
    }

    /// Stages what `write` writes (through a buffer) as the future content of `target`;
    /// returns the file's number for [`StagedFiles::retarget`].
    ///
    /// # Errors
    /// [`StoreError::Io`] (naming `target`) when `write` or the temporary fails.
    pub fn add_with(
        &mut self,
        target: &Path,
        write: impl FnOnce(&mut BufWriter<&File>) -> io::Result<()>,
    ) -> Result<usize, StoreError> {
        let (tmp, listed) = temporary(target, Flush::AtCommit, write)?;
        self.files.push((tmp, listed, target.to_path_buf()));
        Ok(self.files.len() - 1)
    }

    /// Changes the target of staged file `at` to `target`, which must be in the same folder
    /// as the one it was staged for (e.g. a single drawing is not numbered, which is known
    /// only at the end). An unknown `at` changes nothing.
    pub fn retarget(&mut self, at: usize, target: &Path) {
        if let Some((_, _, old)) = self.files.get_mut(at) {
            *old = target.to_path_buf();
        }
    }

    /// Moves every staged file into place: all of them or, on a failure, none (what was
    /// moved is removed and what was replaced is put back). Returns the targets written, in
    /// the order they were staged.
    ///
    /// # Errors
    /// The first target refused by [`check_target`] (nothing is moved then), or the first
    /// failure to move a file ([`StoreError::Exists`] when a file appeared at a target without
    /// `overwrite`, [`StoreError::Io`] otherwise).
    pub fn commit(self) -> Result<Vec<PathBuf>, StoreError> {
        for (_, _, target) in &self.files {
            check_target(target, self.overwrite)?;
        }
        flush_all(&self.files)?;
        // An interrupt waits for the moves (and a roll-back) to end.
        let _moving = moving();
        // (target, the previous file moved aside) for each file moved into place.
        let mut done: Vec<(PathBuf, Option<TempPath>)> = Vec::new();
        for (tmp, _listed, target) in self.files {
            match place(tmp, &target, self.overwrite) {
                Ok(backup) => done.push((target, backup)),
                Err(e) => {
                    for (target, backup) in done.into_iter().rev() {
                        let _ = fs::remove_file(&target);
                        restore(&target, backup);
                    }
                    return Err(e);
                }
            }
        }
        if !done.is_empty() {
            placed();
        }
        // Dropping the backups removes the replaced files.
        Ok(done.into_iter().map(|(target, _)| target).collect())
    }
}

/// Moves `tmp` onto `target`, moving what is there aside first with `overwrite`; returns
/// what was moved aside. On failure `target` is as it was.
fn place(tmp: TempPath, target: &Path, overwrite: bool) -> Result<Option<TempPath>, StoreError> {
    let backup = if overwrite { move_aside(target)? } else { None };
    match persist(tmp, target, overwrite) {
        Ok(()) => Ok(backup),
        Err(e) => {
            restore(target, backup);
            Err(e)
        }
    }
}

/// Puts `backup` (if any) back at `target`.
fn restore(target: &Path, backup: Option<TempPath>) {
    if let Some(backup) = backup {
        let _ = fs::rename(&backup, target);
    }
}

/// Moves what is at `target` (if anything) to a fresh temporary name beside it, removed when
/// the returned path is dropped.
fn move_aside(target: &Path) -> Result<Option<TempPath>, StoreError> {
    match fs::symlink_metadata(target) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io_error(target, e)),
        Ok(_) => {}
    }
    // The name is reserved by creating an empty file, which the rename then replaces.
    let backup = tempfile::Builder::new()
        .prefix(&hidden_prefix(target))
        .suffix(".old")
        .tempfile_in(folder(target))
        .map_err(|e| io_error(target, e))?
        .into_temp_path();
    fs::rename(target, &backup).map_err(|e| io_error(target, e))?;
    Ok(Some(backup))
}

/// When a temporary file is flushed to disk.
#[derive(Clone, Copy, PartialEq)]
enum Flush {
    /// At once (one file written on its own).
    Now,
    /// With the others of its [`StagedFiles`], before they are moved into place
    /// ([`flush_all`]).
    AtCommit,
}

/// A temporary file beside `target` holding what `write` wrote, flushed to disk as `flush`
/// says and closed, and its place on the list of unfinished files (`unfinished.rs`).
fn temporary(
    target: &Path,
    flush: Flush,
    write: impl FnOnce(&mut BufWriter<&File>) -> io::Result<()>,
) -> Result<(TempPath, Listed), StoreError> {
    let io = |e| io_error(target, e);
    let prefix = hidden_prefix(target);
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    // An ordinary output file (0666 less the umask, as `File::create` makes), not the
    // owner-only mode temporary files get by default.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let (tmp, listed) = Listed::create(|| builder.tempfile_in(folder(target))).map_err(io)?;
    let mut out = BufWriter::new(tmp.as_file());
    write(&mut out).map_err(io)?;
    out.into_inner().map_err(|e| io(e.into_error()))?;
    if flush == Flush::Now {
        tmp.as_file().sync_all().map_err(io)?;
    }
    Ok((tmp.into_temp_path(), listed))
}

/// How many staged files [`flush_all`] flushes at a time.
const FLUSHING_THREADS: usize = 8;

/// Flushes the staged `files` to disk, [`FLUSHING_THREADS`] at a time: flushes of different
/// files overlap (a filesystem's journal commits them together), and one after the other they
/// were most of the time of thousands of small drawings (2,000 flushes took 4 s of an 8.6 s
/// run on a loaded disk; 1,000 small files here 0.25 s one by one, 0.05 s eight at a time).
fn flush_all(files: &[(TempPath, Listed, PathBuf)]) -> Result<(), StoreError> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let flush = || -> Result<(), StoreError> {
        loop {
            let at = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let Some((tmp, _, target)) = files.get(at) else {
                return Ok(());
            };
            // Opened for writing: some systems flush only files open for writing.
            fs::OpenOptions::new()
                .write(true)
                .open(tmp)
                .and_then(|file| file.sync_all())
                .map_err(|e| io_error(target, e))?;
        }
    };
    std::thread::scope(|scope| {
        let workers: Vec<_> = (1..FLUSHING_THREADS.min(files.len()))
            .map(|_| scope.spawn(flush))
            .collect();
        let mine = flush();
        workers.into_iter().fold(mine, |first, worker| {
            let theirs = worker.join().unwrap_or_else(|_| {
                Err(StoreError::Io {
                    path: PathBuf::new(),
                    source: io::Error::other("a thread flushing output files panicked"),
                })
            });
            first.and(theirs)
        })
    })
}

/// Renames `tmp` onto `target`: replacing what is there with `overwrite`, otherwise only if
/// nothing is there (no-clobber). On failure `tmp` is removed.
fn persist(tmp: TempPath, target: &Path, overwrite: bool) -> Result<(), StoreError> {
    let persisted = if overwrite {
        tmp.persist(target)
    } else {
        tmp.persist_noclobber(target)
    };
    // On failure the temporary file is dropped with the error, which deletes it.
    persisted.map_err(|e| {
        if e.error.kind() == io::ErrorKind::AlreadyExists {
            StoreError::Exists {
                path: target.to_path_buf(),
            }
        } else {
            io_error(target, e.error)
        }
    })
}

/// The folder `path` is in (`.` for a bare name).
fn folder(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The most bytes of an output's name that its temporary names repeat: with the dots, six
/// random characters and `.tmp`, a temporary name stays within the 255 bytes most file
/// systems allow a name, as long as the output's own may be (trial118: a 250-byte name).
const MAX_PREFIX_NAME_BYTES: usize = 200;

/// `.NAME.`, the start of the temporary names made for `path` (NAME cut to
/// [`MAX_PREFIX_NAME_BYTES`] at a character's end).
fn hidden_prefix(path: &Path) -> String {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy());
    let mut end = name.len().min(MAX_PREFIX_NAME_BYTES);
    while !name.is_char_boundary(end) {
        end -= 1;
    }
    format!(".{}.", &name[..end])
}

/// An operating-system error on `path` (the output, not its temporary file): an error of the
/// system is given as the system's alone, without the temporary file's whole path that
/// `tempfile` adds to its errors (trial118: a 614-character line).
fn io_error(path: &Path, source: io::Error) -> StoreError {
    // `tempfile` wraps the system's error in one of its own (private) that adds
    // ` at path "..."`, the temporary file's whole path: cut there.
    let text = source.to_string();
    let source = match text.find(" at path ") {
        Some(end) if source.raw_os_error().is_none() => {
            io::Error::new(source.kind(), text[..end].to_owned())
        }
        _ => source,
    };
    StoreError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Human name of a non-regular, non-link file type: `directory`, `FIFO`, `character device`,
/// `block device`, `socket` or `special file`.
pub fn file_type_name(kind: &fs::FileType) -> &'static str {
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
