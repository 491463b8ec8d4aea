//! The `camloc` command-line tool. See `camloc --help`.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

mod cli;
mod svg;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    let mut out = String::new();
    let result = cli::run(args, &mut out);
    // A closed pipe (`camloc ... | head`) is a normal end, not an error.
    if let Err(e) = std::io::stdout().lock().write_all(out.as_bytes()) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("camloc: error: cannot write to standard output: {e}");
            return ExitCode::from(cli::EXIT_ERROR);
        }
    }
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("camloc: error: {e}");
            ExitCode::from(cli::EXIT_ERROR)
        }
    }
}
