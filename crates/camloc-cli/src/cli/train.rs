//! `camloc train`.

use std::fmt::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use camloc::dataset::Dataset;
use camloc::features::PaperConfig;
use camloc::learning::{LogisticRegression, Mode};
use camloc::store::{Persist, StagedFiles};
use camloc::{CameraLocalizer, CamlocError, Capacity, Descriptor, LandmarkDropout, TrainOptions};
use clap::ValueEnum;

use super::{CliError, ForceArgs, Out, load_dataset, progress, targets};

/// Warns on standard error of the cameras with fewer training views than the features their
/// viewpoint head reads: such a head is set by its ridge penalty more than by the views, so
/// its continuous directions and uncertainties cannot be trusted.
fn warn_of_thin_heads(localizer: &CameraLocalizer, dataset: &Dataset) {
    let Some(width) = localizer.viewpoint_heads().map(|h| h.n_features()) else {
        return;
    };
    let thin: Vec<String> = dataset
        .samples_per_camera()
        .iter()
        .filter(|c| c.samples < width)
        .map(|c| format!("{:02} ({})", c.label, c.samples))
        .collect();
    if !thin.is_empty() {
        stderr_line!(
            "camloc: warning: fewer training views than the {width} features a viewpoint head \
             reads, for camera(s) {}: their continuous directions and uncertainties are \
             unreliable; train on more views",
            thin.join(", ")
        );
    }
}

/// The datasets at `paths` joined into one ([`Dataset::append`]), and their protocols in
/// words (`"jittered + rig"`).
fn joined_datasets(paths: &[PathBuf]) -> Result<(Dataset, String), CliError> {
    let mut joined: Option<Dataset> = None;
    let mut protocols: Vec<String> = Vec::new();
    for path in paths {
        let dataset = load_dataset(path)?;
        let protocol = dataset.header.protocol.to_string();
        if !protocols.contains(&protocol) {
            protocols.push(protocol);
        }
        match &mut joined {
            None => joined = Some(dataset),
            Some(first) => first
                .append(dataset)
                .map_err(|e| CamlocError::InvalidOption {
                    name: "--dataset",
                    detail: format!("{}: {e}", camloc::store::quoted_path(path)),
                })?,
        }
    }
    let joined = joined.ok_or_else(|| CliError::Usage("--dataset: give at least one".into()))?;
    Ok((joined, protocols.join(" + ")))
}

/// Arguments of `camloc train`.
#[derive(clap::Args)]
pub struct Args {
    /// Training dataset (from `cargo xtask gen-dataset`); repeat it to train on several
    /// together (say `jittered` and `rig` views), all of one camera set. The classifier, the
    /// viewpoint heads and the heads' uncertainty are all fitted on these views (the
    /// uncertainty then holds fewer of new people's errors than of theirs:
    /// docs/conventions.md section 5).
    #[arg(long, value_name = "FILE", required = true)]
    pub dataset: Vec<PathBuf>,
    /// Output model file, e.g. `model.bin` (a name of another format, `m.svg` or `m.json`, is
    /// refused; an existing file is replaced only with --force).
    #[arg(long, value_name = "MODEL")]
    pub out: PathBuf,
    /// Pose descriptor.
    #[arg(long, value_enum, default_value = "joints", value_name = "NAME")]
    pub descriptor: DescriptorArg,
    /// Classifier capacity: `linear` (a linear model of the descriptor, the paper's) or
    /// `quadratic-K` (the descriptor and the products of its K leading whitened principal
    /// components, K from 1 to the descriptor's length and at most 64; more accurate on
    /// unfamiliar motion, fitted by truncated Newton-CG, many times slower to train; its memory
    /// grows with the cameras: quadratic-30 took 1.1 GB for Table 1's 12, 5.3-5.8 GB for 32 on
    /// 29,000-109,000 samples, quadratic-15 1.3 GB for 32).
    #[arg(long, default_value_t = TrainOptions::default().capacity, value_name = "CAPACITY",
          value_parser = str::parse::<Capacity>)]
    pub capacity: Capacity,
    /// Ridge weight lambda of eq. 11 (on the sum of the per-sample losses; scikit-learn's C = 1 /
    /// (2 lambda)).
    ///
    /// A number from 0 to 1e12 [default: 1 for a linear classifier, 100 for a quadratic one].
    #[arg(long, value_name = "L", value_parser = parse_lambda, allow_hyphen_values = true)]
    pub lambda: Option<f64>,
    /// Classifier: multinomial softmax (eq. 8) or one-vs-rest (eq. 9).
    #[arg(long, value_enum, default_value = "multinomial")]
    pub mode: ModeArg,
    /// Copies of the training set with 1-3 random landmarks dropped, so that localization copes
    /// with missing landmarks.
    ///
    /// A number from 0 (disables) to 10; fractions take that share of the samples.
    #[arg(long, default_value_t = 1.0, value_name = "COPIES", value_parser = parse_dropout,
          allow_hyphen_values = true)]
    pub dropout: f64,
    /// Do not add left-right mirrored copies of the samples (mirror augmentation is on by
    /// default: with it, a sample's dropout copy and its mirror image's lose mirror
    /// landmarks, and the model is mirror-symmetric).
    #[arg(long)]
    pub no_mirror: bool,
    /// Do not fit the continuous-viewpoint heads (the model then gives the camera class without an
    /// azimuth, elevation and uncertainty).
    ///
    /// For a dataset that lacks views of some camera, such as one of only `rig` views (nearly all
    /// in the middle ring).
    #[arg(long)]
    pub no_viewpoint: bool,
    #[command(flatten)]
    pub force: ForceArgs,
    /// Do not print the Newton iteration log nor the progress spinner.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Pose descriptors on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum DescriptorArg {
    /// The 12 limb joints in a mid-hip to mid-shoulder frame, robust to how annotations place
    /// the neck and pelvis (the default).
    Joints,
    /// All 15 landmarks in the pelvis-neck frame.
    Landmarks,
    /// The paper's Algorithm 1: Gaussian relative lengths + log-polar shape context.
    Paper,
}

impl DescriptorArg {
    /// The library's descriptor (default settings).
    fn descriptor(self) -> Descriptor {
        match self {
            DescriptorArg::Joints => Descriptor::Joints,
            DescriptorArg::Landmarks => Descriptor::Landmarks,
            DescriptorArg::Paper => Descriptor::Paper(PaperConfig::default()),
        }
    }
}

/// Parses `--lambda`: a number from 0 to 1e12 (the library's check of the setting).
fn parse_lambda(text: &str) -> Result<f64, String> {
    let value = parse_number(text)?;
    LogisticRegression::default()
        .with_lambda(value)
        .validate()
        .map_err(|e| e.to_string())?;
    Ok(value)
}

/// Parses `--dropout`: a number from 0 to [`camloc::MAX_DROPOUT_COPIES`] (the library's check
/// of the setting).
fn parse_dropout(text: &str) -> Result<f64, String> {
    let copies = parse_number(text)?;
    LandmarkDropout {
        copies,
        ..LandmarkDropout::default()
    }
    .validate()
    .map_err(|e| e.to_string())?;
    Ok(copies)
}

/// Parses a decimal number, naming the text when it is none.
fn parse_number(text: &str) -> Result<f64, String> {
    text.trim()
        .parse()
        .map_err(|_| format!("not a number: {text:?}"))
}

/// Classifier modes on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ModeArg {
    /// One multinomial softmax model (eq. 8).
    Multinomial,
    /// One binary problem per class (eq. 9).
    OneVsRest,
}

/// Runs `camloc train`.
pub fn run(args: &Args, out: &mut Out) -> Result<ExitCode, CliError> {
    let descriptor = args.descriptor.descriptor();
    let inputs: Vec<_> = (args.dataset.iter())
        .map(|d| ("--dataset", Some(d.as_path())))
        .collect();
    targets::check(
        [(Some(args.out.as_path()), "--out", None)],
        &inputs,
        args.force.force,
    )?;
    // `--out m.svg` or `m.json` would be a model file named like a drawing or a document.
    targets::check_format(&args.out, "--out", "a camloc model file", &["bin"])?;
    let mut options = TrainOptions {
        descriptor,
        ..TrainOptions::default()
    }
    .with_capacity(args.capacity);
    if let Some(lambda) = args.lambda {
        options.regression.lambda = lambda;
    }
    options.regression = options.regression.with_mode(match args.mode {
        ModeArg::Multinomial => Mode::Multinomial,
        ModeArg::OneVsRest => Mode::OneVsRest,
    });
    options.mirror = !args.no_mirror;
    if args.no_viewpoint {
        options.viewpoint_lambda = None;
    }
    options.dropout = (args.dropout > 0.0).then_some(LandmarkDropout {
        copies: args.dropout,
        ..LandmarkDropout::default()
    });
    options.validate()?;
    let start = Instant::now();
    let (dataset, protocols) = joined_datasets(&args.dataset)?;
    let quiet = args.quiet;
    if !quiet {
        stderr_line!(
            "training on {} samples of {} subjects ({} protocol, {} cameras), descriptor {}, {} classifier, lambda {}",
            dataset.samples.len(),
            dataset.subjects().len(),
            protocols,
            dataset.header.cameras.len(),
            descriptor.name(),
            args.capacity.name(),
            options.regression.lambda
        );
    }
    let bar = progress::spinner(quiet, "training: descriptors and Newton iterations");
    let trained = CameraLocalizer::train(&dataset, &options, |log| {
        bar.set_message(format!(
            "training: Newton iteration {}, objective {:.6e}",
            log.iteration, log.objective
        ));
        if !quiet {
            bar.suspend(|| {
                stderr_line!(
                    "  newton {:>3}: objective {:.6e}  |grad|_inf {:.3e}  step {:.3}  ({})",
                    log.iteration,
                    log.objective,
                    log.gradient_norm,
                    log.step,
                    log.direction_summary()
                )
            });
        }
    });
    bar.finish_and_clear();
    let (localizer, report) = trained?;
    warn_of_thin_heads(&localizer, &dataset);
    // The model is moved into place only after standard output was written.
    let mut staged = StagedFiles::new(args.force.force);
    staged.add(&args.out, &localizer.to_bytes()?)?;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "wrote {} ({} Newton iterations, {}, {:.1} s)",
        camloc::store::escaped(&args.out.display().to_string()),
        report.newton_iterations(),
        if report.converged {
            "converged"
        } else {
            "NOT converged"
        },
        start.elapsed().as_secs_f64()
    );
    out.write(&text)?;
    out.flush()?;
    staged.commit()?;
    Ok(ExitCode::SUCCESS)
}
