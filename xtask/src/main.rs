//! `cargo xtask`: camloc's project automation.
//!
//! * `cargo xtask gen-dataset`: project real mocap through a camera sphere into a dataset file.
//! * `cargo xtask train-default`: train the default model embedded in the `camloc` binary.
//! * `cargo xtask report`: measure everything and write docs/RESULTS.md.
//! * `cargo xtask generalise`: accuracy per motion category, leave-one-category-out, sphere.
//! * `cargo xtask reconstruction`: 3D reconstruction per basis, prior and camera mode.
//! * `cargo xtask compare-sklearn`: camloc's Newton solver against scikit-learn on one matrix.
//! * `cargo xtask postures`: seated and low postures and studio cameras (`rig`).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod compare_sklearn;
mod filled_torso;
mod gen_dataset;
mod generalise;
mod height_inputs;
mod lsp_photos;
mod mocap_data;
mod postures;
mod progress;
mod proportions;
mod recipe;
mod reconstruction;
mod report;
mod train_default;
mod view_scores;

/// camloc project automation.
#[derive(Parser)]
#[command(name = "cargo xtask", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate a labelled dataset of 2D projections from motion capture (docs/conventions.md
    /// section 7).
    GenDataset(gen_dataset::Args),
    /// Train the default model embedded in the camloc binary (fixtures/default-model.bin).
    TrainDefault(train_default::Args),
    /// Measure localization (and reconstruction) and write docs/RESULTS.md.
    Report(report::Args),
    /// Measure generalisation: per motion category, leave-one-category-out, sphere protocol,
    /// the continuous viewpoint, linear against quadratic classifiers (issue 11). Prints
    /// markdown tables.
    Generalise(generalise::Args),
    /// Measure 3D reconstruction on held-out subjects: basis size, dictionary, priors,
    /// camera modes (issue 12). Prints markdown tables.
    Reconstruction(reconstruction::Args),
    /// Compare camloc's Newton solver with scikit-learn on the same design matrix.
    CompareSklearn(compare_sklearn::Args),
    /// Measure seated and low postures and studio cameras (the `rig` protocol): training
    /// recipes on held-out subjects, posture clips left out by subject, leave-posture-out
    /// (issue 21). Prints markdown tables.
    Postures(postures::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::GenDataset(args) => gen_dataset::run(&args),
        Command::TrainDefault(args) => train_default::run(&args),
        Command::Report(args) => report::run(&args),
        Command::CompareSklearn(args) => compare_sklearn::run(&args),
        Command::Generalise(args) => generalise::run(&args),
        Command::Reconstruction(args) => reconstruction::run(&args),
        Command::Postures(args) => postures::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The workspace root (the folder above `xtask/`).
pub fn workspace_root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| ".".into(), |p| p.to_path_buf())
}
