//! Model files: round trip, versioning and corruption.

mod support;

use camloc_learning::{
    FORMAT_VERSION, Features, LearningError, LogisticModel, LogisticRegression, Mode,
};

fn fitted(mode: Mode) -> (LogisticModel, Vec<f64>) {
    let (x, y) = support::gaussian_classes(120, 3, 4, 1.0, 5.0, 77);
    let features = Features::new(&x, 3).expect("valid");
    let (model, _) = LogisticRegression::default()
        .with_mode(mode)
        .fit(&features, &y, 4)
        .expect("fit");
    (model, x)
}

fn temp_path(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("camloc-learning-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

#[test]
fn bytes_round_trip_is_identical() {
    for mode in [Mode::Multinomial, Mode::OneVsRest] {
        let (model, x) = fitted(mode);
        let bytes = model.to_bytes().expect("encode");
        let back = LogisticModel::from_bytes(&bytes).expect("decode");
        assert_eq!(back, model);
        assert_eq!(back.to_bytes().expect("encode"), bytes);
        for row in x.chunks_exact(3) {
            assert_eq!(
                back.predict_proba(row).expect("valid"),
                model.predict_proba(row).expect("valid")
            );
        }
    }
}

#[test]
fn file_round_trip_is_identical_and_leaves_no_temporary_file() {
    let (model, x) = fitted(Mode::Multinomial);
    let path = temp_path("model.bin");
    model.save(&path).expect("save");
    model.save(&path).expect("overwrite");
    let back = LogisticModel::load(&path).expect("load");
    assert_eq!(
        std::fs::read(&path).expect("read"),
        model.to_bytes().expect("encode")
    );
    assert_eq!(
        back.predict_proba(&x[..3]).expect("valid"),
        model.predict_proba(&x[..3]).expect("valid")
    );
    let dir = path.parent().expect("has a parent");
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .expect("list")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    std::fs::remove_dir_all(dir).expect("cleanup");
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let path = temp_path("does-not-exist.bin");
    match LogisticModel::load(&path) {
        Err(LearningError::Io { path: p, .. }) => assert_eq!(p, path),
        other => panic!("expected Io, got {other:?}"),
    }
}

#[test]
fn other_version_is_refused() {
    let (model, _) = fitted(Mode::Multinomial);
    let mut bytes = model.to_bytes().expect("encode");
    bytes[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    match LogisticModel::from_bytes(&bytes) {
        Err(LearningError::Version { found, expected }) => {
            assert_eq!((found, expected), (FORMAT_VERSION + 1, FORMAT_VERSION));
        }
        other => panic!("expected Version, got {other:?}"),
    }
}

#[test]
fn every_flipped_byte_is_refused() {
    let (model, _) = fitted(Mode::OneVsRest);
    let bytes = model.to_bytes().expect("encode");
    for i in 0..bytes.len() {
        for mask in [0x01u8, 0x80, 0xff] {
            let mut damaged = bytes.clone();
            damaged[i] ^= mask;
            match LogisticModel::from_bytes(&damaged) {
                Err(LearningError::Version { .. }) => assert!((8..12).contains(&i), "byte {i}"),
                Err(LearningError::Corrupt(_)) => assert!(!(8..12).contains(&i), "byte {i}"),
                other => panic!("byte {i} ^ {mask:#x}: expected an error, got {other:?}"),
            }
        }
    }
}

#[test]
fn every_truncation_and_extension_is_refused() {
    let (model, _) = fitted(Mode::Multinomial);
    let bytes = model.to_bytes().expect("encode");
    for len in 0..bytes.len() {
        assert!(
            matches!(
                LogisticModel::from_bytes(&bytes[..len]),
                Err(LearningError::Corrupt(_))
            ),
            "truncated to {len} bytes"
        );
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(matches!(
        LogisticModel::from_bytes(&longer),
        Err(LearningError::Corrupt(_))
    ));
    assert!(matches!(
        LogisticModel::from_bytes(b"not a model at all, not at all"),
        Err(LearningError::Corrupt(_))
    ));
}
