//! Per-pose cost of localization with the embedded default model: descriptor extraction alone,
//! descriptor + prediction + continuous viewpoint for one pose, and a batch of one million poses (descriptors and
//! predictions in parallel on all cores).
//!
//! `cargo bench -p camloc --bench localize`

use std::hint::black_box;

use camloc::{CameraLocalizer, Descriptor, PartialPose2, Pose2};
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};

/// A plausible standing pose in pixels, varied by `k` so that batches are not one pose.
fn pose(k: usize) -> Pose2 {
    let t = k as f64 * 0.001;
    Pose2::new([
        [320.0, 250.0],
        [338.0, 260.0],
        [339.0 + 5.0 * t.sin(), 337.0],
        [338.0, 411.0],
        [301.0, 260.0],
        [300.0 - 5.0 * t.cos(), 336.0],
        [300.0, 412.0],
        [319.0, 162.0],
        [320.0, 128.0],
        [353.0, 169.0],
        [361.0, 219.0 + 10.0 * t.sin()],
        [365.0, 263.0],
        [286.0, 169.0],
        [279.0, 221.0],
        [275.0 + 10.0 * t.cos(), 264.0],
    ])
}

fn benches(c: &mut Criterion) {
    let localizer = match CameraLocalizer::default_model() {
        Ok(l) => l,
        Err(e) => {
            eprintln!("skipping the localize benches: {e}");
            return;
        }
    };
    let descriptor = *localizer.descriptor();
    let one = pose(7);
    let mut buffer = vec![0.0; descriptor.len()];
    c.bench_function("descriptor per pose (joints)", |b| {
        b.iter(|| descriptor.extract_into(black_box(&one), &mut buffer))
    });
    let paper = Descriptor::from_name("paper").unwrap_or_default();
    let mut paper_buffer = vec![0.0; paper.len()];
    c.bench_function("descriptor per pose (paper)", |b| {
        b.iter(|| paper.extract_into(black_box(&one), &mut paper_buffer))
    });
    if localizer.viewpoint_heads().is_none() {
        eprintln!("the default model has no viewpoint heads: 'localize per pose' omits them");
    }
    c.bench_function(
        "localize per pose (descriptor + prediction + viewpoint)",
        |b| b.iter(|| localizer.localize(black_box(&one))),
    );

    const BATCH: usize = 1_000_000;
    let mut group = c.benchmark_group("batch");
    group.sample_size(10);
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function("1M poses: descriptors + predicted labels", |b| {
        b.iter_batched(
            || {
                (0..BATCH)
                    .map(|k| PartialPose2::from(pose(k)))
                    .collect::<Vec<_>>()
            },
            |poses| localizer.predict_labels(&poses),
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(localize, benches);
criterion_main!(localize);
