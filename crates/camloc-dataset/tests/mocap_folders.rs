//! Reading folders of motion capture: a bad file is skipped with a warning naming it and its
//! line; the good files are still used.

use std::path::{Path, PathBuf};

use camloc_dataset::{GenerateConfig, Protocol, generate, load_mocap_folders};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/mocap")
        .join(name)
}

#[test]
fn one_bad_file_is_skipped_with_a_warning_and_the_others_are_used() {
    let dir = std::env::temp_dir().join(format!("camloc-folders-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("nested")).unwrap();
    std::fs::copy(fixture("98_01.bvh"), dir.join("98_01.bvh")).unwrap();
    std::fs::copy(fixture("99.asf"), dir.join("nested/99.asf")).unwrap();
    std::fs::copy(fixture("99_01.amc"), dir.join("nested/99_01.amc")).unwrap();
    let good = std::fs::read_to_string(fixture("98_01.bvh")).unwrap();
    // Corrupt one number of the motion section.
    let broken = good.replacen("MOTION", "MOTION\nbroken", 1);
    std::fs::write(dir.join("97_02.bvh"), broken).unwrap();
    // An AMC without its ASF.
    std::fs::copy(fixture("99_01.amc"), dir.join("55_01.amc")).unwrap();

    let mut warnings = Vec::new();
    let mut progress_calls = 0;
    let (sequences, summary) = load_mocap_folders(
        std::slice::from_ref(&dir),
        &mut |w| warnings.push(w.to_string()),
        &mut |_, _, _| progress_calls += 1,
    )
    .unwrap();
    assert_eq!(summary.files_read, 2);
    assert_eq!(summary.skipped.len(), 2);
    assert_eq!(warnings, summary.skipped);
    assert_eq!(progress_calls, 4);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("97_02.bvh") && w.contains(':')),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.contains("55.asf")),
        "{warnings:?}"
    );
    let names: Vec<&str> = sequences.iter().map(|s| s.clip.name.as_str()).collect();
    assert_eq!(names, ["98_01", "99_01"]);
    let dataset = generate(
        &sequences,
        &GenerateConfig::new(Protocol::Canonical),
        &|_, _| {},
    )
    .unwrap();
    assert_eq!(dataset.subjects().len(), 2);

    // A folder with nothing readable is an error, not an empty dataset.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    assert!(load_mocap_folders(&[empty], &mut |_| {}, &mut |_, _, _| {}).is_err());
    std::fs::remove_dir_all(&dir).unwrap();
}
