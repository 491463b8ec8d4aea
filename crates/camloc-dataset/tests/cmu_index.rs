//! The CMU index text of the shared data describes every clip there, and the keyword rules
//! give each a category other than `other`. Skipped (with a message) when the data folder is
//! absent; `CAMLOC_DATA` overrides its path.

use std::path::PathBuf;

use camloc_dataset::{CategorySource, MocapIndex, MotionCategory};

fn cmu_dir() -> Option<PathBuf> {
    let data = std::env::var_os("CAMLOC_DATA").map_or_else(
        || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
        PathBuf::from,
    );
    let cmu = data.join("cmu");
    cmu.is_dir().then_some(cmu)
}

#[test]
fn every_clip_of_the_shared_data_has_a_known_category() {
    let Some(cmu) = cmu_dir() else {
        eprintln!("skipping: ../shared/data not found");
        return;
    };
    let index = MocapIndex::load(&cmu.join("cmu-mocap-index-text.txt")).unwrap();
    assert!(index.trials() > 2000, "{} trials", index.trials());
    let mut seen = std::collections::BTreeSet::new();
    for folder in ["bvh", "asfamc"] {
        for entry in std::fs::read_dir(cmu.join(folder)).unwrap() {
            let path = entry.unwrap().path();
            let ext = path.extension().and_then(|e| e.to_str());
            if !matches!(ext, Some("bvh" | "amc")) {
                continue;
            }
            let clip = path.file_stem().unwrap().to_str().unwrap().to_string();
            let subject = clip.split('_').next().unwrap().to_string();
            let (category, source) = index.category(&subject, &clip);
            assert_ne!(source, CategorySource::NotFound, "{clip}");
            assert_ne!(category, MotionCategory::Other, "{clip}");
            seen.insert(category);
        }
    }
    // The new subjects bring dance, fight, acrobatics and gestures beside walking.
    for c in [
        MotionCategory::Walk,
        MotionCategory::Run,
        MotionCategory::Jump,
        MotionCategory::Dance,
        MotionCategory::Fight,
        MotionCategory::Acrobatics,
        MotionCategory::Gesture,
        MotionCategory::Everyday,
        MotionCategory::Sport,
    ] {
        assert!(seen.contains(&c), "{c} missing");
    }
}
