//! The output files of a command, checked before any work to be different files: two outputs
//! written to one file would leave only the last (with `--force`) or fail at the end.

use std::path::{Path, PathBuf};

use camloc::CamlocError;
use camloc::store::{StoreError, check_target, quoted_path};

use super::CliError;

/// One output option: its name (`--svg`), the path of its file, and whether it stands for
/// numbered files instead when there are several (`OUT-001.svg`, `OUT-002.svg`, ...).
pub struct Output<'a> {
    /// The option, e.g. `--summary-svg`.
    pub option: &'static str,
    /// The file written when there is one (for `--bvh`, the path given with `.bvh` added
    /// when it has no extension).
    pub path: &'a Path,
    /// For outputs numbered when there are several files (`--svg`, `--bvh`,
    /// `--bone-lengths-out`), the extension their numbered names take when `path` has none
    /// (as [`numbered_path`](super::numbered_path) and the writers name them).
    pub numbered: Option<&'static str>,
}

/// Checks a command's outputs before any work: the outputs among `given` (`(path if given,
/// option, numbered)`, `numbered` as [`Output::numbered`]) are distinct files
/// (`check_distinct`), none is a file the run reads or `-` (`check_not_input`, with
/// `inputs` the reading options, "the input" for the keypoints given as `--input` or as the
/// argument, and their paths, if given), every one's folder exists
/// (`check_folders`), none is named like a file of another format (`check_format`), and
/// nothing is in the way of their files (`check_existing`).
pub fn check<'a>(
    given: impl IntoIterator<Item = (Option<&'a Path>, &'static str, Option<&'static str>)>,
    inputs: &[(&'static str, Option<&Path>)],
    force: bool,
) -> Result<(), CliError> {
    let outputs: Vec<Output> = given
        .into_iter()
        .filter_map(|(path, option, numbered)| {
            path.map(|path| Output {
                option,
                path,
                numbered,
            })
        })
        .collect();
    check_distinct(&outputs)?;
    check_not_input(&outputs, inputs)?;
    check_folders(&outputs)?;
    for out in &outputs {
        if let Some((what, own)) = format_of(out.option) {
            check_format(out.path, out.option, what, own)?;
        }
    }
    check_existing(&outputs, force)
}

/// Refuses, before any work, what is in the way of the outputs' files (their
/// [`numbered_targets`] for numbered outputs; they are checked again when the files are moved
/// into place): a folder, device or (without `force`) symbolic link as [`check_target`] says
/// it; existing files without `force` all named at once ([`CliError::SeveralExist`]; one as
/// [`check_target`] names it, or [`CliError::NumberedExists`] a numbered file). A
/// simulated animator removed the one file named, ran again and met the next; a reviewer
/// found one existing file refused only after the model was loaded and the input read.
fn check_existing(outputs: &[Output], force: bool) -> Result<(), CliError> {
    let mut existing: Vec<(PathBuf, &Output)> = Vec::new();
    for out in outputs {
        let targets = match out.numbered {
            Some(ext) => numbered_targets(out.path, ext),
            None => vec![out.path.to_path_buf()],
        };
        for path in targets {
            match check_target(&path, force) {
                Ok(()) => {}
                Err(StoreError::Exists { path }) => existing.push((path, out)),
                Err(e) => return Err(CamlocError::from(e).into()),
            }
        }
    }
    match existing.as_slice() {
        [] => Ok(()),
        [(path, out)] if out.numbered.is_some() && path != out.path => {
            Err(CliError::NumberedExists {
                path: path.clone(),
                out: out.path.to_path_buf(),
            })
        }
        [(path, _)] => Err(CamlocError::from(StoreError::Exists { path: path.clone() }).into()),
        _ => Err(CliError::SeveralExist(
            existing.into_iter().map(|(path, _)| path).collect(),
        )),
    }
}

/// Refuses ([`CliError::Usage`]) an output whose folder does not exist (or is no folder), so
/// that the run does not find it out after its work.
fn check_folders(outputs: &[Output]) -> Result<(), CliError> {
    for out in outputs {
        let Some(folder) = out.path.parent().filter(|p| !p.as_os_str().is_empty()) else {
            continue;
        };
        if !folder.is_dir() {
            let problem = if folder.exists() {
                "is not a folder"
            } else {
                "does not exist; create it first"
            };
            return Err(CliError::Usage(format!(
                "{} {}: the folder {} {problem}",
                out.option,
                quoted_path(out.path),
                quoted_path(folder)
            )));
        }
    }
    Ok(())
}

/// Extensions of file formats a user may take an output for: an output whose path ends in
/// one of them that is not its own is refused.
const KNOWN_EXTENSIONS: [&str; 21] = [
    "svg", "png", "jpg", "jpeg", "gif", "webp", "bmp", "tif", "tiff", "pdf", "eps", "html", "htm",
    "json", "jsonl", "csv", "npy", "npz", "bvh", "txt", "bin",
];

/// What the output `option` writes and the extensions its files may have; `None` for
/// options whose format is not fixed by the option (`--out`).
fn format_of(option: &str) -> Option<(&'static str, &'static [&'static str])> {
    match option {
        "--svg" | "--summary-svg" => Some(("an SVG drawing", &["svg"])),
        "--html" => Some(("an HTML page", &["html", "htm"])),
        "--npz" => Some(("a NumPy .npz archive", &["npz"])),
        "--npy" => Some(("a NumPy .npy array", &["npy"])),
        "--bvh" => Some(("a BVH animation", &["bvh"])),
        "--bone-lengths-out" => Some(("JSON", &["json"])),
        _ => None,
    }
}

/// Refuses ([`CliError::Usage`]) an output `path` of `option`, which writes `what` in files
/// ending in one of `own` (the first the usual one), whose path ends in the extension of
/// another known format (`--svg view.png` would be an SVG file named like a PNG image);
/// other and missing extensions pass.
pub fn check_format(path: &Path, option: &str, what: &str, own: &[&str]) -> Result<(), CliError> {
    let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
        return Ok(());
    };
    let ext = ext.to_ascii_lowercase();
    if KNOWN_EXTENSIONS.contains(&ext.as_str()) && !own.contains(&ext.as_str()) {
        return Err(CliError::Usage(format!(
            "{option} writes {what}, but {} ends in .{ext}; give a name ending in .{}",
            quoted_path(path),
            own.first().copied().unwrap_or_default()
        )));
    }
    Ok(())
}

/// Refuses ([`CliError::Usage`]) two of `outputs` that name one file: the same path however
/// spelled (`s.svg`, `./s.svg`, `d/../s.svg`), two links (symbolic or hard) to one file, or a
/// path that is one of the numbered names of a `--svg` output.
fn check_distinct(outputs: &[Output]) -> Result<(), CliError> {
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

/// Refuses ([`CliError::Usage`]) an output path `-` (`-` is standard input for `--input`,
/// but would be a file named `-` here), and an output that names a file the run reads, even
/// with `--force` (the run would replace what it reads): one of `inputs` (an option and its
/// path, if given), or, for an input folder, a file in it that the folder's reader reads
/// (`.json`, `.csv`, `.npy`), the existing numbered files of a numbered output included.
fn check_not_input(
    outputs: &[Output],
    inputs: &[(&'static str, Option<&Path>)],
) -> Result<(), CliError> {
    for out in outputs {
        if out.path == Path::new("-") {
            return Err(CliError::Usage(format!(
                "{} -: outputs are files, not standard output; give a path",
                out.option
            )));
        }
        for &(option, path) in inputs {
            // Standard input redirected from a file is that file (`/dev/stdin` names it).
            let Some(path) = path.and_then(|p| match p == Path::new("-") {
                true => cfg!(unix).then(|| Path::new("/dev/stdin")),
                false => Some(p),
            }) else {
                continue;
            };
            let read = Output {
                option,
                path,
                numbered: None,
            };
            let clash = if path.is_dir() {
                // A numbered output may replace any of its existing numbered files.
                let targets = match out.numbered {
                    Some(ext) => numbered_targets(out.path, ext),
                    None => vec![out.path.to_path_buf()],
                };
                targets.into_iter().find(|file| reads_in_folder(file, path))
            } else {
                // (Named as the input names it: a numbered output's clash is one of its
                // numbered files, not the name given.)
                (path.is_file() && same_file(&read, out)).then(|| path.to_path_buf())
            };
            if let Some(file) = clash {
                return Err(CliError::Usage(format!(
                    "{} names a file of {option} ({}), which the run reads; write the output \
                     elsewhere",
                    out.option,
                    quoted_path(&file)
                )));
            }
        }
    }
    Ok(())
}

/// `true` when `out` names an existing file in `folder` (or below it) that a folder input
/// reads (`.json`, `.csv` or `.npy`), through any path or link: a hard link elsewhere to
/// one of them included.
fn reads_in_folder(out: &Path, folder: &Path) -> bool {
    let read = out
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| ["json", "csv", "npy"].contains(&e.to_ascii_lowercase().as_str()));
    let (Ok(file), Ok(folder)) = (std::fs::canonicalize(out), std::fs::canonicalize(folder)) else {
        return false;
    };
    if file.starts_with(&folder) {
        return read;
    }
    // The folder's reader picks its files by their own names, whatever `out` is called.
    hard_linked(out)
        && camloc::keypoints::keypoint_files(&folder, true)
            .is_ok_and(|files| files.iter().any(|f| same_inode(out, f)))
}

/// `true` when `a` (or, if `b` is numbered, one of `b`'s numbered names) is the file `b` names.
fn same_file(a: &Output, b: &Output) -> bool {
    let (spelled_a, spelled_b) = (spelled(a.path), spelled(b.path));
    if spelled_a == spelled_b {
        return true;
    }
    same_inode(a.path, b.path)
        || b.numbered.is_some_and(|ext| {
            (spelled_a.parent() == spelled_b.parent() && is_numbered(a.path, b.path, ext))
                // A link (symbolic or hard) to one of `b`'s existing numbered files.
                || (std::fs::metadata(a.path).is_ok()
                    && numbered_targets(b.path, ext)[1..]
                        .iter()
                        .any(|t| same_inode(a.path, t)))
        })
}

/// `true` when `path` is a file with other hard links (unix; elsewhere never).
#[cfg(unix)]
fn hard_linked(path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.nlink() > 1)
}

/// Hard links are not told apart here.
#[cfg(not(unix))]
fn hard_linked(_: &Path) -> bool {
    false
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
    let folder = folder_of(path);
    let name = path.file_name().unwrap_or(path.as_os_str());
    match std::fs::canonicalize(folder) {
        Ok(folder) => folder.join(name),
        Err(_) => path.to_path_buf(),
    }
}

/// The files a numbered output `out` may write, to be checked before any work: `out` itself
/// and every existing file of its folder with one of its numbered names (`OUT-NNN.EXT`, as
/// [`numbered_path`](super::numbered_path) makes them; EXT `out`'s extension, else `ext`).
/// How many files a run writes is known only at its end, so any of them may be replaced.
pub fn numbered_targets(out: &Path, ext: &str) -> Vec<PathBuf> {
    let mut paths = vec![out.to_path_buf()];
    let folder = folder_of(out);
    // An unreadable folder is found when the files are written.
    if let Ok(entries) = std::fs::read_dir(folder) {
        paths.extend(
            entries
                .flatten()
                .map(|entry| folder.join(entry.file_name()))
                .filter(|path| is_numbered(path, out, ext)),
        );
        // In number order, so that a refusal names the first.
        paths[1..].sort();
    }
    paths
}

/// Warns on standard error of the files among `checked` (targets checked before the run,
/// which [`numbered_targets`] lists with every existing numbered file) that the run did not
/// replace (not in `written`) and that still exist: with `--force`, a run of 500 poses leaves
/// an earlier run's `OUT-501` ... `OUT-2000` beside its own, which would pass for one result.
pub fn warn_left_over(checked: &[PathBuf], written: &[PathBuf]) {
    // Mostly none is left (without --force an existing target refuses the run), and the
    // written paths are resolved only then.
    let mut left: Vec<&PathBuf> = checked
        .iter()
        .filter(|path| std::fs::symlink_metadata(path).is_ok())
        .collect();
    if left.is_empty() {
        return;
    }
    let written: std::collections::HashSet<PathBuf> = written.iter().map(|p| spelled(p)).collect();
    left.retain(|path| !written.contains(&spelled(path)));
    left.sort();
    if left.is_empty() {
        return;
    }
    // The first few by name: the files may belong to several outputs, and numbers of
    // different widths do not sort into one range.
    let mut names: Vec<String> = left.iter().take(3).map(|p| quoted_path(p)).collect();
    if left.len() > names.len() {
        names.push(format!("{} more", left.len() - names.len()));
    }
    let list = match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.concat(),
    };
    let (count, was, is, it) = if left.len() == 1 {
        ("1 file".to_string(), "was", "is", "it")
    } else {
        (format!("{} files", left.len()), "were", "are", "them")
    };
    stderr_line!(
        "camloc: warning: {count} named like this run's outputs {was} not written by this run \
         and {is} left from an earlier one ({list}); remove {it}, or write to an empty folder"
    );
}

/// The folder `path` is in (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// `true` when the file name of `path` is a numbered name of `out` (`STEM-NNN.EXT`, as
/// [`numbered_path`](super::numbered_path) makes them; EXT `out`'s extension, else `ext`).
fn is_numbered(path: &Path, out: &Path, ext: &str) -> bool {
    let (Some(name), Some(stem)) = (
        path.file_name().and_then(|n| n.to_str()),
        out.file_stem().and_then(|s| s.to_str()),
    ) else {
        return false;
    };
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or(ext);
    name.strip_prefix(stem)
        .and_then(|rest| rest.strip_prefix('-'))
        .and_then(|rest| rest.strip_suffix(ext))
        .and_then(|rest| rest.strip_suffix('.'))
        .is_some_and(|digits| digits.len() >= 3 && digits.bytes().all(|b| b.is_ascii_digit()))
}
