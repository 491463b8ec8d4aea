//! Where results go: standard output (buffered, a closed pipe is a normal end) and output files
//! that are all or nothing (staged as temporaries, moved into place at the end of the run).

use std::fs::{self, File};
use std::io::{self, BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use camloc::keypoints::{NpyPose, NpyPoseWriter};
use camloc::skeleton::NUM_LANDMARKS;
use camloc::store::StoreError;

use super::CliError;

/// Standard output through a buffer. A closed pipe (`camloc ... | head`) is not an error: it
/// marks the output closed and later text is dropped; any other failure is
/// [`CliError::Stdout`].
pub struct Out {
    inner: BufWriter<Box<dyn Write>>,
    closed: bool,
}

impl Out {
    /// Buffered output to `inner` (the process's standard output, or a test's buffer).
    pub fn new(inner: Box<dyn Write>) -> Out {
        Out {
            inner: BufWriter::with_capacity(1 << 16, inner),
            closed: false,
        }
    }

    /// Writes `text`.
    pub fn write(&mut self, text: &str) -> Result<(), CliError> {
        if self.closed {
            return Ok(());
        }
        let result = self.inner.write_all(text.as_bytes());
        self.check(result)
    }

    /// Writes out the buffer; a failure here is a failed run.
    pub fn flush(&mut self) -> Result<(), CliError> {
        if self.closed {
            return Ok(());
        }
        let result = self.inner.flush();
        self.check(result)
    }

    /// `true` once the reader of standard output has gone away.
    pub fn closed(&self) -> bool {
        self.closed
    }

    fn check(&mut self, result: io::Result<()>) -> Result<(), CliError> {
        match result {
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe => {
                self.closed = true;
                Ok(())
            }
            other => other.map_err(CliError::Stdout),
        }
    }
}

/// A distinct number for every temporary file of this process.
static TEMPORARIES: AtomicUsize = AtomicUsize::new(0);

/// A file being written beside `target` (same folder, so that moving it into place is a
/// rename), removed when dropped unless moved into place.
struct Temporary {
    path: PathBuf,
    target: PathBuf,
}

impl Temporary {
    fn new(target: &Path, tag: &str) -> Temporary {
        let name = target
            .file_name()
            .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
        let n = TEMPORARIES.fetch_add(1, Ordering::Relaxed);
        Temporary {
            path: target.with_file_name(format!(".{name}.{tag}-{}-{n}", std::process::id())),
            target: target.to_path_buf(),
        }
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.path);
    }
}

/// An operating-system error on `path`.
fn io_error(path: &Path) -> impl Fn(io::Error) -> CliError + '_ {
    move |source| {
        StoreError::Io {
            path: path.to_path_buf(),
            source,
        }
        .into()
    }
}

/// Checks that `target` may be written: it does not exist, or `force` is given and it is a
/// regular file or a symbolic link (replaced itself, not followed). A folder, device, pipe or
/// socket is never replaced.
pub fn check_target(target: &Path, force: bool) -> Result<(), CliError> {
    let Ok(meta) = fs::symlink_metadata(target) else {
        return Ok(());
    };
    if !force {
        return Err(StoreError::Exists {
            path: target.to_path_buf(),
        }
        .into());
    }
    if meta.is_file() || meta.is_symlink() {
        Ok(())
    } else {
        Err(io_error(target)(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a regular file; refusing to replace it",
        )))
    }
}

/// The output files of one run, all or nothing: each is written to a temporary beside its
/// target; [`Staged::commit`] moves them all into place (refusing existing targets without
/// `force`), and on any failure removes what it moved and puts back what it replaced. Dropped
/// without a commit, it removes its temporaries.
pub struct Staged {
    force: bool,
    files: Vec<Temporary>,
}

impl Staged {
    /// No files yet; `force` allows replacing existing targets.
    pub fn new(force: bool) -> Staged {
        Staged {
            force,
            files: Vec::new(),
        }
    }

    /// Writes `bytes` as the future content of `target`; returns the file's number for
    /// [`Staged::retarget`].
    pub fn add(&mut self, target: &Path, bytes: &[u8]) -> Result<usize, CliError> {
        let tmp = Temporary::new(target, "tmp");
        fs::write(&tmp.path, bytes).map_err(io_error(target))?;
        self.files.push(tmp);
        Ok(self.files.len() - 1)
    }

    /// Changes the target of staged file `at` to `target`, in the same folder (a single SVG is
    /// not numbered, which is known only at the end).
    pub fn retarget(&mut self, at: usize, target: &Path) {
        if let Some(file) = self.files.get_mut(at) {
            file.target = target.to_path_buf();
        }
    }

    /// Moves every staged file into place: all of them, or (on a failure) none. Returns the
    /// targets written.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, CliError> {
        for file in &self.files {
            check_target(&file.target, self.force)?;
        }
        // (target, the previous file moved aside) for each file moved into place.
        let mut done: Vec<(PathBuf, Option<Temporary>)> = Vec::new();
        let mut failure = None;
        for file in &self.files {
            match replace(file) {
                Ok(backup) => done.push((file.target.clone(), backup)),
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            }
        }
        if let Some(e) = failure {
            for (target, backup) in done.into_iter().rev() {
                let _ = fs::remove_file(&target);
                if let Some(backup) = backup {
                    let _ = fs::rename(&backup.path, &target);
                }
            }
            return Err(e);
        }
        // The moved temporaries are gone; dropping them (and the backups) removes nothing else.
        let targets = self.files.drain(..).map(|t| t.target.clone()).collect();
        drop(done);
        Ok(targets)
    }
}

/// Moves `file` onto its target, moving an existing target aside first; returns the moved-aside
/// file.
fn replace(file: &Temporary) -> Result<Option<Temporary>, CliError> {
    let target = &file.target;
    let backup = match fs::symlink_metadata(target) {
        Ok(_) => {
            let backup = Temporary::new(target, "old");
            fs::rename(target, &backup.path).map_err(io_error(target))?;
            Some(backup)
        }
        Err(_) => None,
    };
    if let Err(e) = fs::rename(&file.path, target) {
        if let Some(backup) = &backup {
            let _ = fs::rename(&backup.path, target);
        }
        return Err(io_error(target)(e));
    }
    Ok(backup)
}

/// A `.npy` array of poses written as they come, whose length is known only at the end: the
/// numbers go to a temporary body file, and [`NpyStage::finish`] writes the array (header with
/// N, then the body) into a [`Staged`] file.
pub struct NpyStage<P: NpyPose> {
    target: PathBuf,
    body: Temporary,
    writer: BufWriter<File>,
    count: u64,
    _pose: std::marker::PhantomData<fn(&P)>,
}

impl<P: NpyPose> NpyStage<P> {
    /// Starts an array for `target`.
    pub fn new(target: &Path) -> Result<NpyStage<P>, CliError> {
        let body = Temporary::new(target, "body");
        let writer = BufWriter::new(File::create(&body.path).map_err(io_error(target))?);
        Ok(NpyStage {
            target: target.to_path_buf(),
            body,
            writer,
            count: 0,
            _pose: std::marker::PhantomData,
        })
    }

    /// Appends one pose, or a row of NaN for `None`.
    pub fn push(&mut self, pose: Option<&P>) -> Result<(), CliError> {
        let mut result = Ok(());
        let mut write = |v: f64| {
            if result.is_ok() {
                result = self.writer.write_all(&v.to_le_bytes());
            }
        };
        match pose {
            Some(pose) => pose.values(write),
            None => (0..NUM_LANDMARKS * P::CHANNELS).for_each(|_| write(f64::NAN)),
        }
        self.count += 1;
        result.map_err(io_error(&self.target))
    }

    /// Writes the whole array into `staged` as the content of the target.
    pub fn finish(self, staged: &mut Staged) -> Result<(), CliError> {
        let io = io_error(&self.target);
        self.writer
            .into_inner()
            .map_err(|e| io_error(&self.target)(e.into_error()))?;
        let tmp = Temporary::new(&self.target, "tmp");
        let file = File::create(&tmp.path).map_err(&io)?;
        let mut out =
            NpyPoseWriter::<_, Row<P>>::new(BufWriter::new(file), self.count).map_err(&io)?;
        let mut body = BufReader::new(File::open(&self.body.path).map_err(&io)?);
        let mut row = Row::<P>::new();
        for _ in 0..self.count {
            body.read_exact(&mut row.bytes).map_err(&io)?;
            out.push(&row).map_err(&io)?;
        }
        out.finish().map_err(&io)?;
        staged.files.push(tmp);
        Ok(())
    }
}

/// One pose as the little-endian bytes [`NpyStage::push`] wrote.
struct Row<P> {
    bytes: Vec<u8>,
    _pose: std::marker::PhantomData<fn(&P)>,
}

impl<P: NpyPose> Row<P> {
    fn new() -> Row<P> {
        Row {
            bytes: vec![0; 8 * NUM_LANDMARKS * P::CHANNELS],
            _pose: std::marker::PhantomData,
        }
    }
}

impl<P: NpyPose> NpyPose for Row<P> {
    const CHANNELS: usize = P::CHANNELS;

    fn values(&self, mut push: impl FnMut(f64)) {
        for chunk in self.bytes.chunks_exact(8) {
            let mut b = [0u8; 8];
            b.copy_from_slice(chunk);
            push(f64::from_le_bytes(b));
        }
    }
}
