//! The CMU index text of the shared data describes every clip there (in any folder), and the
//! keyword rules give each a category other than `other`. Skipped (with a visible `SKIPPED`
//! line) when the data folder is absent; `CAMLOC_DATA` overrides its path.

use camloc_dataset::{CategorySource, MocapIndex, MotionCategory};
use camloc_mocap::discover;

#[test]
fn every_clip_of_the_shared_data_has_a_known_category() {
    let test = "camloc-dataset::every_clip_of_the_shared_data_has_a_known_category";
    let Some(cmu) = camloc_skeleton::data::data_path_or_skip("cmu", test) else {
        return;
    };
    let index = MocapIndex::load(&cmu.join("cmu-mocap-index-text.txt")).unwrap();
    assert!(index.trials() > 2000, "{} trials", index.trials());
    let mut seen = std::collections::BTreeSet::new();
    for source in discover(&cmu).unwrap() {
        let clip = source.clip();
        let (category, how) = index.category(&source.subject(), &clip);
        assert_ne!(how, CategorySource::NotFound, "{clip}");
        assert_ne!(category, MotionCategory::Other, "{clip}");
        seen.insert(category);
    }
    // The subjects bring dance, fight, acrobatics, gestures and the seated and low postures
    // beside walking.
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
        MotionCategory::Sit,
        MotionCategory::Squat,
        MotionCategory::Crawl,
    ] {
        assert!(seen.contains(&c), "{c} missing");
    }
}
