//! The `camloc` command-line tool. See `camloc --help`.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

mod cli;
mod html;
mod svg;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    let stdout = match standard_output() {
        Ok(stdout) => stdout,
        Err(e) => {
            eprintln!("camloc: error: {}", cli::CliError::Stdout(e));
            return ExitCode::from(cli::EXIT_ERROR);
        }
    };
    let mut out = cli::Out::new(stdout);
    match cli::run(args, &mut out) {
        Ok(code) => code,
        Err(e) => {
            // Whatever was written before the error still goes out (a failure here adds
            // nothing to report).
            let _ = out.flush();
            eprintln!("camloc: error: {e}");
            ExitCode::from(match e {
                cli::CliError::Usage(_) => cli::EXIT_USAGE,
                _ => cli::EXIT_ERROR,
            })
        }
    }
}

/// Standard output, or an error when it was closed when camloc started (`camloc ... >&-`).
///
/// Rust's runtime opens `/dev/null` (for reading and writing) in place of a standard descriptor
/// that is closed at startup, so that writes would seem to succeed; a user's `>/dev/null` opens
/// it for writing only. Where the operating system shows a descriptor's flags
/// (`/proc/self/fdinfo`, Linux), the first case is told from the second and refused.
#[cfg(unix)]
fn standard_output() -> std::io::Result<Box<dyn Write>> {
    use std::os::fd::AsFd;
    use std::os::unix::fs::MetadataExt;
    let file = std::fs::File::from(std::io::stdout().as_fd().try_clone_to_owned()?);
    let null = std::fs::metadata("/dev/null")?;
    let meta = file.metadata()?;
    let read_write = std::fs::read_to_string("/proc/self/fdinfo/1")
        .ok()
        .and_then(|info| {
            let flags = info.lines().find_map(|l| l.strip_prefix("flags:"))?;
            u32::from_str_radix(flags.trim(), 8).ok()
        })
        .is_some_and(|flags| flags & 3 == 2);
    if read_write && (meta.dev(), meta.ino()) == (null.dev(), null.ino()) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::BrokenPipe,
            "it was closed when camloc started",
        ));
    }
    Ok(Box::new(file))
}

/// Standard output (see the Unix version).
#[cfg(not(unix))]
fn standard_output() -> std::io::Result<Box<dyn Write>> {
    Ok(Box::new(std::io::stdout().lock()))
}
