//! The PCA basis: fitting, invariants, errors, storage.

mod common;

use camloc_reconstruct::{
    BasisConfig, BasisKind, JointLimits, POSE_DIM, PoseBasis, ReconstructError,
    sum_squared_limb_lengths,
};
use camloc_skeleton::Pose3;
use camloc_store::{Persist, StoreError};
use nalgebra::{DMatrix, DVector};

fn fit(n: usize, seed: u64, k: usize) -> PoseBasis {
    PoseBasis::fit(
        &common::training_set(n, seed),
        &BasisConfig {
            n_components: k,
            kind: BasisKind::Pca,
            ..BasisConfig::default()
        },
    )
    .unwrap()
}

#[test]
fn basis_invariants() {
    let poses = common::training_set(1500, 11);
    let basis = PoseBasis::fit(
        &poses,
        &BasisConfig {
            n_components: 20,
            kind: BasisKind::Pca,
            ..BasisConfig::default()
        },
    )
    .unwrap();
    assert_eq!(basis.n_components(), 20);
    assert_eq!(basis.n_training(), 1500);
    // The target is the average raw sum of squared limb lengths.
    let average = poses.iter().map(sum_squared_limb_lengths).sum::<f64>() / 1500.0;
    assert!((basis.anthropometric_target() - average).abs() < 1e-12 * average);
    // Orthonormal components, variances sorted and positive, ratio in (0, 1].
    let b = basis.components();
    assert_eq!(b.shape(), (POSE_DIM, 20));
    let gram = b.transpose() * b;
    assert!((gram - DMatrix::identity(20, 20)).abs().max() < 1e-10);
    let v = basis.explained_variance();
    assert!(v.windows(2).all(|w| w[0] >= w[1]) && v[19] > 0.0);
    let ratio = basis.explained_variance_ratio();
    assert!(ratio > 0.9 && ratio <= 1.0 + 1e-12, "{ratio}");
    // Pelvis-centred: the mean and every component have a zero pelvis.
    assert!(basis.mean().points[0].iter().all(|c| c.abs() < 1e-15));
    assert!((0..20).all(|j| (0..3).all(|r| b[(r, j)].abs() < 1e-9)));
    // Variance along a component equals the spread of the normalised training poses along it.
    let normalised: Vec<DVector<f64>> = poses
        .iter()
        .map(|p| {
            let s = (basis.anthropometric_target() / sum_squared_limb_lengths(p)).sqrt();
            let pelvis = p.points[0];
            DVector::from_iterator(
                POSE_DIM,
                p.points
                    .iter()
                    .flat_map(|q| (0..3).map(move |k| (q[k] - pelvis[k]) * s)),
            )
        })
        .collect();
    let first = b.column(0);
    let projections: Vec<f64> = normalised
        .iter()
        .map(|x| (x - basis.mean_vector()).dot(&first))
        .collect();
    let var = projections.iter().map(|p| p * p).sum::<f64>() / 1500.0;
    assert!((var - v[0]).abs() < 1e-9 * v[0]);
    // `pose` with zero coefficients is the mean.
    assert_eq!(basis.pose(&[0.0; 20]).unwrap(), basis.mean());
    assert!(matches!(
        basis.pose(&[0.0; 3]),
        Err(ReconstructError::DimensionMismatch { .. })
    ));
}

#[test]
fn translation_of_training_poses_does_not_change_the_basis() {
    let poses = common::training_set(300, 5);
    let shifted: Vec<Pose3> = poses
        .iter()
        .enumerate()
        .map(|(i, p)| Pose3::new(p.points.map(|q| [q[0] + i as f64, q[1] - 2.0, q[2] + 0.5])))
        .collect();
    let config = BasisConfig {
        n_components: 10,
        kind: BasisKind::Pca,
        ..BasisConfig::default()
    };
    let a = PoseBasis::fit(&poses, &config).unwrap();
    let b = PoseBasis::fit(&shifted, &config).unwrap();
    assert!((a.mean_vector() - b.mean_vector()).abs().max() < 1e-9);
    assert!((a.components() - b.components()).abs().max() < 1e-6);
}

#[test]
fn fit_errors_are_typed() {
    let poses = common::training_set(50, 2);
    let config = BasisConfig {
        kind: BasisKind::Pca,
        ..BasisConfig::default()
    };
    assert!(matches!(
        PoseBasis::fit(&[], &config),
        Err(ReconstructError::EmptyTrainingSet)
    ));
    assert!(matches!(
        PoseBasis::fit(
            &poses,
            &BasisConfig {
                n_components: 0,
                kind: BasisKind::Pca,
                ..BasisConfig::default()
            }
        ),
        Err(ReconstructError::InvalidConfig { .. })
    ));
    let mut nan = poses.clone();
    nan[7].points[3][2] = f64::NAN;
    assert!(matches!(
        PoseBasis::fit(&nan, &config),
        Err(ReconstructError::NonFiniteTrainingPose { index: 7 })
    ));
    let mut flat = poses.clone();
    flat[4] = Pose3::new([[1.0, 1.0, 1.0]; 15]);
    assert!(matches!(
        PoseBasis::fit(&flat, &config),
        Err(ReconstructError::DegenerateTrainingPose { index: 4 })
    ));
    // 42 directions at most (the pelvis is fixed), at most n - 1 with n poses.
    assert!(matches!(
        PoseBasis::fit(&poses, &BasisConfig { n_components: 43, kind: BasisKind::Pca, ..BasisConfig::default() }),
        Err(ReconstructError::TooManyComponents { available, .. }) if available <= 42
    ));
    assert!(matches!(
        PoseBasis::fit(
            &poses[..5],
            &BasisConfig {
                n_components: 5,
                kind: BasisKind::Pca,
                ..BasisConfig::default()
            }
        ),
        Err(ReconstructError::TooManyComponents { available: 4, .. })
    ));
}

#[test]
fn bytes_round_trip_is_byte_identical() {
    let basis = fit(400, 3, 15);
    let bytes = basis.to_bytes().unwrap();
    let back = PoseBasis::from_bytes(&bytes).unwrap();
    assert_eq!(back, basis);
    assert_eq!(back.to_bytes().unwrap(), bytes);
}

#[test]
fn file_round_trip_and_overwrite_rules() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let path = dir.join("basis.bin");
    let basis = fit(400, 3, 15);
    basis.save(&path, false).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), basis.to_bytes().unwrap());
    let back = PoseBasis::load(&path).unwrap();
    assert_eq!(back, basis);
    let err = basis.save(&path, false).unwrap_err();
    assert!(matches!(err, StoreError::Exists { .. }));
    assert!(err.to_string().contains("basis.bin"), "{err}");
    let other = fit(400, 4, 10);
    other.save(&path, true).unwrap();
    assert_eq!(PoseBasis::load(&path).unwrap(), other);
    let missing = PoseBasis::load(&dir.join("missing.bin")).unwrap_err();
    assert!(missing.to_string().contains("missing.bin"), "{missing}");
}

#[test]
fn damaged_or_foreign_bytes_are_refused() {
    let bytes = fit(200, 8, 6).to_bytes().unwrap();
    let mut version = bytes.clone();
    version[8] = version[8].wrapping_add(1);
    assert!(matches!(
        PoseBasis::from_bytes(&version),
        Err(StoreError::Version { .. })
    ));
    let mut magic = bytes.clone();
    magic[0] = b'X';
    assert!(matches!(
        PoseBasis::from_bytes(&magic),
        Err(StoreError::WrongKind { .. })
    ));
    let mut flipped = bytes.clone();
    let last = flipped.len() - 1;
    flipped[last] ^= 0x10;
    assert!(matches!(
        PoseBasis::from_bytes(&flipped),
        Err(StoreError::Corrupt { .. })
    ));
    assert!(PoseBasis::from_bytes(&bytes[..bytes.len() / 2]).is_err());
}

/// Same serde layout as `PoseBasis`, to write well-formed files with inconsistent content.
#[derive(serde::Serialize)]
struct RawBasis {
    mean: DVector<f64>,
    components: DMatrix<f64>,
    variances: Vec<f64>,
    total_variance: f64,
    anthropometric_target: f64,
    n_training: usize,
    n_principal: usize,
    limits: JointLimits,
    lengths: RawPrior,
}

/// Same serde layout as `LengthPrior`.
#[derive(serde::Serialize, Clone)]
struct RawPrior {
    mean_log: [f64; 14],
    covariance: [[f64; 14]; 14],
}

/// A valid prior: every limb 0.3 m, log deviation 0.1, no correlation.
fn prior() -> RawPrior {
    let mut covariance = [[0.0; 14]; 14];
    for (i, row) in covariance.iter_mut().enumerate() {
        row[i] = 0.01;
    }
    RawPrior {
        mean_log: [0.3f64.ln(); 14],
        covariance,
    }
}

#[test]
fn inconsistent_content_is_refused() {
    let limits = fit(200, 8, 6).joint_limits().clone();
    let good = RawBasis {
        mean: DVector::zeros(POSE_DIM),
        components: DMatrix::identity(POSE_DIM, 3),
        variances: vec![2.0, 1.0, 0.5],
        total_variance: 3.0,
        anthropometric_target: 2.0,
        n_training: 10,
        n_principal: 2,
        limits,
        lengths: prior(),
    };
    let decode = |raw: &RawBasis| {
        PoseBasis::from_bytes(&camloc_store::encode(camloc_store::POSE_BASIS_KIND, raw).unwrap())
    };
    assert!(decode(&good).is_ok());
    let cases = [
        RawBasis {
            components: DMatrix::identity(POSE_DIM, 2) * 2.0,
            ..clone(&good)
        },
        RawBasis {
            mean: DVector::zeros(10),
            ..clone(&good)
        },
        RawBasis {
            variances: vec![1.0],
            ..clone(&good)
        },
        RawBasis {
            anthropometric_target: -1.0,
            ..clone(&good)
        },
        RawBasis {
            total_variance: f64::NAN,
            ..clone(&good)
        },
        RawBasis {
            n_principal: 0,
            ..clone(&good)
        },
        RawBasis {
            n_principal: 4,
            ..clone(&good)
        },
        RawBasis {
            components: {
                let mut c = DMatrix::identity(POSE_DIM, 3);
                c[(0, 2)] = 0.5;
                c
            },
            ..clone(&good)
        },
        RawBasis {
            lengths: RawPrior {
                mean_log: [f64::NAN; 14],
                ..prior()
            },
            ..clone(&good)
        },
        RawBasis {
            lengths: RawPrior {
                mean_log: [5f64.ln(); 14],
                ..prior()
            },
            ..clone(&good)
        },
        RawBasis {
            lengths: {
                let mut p = prior();
                p.covariance[0][1] = 0.005;
                p
            },
            ..clone(&good)
        },
        RawBasis {
            lengths: {
                let mut p = prior();
                p.covariance[3][3] = -0.01;
                p
            },
            ..clone(&good)
        },
    ];
    for raw in &cases {
        let err = decode(raw).unwrap_err();
        let StoreError::Invalid { source, .. } = &err else {
            panic!("expected Invalid, got {err:?}");
        };
        assert!(
            matches!(
                source.downcast_ref::<ReconstructError>(),
                Some(ReconstructError::InvalidBasis { .. })
            ),
            "{err}"
        );
    }
}

/// The nalgebra layout `(data, rows, columns)` with any shape, to forge hostile matrices.
#[derive(serde::Serialize)]
struct ShapedBasis {
    mean: (Vec<f64>, usize, ()),
    components: (Vec<f64>, usize, usize),
    variances: Vec<f64>,
    total_variance: f64,
    anthropometric_target: f64,
    n_training: usize,
    n_principal: usize,
    limits: JointLimits,
    lengths: RawPrior,
}

#[test]
fn hostile_shapes_are_errors_not_panics() {
    let limits = fit(200, 8, 6).joint_limits().clone();
    let shaped = |mean_rows: usize, rows: usize, cols: usize, data: usize| ShapedBasis {
        mean: (vec![0.0; POSE_DIM], mean_rows, ()),
        components: (vec![0.0; data], rows, cols),
        variances: vec![1.0],
        total_variance: 1.0,
        anthropometric_target: 1.0,
        n_training: 1,
        n_principal: 1,
        limits: limits.clone(),
        lengths: prior(),
    };
    let cases = [
        shaped(POSE_DIM, 1 << 32, 1 << 32, 0), // rows x columns overflows
        shaped(POSE_DIM, usize::MAX, 2, 0),
        shaped(POSE_DIM, POSE_DIM, 1, 44),       // one number short
        shaped(POSE_DIM + 1, POSE_DIM, 1, 45),   // mean declares a row it lacks
        shaped(POSE_DIM, POSE_DIM, 0, 0),        // no component
        shaped(POSE_DIM, 1, POSE_DIM, POSE_DIM), // transposed
    ];
    for (i, raw) in cases.iter().enumerate() {
        let bytes = camloc_store::encode(camloc_store::POSE_BASIS_KIND, raw).unwrap();
        let err = PoseBasis::from_bytes_named(&bytes, "b.bin").unwrap_err();
        assert!(
            matches!(err, StoreError::Corrupt { .. } | StoreError::Invalid { .. }),
            "case {i}: {err:?}"
        );
        assert!(err.to_string().starts_with("b.bin: "), "case {i}: {err}");
    }
}

#[test]
fn dev_zero_and_forged_lengths_fail_fast() {
    let zero = std::path::Path::new("/dev/zero");
    if zero.exists() {
        assert!(matches!(
            PoseBasis::load(zero),
            Err(StoreError::WrongKind { .. })
        ));
    } else {
        eprintln!("SKIPPED /dev/zero part: it does not exist here");
    }
    let mut forged = camloc_store::envelope(camloc_store::POSE_BASIS_KIND, b"");
    forged[12..20].copy_from_slice(&u64::MAX.to_le_bytes());
    assert!(matches!(
        PoseBasis::from_bytes(&forged),
        Err(StoreError::TooLarge { .. })
    ));
}

fn clone(raw: &RawBasis) -> RawBasis {
    RawBasis {
        mean: raw.mean.clone(),
        components: raw.components.clone(),
        variances: raw.variances.clone(),
        total_variance: raw.total_variance,
        anthropometric_target: raw.anthropometric_target,
        n_training: raw.n_training,
        n_principal: raw.n_principal,
        limits: raw.limits.clone(),
        lengths: raw.lengths.clone(),
    }
}

#[test]
fn dictionary_appends_unit_cluster_centres_to_the_principal_components() {
    let poses = common::training_set(400, 5);
    let config = |atoms| BasisConfig {
        n_components: 10,
        kind: BasisKind::Dictionary { atoms },
        ..BasisConfig::default()
    };
    let basis = PoseBasis::fit(&poses, &config(30)).unwrap();
    let pca = fit(400, 5, 10);
    assert_eq!(basis.n_principal(), 10);
    assert_eq!(basis.n_components(), 40);
    assert_eq!(basis.explained_variance().len(), 40);
    // The principal part is the PCA basis; the ratio counts it only.
    let b = basis.components();
    assert!((b.columns(0, 10) - pca.components()).abs().max() < 1e-9);
    assert!((basis.explained_variance_ratio() - pca.explained_variance_ratio()).abs() < 1e-12);
    // Atoms: unit norm, pelvis-free, distinct, with positive variance along them.
    for j in 10..40 {
        assert!((b.column(j).norm() - 1.0).abs() < 1e-9);
        assert!((0..3).all(|r| b[(r, j)].abs() < 1e-9));
        assert!(basis.explained_variance()[j] > 0.0);
        for k in 10..j {
            assert!(
                b.column(j).dot(&b.column(k)) < 1.0 - 1e-6,
                "atoms {j} and {k}"
            );
        }
    }
    // Deterministic, and it survives storage.
    let again = PoseBasis::fit(&poses, &config(30)).unwrap();
    assert_eq!(basis.to_bytes().unwrap(), again.to_bytes().unwrap());
    let back = PoseBasis::from_bytes(&basis.to_bytes().unwrap()).unwrap();
    assert_eq!(back.n_principal(), 10);
    assert_eq!(back.components(), basis.components());
    // More atoms than poses, or none, is a typed error.
    for atoms in [0, 401] {
        assert!(matches!(
            PoseBasis::fit(&poses, &config(atoms)),
            Err(ReconstructError::InvalidConfig { .. })
        ));
    }
}
