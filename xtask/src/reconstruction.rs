//! `cargo xtask reconstruction`: how 3D reconstruction holds on held-out subjects, walking
//! and diverse motion (issue 12): the pose basis (PCA sizes chosen by cross-validation
//! grouped by subject, and the sparse dictionary), the priors, the depth-flip hypotheses and
//! the camera modes, all on one split. Prints markdown tables; writes nothing.

use std::fmt::Write;
use std::path::PathBuf;
use std::time::Instant;

use camloc::dataset::{GenerateConfig, MotionCategory, PoseSequence, Protocol};
use camloc::reconstruct::{
    BasisConfig, BasisKind, EvalReport, EvalSample, ModeKind, PoseBasis, ReconstructConfig,
    Reconstructor, evaluate, mpjpe_after_scale, mpjpe_after_similarity,
};
use camloc::{
    CameraLocalizer, DepthLifter, PartialPose2, Pose3, PoseReconstructor, evaluation_samples,
};
use rayon::prelude::*;

use crate::generalise::TEST_SUBJECTS;
use crate::mocap_data::{basis_poses, load_split, project};
use crate::recipe::{DEFAULT_MIN_POSE_DISTANCE_MM, Recipe};

/// Arguments of `reconstruction`.
#[derive(clap::Args)]
pub struct Args {
    /// Motion capture folders [default: $CAMLOC_DATA/cmu, else ../shared/data/cmu].
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Held-out subjects (never in the basis, the priors or the localizer).
    #[arg(long, value_delimiter = ',', default_value = TEST_SUBJECTS)]
    pub test_subjects: Vec<String>,
    /// Use every N-th test sample (the jittered views of the held-out subjects; the default
    /// mode by motion category also on their `rig` views).
    #[arg(long, default_value_t = 4, value_name = "N")]
    pub every: usize,
    /// PCA sizes compared by cross-validation grouped by subject on the training subjects.
    #[arg(long, value_delimiter = ',', default_value = "12,16,24,32")]
    pub components: Vec<usize>,
    /// Folds of that cross-validation.
    #[arg(long, default_value_t = 3)]
    pub folds: usize,
    /// Coefficient priors compared (ReconstructConfig::coefficient_prior) by the same
    /// cross-validation, with each PCA size.
    #[arg(long, value_delimiter = ',', default_value = "0,0.001,0.01,0.1")]
    pub priors: Vec<f64>,
    /// Dictionary sizes (cluster centres) compared.
    #[arg(long, value_delimiter = ',', default_value = "256")]
    pub atoms: Vec<usize>,
    /// Only these variants (by their position in the table, from 0); all when empty.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<usize>,
    /// Only the proportions test (issue 23: rescaled held-out people, single frames and
    /// sequences), which otherwise ends the run.
    #[arg(long)]
    pub proportions_only: bool,
    /// The proportions test without `hybrid` (no localizer is trained).
    #[arg(long)]
    pub no_hybrid: bool,
    /// Proportions test: every n-th held-out pose is a single-frame sample.
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub proportions_every: usize,
    /// Proportions test: frames per window of a sequence.
    #[arg(long, default_value_t = 60, value_name = "FRAMES")]
    pub window: usize,
    /// Proportions test: most windows per clip.
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub windows_per_clip: usize,
}

/// Mean MPJPE of `mode` in `report`, formatted, "-" when none.
fn cell(report: &EvalReport, mode: ModeKind) -> String {
    report
        .modes
        .iter()
        .find(|m| m.mode == mode)
        .and_then(|m| m.mean_pa_mpjpe_mm)
        .map_or("-".into(), |v| format!("{v:.1}"))
}

/// What [`measure`] found.
pub struct Measured {
    /// The markdown tables, ending with the issue-12 targets.
    pub markdown: String,
}

/// Runs `reconstruction`: prints [`measure`]'s tables.
pub fn run(args: &Args) -> Result<(), String> {
    print!("{}", measure(args)?.markdown);
    Ok(())
}

/// Measures everything `reconstruction` reports.
pub fn measure(args: &Args) -> Result<Measured, String> {
    let started = Instant::now();
    let mut md = String::new();
    let (train_seqs, test_seqs) = load_split(&args.mocap, &args.test_subjects)?;
    let training = basis_poses(&train_seqs, DEFAULT_MIN_POSE_DISTANCE_MM);
    let poses: Vec<Pose3> = training.iter().map(|(p, _)| *p).collect();
    let groups: Vec<&str> = training.iter().map(|(_, s)| s.as_str()).collect();
    if args.proportions_only {
        let trained = if args.no_hybrid {
            None
        } else {
            Some(train_localizer(&train_seqs)?)
        };
        let basis = PoseBasis::fit(&poses, &BasisConfig::default()).map_err(|e| e.to_string())?;
        let _ = writeln!(
            md,
            "{}",
            proportions_section(
                &basis,
                trained.as_ref().map(|(l, f)| (l, f)),
                &test_seqs,
                args
            )?
        );
        let _ = writeln!(md, "\nTotal {:.0} s.", started.elapsed().as_secs_f64());
        return Ok(Measured { markdown: md });
    }

    // The localizer of the classified and hybrid modes: the default training on the
    // training subjects.
    let (localizer, lifter) = train_localizer(&train_seqs)?;

    let every = args.every.max(1);
    let jittered = categorised_samples(&test_seqs, Protocol::Jittered, every, &localizer)?;
    // The samples of walking clips (`true`) or of the other categories.
    let of_walking = |walk: bool| -> Vec<EvalSample> {
        jittered
            .iter()
            .filter(|(c, _)| (*c == MotionCategory::Walk) == walk)
            .map(|(_, s)| s.clone())
            .collect()
    };
    let (walking, diverse) = (of_walking(true), of_walking(false));
    let _ = writeln!(
        md,
        "Basis and priors: {} canonical poses of the training subjects (selection by pose at \
         {DEFAULT_MIN_POSE_DISTANCE_MM} mm, no augmentation); test: every {every}th jittered \
         view (+-30 deg azimuth, +-15 deg elevation, perspective 3-8 m, 3% noise) of the \
         held-out subjects {}: {} walking and {} diverse (every other category) samples; \
         `classified` and `hybrid` use the default localizer trained on the training \
         subjects. Mean MPJPE after similarity alignment, mm.\n",
        poses.len(),
        args.test_subjects.join(", "),
        walking.len(),
        diverse.len()
    );

    // 1. PCA size and coefficient prior by grouped cross-validation.
    let _ = writeln!(
        md,
        "Cross-validated MPJPE (opt camera, {}-fold by subject on the training subjects, one \
         jittered view per pose), mm:\n\n| PCA components | {} |\n|---|{}",
        args.folds,
        args.priors
            .iter()
            .map(|p| format!("coefficient prior {p}"))
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(args.priors.len())
    );
    let mut best = (f64::INFINITY, 0usize, 0.0);
    for &k in &args.components {
        let mut cells = Vec::new();
        for &prior in &args.priors {
            let e = cross_validated_mpjpe(&poses, &groups, k, prior, args.folds)?;
            cells.push(format!("{e:.1}"));
            if e < best.0 {
                best = (e, k, prior);
            }
        }
        let _ = writeln!(md, "| {k} | {} |", cells.join(" | "));
    }
    let (_, chosen, chosen_prior) = best;
    let _ = writeln!(
        md,
        "\nChosen: {chosen} components, coefficient prior {chosen_prior}.\n"
    );
    let variants: Vec<_> = variants(chosen, chosen_prior, &args.atoms)
        .into_iter()
        .enumerate()
        .filter(|(i, _)| args.only.is_empty() || args.only.contains(i))
        .map(|(_, v)| v)
        .collect();
    let _ = writeln!(
        md,
        "| basis and priors | walking: opt | classified | oracle | hybrid | diverse: opt | classified | oracle | hybrid | one core, per pose: opt | hybrid |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut shipped = None;
    let mut by_category = String::new();
    for (name, basis_config, reconstruct_config) in variants {
        let is_shipped = basis_config == BasisConfig::default()
            && reconstruct_config == ReconstructConfig::default();
        let basis = PoseBasis::fit(&poses, &basis_config).map_err(|e| e.to_string())?;
        let reconstructor =
            Reconstructor::new(basis, reconstruct_config).map_err(|e| e.to_string())?;
        let w = evaluate(&walking, &reconstructor, &ModeKind::ALL);
        let d = evaluate(&diverse, &reconstructor, &ModeKind::ALL);
        let timed: Vec<&EvalSample> = walking.iter().chain(&diverse).step_by(16).collect();
        let per_pose_ms = |kind: ModeKind| {
            let t = Instant::now();
            for s in &timed {
                if let Some(mode) = kind.camera_mode(s) {
                    let _ = reconstructor.reconstruct(&s.pose2, &mode);
                }
            }
            1000.0 * t.elapsed().as_secs_f64() / timed.len().max(1) as f64
        };
        let _ = writeln!(
            md,
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} ms | {:.2} ms |",
            cell(&w, ModeKind::Opt),
            cell(&w, ModeKind::Classified),
            cell(&w, ModeKind::Oracle),
            cell(&w, ModeKind::Hybrid),
            cell(&d, ModeKind::Opt),
            cell(&d, ModeKind::Classified),
            cell(&d, ModeKind::Oracle),
            cell(&d, ModeKind::Hybrid),
            per_pose_ms(ModeKind::Opt),
            per_pose_ms(ModeKind::Hybrid)
        );
        if is_shipped {
            let rig = categorised_samples(&test_seqs, Protocol::Rig, every, &localizer)?;
            by_category = lifted_rows(
                &mut md,
                &reconstructor,
                (&localizer, &lifter),
                &jittered,
                &rig,
            )?;
            shipped = Some((w, d));
        }
    }
    if let Some((walking, diverse)) = &shipped {
        targets(&mut md, walking, diverse);
    }
    md.push_str(&by_category);
    let basis = PoseBasis::fit(&poses, &BasisConfig::default()).map_err(|e| e.to_string())?;
    let _ = writeln!(
        md,
        "\n{}",
        proportions_section(&basis, Some((&localizer, &lifter)), &test_seqs, args)?
    );
    let _ = writeln!(md, "\nTotal {:.0} s.", started.elapsed().as_secs_f64());
    Ok(Measured { markdown: md })
}

/// The default localizer's training on the training subjects' clips `train_seqs`, and its
/// depth lifter.
fn train_localizer(train_seqs: &[PoseSequence]) -> Result<(CameraLocalizer, DepthLifter), String> {
    eprintln!(
        "reconstruction: training the localizer and the depth lifter on the training subjects"
    );
    let trained =
        Recipe::default_model().train(train_seqs, DEFAULT_MIN_POSE_DISTANCE_MM, |_| {})?;
    Ok((trained.localizer, trained.lifter))
}

/// Every `every`-th complete `protocol` view (seed 2) of the held-out clips `test_seqs` as
/// an evaluation sample (classified by `localizer`), with its clip's motion category.
fn categorised_samples(
    test_seqs: &[PoseSequence],
    protocol: Protocol,
    every: usize,
    localizer: &CameraLocalizer,
) -> Result<Vec<(MotionCategory, EvalSample)>, String> {
    let mut config = GenerateConfig::new(protocol);
    config.seed = 2;
    config.min_pose_distance_mm = DEFAULT_MIN_POSE_DISTANCE_MM;
    let test = project(test_seqs, &config)?;
    // evaluation_samples keeps the complete samples, in order.
    let complete = test.samples.iter().filter(|s| s.missing_mask == 0);
    let samples = evaluation_samples(&test, localizer).map_err(|e| e.to_string())?;
    Ok(samples
        .into_iter()
        .zip(complete)
        .step_by(every.max(1))
        .map(|(s, sample)| (test.category_of(sample), s))
        .collect())
}

/// The row of `hybrid` with the depth lifter, as `camloc reconstruct` runs it by default (a
/// `PoseReconstructor` on the basis and settings of `pursuit`, with the localizer and the
/// lifter), on the `jittered` walking and diverse samples, beside the shipped basis's row of
/// the table; returns the table of that default by motion category on the `jittered` and
/// `rig` samples.
fn lifted_rows(
    md: &mut String,
    pursuit: &Reconstructor,
    (localizer, lifter): (&CameraLocalizer, &DepthLifter),
    jittered: &[(MotionCategory, EvalSample)],
    rig: &[(MotionCategory, EvalSample)],
) -> Result<String, String> {
    let reconstructor =
        PoseReconstructor::with_config(pursuit.basis().clone(), pursuit.config().clone())
            .and_then(|r| {
                r.with_localizer(localizer.clone())
                    .with_mode(ModeKind::Hybrid)
            })
            .map_err(|e| e.to_string())?
            .with_lifter(lifter.clone());
    // Per sample: its category, PA-MPJPE and error without rotation alignment (None: failed).
    type Errors = Vec<(MotionCategory, Option<[f64; 2]>)>;
    let errors = |samples: &[(MotionCategory, EvalSample)]| -> Errors {
        samples
            .par_iter()
            .map(|(c, s)| {
                let r = reconstructor.reconstruct(&PartialPose2::from(s.pose2)).ok();
                (
                    *c,
                    r.map(|r| {
                        let pose = &r.reconstruction.pose;
                        [
                            mpjpe_after_similarity(pose, &s.truth),
                            mpjpe_after_scale(pose, &s.truth),
                        ]
                    }),
                )
            })
            .collect()
    };
    // Mean errors, samples and failures of the samples whose category passes `keep`.
    let mean = |errors: &Errors, keep: &dyn Fn(MotionCategory) -> bool| {
        let kept: Vec<Option<[f64; 2]>> =
            errors.iter().filter(|e| keep(e.0)).map(|e| e.1).collect();
        let ok: Vec<[f64; 2]> = kept.iter().flatten().copied().collect();
        let n = ok.len().max(1) as f64;
        (
            [0, 1].map(|k| ok.iter().map(|e| e[k]).sum::<f64>() / n),
            kept.len(),
            kept.len() - ok.len(),
        )
    };
    let (jittered, rig) = (errors(jittered), errors(rig));
    let (w, _, wf) = mean(&jittered, &|c| c == MotionCategory::Walk);
    let (d, _, df) = mean(&jittered, &|c| c != MotionCategory::Walk);
    let _ = writeln!(
        md,
        "| the same, `hybrid` with the depth lifter (`camloc reconstruct`'s default) | - | - \
         | - | {:.1} ({wf} failed) | - | - | - | {:.1} ({df} failed) | - | - |",
        w[0], d[0]
    );
    let mut table = String::from(
        "\n`camloc reconstruct`'s default (`hybrid` with the depth lifter) by motion category \
         of the held-out clips: PA-MPJPE / the error without rotation alignment (the pelvises \
         together and one common scale, the pose as its body frame turns it: what a BVH file \
         shows; `mpjpe_after_scale`), mm, views and failures; `jittered` as above, `rig` \
         (tripod cameras of a studio, seed 2, every same N-th view):\n\n\
         | motion category | jittered | rig |\n|---|---|---|\n",
    );
    let mut categories: Vec<MotionCategory> = jittered.iter().chain(&rig).map(|e| e.0).collect();
    categories.sort();
    categories.dedup();
    let cell = |errors: &Errors, keep: &dyn Fn(MotionCategory) -> bool| match mean(errors, keep) {
        (_, 0, _) => "-".to_string(),
        (e, n, f) => format!("{:.1} / {:.1} ({n} views, {f} failed)", e[0], e[1]),
    };
    for category in categories {
        let _ = writeln!(
            table,
            "| {category} | {} | {} |",
            cell(&jittered, &|c| c == category),
            cell(&rig, &|c| c == category)
        );
    }
    let _ = writeln!(
        table,
        "| all | {} | {} |",
        cell(&jittered, &|_| true),
        cell(&rig, &|_| true)
    );
    Ok(table)
}

/// The proportions test (issue 23) with its heading.
fn proportions_section(
    basis: &PoseBasis,
    trained: Option<(&CameraLocalizer, &DepthLifter)>,
    test_seqs: &[PoseSequence],
    args: &Args,
) -> Result<String, String> {
    let options = crate::proportions::Options {
        every: args.proportions_every,
        window: args.window,
        per_clip: args.windows_per_clip,
        seed: 23,
    };
    Ok(format!(
        "### 3D in the person's own proportions, and from video\n\n{}",
        crate::proportions::measure(
            basis,
            (trained.map(|t| t.0), trained.map(|t| t.1)),
            test_seqs,
            &options
        )?
    ))
}

/// The camera mode with the lowest mean 3D error in `report` other than `oracle` (which
/// needs the true camera), with that error in mm.
pub fn best_without_truth(report: &EvalReport) -> Option<(ModeKind, f64)> {
    report
        .modes
        .iter()
        .filter(|m| m.mode != ModeKind::Oracle)
        .filter_map(|m| m.mean_pa_mpjpe_mm.map(|e| (m.mode, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The issue-12 targets against the shipped defaults' `walking` and `diverse` reports.
fn targets(md: &mut String, walking: &EvalReport, diverse: &EvalReport) {
    let met = |ok: bool| if ok { "met" } else { "NOT met" };
    let _ = writeln!(
        md,
        "\nIssue 12 targets against the shipped defaults (`BasisConfig::default`, \
         `ReconstructConfig::default`):\n"
    );
    for (what, report, goal) in [
        ("diverse held-out subjects", diverse, 80.0),
        ("walking held-out subjects", walking, 55.0),
    ] {
        if let Some((mode, e)) = best_without_truth(report) {
            let _ = writeln!(
                md,
                "- {what}: best non-oracle mode `{}` {e:.1} mm, goal <= {goal} mm ({}); \
                 `opt` (the library's camera without a localizer) {}",
                mode.name(),
                met(e <= goal),
                cell(report, ModeKind::Opt)
            );
        }
    }
}

/// The variants compared: plain PCA of `components`, then each addition on its own.
fn variants(
    components: usize,
    prior: f64,
    atoms: &[usize],
) -> Vec<(String, BasisConfig, ReconstructConfig)> {
    let pca = BasisConfig {
        n_components: components,
        kind: BasisKind::Pca,
        ..BasisConfig::default()
    };
    let plain = ReconstructConfig {
        coefficient_prior: 0.0,
        symmetry: false,
        joint_limits: false,
        ..ReconstructConfig::default()
    };
    let priors = ReconstructConfig {
        coefficient_prior: prior,
        ..ReconstructConfig::default()
    };
    let mut out = vec![(format!("PCA {components}"), pca.clone(), plain.clone())];
    for &a in atoms {
        let dictionary = BasisConfig {
            kind: BasisKind::Dictionary { atoms: a },
            ..pca.clone()
        };
        out.push((
            format!("dictionary of {a} cluster centres over PCA {components}"),
            dictionary.clone(),
            plain.clone(),
        ));
        out.push((
            format!("dictionary of {a} + all priors"),
            dictionary.clone(),
            priors.clone(),
        ));
        out.push((
            format!("dictionary of {a} + all priors, no depth-mirror hypothesis"),
            dictionary,
            ReconstructConfig {
                try_depth_reflection: false,
                ..priors.clone()
            },
        ));
    }
    out.extend([
        (
            format!("PCA {components} + limb symmetry"),
            pca.clone(),
            ReconstructConfig {
                symmetry: true,
                ..plain.clone()
            },
        ),
        (
            format!("PCA {components} + joint limits"),
            pca.clone(),
            ReconstructConfig {
                joint_limits: true,
                ..plain.clone()
            },
        ),
        (
            format!("PCA {components} + coefficient prior {prior}"),
            pca.clone(),
            ReconstructConfig {
                coefficient_prior: prior,
                ..plain.clone()
            },
        ),
        (
            format!("PCA {components}, no depth-mirror hypothesis"),
            pca.clone(),
            ReconstructConfig {
                try_depth_reflection: false,
                ..plain.clone()
            },
        ),
        (format!("PCA {components} + all priors"), pca, priors),
    ]);
    let shipped = (BasisConfig::default(), ReconstructConfig::default());
    if !out
        .iter()
        .any(|(_, b, r)| (b, r) == (&shipped.0, &shipped.1))
    {
        out.push(("shipped defaults".into(), shipped.0, shipped.1));
    }
    out
}

/// Mean MPJPE (opt camera, jittered views) over `folds` folds grouped by subject of a PCA
/// basis of `k` components fitted on the other folds' poses.
fn cross_validated_mpjpe(
    poses: &[Pose3],
    groups: &[&str],
    k: usize,
    prior: f64,
    folds: usize,
) -> Result<f64, String> {
    let assignment = camloc::learning::group_k_fold(groups, folds).map_err(|e| e.to_string())?;
    let (mut total, mut count) = (0.0, 0usize);
    for fold in 0..folds {
        let train: Vec<Pose3> = poses
            .iter()
            .zip(&assignment)
            .filter(|(_, f)| **f != fold)
            .map(|(p, _)| *p)
            .collect();
        let held: Vec<Pose3> = poses
            .iter()
            .zip(&assignment)
            .filter(|(_, f)| **f == fold)
            .map(|(p, _)| *p)
            .step_by(8)
            .collect();
        let basis = PoseBasis::fit(
            &train,
            &BasisConfig {
                n_components: k,
                kind: BasisKind::Pca,
                ..BasisConfig::default()
            },
        )
        .map_err(|e| e.to_string())?;
        let config = ReconstructConfig {
            coefficient_prior: prior,
            symmetry: false,
            joint_limits: false,
            ..ReconstructConfig::default()
        };
        let reconstructor = Reconstructor::new(basis, config).map_err(|e| e.to_string())?;
        let samples = jittered_samples(&held, 10 + fold as u64)?;
        let report = evaluate(&samples, &reconstructor, &[ModeKind::Opt]);
        if let Some(m) = report.modes.first().and_then(|m| m.mean_pa_mpjpe_mm) {
            total += m * samples.len() as f64;
            count += samples.len();
        }
    }
    Ok(total / count.max(1) as f64)
}

/// One jittered view (a random Table-1 class) per pose, as evaluation samples.
fn jittered_samples(poses: &[Pose3], seed: u64) -> Result<Vec<EvalSample>, String> {
    let sequence = PoseSequence {
        clip: camloc::dataset::ClipInfo::new("cv", "cv"),
        frames: poses
            .iter()
            .enumerate()
            .map(|(i, p)| (i as u32, *p))
            .collect(),
    };
    let mut config = GenerateConfig::new(Protocol::Jittered);
    config.seed = seed;
    let data = project(&[sequence], &config)?;
    Ok(data
        .samples
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 12 == (i / 12) % 12)
        .map(|(_, s)| EvalSample {
            pose2: s.landmarks,
            truth: s.pose3,
            true_rotation: s.rotation,
            classified_rotation: None,
        })
        .collect())
}
