//! The problems `compare-sklearn` fits: synthetic Gaussian classes, the descriptors of a
//! dataset file, or those of the default model's training set, standardised once.

use std::path::{Path, PathBuf};

use camloc::Descriptor;
use camloc::dataset::{Dataset, Sample};
use camloc::learning::{Features, Standardiser};
use camloc::store::Persist;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::mocap_data::{categorise, load_sequences};
use crate::recipe::{DEFAULT_MIN_POSE_DISTANCE_MM, Recipe};

/// Standard deviation of each coordinate of a synthetic class mean, in units of the
/// within-class standard deviation: small enough that the classes overlap (about 80%
/// training accuracy), so that Newton's method needs several iterations.
const CLASS_SEPARATION: f64 = 0.3;

/// A classification problem with standardised features.
pub struct Problem {
    /// Row-major `n x n_features` features, every column standardised.
    pub x: Vec<f64>,
    /// Labels in `0..n_classes`.
    pub y: Vec<usize>,
    /// Features per sample.
    pub n_features: usize,
    /// Classes.
    pub n_classes: usize,
    /// Where the data come from, for the output.
    pub description: String,
}

/// `n` samples of `d` features in `k` overlapping Gaussian classes, deterministic for a
/// seed: class means drawn from `N(0, CLASS_SEPARATION^2 I)`, samples `mean + N(0, I)`,
/// balanced labels `i mod k`.
pub fn synthetic(n: usize, d: usize, k: usize, seed: u64) -> Result<Problem, String> {
    if d == 0 || k < 2 || n < k {
        return Err(format!(
            "synthetic problem needs d >= 1, k >= 2 and n >= k (every class present), got \
             n = {n}, d = {d}, k = {k}"
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gaussian = move || -> f64 { StandardNormal.sample(&mut rng) };
    let means: Vec<f64> = (0..k * d).map(|_| CLASS_SEPARATION * gaussian()).collect();
    let y: Vec<usize> = (0..n).map(|i| i % k).collect();
    let x = y
        .iter()
        .flat_map(|&label| &means[label * d..(label + 1) * d])
        .map(|mean| mean + gaussian())
        .collect();
    Ok(Problem {
        x,
        y,
        n_features: d,
        n_classes: k,
        description: format!(
            "synthetic Gaussian classes, n = {n}, d = {d}, K = {k}, class-mean spread \
             {CLASS_SEPARATION}, seed {seed}"
        ),
    })
}

/// The landmark descriptors and 0-based camera labels of the complete poses (no dropped
/// landmark) of the dataset file at `path`.
pub fn from_dataset(path: &Path) -> Result<Problem, String> {
    // Store errors (validation included) name the file.
    let dataset = Dataset::load(path).map_err(|e| e.to_string())?;
    complete_poses(&dataset, Descriptor::Landmarks, &path.display().to_string())
}

/// The descriptors of the default model and the 0-based camera labels of the complete poses
/// of its training set: the dataset that `cargo xtask train-default` generates (with its
/// recipe, [`Recipe::classifier_views`]) from the motion capture under `mocap` (default:
/// the CMU data beside the workspace). The classifier itself is fitted on these samples with
/// their mirror images and dropout copies added (four times as many rows).
pub fn default_training_set(mocap: &[PathBuf]) -> Result<Problem, String> {
    let (mut sequences, _, _) = load_sequences(mocap)?;
    categorise(&mut sequences, mocap, None)?;
    let recipe = Recipe::default_model();
    let dataset = recipe.classifier_views(&sequences, DEFAULT_MIN_POSE_DISTANCE_MM)?;
    complete_poses(
        &dataset,
        recipe.options.descriptor,
        "the default model's training set (cargo xtask train-default)",
    )
}

/// The `descriptor`s and 0-based camera labels of the complete poses (no dropped landmark)
/// of `dataset`, read from `source` (named in errors and in the description).
fn complete_poses(
    dataset: &Dataset,
    descriptor: Descriptor,
    source: &str,
) -> Result<Problem, String> {
    let complete: Vec<(usize, &Sample)> = dataset
        .samples
        .iter()
        .enumerate()
        .filter(|(_, s)| s.missing_mask == 0)
        .collect();
    let y = complete
        .iter()
        .map(|(i, s)| {
            usize::from(s.label)
                .checked_sub(1)
                .ok_or_else(|| format!("{source}: sample {i} has label 0"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let poses: Vec<_> = complete.iter().map(|(_, s)| s.landmarks).collect();
    let x = descriptor.extract_batch(&poses).map_err(|(i, e)| {
        let sample = complete.get(i).map_or(i, |(original, _)| *original);
        format!("{source}: sample {sample}: {e}")
    })?;
    let n_classes = dataset.header.cameras.len();
    Ok(Problem {
        description: format!(
            "{source}: '{}' descriptors of {} complete poses ({} with dropped landmarks left \
             out), d = {}, K = {n_classes}",
            descriptor.name(),
            y.len(),
            dataset.samples.len() - y.len(),
            descriptor.len()
        ),
        x,
        y,
        n_features: descriptor.len(),
        n_classes,
    })
}

/// Standardises every column of the row-major `x` (`d` columns) in place with camloc's own
/// [`Standardiser`] (column mean 0, population standard deviation 1; a constant column is
/// only centred).
pub fn standardise(x: &mut [f64], d: usize) -> Result<(), String> {
    let standardiser = Standardiser::fit(&Features::new(x, d).map_err(|e| e.to_string())?);
    for row in x.chunks_exact_mut(d) {
        for ((v, m), s) in row
            .iter_mut()
            .zip(standardiser.means())
            .zip(standardiser.scales())
        {
            *v = (*v - m) / s;
        }
    }
    Ok(())
}
