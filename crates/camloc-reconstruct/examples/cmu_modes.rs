//! Compares the camera modes on CMU motion capture (BVH and ASF/AMC under `<data>/cmu`).
//!
//! ```text
//! cargo run --release -p camloc-reconstruct --example cmu_modes -- [n_components] [max_basis] [stride] [samples]
//! ```
//!
//! Frames (every `stride`-th, default 10, i.e. 12 per second) are canonicalised and split by
//! subject: every fourth subject in sorted order is held out. A basis is fitted on the other
//! subjects; each held-out pose (at most `samples`, default 1500, evenly spaced) is seen by a
//! random Table-1 camera under two protocols (SPEC.md section 7): `canonical` (the exact
//! Table-1 rotation, orthographic, no noise) and `jittered` (azimuth +-30 deg, elevation +-15
//! deg, roll +-5 deg, weak perspective, Gaussian noise of 3% of the 2D torso). `classified` and
//! `hybrid` are given the Table-1 rotation of the true class, i.e. they model a classifier that
//! is always right; `oracle` gets the exact rotation.
//!
//! The data folder is `CAMLOC_DATA` or `../shared/data` beside the workspace; without it the
//! example prints a message and exits successfully.

use std::collections::BTreeSet;
use std::error::Error;
use std::path::PathBuf;

use camloc_geometry::{
    CameraSet, WeakPerspective, look_at_origin, roll_about_optical_axis, sphere_point,
};
use camloc_reconstruct::{
    BasisConfig, EvalSample, ModeKind, PoseBasis, ReconstructConfig, Reconstructor, evaluate,
};
use camloc_skeleton::Pose2;
use camloc_skeleton::Pose3;
use camloc_skeleton::mocap::{canonicalise, discover};
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
    let n_components = arg(1, BasisConfig::default().n_components)?;
    let max_basis = arg(2, ReconstructConfig::default().max_basis)?;
    let stride = arg(3, 10)?.max(1);
    let max_samples = arg(4, 1500)?.max(1);
    let data = std::env::var_os("CAMLOC_DATA").map_or_else(
        || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
        PathBuf::from,
    );
    let cmu = data.join("cmu");
    if !cmu.is_dir() {
        println!("skipping: {} not found (set CAMLOC_DATA)", cmu.display());
        return Ok(());
    }
    let sources = discover(&cmu)?;
    let subjects: Vec<String> = sources
        .iter()
        .map(|s| s.subject())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let held_out: BTreeSet<&String> = subjects.iter().step_by(4).collect();
    let (mut train, mut test): (Vec<Pose3>, Vec<Pose3>) = (Vec::new(), Vec::new());
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
    let step = test.len().div_ceil(max_samples).max(1);
    let test: Vec<Pose3> = test.into_iter().step_by(step).collect();
    println!(
        "{} motions, {} subjects ({} held out); {} training poses, {} test poses",
        sources.len(),
        subjects.len(),
        held_out.len(),
        train.len(),
        test.len()
    );
    let basis = PoseBasis::fit(&train, &BasisConfig { n_components })?;
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
    let table = CameraSet::table1();
    for jittered in [false, true] {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let mut samples = Vec::with_capacity(test.len());
        for truth in &test {
            let class = &table.viewpoints()[rng.random_range(0..table.viewpoints().len())];
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
            samples.push(EvalSample {
                pose2: Pose2::new(points),
                truth: *truth,
                true_rotation: rotation,
                classified_rotation: Some(class.rotation),
            });
        }
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
