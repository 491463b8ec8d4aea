//! The `camloc` command-line tool. See `camloc --help`.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

/// Writes a line to standard error as `eprintln!` does, but a failed write (a closed
/// terminal, a pipe whose reader is gone, `/dev/full`) is ignored instead of a panic: messages
/// are lost then, never the run or its output files.
macro_rules! stderr_line {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod cli;
mod html;
mod interrupt;
mod svg;

fn main() -> ExitCode {
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        Err(e) => return parse_failure(&e),
    };
    interrupt::install();
    let stdout = match standard_output() {
        Ok(stdout) => stdout,
        Err(e) => {
            stderr_line!("camloc: error: {}", cli::CliError::Stdout(e));
            return ExitCode::from(cli::EXIT_ERROR);
        }
    };
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stdout());
    let mut out = cli::Out::new(stdout, terminal);
    match cli::run(args, &mut out) {
        Ok(code) => code,
        Err(e) => {
            // Whatever was written before the error still goes out (a failure here adds
            // nothing to report).
            let _ = out.flush();
            stderr_line!("camloc: error: {e}");
            ExitCode::from(match e {
                cli::CliError::Usage(_) => cli::EXIT_USAGE,
                _ => cli::EXIT_ERROR,
            })
        }
    }
}

/// Prints clap's answer to arguments it did not run (`--help`, `--version`, a usage error)
/// and gives its exit code, unless the help or version could not be written to standard
/// output (`camloc --help >/dev/full`): clap's own `exit` ignores that and exits 0. A reader
/// that went away (`camloc --help | head`) is not an error, as for the commands' output.
fn parse_failure(e: &clap::Error) -> ExitCode {
    let printed = e.print().and_then(|()| std::io::stdout().flush());
    match printed {
        Err(write) if !e.use_stderr() && write.kind() != std::io::ErrorKind::BrokenPipe => {
            stderr_line!("camloc: error: {}", cli::CliError::Stdout(write));
            ExitCode::from(cli::EXIT_ERROR)
        }
        _ => ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(cli::EXIT_USAGE)),
    }
}

/// Standard output, or an error when it was closed when camloc started (`camloc ... >&-`).
///
/// Rust's runtime opens `/dev/null` in place of a standard descriptor that is closed at
/// startup, so that writes would seem to succeed. A `/dev/null` given on purpose looks the
/// same afterwards (Python's `subprocess.DEVNULL` opens it for reading and writing too), so
/// the descriptor is looked at before the runtime starts ([`closed_at_start`], Linux).
#[cfg(unix)]
fn standard_output() -> std::io::Result<Box<dyn Write>> {
    use std::os::fd::AsFd;
    #[cfg(target_os = "linux")]
    if closed_at_start::standard_output() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::BrokenPipe,
            "it was closed when camloc started",
        ));
    }
    let file = std::fs::File::from(std::io::stdout().as_fd().try_clone_to_owned()?);
    Ok(Box::new(file))
}

/// Whether standard output was closed when the process started, seen by a function the
/// loader runs before Rust's runtime opens `/dev/null` in its place (`.init_array`).
#[cfg(target_os = "linux")]
mod closed_at_start {
    use std::sync::atomic::{AtomicBool, Ordering};

    /// Set by [`probe`] when descriptor 1 was closed.
    static CLOSED: AtomicBool = AtomicBool::new(false);

    /// Records whether descriptor 1 is open (the loader calls it before `main`).
    extern "C" fn probe() {
        // SAFETY: F_GETFD only reads the descriptor's flags; it fails (EBADF) on a closed one.
        let closed = unsafe { libc::fcntl(1, libc::F_GETFD) } == -1;
        CLOSED.store(closed, Ordering::Relaxed);
    }

    /// The loader's list of functions to run at startup holds [`probe`].
    #[used]
    #[unsafe(link_section = ".init_array")]
    static PROBE: extern "C" fn() = probe;

    /// Whether standard output was closed when camloc started.
    pub fn standard_output() -> bool {
        CLOSED.load(Ordering::Relaxed)
    }
}

/// Standard output (see the Unix version).
#[cfg(not(unix))]
fn standard_output() -> std::io::Result<Box<dyn Write>> {
    Ok(Box::new(std::io::stdout().lock()))
}
