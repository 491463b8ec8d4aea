//! The `camloc` command-line tool. See `camloc --help`.

use std::process::ExitCode;

use clap::Parser;

mod cli;
mod svg;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    let mut out = cli::Out::new(Box::new(std::io::stdout().lock()));
    match cli::run(args, &mut out) {
        Ok(code) => code,
        Err(e) => {
            // Whatever was written before the error still goes out (a failure here adds
            // nothing to report).
            let _ = out.flush();
            eprintln!("camloc: error: {e}");
            ExitCode::from(cli::EXIT_ERROR)
        }
    }
}
