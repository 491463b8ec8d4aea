//! Per-pose cost of localization with the embedded default model: descriptor extraction alone,
//! descriptor + prediction + continuous viewpoint for one pose, and a batch of one million poses (descriptors and
//! predictions in parallel on all cores).
//!
//! `cargo bench -p camloc --bench localize`

use std::hint::black_box;

mod common;

use camloc::{CameraLocalizer, Descriptor, PartialPose2};
use common::pose;
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};

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
