//! The output files of a command, checked before any work to be different files: two outputs
//! written to one file would leave only the last (with `--force`) or fail at the end.

use std::path::{Path, PathBuf};

use camloc::store::quoted_path;

use super::CliError;

/// One output option: its name (`--svg`), its path, and whether it stands for numbered files
/// (`OUT-001.svg`, `OUT-002.svg`, ... beside `OUT.svg` when there are several drawings).
pub struct Output<'a> {
    /// The option, e.g. `--summary-svg`.
    pub option: &'static str,
    /// The path given.
    pub path: &'a Path,
    /// `true` for `--svg`, whose several drawings are numbered.
    pub numbered: bool,
}

/// The outputs among `(path if given, option, numbered)`.
pub fn outputs<'a>(
    given: impl IntoIterator<Item = (Option<&'a Path>, &'static str, bool)>,
) -> Vec<Output<'a>> {
    given
        .into_iter()
        .filter_map(|(path, option, numbered)| {
            path.map(|path| Output {
                option,
                path,
                numbered,
            })
        })
        .collect()
}

/// Refuses ([`CliError::Usage`]) two of `outputs` that name one file: the same path however
/// spelled (`s.svg`, `./s.svg`, `d/../s.svg`), two links (symbolic or hard) to one file, or a
/// path that is one of the numbered names of a `--svg` output.
pub fn check_distinct(outputs: &[Output]) -> Result<(), CliError> {
    for (i, a) in outputs.iter().enumerate() {
        for b in &outputs[..i] {
            if same_file(a, b) || same_file(b, a) {
                return Err(CliError::Usage(format!(
                    "{} and {} name the same file ({}); give each output its own path",
                    b.option,
                    a.option,
                    quoted_path(a.path)
                )));
            }
        }
    }
    Ok(())
}

/// Refuses ([`CliError::Usage`]) an output that names the `--input` file (even with
/// `--force`: the run would replace what it reads), and `-`, which names standard input for
/// `--input` but would be a file named `-` here.
pub fn check_not_input(outputs: &[Output], input: &Path) -> Result<(), CliError> {
    let read = Output {
        option: "--input",
        path: input,
        numbered: false,
    };
    for out in outputs {
        if out.path == Path::new("-") {
            return Err(CliError::Usage(format!(
                "{} -: outputs are files, not standard output; give a path",
                out.option
            )));
        }
        if input != Path::new("-") && input.is_file() && same_file(&read, out) {
            return Err(CliError::Usage(format!(
                "{} names the input file ({}); write the output elsewhere",
                out.option,
                quoted_path(out.path)
            )));
        }
    }
    Ok(())
}

/// `true` when `a` (or, if `b` is numbered, one of `b`'s numbered names) is the file `b` names.
fn same_file(a: &Output, b: &Output) -> bool {
    let (spelled_a, spelled_b) = (spelled(a.path), spelled(b.path));
    if spelled_a == spelled_b {
        return true;
    }
    same_inode(a.path, b.path)
        || b.numbered && spelled_a.parent() == spelled_b.parent() && is_numbered(a.path, b.path)
}

/// `true` when both paths exist and are one file (links followed, hard links included).
#[cfg(unix)]
fn same_inode(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => (x.dev(), x.ino()) == (y.dev(), y.ino()),
        _ => false,
    }
}

/// Hard links are not told apart here.
#[cfg(not(unix))]
fn same_inode(_: &Path, _: &Path) -> bool {
    false
}

/// `path` with its folder made absolute and resolved (links, `.` and `..`) where it exists.
fn spelled(path: &Path) -> PathBuf {
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path.file_name().unwrap_or(path.as_os_str());
    match std::fs::canonicalize(folder) {
        Ok(folder) => folder.join(name),
        Err(_) => path.to_path_buf(),
    }
}

/// `true` when the file name of `path` is a numbered name of `out` (`STEM-NNN.EXT`, as
/// [`numbered_path`](super::numbered_path) makes them).
fn is_numbered(path: &Path, out: &Path) -> bool {
    let (Some(name), Some(stem)) = (
        path.file_name().and_then(|n| n.to_str()),
        out.file_stem().and_then(|s| s.to_str()),
    ) else {
        return false;
    };
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("svg");
    name.strip_prefix(stem)
        .and_then(|rest| rest.strip_prefix('-'))
        .and_then(|rest| rest.strip_suffix(ext))
        .and_then(|rest| rest.strip_suffix('.'))
        .is_some_and(|digits| digits.len() >= 3 && digits.bytes().all(|b| b.is_ascii_digit()))
}
