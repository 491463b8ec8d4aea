//! Where the project's real data lives (`../shared/data` beside the workspace, or
//! `$CAMLOC_DATA`), for the tools and tests that read it. Nothing is ever copied from it.

use std::io::Write;
use std::path::PathBuf;

/// The environment variable that overrides the data folder.
pub const DATA_ENV: &str = "CAMLOC_DATA";

/// The data folder (the one holding `cmu/` and `lsp/`): `$CAMLOC_DATA` when set, else
/// `../shared/data` beside the workspace this crate was built in. It may not exist.
pub fn data_folder() -> PathBuf {
    std::env::var_os(DATA_ENV).map_or_else(
        || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
        PathBuf::from,
    )
}

/// `relative` inside the [`data_folder`] when it exists. Otherwise `None`, after writing
/// `SKIPPED: <what>: <path> not found (set CAMLOC_DATA)` straight to standard error: the line
/// bypasses the test harness's output capture, so a test that returns early for lack of data
/// shows it in the test output (and `.ci/run` counts these lines).
pub fn data_path_or_skip(relative: &str, what: &str) -> Option<PathBuf> {
    let path = data_folder().join(relative);
    if path.exists() {
        return Some(path);
    }
    // The leading newline keeps the line whole when the harness has half-written a line of its
    // own (parallel tests).
    let line = format!(
        "\nSKIPPED: {what}: {} not found (set {DATA_ENV})\n",
        path.display()
    );
    // Nothing useful can be done when standard error is closed.
    let _ = std::io::stderr().lock().write_all(line.as_bytes());
    None
}
