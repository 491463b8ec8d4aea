//! The batch loop of `localize` and `reconstruct`: read a batch of poses, process it in
//! parallel, write its results (standard output as text, a JSON array or JSON lines; SVG files
//! and the file of one row per pose staged), the three stages on different threads so that
//! reading, processing and writing of consecutive batches overlap. Memory is bounded by a few
//! batches, not the input.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use camloc::keypoints::{KeypointError, KeypointRecord};
use camloc::reconstruct::Intrinsics;
use camloc::store::{StagedFiles, escaped, quoted, quoted_path};
use indicatif::ProgressBar;
use rayon::prelude::*;
use serde::Serialize;

use super::input::Inputs;
use super::output::{Out, RowFile};
use super::outside_image::OutsideImage;
use super::{CliError, EXIT_ERROR, numbered_path};

/// Poses per batch: enough to keep both cores busy, small enough to bound memory.
pub const BATCH: usize = 4096;

/// Poses computed between two advances of the progress bar.
const PROGRESS_STEP: usize = 64;

/// How results are written to standard output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Lines of text per pose.
    Text,
    /// One JSON array, one object per pose (written as the poses are done).
    Json,
    /// One JSON object per line.
    Jsonl,
}

impl Format {
    /// The format `--json` / `--jsonl` ask for (clap keeps them exclusive).
    pub fn from_flags(json: bool, jsonl: bool) -> Format {
        match (json, jsonl) {
            (true, _) => Format::Json,
            (_, true) => Format::Jsonl,
            _ => Format::Text,
        }
    }

    /// `true` for the JSON formats.
    pub fn is_json(self) -> bool {
        self != Format::Text
    }
}

/// The result of one pose, made in parallel: its text (lines for [`Format::Text`], one JSON
/// object without a newline otherwise), its drawing for `--svg`, its row for `--npy` or
/// `--npz`, and what the run keeps of it until the end (for `--bvh` and `--html`).
pub struct Done<P, K> {
    /// What goes to standard output.
    pub text: String,
    /// The SVG drawing, when asked for and possible.
    pub svg: Option<String>,
    /// The row of the [`Files::rows`] file, when asked for.
    pub row: Option<P>,
    /// What [`Files::finish`] gets of this pose, when asked for.
    pub keep: Option<K>,
}

/// A pose that could not be processed: its message, and what the run keeps of it.
pub struct Failed<K> {
    /// Why it failed.
    pub message: String,
    /// What [`Files::finish`] gets of this pose, when asked for (boxed: the error side of a
    /// result stays small).
    pub keep: Option<Box<K>>,
}

impl<K> From<String> for Failed<K> {
    fn from(message: String) -> Self {
        Failed {
            message,
            keep: None,
        }
    }
}

/// Most poses a run keeps until the end for [`Files::finish`] (`--bvh`, `--html`).
pub const KEEP_MAX_POSES: u64 = 100_000;

/// Refuses ([`CliError::TooManyKept`]) a run that `keeps` `poses` for the end's files
/// (`--bvh`, `--html`) when they are more than [`KEEP_MAX_POSES`]: each pose about to be kept,
/// counted with it, and before any work the input's length when known at opening
/// ([`check_kept_input`]).
pub fn check_kept(keeps: bool, poses: u64) -> Result<(), CliError> {
    if keeps && poses > KEEP_MAX_POSES {
        return Err(CliError::TooManyKept(KEEP_MAX_POSES));
    }
    Ok(())
}

/// [`check_kept`] of the whole input when its length is known at opening, so that it is
/// refused now, not when the poses past the limit are reached.
pub fn check_kept_input(keeps: bool, inputs: &Inputs) -> Result<(), CliError> {
    check_kept(keeps, inputs.len_hint().unwrap_or(0))
}

/// Makes files, once every pose is done, from what the run kept of each (in input order):
/// `(path, content)` pairs, written with the run's other files (all or nothing).
pub type Finish<K> = Box<dyn FnOnce(Vec<K>, &mut StagedFiles) -> Result<(), CliError>>;

/// The files a run writes besides standard output.
pub struct Files<P, K> {
    /// `--svg`: one drawing per pose (numbered when there are several).
    pub svg: Option<PathBuf>,
    /// `--npy` or `--npz`: one row per pose read (a pose that failed is marked so in its row),
    /// started before the run.
    pub rows: Option<Box<dyn RowFile<P>>>,
    /// `--summary-svg`: a drawing of the whole run, made by the function once every pose is
    /// done.
    pub summary: Option<(PathBuf, SummaryDrawing)>,
    /// Files made from what the run keeps of every pose (`--bvh`, `--html`): the paths to
    /// check before any work, and the function that makes them at the end.
    pub finish: Option<(Vec<PathBuf>, Finish<K>)>,
    /// `--force`: replace existing files.
    pub force: bool,
}

/// Draws the summary of a run (see [`Files::summary`]).
pub type SummaryDrawing = Box<dyn Fn() -> String>;

/// What a run did.
#[derive(Debug, Default)]
pub struct Summary {
    /// Poses read.
    pub poses: u64,
    /// Poses that could not be processed.
    pub failed_poses: u64,
    /// Files of a folder (or the rest of a stream) that could not be read.
    pub failed_files: u64,
    /// Frames of a sequence without a single landmark ([`nothing_detected`]: the library's
    /// `CamlocError::NothingDetected`): frames the person is missing from, not failures.
    pub undetected: u64,
    /// Poses read without a single landmark, failed or not ([`nothing_detected`]).
    pub empty: u64,
    /// What the poses say of how they were given, for the warnings of [`Summary::exit_code`]
    /// (with the camera's intrinsics when given: [`camloc::InputConventions::aimed`]).
    pub conventions: camloc::InputConventions,
    /// The input's `--min-score` ([`Inputs::min_score`]): when every pose is empty,
    /// [`Summary::exit_code`] asks whether a minimum above 0 is on the scores' scale.
    pub min_score: f64,
    /// The poses with landmarks outside the image of `--image-size`
    /// ([`Inputs::image_size`]), which [`Summary::exit_code`] warns of.
    pub outside_image: OutsideImage,
}

/// Whether `pose` has no landmark at all.
pub fn nothing_detected(pose: &camloc::PartialPose2) -> bool {
    pose.present_mask() == 0
}

impl Summary {
    /// Counts a pose read, and what it says of the input's conventions
    /// ([`camloc::InputConventions`]: `v` up, a rolled camera, placeholders at the image
    /// origin), which [`Summary::exit_code`] warns of.
    pub fn count(&mut self, pose: &camloc::PartialPose2) {
        self.poses += 1;
        self.empty += u64::from(nothing_detected(pose));
        self.conventions.add(pose);
        self.outside_image.add(pose);
    }

    /// Reports failures on standard error (`verb`: "localized", ...) and gives the exit code:
    /// an error when a pose failed, a file could not be read, or no pose had a landmark.
    pub fn exit_code(&self, verb: &str) -> ExitCode {
        let outside = self.outside_image.warning();
        for warning in self.conventions.warnings().chain(outside) {
            stderr_line!("camloc: warning: {warning}");
        }
        // Every pose empty is more often a threshold above the input's scores (30 for scores
        // from 0 to 1) than an input without anyone in it.
        let hint = if self.empty == self.poses && self.min_score > 0.0 {
            "; is --min-score on the scale of the input's scores, or above all of them?"
        } else {
            ""
        };
        if self.undetected > 0 {
            stderr_line!(
                "camloc: {} of {} poses have no landmarks (nothing detected): taken as frames the \
                 person is missing from{hint}",
                self.undetected,
                self.poses
            );
        }
        if self.failed_poses > 0 {
            // (A sequence's empty frames are not failures: their line above has the hint.)
            let hint = if self.undetected == 0 { hint } else { "" };
            stderr_line!(
                "camloc: {} of {} poses could not be {verb}{hint}",
                self.failed_poses,
                self.poses
            );
        }
        if self.failed_files > 0 {
            stderr_line!(
                "camloc: {} input file(s) could not be read",
                self.failed_files
            );
        }
        let nothing = self.undetected > 0 && self.undetected == self.poses;
        if self.failed_poses > 0 || self.failed_files > 0 || nothing {
            ExitCode::from(EXIT_ERROR)
        } else {
            ExitCode::SUCCESS
        }
    }
}

/// An error object of the JSON outputs.
#[derive(Serialize)]
pub struct ErrorJson<'a> {
    /// The pose's id (none for a file that cannot be read).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub id: Option<&'a str>,
    /// The pose's place in the input.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub source: Option<&'a str>,
    /// The pose's video frame, for inputs that have frames (as a pose's object has it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<u64>,
    /// The person's position in its frame, for inputs that have persons.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub person: Option<u64>,
    /// The message.
    pub error: &'a str,
}

/// Writes the results of a run to standard output in its [`Format`]: lines of text, the
/// objects of one JSON array (opened at the first, closed by [`Emitter::end`]) or JSON lines.
pub struct Emitter {
    format: Format,
    written: u64,
}

impl Emitter {
    /// Nothing written yet.
    pub fn new(format: Format) -> Emitter {
        Emitter { format, written: 0 }
    }

    /// Writes one result: lines of text, or one JSON object without a newline.
    pub fn write(&mut self, out: &mut Out, text: &str) -> Result<(), CliError> {
        match self.format {
            Format::Text => out.write(text)?,
            Format::Json => {
                out.write(if self.written == 0 { "[\n" } else { ",\n" })?;
                out.write(text)?;
            }
            Format::Jsonl => {
                out.write(text)?;
                out.write("\n")?;
            }
        }
        self.written += 1;
        Ok(())
    }

    /// Reports an input file that could not be read: counted in `summary`, printed on
    /// standard error (above the progress bar) and, in JSON output, written as an error object.
    /// (A pose its reader refused is a failed pose in its place, which its caller reports:
    /// `KeypointRecord::of_refused_pose`.)
    pub fn file_error(
        &mut self,
        out: &mut Out,
        summary: &mut Summary,
        bar: &ProgressBar,
        error: &KeypointError,
    ) -> Result<(), CliError> {
        summary.failed_files += 1;
        let message = error.to_string();
        report_error(&FILE_ERRORS, bar, || message.clone());
        if self.format.is_json() {
            let object = ErrorJson {
                id: None,
                source: None,
                frame: None,
                person: None,
                error: &message,
            };
            self.write(out, &json_line(&object))?;
        }
        Ok(())
    }

    /// In JSON output, writes the error object of the pose `record` that failed with
    /// `message`.
    pub fn pose_error(
        &mut self,
        out: &mut Out,
        record: &KeypointRecord,
        message: &str,
    ) -> Result<(), CliError> {
        if self.format.is_json() {
            let object = ErrorJson {
                id: Some(&record.id),
                source: Some(&record.source),
                frame: record.frame,
                person: record.person,
                error: message,
            };
            self.write(out, &json_line(&object))?;
        }
        Ok(())
    }

    /// Ends the output (closes the JSON array).
    pub fn end(&self, out: &mut Out) -> Result<(), CliError> {
        if self.format == Format::Json {
            out.write(if self.written == 0 { "[]\n" } else { "\n]\n" })?;
        }
        Ok(())
    }

    /// `read_to_end` (an input's [`check_read_to_end`](super::input::Inputs::check_read_to_end)),
    /// the output ended first when it is an error: standard output stays one valid document (a
    /// JSON array closed after the file's error object) when the input ended early, and the
    /// run then fails. For commands that write their poses only after the whole input is read.
    pub fn end_if_unread(
        &self,
        out: &mut Out,
        read_to_end: Result<(), CliError>,
    ) -> Result<(), CliError> {
        if read_to_end.is_err() {
            self.end(out)?;
        }
        read_to_end
    }
}

/// How many errors of poses, and how many of a folder's files, are written on standard
/// error one by one; the rest are only counted (in the end's summary, and in the JSON outputs'
/// error objects): a detector's dump with 100,000 failed poses would otherwise write 100,000
/// lines. (One input file has at most one error of its own, always written.)
pub const ERRORS_SHOWN: u64 = 20;

/// Messages of one kind ([`POSE_ERRORS`], [`FILE_ERRORS`], [`JUMP_WARNINGS`]) reported so far
/// in this run.
pub struct ErrorCount {
    count: std::sync::atomic::AtomicU64,
    /// The line (after `camloc: `) that says the rest are not listed.
    rest: &'static str,
}

/// The poses that failed so far.
pub static POSE_ERRORS: ErrorCount = ErrorCount {
    count: std::sync::atomic::AtomicU64::new(0),
    rest: "further poses that could not be processed are not listed; their count is at the end",
};

/// The files of a folder that could not be read so far.
pub static FILE_ERRORS: ErrorCount = ErrorCount {
    count: std::sync::atomic::AtomicU64::new(0),
    rest: "further files that could not be processed are not listed; their count is at the end",
};

/// The persons whose poses jump across the image, warned of so far (a crowd of 1,000
/// untracked people had made 1,000 lines).
pub static JUMP_WARNINGS: ErrorCount = ErrorCount {
    count: std::sync::atomic::AtomicU64::new(0),
    rest: "warning: more persons' poses jump across the image: not named one by one",
};

/// Writes `camloc: LINE` on standard error, above the progress bar, for the first
/// [`ERRORS_SHOWN`] messages of `kind` in a run; then one line says that the rest are not
/// listed.
pub fn report_capped(kind: &ErrorCount, bar: &ProgressBar, line: impl FnOnce() -> String) {
    let seen = kind
        .count
        .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    if seen < ERRORS_SHOWN {
        let line = line();
        bar.suspend(|| stderr_line!("camloc: {line}"));
    } else if seen == ERRORS_SHOWN {
        bar.suspend(|| stderr_line!("camloc: {}", kind.rest));
    }
}

/// [`report_capped`] of `camloc: error: LINE`; the rest are only counted.
pub fn report_error(kind: &ErrorCount, bar: &ProgressBar, line: impl FnOnce() -> String) {
    report_capped(kind, bar, || format!("error: {}", line()));
}

/// Reports ([`report_error`]) that pose `id` of `source` failed with `message` (quoted and
/// escaped: ids and names come from the input).
pub fn report_pose_error(bar: &ProgressBar, id: &str, source: &str, message: &str) {
    report_error(&POSE_ERRORS, bar, || {
        let (id, source) = (quoted(id), quoted_path(Path::new(source)));
        format!("{id} ({source}): {}", escaped(message))
    });
}

/// `n` and `noun`, the noun in the plural unless `n` is 1 ("1 frame", "3 frames").
pub fn counted(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Serialises one output object on one line.
pub fn json_line<T: Serialize>(value: &T) -> String {
    // Room for a typical object at once (no regrowth while writing it).
    let mut bytes = Vec::with_capacity(1024);
    // Serialising plain structs of numbers and strings into memory cannot fail, and
    // serde_json writes UTF-8; an empty object is the conservative answer if either ever did.
    match serde_json::to_writer(&mut bytes, value) {
        Ok(()) => String::from_utf8(bytes).unwrap_or_else(|_| "{}".to_owned()),
        Err(_) => "{}".to_owned(),
    }
}

/// Runs `compute` over every pose of `inputs` in batches and writes the results. A pose for
/// which `compute` fails (its `Err` is the message) and a file that cannot be read are reported
/// on standard error (and as `{"error": ..}` objects in JSON) and the run goes on. Files are
/// moved into place only after standard output was written successfully (all or nothing).
/// An input without any pose is [`CliError::NoPoses`].
pub fn run<P, K, F>(
    mut inputs: Inputs,
    out: &mut Out,
    format: Format,
    files: Files<P, K>,
    bar: &ProgressBar,
    aim: Option<Intrinsics>,
    compute: F,
) -> Result<Summary, CliError>
where
    P: Send,
    K: Send,
    F: Fn(&KeypointRecord) -> Result<Done<P, K>, Failed<K>> + Sync,
{
    let svg_out = files.svg.clone();
    // Existing outputs were refused before any work (`targets::check`; checked again when the
    // files are moved in place); the numbered ones are looked at again after the run
    // (`warn_left_over`).
    let mut numbered = Vec::new();
    if let Some(svg) = &files.svg {
        numbered = super::targets::numbered_targets(svg, "svg");
    }
    numbered.extend(
        files
            .finish
            .iter()
            .flat_map(|(paths, _)| paths.iter().cloned()),
    );
    check_kept_input(files.finish.is_some(), &inputs)?;
    let mut kept = Vec::new();
    let mut staged = StagedFiles::new(files.force);
    let mut rows = files.rows;
    let has_files =
        files.svg.is_some() || rows.is_some() || files.summary.is_some() || files.finish.is_some();
    let mut summary = Summary {
        conventions: camloc::InputConventions::aimed(aim),
        min_score: inputs.min_score(),
        outside_image: OutsideImage::new(inputs.image_size(), aim),
        ..Summary::default()
    };
    // The staged drawings: (pose index, staged file).
    let mut drawn: Vec<(usize, usize)> = Vec::new();
    let mut emitter = Emitter::new(format);
    // Three stages overlap: one thread reads the next batch, another processes the one before
    // it (on every core), and this one writes the results of the one before that.
    let (sender, batches) = std::sync::mpsc::sync_channel(1);
    let (done_sender, done_batches) = std::sync::mpsc::sync_channel(1);
    let live = inputs.is_live();
    let reader = &mut inputs;
    let compute = &compute;
    std::thread::scope(|scope| -> Result<(), CliError> {
        if live {
            // A live input's records go one by one to the batcher, which sends what has come
            // (up to a batch) as soon as the previous batch is taken: a pose written by a
            // detector 30 times a second is answered at once, a file piped in still goes in
            // full batches.
            let (record_sender, records) = std::sync::mpsc::sync_channel(BATCH);
            scope.spawn(move || {
                for record in reader.by_ref() {
                    if record_sender.send(record).is_err() {
                        break;
                    }
                }
            });
            scope.spawn(move || {
                while let Ok(first) = records.recv() {
                    let mut batch = Vec::with_capacity(BATCH);
                    batch.push(first);
                    batch.extend(records.try_iter().take(BATCH - 1));
                    if sender.send(batch).is_err() {
                        break;
                    }
                }
            });
        } else {
            scope.spawn(move || {
                loop {
                    let mut batch = Vec::with_capacity(BATCH);
                    batch.extend(reader.by_ref().take(BATCH));
                    // Stop at the end, or when the receiver has stopped (an error, a closed
                    // pipe).
                    if batch.is_empty() || sender.send(batch).is_err() {
                        break;
                    }
                }
            });
        }
        let computing = bar.clone();
        scope.spawn(move || {
            for batch in batches {
                // Progress counts poses as they are computed, PROGRESS_STEP at a time (a
                // batch of slow reconstructions takes seconds).
                let results: Vec<Result<Done<P, K>, Failed<K>>> = batch
                    .par_iter()
                    .enumerate()
                    .map(|(i, item)| {
                        let result = match item {
                            Ok(record) => compute(record),
                            // Reported by the writer; nothing to compute.
                            Err(_) => Err(Failed::from(String::new())),
                        };
                        if i % PROGRESS_STEP == PROGRESS_STEP - 1 {
                            computing.inc(PROGRESS_STEP as u64);
                        }
                        result
                    })
                    .collect();
                computing.inc((batch.len() % PROGRESS_STEP) as u64);
                // Stop when the writer has stopped (an error, a closed pipe).
                if done_sender.send((batch, results)).is_err() {
                    break;
                }
            }
        });
        for (batch, results) in done_batches {
            for (item, result) in batch.iter().zip(results) {
                // A pose the reader refused is a failed pose in its place (its row kept).
                let refused;
                let (record, result) = match item {
                    Ok(record) => (record, result),
                    Err(e) => match KeypointRecord::of_refused_pose(e) {
                        Some((record, message)) => {
                            refused = record;
                            (&refused, Err(Failed::from(message)))
                        }
                        None => {
                            emitter.file_error(out, &mut summary, bar, e)?;
                            continue;
                        }
                    },
                };
                let index = summary.poses;
                summary.count(&record.pose);
                let keep = match &result {
                    Ok(done) => done.keep.is_some(),
                    Err(failed) => failed.keep.is_some(),
                };
                check_kept(keep, kept.len() as u64 + 1)?;
                match result {
                    Ok(done) => {
                        emitter.write(out, &done.text)?;
                        if let (Some(svg), Some(drawing)) = (&files.svg, &done.svg) {
                            let path = numbered_path(svg, index as usize, 2);
                            drawn.push((index as usize, staged.add(&path, drawing.as_bytes())?));
                        }
                        if let Some(rows) = &mut rows {
                            rows.push(record, done.row.as_ref())?;
                        }
                        kept.extend(done.keep);
                    }
                    Err(Failed { message, keep }) => {
                        kept.extend(keep.map(|k| *k));
                        summary.failed_poses += 1;
                        report_pose_error(bar, &record.id, &record.source, &message);
                        emitter.pose_error(out, record, &message)?;
                        if let Some(rows) = &mut rows {
                            rows.push(record, None)?;
                        }
                    }
                }
            }
            // A batch's lines leave now, not with the next batch's.
            out.flush()?;
            if out.closed() && !has_files {
                break;
            }
        }
        Ok(())
    })?;
    bar.finish_and_clear();
    if summary.poses == 0 && summary.failed_files == 0 {
        return Err(inputs.no_poses());
    }
    // Standard output stays one valid document (the array closed after the file's error
    // object) even when the input ended early; then the run fails without writing files.
    let read_to_end = inputs.check_read_to_end(summary.failed_files);
    emitter.end(out)?;
    out.flush()?;
    read_to_end?;
    if let Some(rows) = rows {
        rows.finish(&mut staged)?;
    }
    if let Some((path, draw)) = &files.summary {
        staged.add(path, draw().as_bytes())?;
    }
    if let Some(svg) = &svg_out {
        super::rename_numbered(&mut staged, svg, &drawn, summary.poses as usize);
    }
    if let Some((_, finish)) = files.finish {
        finish(kept, &mut staged)?;
    }
    let written = staged.commit()?;
    super::targets::warn_left_over(&numbered, &written);
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::counted;

    #[test]
    fn counts_take_the_plural_unless_one() {
        assert_eq!(counted(1, "frame"), "1 frame");
        assert_eq!(counted(0, "frame"), "0 frames");
        assert_eq!(counted(60, "pose"), "60 poses");
    }
}
