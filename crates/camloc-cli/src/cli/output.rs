//! Where results go: standard output (buffered, a closed pipe is a normal end) and files of one
//! row per pose ([`RowFile`]: `.npy` arrays here, `.npz` archives in `localize_npz`) staged in a
//! [`StagedFiles`] (the store's all-or-nothing output files, moved into place at the end of the
//! run), and which person each numbered file of a run of several is.

use std::fs::File;
use std::io::{self, BufReader, BufWriter, Read, Seek, Write};
use std::path::{Path, PathBuf};

use camloc::keypoints::{KeypointRecord, NpyPose, NpyPoseWriter};
use camloc::skeleton::NUM_LANDMARKS;
use camloc::store::{StagedFiles, StoreError, scratch_beside};

use camloc::store::escaped;

use super::{CliError, numbered_path};

/// Standard output through a buffer. A reader that has gone away is not an error: a closed
/// pipe (`camloc ... | head`), or a terminal that hung up (a run left behind by a closed
/// session); it marks the output closed, later text is dropped and the run goes on to write
/// its files. Any other failure is [`CliError::Stdout`].
pub struct Out {
    inner: BufWriter<Box<dyn Write>>,
    closed: bool,
    /// Whether standard output is a terminal (whose hang-up is an I/O error).
    terminal: bool,
}

impl Out {
    /// Buffered output to `inner` (the process's standard output, or a test's buffer), a
    /// terminal or not.
    pub fn new(inner: Box<dyn Write>, terminal: bool) -> Out {
        Out {
            inner: BufWriter::with_capacity(1 << 16, inner),
            closed: false,
            terminal,
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

    /// Whether `e` is a terminal's hang-up (`EIO` on a terminal).
    fn hung_up(&self, e: &io::Error) -> bool {
        #[cfg(unix)]
        let hang_up = e.raw_os_error() == Some(libc::EIO);
        #[cfg(not(unix))]
        let hang_up = false;
        self.terminal && hang_up
    }

    /// `true` once the reader of standard output has gone away.
    pub fn closed(&self) -> bool {
        self.closed
    }

    fn check(&mut self, result: io::Result<()>) -> Result<(), CliError> {
        match result {
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe || self.hung_up(&e) => {
                self.closed = true;
                Ok(())
            }
            other => other.map_err(CliError::Stdout),
        }
    }
}

/// A file of one row per pose read, in input order, written as the poses are done and staged
/// at the end of the run: `--npy` ([`NpyStage`]), `localize --npz`.
pub trait RowFile<P> {
    /// Appends the row of the pose `record`: `row`, or the file's mark of a failed pose for
    /// `None`.
    ///
    /// # Errors
    /// A failed write of the file's scratch data.
    fn push(&mut self, record: &KeypointRecord, row: Option<&P>) -> Result<(), CliError>;

    /// Writes the whole file into `staged` as the content of its target.
    ///
    /// # Errors
    /// A failed read of the scratch data or write of the staged file.
    fn finish(self: Box<Self>, staged: &mut StagedFiles) -> Result<(), CliError>;
}

/// An operating-system error on `path`.
pub fn io_error(path: &Path) -> impl Fn(io::Error) -> CliError + '_ {
    move |source| {
        StoreError::Io {
            path: path.to_path_buf(),
            source,
        }
        .into()
    }
}

/// A `.npy` array of poses written as they come, whose length is known only at the end: the
/// numbers go to an anonymous scratch file, and [`RowFile::finish`] writes the array (header
/// with N, then the body) into a [`StagedFiles`] file.
pub struct NpyStage<P: NpyPose> {
    target: PathBuf,
    writer: BufWriter<File>,
    count: u64,
    _pose: std::marker::PhantomData<fn(&P)>,
}

impl<P: NpyPose> NpyStage<P> {
    /// Starts an array for `target`.
    ///
    /// # Errors
    /// When the scratch file cannot be made beside `target`.
    pub fn new(target: &Path) -> Result<NpyStage<P>, CliError> {
        let writer = BufWriter::new(scratch_beside(target)?);
        Ok(NpyStage {
            target: target.to_path_buf(),
            writer,
            count: 0,
            _pose: std::marker::PhantomData,
        })
    }

    /// [`NpyStage::new`] as the row file of a run, or `None` without `target`.
    ///
    /// # Errors
    /// As [`NpyStage::new`].
    pub fn boxed(target: Option<&Path>) -> Result<Option<Box<dyn RowFile<P>>>, CliError>
    where
        P: 'static,
    {
        Ok(match target {
            Some(target) => Some(Box::new(NpyStage::<P>::new(target)?)),
            None => None,
        })
    }
}

impl<P: NpyPose> RowFile<P> for NpyStage<P> {
    /// Appends one pose, or a row of NaN for `None`.
    fn push(&mut self, _record: &KeypointRecord, pose: Option<&P>) -> Result<(), CliError> {
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
    fn finish(self: Box<Self>, staged: &mut StagedFiles) -> Result<(), CliError> {
        let this = *self;
        let io = io_error(&this.target);
        let mut body = this.writer.into_inner().map_err(|e| io(e.into_error()))?;
        body.rewind().map_err(&io)?;
        let mut body = BufReader::new(body);
        let count = this.count;
        staged.add_with(&this.target, |file| {
            let mut out = NpyPoseWriter::<_, Row<P>>::new(file, count)?;
            let mut row = Row::<P>::new();
            for _ in 0..count {
                body.read_exact(&mut row.bytes)?;
                out.push(&row)?;
            }
            out.finish()
        })?;
        Ok(())
    }
}

/// One pose as the little-endian bytes [`NpyStage`] wrote.
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

/// Says on standard error which person each numbered file of `out` is, when there are
/// several `persons` (their names, `person 7`, in order): the files are numbered in the
/// persons' order, and a file's number is not the person's id (track ids 1, 2 and 7 write
/// `-001` to `-003`).
pub fn name_numbered_persons(out: &Path, persons: &[String]) {
    if persons.len() < 2 {
        return;
    }
    let name = |n: usize| {
        let path = numbered_path(out, n, persons.len());
        path.file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned())
    };
    let mut pairs: Vec<String> = persons
        .iter()
        .take(10)
        .enumerate()
        .map(|(n, person)| format!("{} is {}", escaped(&name(n)), escaped(person)))
        .collect();
    if persons.len() > pairs.len() {
        pairs.push(format!(
            "{} more in the persons' order",
            persons.len() - pairs.len()
        ));
    }
    stderr_line!("camloc: {}", pairs.join(", "));
}
