//! Time to reconstruct one pose per camera mode (goal: < 5 ms per pose in release; `opt` <= 1
//! ms, issue 23), and `opt` without the skeleton refinement (the pursuit alone).
//!
//! Basis: 24 components from 4000 synthetic poses; default configuration (`max_basis` 12, depth
//! reflection on, bone lengths estimated). The true camera is 20 degrees of azimuth and 10 of elevation away from the
//! Table-1 front camera (05) that `classified` and `hybrid` are given.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use camloc_geometry::{WeakPerspective, look_at_origin, sphere_point};
use camloc_reconstruct::{BasisConfig, CameraMode, PoseBasis, ReconstructConfig, Reconstructor};
use camloc_skeleton::Pose2;
use criterion::{Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let basis = PoseBasis::fit(&common::training_set(4000, 1), &BasisConfig::default())
        .expect("synthetic training set fits");
    let reconstructor =
        Reconstructor::new(basis, ReconstructConfig::default()).expect("default config is valid");
    let mut rng = common::rng(2);
    let truth = common::random_pose(&mut rng);
    let rotation = look_at_origin(sphere_point(200.0, 10.0, 1.0)).expect("not a pole");
    let classified = look_at_origin(sphere_point(180.0, 0.0, 1.0)).expect("not a pole");
    let camera = WeakPerspective {
        scale: 300.0,
        rotation,
        translation: [320.0, 240.0],
    };
    let pose2 = Pose2::new(camera.project(&truth.points));
    let modes = [
        CameraMode::Opt,
        CameraMode::Classified(classified),
        CameraMode::Oracle(rotation),
        CameraMode::Hybrid(classified),
    ];
    let mut group = c.benchmark_group("reconstruct");
    for mode in &modes {
        group.bench_function(mode.name(), |b| {
            b.iter(|| reconstructor.reconstruct(black_box(&pose2), black_box(mode)))
        });
    }
    let mut config = ReconstructConfig::default();
    config.refinement.estimate_lengths = false;
    let pursuit =
        Reconstructor::new(reconstructor.basis().clone(), config).expect("default config is valid");
    group.bench_function("opt without the refinement", |b| {
        b.iter(|| pursuit.reconstruct(black_box(&pose2), black_box(&CameraMode::Opt)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
