//! Per-pose cost of 3D reconstruction with the embedded default basis (and, for the
//! `classified` and `hybrid` modes, the embedded default model; `hybrid + lifter`, the command
//! line's default, also the embedded depth lifter), one pose at a time on one core.
//!
//! `cargo bench -p camloc --bench reconstruct`

mod common;

use std::hint::black_box;

use camloc::{
    CameraLocalizer, DepthLifter, ModeKind, PartialPose2, PoseReconstructor, default_basis,
};
use common::pose;
use criterion::{Criterion, criterion_group, criterion_main};

fn benches(c: &mut Criterion) {
    let (basis, localizer) = match (default_basis(), CameraLocalizer::default_model()) {
        (Ok(b), Ok(l)) => (b, l),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("skipping the reconstruct benches: {e}");
            return;
        }
    };
    let one = PartialPose2::from(pose(7));
    let mut group = c.benchmark_group("reconstruct per pose");
    for mode in [ModeKind::Opt, ModeKind::Classified, ModeKind::Hybrid] {
        let reconstructor = PoseReconstructor::new(basis.clone())
            .map(|r| r.with_localizer(localizer.clone()))
            .and_then(|r| r.with_mode(mode));
        match reconstructor {
            Ok(r) => {
                group.bench_function(mode.name(), |b| b.iter(|| r.reconstruct(black_box(&one))));
            }
            Err(e) => eprintln!("skipping reconstruct {}: {e}", mode.name()),
        }
    }
    let lifted = DepthLifter::default_lifter().and_then(|lifter| {
        Ok(PoseReconstructor::new(basis)?
            .with_localizer(localizer)
            .with_mode(ModeKind::Hybrid)?
            .with_lifter(lifter))
    });
    match lifted {
        Ok(r) => {
            group.bench_function("hybrid + lifter", |b| {
                b.iter(|| r.reconstruct(black_box(&one)))
            });
        }
        Err(e) => eprintln!("skipping reconstruct hybrid + lifter: {e}"),
    }
    group.finish();
}

criterion_group!(reconstruct, benches);
criterion_main!(reconstruct);
