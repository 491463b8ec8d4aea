//! Compares the camera modes on CMU motion capture (BVH and ASF/AMC under `<data>/cmu`) or on
//! the synthetic poses of the crate's tests.
//!
//! ```text
//! cargo run --release -p camloc-reconstruct --example compare_modes -- \
//!     [cmu|synthetic] [n_components] [max_basis] [stride] [samples]
//! ```
//!
//! `cmu` (the default): frames (every `stride`-th, default 10, i.e. 12 per second) are
//! canonicalised and split by subject: every fourth subject in sorted order is held out and the
//! basis is fitted on the others. `synthetic`: 4000 training poses and `samples` test poses
//! from the random skeleton of `tests/common` (seeds 1 and 99). At most `samples` test poses
//! (default 1500, evenly spaced) are each seen by a random Table-1 camera under two protocols
//! (docs/conventions.md section 7): `canonical` (the exact Table-1 rotation, orthographic, no
//! noise) and
//! `jittered` (azimuth +-30 deg, elevation +-15 deg, roll +-5 deg, weak perspective, Gaussian
//! noise of 3% of the 2D torso). `classified` and `hybrid` are given the Table-1 rotation of the
//! true class, i.e. they model a classifier that is always right; `oracle` gets the exact
//! rotation.
//!
//! The data folder is `CAMLOC_DATA` or `../shared/data` beside the workspace; without it the
//! `cmu` run prints a message and exits successfully.

#[path = "../tests/common/mod.rs"]
mod common;

use std::collections::BTreeSet;
use std::error::Error;

use camloc_geometry::{
    CameraSet, WeakPerspective, look_at_origin, roll_about_optical_axis, sphere_point,
};
use camloc_mocap::{canonicalise, discover};
use camloc_reconstruct::{
    BasisConfig, EvalSample, ModeKind, PoseBasis, ReconstructConfig, Reconstructor, evaluate,
};
use camloc_skeleton::{Pose2, Pose3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

fn arg(index: usize, default: usize) -> Result<usize, Box<dyn Error>> {
    match std::env::args().nth(index) {
        Some(s) => Ok(s
            .parse()
            .map_err(|e| format!("argument {index} ({s}): {e}"))?),
        None => Ok(default),
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let source = std::env::args().nth(1).unwrap_or_else(|| "cmu".into());
    let n_components = arg(2, BasisConfig::default().n_components)?;
    let max_basis = arg(3, ReconstructConfig::default().max_basis)?;
    let stride = arg(4, 10)?.max(1);
    let max_samples = arg(5, 1500)?.max(1);
    let (train, test) = match source.as_str() {
        "cmu" => match cmu(stride)? {
            Some(split) => split,
            None => return Ok(()),
        },
        "synthetic" => (
            common::training_set(4000, 1),
            common::training_set(max_samples, 99),
        ),
        other => return Err(format!("unknown pose source {other:?}: use cmu or synthetic").into()),
    };
    let step = test.len().div_ceil(max_samples).max(1);
    let test: Vec<Pose3> = test.into_iter().step_by(step).collect();
    println!("{} training poses, {} test poses", train.len(), test.len());
    let basis = PoseBasis::fit(
        &train,
        &BasisConfig {
            n_components,
            ..BasisConfig::default()
        },
    )?;
    println!(
        "basis: {} components, {:.2}% of the variance; max_basis {max_basis}",
        basis.n_components(),
        100.0 * basis.explained_variance_ratio()
    );
    let reconstructor = Reconstructor::new(
        basis,
        ReconstructConfig {
            max_basis,
            ..ReconstructConfig::default()
        },
    )?;
    for jittered in [false, true] {
        let samples = samples(&test, jittered)?;
        let started = std::time::Instant::now();
        let report = evaluate(&samples, &reconstructor, &ModeKind::ALL);
        println!(
            "\nprotocol {} ({:.1} s)\n{report}",
            if jittered { "jittered" } else { "canonical" },
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

/// Training and held-out poses.
type Split = (Vec<Pose3>, Vec<Pose3>);

/// Canonical CMU poses split by subject into (training, held-out); `None` without the data.
fn cmu(stride: usize) -> Result<Option<Split>, Box<dyn Error>> {
    let Some(dir) = camloc_skeleton::data::data_path_or_skip("cmu", "compare_modes cmu") else {
        return Ok(None);
    };
    let sources = discover(&dir)?;
    let subjects: BTreeSet<String> = sources.iter().map(|s| s.subject()).collect();
    let held_out: BTreeSet<&String> = subjects.iter().step_by(4).collect();
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for source in &sources {
        let clip = source.read()?;
        let poses = clip
            .frames
            .iter()
            .step_by(stride)
            .filter_map(|p| canonicalise(p).ok());
        if held_out.contains(&clip.subject) {
            test.extend(poses);
        } else {
            train.extend(poses);
        }
    }
    println!(
        "{} motions, {} subjects ({} held out)",
        sources.len(),
        subjects.len(),
        held_out.len()
    );
    Ok(Some((train, test)))
}

/// One evaluation sample per pose, seen by a random Table-1 class camera (seed 17).
fn samples(poses: &[Pose3], jittered: bool) -> Result<Vec<EvalSample>, Box<dyn Error>> {
    let table = CameraSet::table1();
    let classes = table.viewpoints();
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut out = Vec::with_capacity(poses.len());
    for truth in poses {
        let class = &classes[rng.random_range(0..classes.len())];
        let rotation = if jittered {
            let az = class.azimuth_deg + rng.random_range(-30.0..30.0);
            let el = class.elevation_deg + rng.random_range(-15.0..15.0);
            let roll = rng.random_range(-5.0f64..5.0).to_radians();
            roll_about_optical_axis(&look_at_origin(sphere_point(az, el, 1.0))?, roll)
        } else {
            class.rotation
        };
        let camera = WeakPerspective {
            scale: 400.0,
            rotation,
            translation: [320.0, 240.0],
        };
        let mut points = camera.project(&truth.points);
        if jittered {
            let noise = Normal::new(0.0, 0.03 * Pose2::new(points).torso_length())?;
            for p in points.iter_mut() {
                p[0] += noise.sample(&mut rng);
                p[1] += noise.sample(&mut rng);
            }
        }
        out.push(EvalSample {
            pose2: Pose2::new(points),
            truth: *truth,
            true_rotation: rotation,
            classified_rotation: Some(class.rotation),
        });
    }
    Ok(out)
}
