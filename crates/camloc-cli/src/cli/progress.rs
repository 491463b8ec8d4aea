//! Progress on standard error (indicatif), shown only when standard error is a terminal and
//! `--quiet` is not given ([`shown`], which the notes on standard error follow too).

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressState, ProgressStyle};

/// `true` when progress, and notes such as the camera heights estimated, may be shown.
pub fn shown(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

/// A bar counting `unit` (e.g. "poses") up to `len` when it is known, a counter otherwise.
pub fn counter(quiet: bool, len: Option<u64>, message: &str, unit: &str) -> ProgressBar {
    if !shown(quiet) {
        return ProgressBar::hidden();
    }
    let (bar, template) = match len {
        Some(len) => (
            ProgressBar::new(len),
            format!(
                "{{msg}} [{{wide_bar}}] {{human_pos}}/{{human_len}} {unit} ({{rate}}, {{eta}} left)"
            ),
        ),
        None => (
            ProgressBar::no_length(),
            format!("{{spinner}} {{msg}}: {{human_pos}} {unit} ({{rate}}, {{elapsed}})"),
        ),
    };
    // The rate as a whole number a second (indicatif's `per_sec` prints four decimals).
    let style = ProgressStyle::with_template(&template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .with_key(
            "rate",
            |state: &ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.0}/s", state.per_sec());
            },
        );
    bar.set_style(style);
    bar.set_message(message.to_owned());
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// A spinner with a message, for work whose length is not known.
pub fn spinner(quiet: bool, message: &str) -> ProgressBar {
    if !shown(quiet) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
        bar.set_style(style);
    }
    bar.set_message(message.to_owned());
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}
