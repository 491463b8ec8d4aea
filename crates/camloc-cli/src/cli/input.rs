//! The keypoint input of a command: a file, a folder or standard input, read as one stream of
//! records.

use std::path::PathBuf;

use camloc::keypoints::{
    ImageSize, KeypointError, KeypointFormat, KeypointRecord, KeypointStream, ReadOptions,
    has_subfolders, keypoint_files, open_folder_file, open_keypoints, open_keypoints_reader,
};

use super::{CliError, InputArgs};

/// The name standard input has in records and messages.
pub const STDIN_NAME: &str = "standard input";

/// The records of `--input`, one at a time. A file or standard input that cannot be opened is
/// an error of [`Inputs::open`]; in a folder, each file that cannot be read is an `Err` item and
/// the next files are still read. A `.npy` array is read pose by pose; other files are parsed
/// one at a time.
pub struct Inputs {
    name: String,
    /// Records read already and given back ([`Inputs::put_back`]), given before the rest.
    kept: std::vec::IntoIter<Result<KeypointRecord, KeypointError>>,
    current: Option<KeypointStream>,
    files: std::vec::IntoIter<PathBuf>,
    /// The number of poses when known at opening (one file), for progress bars.
    len_hint: Option<u64>,
    format: Option<KeypointFormat>,
    options: ReadOptions,
    /// Whether the input is a folder read without `--recursive` that has sub-folders.
    unread_folders: bool,
    /// Whether the input is a folder (else one file or standard input).
    folder: bool,
    /// Whether the input arrives as it is written (standard input, a named pipe), so that
    /// poses are answered as they come rather than a batch at a time.
    live: bool,
}

impl Inputs {
    /// Opens the input `args` name.
    pub fn open(args: &InputArgs) -> Result<Inputs, CliError> {
        let options = args.options();
        let mut inputs = Inputs {
            name: String::new(),
            kept: Vec::new().into_iter(),
            current: None,
            len_hint: None,
            files: Vec::new().into_iter(),
            format: args.format,
            options,
            unread_folders: false,
            folder: false,
            live: args.is_standard_input()
                || std::fs::metadata(args.path()).is_ok_and(|m| !m.is_file() && !m.is_dir()),
        };
        if args.is_standard_input() {
            inputs.name = STDIN_NAME.to_owned();
            let stream =
                open_keypoints_reader(std::io::stdin(), STDIN_NAME, None, args.format, &options)?;
            inputs.len_hint = stream.size_hint().1.map(|n| n as u64);
            inputs.current = Some(stream);
        } else if args.path().is_dir() {
            inputs.name = args.path().display().to_string();
            inputs.folder = true;
            inputs.files = keypoint_files(args.path(), args.recursive)?.into_iter();
            inputs.unread_folders = !args.recursive && has_subfolders(args.path());
        } else {
            inputs.name = args.path().display().to_string();
            let stream = open_keypoints(args.path(), args.format, &options)?;
            inputs.len_hint = stream.size_hint().1.map(|n| n as u64);
            inputs.current = Some(stream);
        }
        Ok(inputs)
    }

    /// Gives `records`, read from this input already, back in front of the rest.
    pub fn put_back(&mut self, records: Vec<Result<KeypointRecord, KeypointError>>) {
        let mut all = records;
        all.extend(std::mem::take(&mut self.kept));
        self.kept = all.into_iter();
    }

    /// [`CliError::NoPoses`] for this input, with a hint when it is a folder whose
    /// sub-folders were not read.
    pub fn no_poses(&self) -> CliError {
        let hint = if self.unread_folders {
            " (its sub-folders are read with --recursive)"
        } else {
            ""
        };
        CliError::NoPoses(self.name.clone(), hint)
    }

    /// [`CliError::NotReadToEnd`] when this input is one file or standard input and
    /// `failed_files` (its read errors, each reported already) is not 0: its output files
    /// would pass for the whole input's (a cut-off file's rows end early, unmarked), so the
    /// run writes none. A folder's other files are still written (docs/cli.md).
    pub fn check_read_to_end(&self, failed_files: u64) -> Result<(), CliError> {
        if failed_files > 0 && !self.folder {
            return Err(CliError::NotReadToEnd(self.name.clone()));
        }
        Ok(())
    }

    /// Whether the input arrives as it is written (standard input, a named pipe).
    pub fn is_live(&self) -> bool {
        self.live
    }

    /// Whether the input is a folder (else one file or standard input).
    pub fn is_folder(&self) -> bool {
        self.folder
    }

    /// How the input is named in messages (`no poses in NAME`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The number of poses when known in advance (one file), for progress bars: the whole
    /// input's, however much of it has been read.
    pub fn len_hint(&self) -> Option<u64> {
        self.len_hint
    }

    /// The minimum score the input is read at (`--min-score`; 0 keeps every joint).
    pub fn min_score(&self) -> f64 {
        self.options.min_score
    }

    /// The image size the input was given (`--image-size`), if any.
    pub fn image_size(&self) -> Option<ImageSize> {
        self.options.image_size
    }
}

impl Inputs {
    /// `item`; when it is an error of the reading options that every other file of a folder
    /// would repeat ([`KeypointError::is_option_error`]: no `--image-size` for normalised
    /// coordinates, a `--layout` the format does not take), the folder's other files are not
    /// read (one message, not one a file).
    fn stop_at_option_error(
        &mut self,
        item: Result<KeypointRecord, KeypointError>,
    ) -> Result<KeypointRecord, KeypointError> {
        if item.as_ref().is_err_and(KeypointError::is_option_error) {
            self.files = Vec::new().into_iter();
            self.current = None;
        }
        item
    }
}

impl Iterator for Inputs {
    type Item = Result<KeypointRecord, KeypointError>;

    fn next(&mut self) -> Option<Self::Item> {
        if let Some(record) = self.kept.next() {
            return Some(record);
        }
        loop {
            if let Some(stream) = &mut self.current {
                if let Some(item) = stream.next() {
                    return Some(self.stop_at_option_error(item));
                }
                self.current = None;
            }
            let path = self.files.next()?;
            match open_folder_file(&path, self.format, &self.options) {
                Ok(stream) => self.current = Some(stream),
                Err(e) => return Some(self.stop_at_option_error(Err(e))),
            }
        }
    }
}
