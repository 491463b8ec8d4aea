//! Issue 23, the test that cannot flatter itself: held-out subjects whose limbs are rescaled
//! by known random factors (each limb type +-20%, hip and shoulder widths among them, the
//! head point moved as detectors place it), filmed under `jittered` and `rig`, single poses
//! and windows of consecutive frames; recovered bone lengths and PA-MPJPE with and without
//! each part of the skeleton refinement. Part of `cargo xtask reconstruction`.

mod gaps;
mod missing;
pub mod people;
mod views;

use std::fmt::Write;
use std::time::Instant;

use camloc::dataset::{MotionCategory, PoseSequence, annotated};
use camloc::reconstruct::{
    BoneLengths, CameraMode, Given, Intrinsics, LiftedDepths, ModeKind, PoseBasis,
    ReconstructConfig, Reconstructor, mpjpe_after_similarity,
};
use camloc::skeleton::NUM_LIMBS;
use camloc::{
    CameraLocalizer, DepthLifter, PartialPose2, Pose2, Pose3, hybrid_camera,
    sequence_own_placement_weight,
};
use rayon::prelude::*;

use people::{Frames, HEAD_FACTOR, LIMB_FACTOR, factors, rescale, single_poses, windows};
use views::{Studio, View, film};

/// What the proportions test measures.
pub struct Options {
    /// Every n-th held-out pose (selected by pose at 100 mm) is a single-frame sample.
    pub every: usize,
    /// Frames per window of a sequence (about 30 frames a second).
    pub window: usize,
    /// Most windows per clip.
    pub per_clip: usize,
    /// Seed of the rescaling, cameras and noise.
    pub seed: u64,
}

/// A variant of the reconstruction: its settings and what it is given.
struct Variant {
    name: &'static str,
    config: ReconstructConfig,
    /// The true bone lengths are given.
    lengths: bool,
    /// The focal length is given (full perspective refinement).
    focal: bool,
    /// With `hybrid`, the refinement starts from the depth lifter's pose (`opt` has no
    /// class to lift with).
    lifted: bool,
}

impl Variant {
    /// Whether this is what `camloc reconstruct` runs with the default settings and nothing
    /// given but, when `lengths`, the true bone lengths; `lifted` as the camera lifts.
    fn is_default(&self, lengths: bool, lifted: bool) -> bool {
        self.config == ReconstructConfig::default()
            && self.lengths == lengths
            && !self.focal
            && self.lifted == lifted
    }
}

/// A test item filmed: the truth and the views.
struct Filmed {
    truth: Vec<Pose3>,
    lengths: BoneLengths,
    views: Vec<View>,
    walking: bool,
}

/// What a variant achieved over a set of items.
#[derive(Default)]
struct Scores {
    /// PA-MPJPE sum (mm) and frames, walking and other motions.
    mpjpe: [(f64, usize); 2],
    /// Per answer (a sequence, or a single frame): mean and largest absolute relative length
    /// error (after one common scale).
    length_errors: Vec<(f64, f64)>,
    /// Per limb: the sum over answers of the absolute relative length error.
    limb_errors: [f64; NUM_LIMBS],
    failures: usize,
    seconds: f64,
}

impl Scores {
    /// Each limb's mean absolute relative length error over the answers.
    fn limb_means(&self) -> [f64; NUM_LIMBS] {
        let n = self.length_errors.len().max(1) as f64;
        self.limb_errors.map(|e| e / n)
    }

    /// The share of answers whose every limb is within 5%.
    fn within_5(&self) -> f64 {
        let n = self.length_errors.len().max(1) as f64;
        self.length_errors.iter().filter(|e| e.1 <= 0.05).count() as f64 / n
    }

    /// The mean over answers of the mean absolute relative length error.
    fn mean_length_error(&self) -> f64 {
        let n = self.length_errors.len().max(1) as f64;
        self.length_errors.iter().map(|e| e.0).sum::<f64>() / n
    }

    fn mean_mpjpe(&self) -> Option<f64> {
        let (sum, n) = (
            self.mpjpe[0].0 + self.mpjpe[1].0,
            self.mpjpe[0].1 + self.mpjpe[1].1,
        );
        (n > 0).then(|| sum / n as f64)
    }

    fn cells(&self) -> String {
        let mm = |(s, n): (f64, usize)| {
            if n > 0 {
                format!("{:.1}", s / n as f64)
            } else {
                "-".into()
            }
        };
        let n = self.length_errors.len().max(1) as f64;
        let mean = 100.0 * self.mean_length_error();
        let worst = 100.0 * self.length_errors.iter().map(|e| e.1).sum::<f64>() / n;
        let within = 100.0 * self.within_5();
        let frames = self.mpjpe[0].1 + self.mpjpe[1].1;
        format!(
            "{} | {} | {} | {mean:.1}% | {worst:.1}% | {within:.0}% | {} | {:.2} ms",
            frames,
            self.mean_mpjpe().map_or("-".into(), |v| format!("{v:.1}")),
            format_args!("{} / {}", mm(self.mpjpe[0]), mm(self.mpjpe[1])),
            self.failures,
            1000.0 * self.seconds / frames.max(1) as f64
        )
    }
}

/// The variants of single frames and of sequences. `hybrid` lifts (the command line's
/// default) in the variants marked so; the pursuit-only rows before them are the ablation.
fn variants() -> (Vec<Variant>, Vec<Variant>) {
    let base = ReconstructConfig::default();
    let with = |f: &dyn Fn(&mut ReconstructConfig)| {
        let mut c = base.clone();
        f(&mut c);
        c
    };
    let v = |name, config: &ReconstructConfig, lengths, focal, lifted| Variant {
        name,
        config: config.clone(),
        lengths,
        focal,
        lifted,
    };
    let template = with(&|c| c.refinement.estimate_lengths = false);
    let single = vec![
        v(
            "template proportions (no refinement)",
            &template,
            false,
            false,
            false,
        ),
        v(
            "lengths estimated, the pursuit's pose (the default of opt)",
            &base,
            false,
            false,
            false,
        ),
        v(
            "lengths estimated, lifted depths (the default of hybrid)",
            &base,
            false,
            false,
            true,
        ),
        v(
            "lengths estimated, focal length known",
            &base,
            false,
            true,
            true,
        ),
        v("true lengths given", &base, true, false, true),
        v(
            "true lengths and focal length given",
            &base,
            true,
            true,
            true,
        ),
    ];
    let plain = with(&|c| {
        c.refinement.smoothness = 0.0;
        c.refinement.consistent_depth = false;
    });
    let viterbi = with(&|c| c.refinement.smoothness = 0.0);
    let sequence = vec![
        v(
            "sequence: template proportions",
            &template,
            false,
            false,
            false,
        ),
        v("sequence: shared lengths only", &plain, false, false, false),
        v(
            "sequence: + depths by Viterbi",
            &viterbi,
            false,
            false,
            false,
        ),
        v(
            "sequence: + smoothness (the default of opt)",
            &base,
            false,
            false,
            false,
        ),
        v(
            "sequence: + lifted depths (the default of hybrid)",
            &base,
            false,
            false,
            true,
        ),
        v("sequence, focal length known", &base, false, true, true),
        v("sequence, true lengths given", &base, true, false, true),
    ];
    (single, sequence)
}

/// The skeletons the held-out people are filmed with.
#[derive(Clone, Copy)]
enum Skeletons {
    /// Their own (unscaled).
    Own,
    /// Rescaled by each subject's random factors ([`factors`]).
    Random,
    /// Rescaled by these factors, every subject alike.
    Fixed([f64; NUM_LIMBS]),
    /// Their own, with the landmarks placed as detectors and photo annotations place them
    /// (`camloc::dataset::annotated`: the neck at the mid-shoulder point, the pelvis at the
    /// mid-hip point).
    Annotated,
}

/// Films every item of `items` under `studio` with `skeletons`.
fn film_all(
    items: &[Frames],
    studio: Studio,
    skeletons: Skeletons,
    seed: u64,
) -> Result<Vec<Filmed>, String> {
    items
        .par_iter()
        .enumerate()
        .map(|(i, item)| {
            let truth: Vec<Pose3> = match skeletons {
                Skeletons::Own => item.poses.clone(),
                Skeletons::Random => {
                    let f = factors(&item.subject, seed);
                    item.poses.iter().map(|p| rescale(p, &f)).collect()
                }
                Skeletons::Fixed(f) => item.poses.iter().map(|p| rescale(p, &f)).collect(),
                Skeletons::Annotated => item.poses.iter().map(|p| annotated(p, 1.0)).collect(),
            };
            let lengths = BoneLengths::of_pose(&truth[0]).map_err(|e| e.to_string())?;
            let views = film(
                &truth,
                studio,
                seed.wrapping_mul(1_000_003).wrapping_add(i as u64),
            )?;
            Ok(Filmed {
                truth,
                lengths,
                views,
                walking: item.category == MotionCategory::Walk,
            })
        })
        .collect()
}

/// The camera mode of `pose2` under `kind` (for `hybrid`, the localizer's continuous
/// viewpoint, as `camloc reconstruct` starts from), and with a `lifter` the depths it predicts
/// for the localizer's class, with the weight `placement` of the skeleton's own placement of
/// the pelvis and the neck (a sequence's; none: the pose's own).
fn mode_of(
    kind: ModeKind,
    pose2: &Pose2,
    localizer: Option<&CameraLocalizer>,
    lifter: Option<&DepthLifter>,
    placement: Option<f64>,
) -> (Option<CameraMode>, Option<LiftedDepths>) {
    match kind {
        ModeKind::Opt => (Some(CameraMode::Opt), None),
        ModeKind::Hybrid => match localizer.and_then(|l| l.localize(pose2).ok()) {
            Some(l) => {
                // As camloc reconstruct chooses its camera (camloc::hybrid_camera).
                let depths = localizer.zip(lifter).and_then(|(localizer, f)| {
                    (f.mirror_symmetric_placed_depths(
                        pose2,
                        localizer.cameras(),
                        l.label,
                        placement,
                    ))
                    .ok()
                });
                (Some(hybrid_camera(&l, depths.is_some())), depths)
            }
            None => (None, None),
        },
        _ => (None, None),
    }
}

/// The 2D poses of `views` (a window of consecutive frames at about 30 a second) with their
/// landmarks smoothed over time ([`camloc::smooth_landmarks`]).
fn smoothed(views: &[View]) -> Vec<Pose2> {
    let partial: Vec<PartialPose2> = views.iter().map(|v| PartialPose2::from(v.pose2)).collect();
    camloc::smooth_landmarks(
        &partial,
        None,
        &[],
        camloc::reconstruct::FrameRate::default(),
    )
    .iter()
    .zip(views)
    .map(|(p, v)| p.complete().unwrap_or(v.pose2))
    .collect()
}

/// Runs `variant` with camera `kind` on every item: each frame alone, or each item as one
/// sequence.
fn run(
    basis: &PoseBasis,
    variant: &Variant,
    kind: ModeKind,
    (localizer, lifter): (Option<&CameraLocalizer>, Option<&DepthLifter>),
    items: &[Filmed],
    sequence: bool,
) -> Result<Scores, String> {
    let reconstructor =
        Reconstructor::new(basis.clone(), variant.config.clone()).map_err(|e| e.to_string())?;
    // `camloc reconstruct`'s default, `--camera-height from-input`: the shares of the camera
    // heights among the views of `items` (one input; its first `HEIGHT_SHARE_MAX_POSES`),
    // estimated before any is localized.
    let estimated = localizer.map(|l| {
        let poses: Vec<PartialPose2> = items
            .iter()
            .flat_map(|item| &item.views)
            .map(|v| PartialPose2::from(v.pose2))
            .collect();
        l.clone()
            .with_camera_height(l.estimate_height_shares(&poses).camera_height())
    });
    let localizer = estimated.as_ref();
    let given = |item: &Filmed, view: &View| Given {
        lengths: variant.lengths.then_some(item.lengths),
        intrinsics: variant.focal.then_some(Intrinsics {
            focal_px: view.focal,
            principal_point: Some([0.0, 0.0]),
        }),
    };
    let started = Instant::now();
    // Per item: per-frame PA-MPJPE (None: failed) and the lengths of the answers (one per
    // sequence, one per reconstructed frame otherwise).
    let lifter = lifter.filter(|_| variant.lifted);
    let results: Vec<(Vec<Option<f64>>, Vec<BoneLengths>)> = items
        .par_iter()
        .map(|item| {
            // A sequence's landmarks smoothed over its frames, as `camloc reconstruct
            // --sequence` smooths them before it localizes and solves.
            let poses: Vec<Pose2> = match sequence {
                true => smoothed(&item.views),
                false => item.views.iter().map(|v| v.pose2).collect(),
            };
            // A sequence's poses lifted in one placement of the pelvis and the neck, as
            // `camloc reconstruct --sequence` lifts them.
            let placement = sequence
                .then(|| {
                    let partial: Vec<PartialPose2> =
                        poses.iter().map(|p| PartialPose2::from(*p)).collect();
                    sequence_own_placement_weight(&partial)
                })
                .flatten();
            let (modes, depths): (Vec<Option<CameraMode>>, Vec<Option<LiftedDepths>>) = poses
                .iter()
                .map(|p| mode_of(kind, p, localizer, lifter, placement))
                .unzip();
            if sequence {
                let frames: Vec<(Pose2, CameraMode)> = poses
                    .iter()
                    .zip(&modes)
                    .map(|(p, m)| (*p, m.unwrap_or(CameraMode::Opt)))
                    .collect();
                match reconstructor.reconstruct_sequence_lifted(
                    &frames,
                    &depths,
                    &given(item, &item.views[0]),
                ) {
                    Ok(seq) => (
                        seq.frames
                            .iter()
                            .zip(&item.truth)
                            .map(|(r, t)| {
                                r.as_ref().ok().map(|r| mpjpe_after_similarity(&r.pose, t))
                            })
                            .collect(),
                        vec![seq.lengths],
                    ),
                    Err(_) => (vec![None; item.views.len()], Vec::new()),
                }
            } else {
                let mut lengths = Vec::new();
                let errors = item
                    .views
                    .iter()
                    .zip(modes.iter().zip(&depths))
                    .zip(&item.truth)
                    .map(|((v, (m, z)), t)| {
                        let r = reconstructor
                            .reconstruct_lifted(
                                &v.pose2,
                                m.as_ref()?,
                                1,
                                &given(item, v),
                                z.as_ref(),
                            )
                            .ok()?
                            .into_iter()
                            .next()?;
                        lengths.extend(BoneLengths::of_pose(&r.pose).ok());
                        Some(mpjpe_after_similarity(&r.pose, t))
                    })
                    .collect();
                (errors, lengths)
            }
        })
        .collect();
    let mut scores = Scores {
        seconds: started.elapsed().as_secs_f64(),
        ..Scores::default()
    };
    for (item, (errors, lengths)) in items.iter().zip(results) {
        for e in errors {
            match e {
                Some(e) if e.is_finite() => {
                    let slot = &mut scores.mpjpe[usize::from(!item.walking)];
                    slot.0 += e;
                    slot.1 += 1;
                }
                _ => scores.failures += 1,
            }
        }
        for l in lengths {
            let errors = l.relative_errors(&item.lengths).map(f64::abs);
            for (sum, e) in scores.limb_errors.iter_mut().zip(errors) {
                *sum += e;
            }
            let mean = errors.iter().sum::<f64>() / NUM_LIMBS as f64;
            scores
                .length_errors
                .push((mean, errors.iter().copied().fold(0.0, f64::max)));
        }
    }
    Ok(scores)
}

/// The template's length errors over `items`: (mean, mean largest) absolute relative error,
/// and each limb's mean absolute relative error.
fn template_errors(
    basis: &PoseBasis,
    items: &[Filmed],
) -> Result<(f64, f64, [f64; NUM_LIMBS]), String> {
    let template = basis.length_prior().template().map_err(|e| e.to_string())?;
    let n = items.len().max(1) as f64;
    let (mut mean, mut worst) = (0.0, 0.0);
    let mut limbs = [0.0; NUM_LIMBS];
    for item in items {
        let e = template.relative_errors(&item.lengths).map(f64::abs);
        for (sum, e) in limbs.iter_mut().zip(e) {
            *sum += e / n;
        }
        mean += e.iter().sum::<f64>() / NUM_LIMBS as f64 / n;
        worst += e.iter().copied().fold(0.0, f64::max) / n;
    }
    Ok((mean, worst, limbs))
}

/// One row of the per-limb table: `name` and each limb's mean absolute error, %.
fn limb_row(name: &str, errors: &[f64; NUM_LIMBS]) -> String {
    let cells: Vec<String> = errors.iter().map(|e| format!("{:.1}", 100.0 * e)).collect();
    format!("| {name} | {} |\n", cells.join(" | "))
}

/// Issue 23's targets for a shipped variant: sequences, every limb within 5%; single frames,
/// half the template's mean length error (`template`); PA-MPJPE within 10% of the same
/// subjects unscaled (`unscaled`).
fn target_line(
    name: &str,
    kind: ModeKind,
    sequence: bool,
    scaled: &Scores,
    unscaled: &Scores,
    template: f64,
) -> String {
    let mark = |ok: bool| if ok { "met" } else { "not met" };
    let lengths = if sequence {
        format!(
            "every limb within 5% in {:.0}% of the windows (target: all): {}",
            100.0 * scaled.within_5(),
            mark(scaled.within_5() >= 1.0)
        )
    } else {
        let e = scaled.mean_length_error();
        format!(
            "mean length error {:.1}% against the template's {:.1}% (target: half): {}",
            100.0 * e,
            100.0 * template,
            mark(e <= 0.5 * template)
        )
    };
    let ratio = match (scaled.mean_mpjpe(), unscaled.mean_mpjpe()) {
        (Some(a), Some(b)) if b > 0.0 => a / b,
        _ => f64::NAN,
    };
    format!(
        "- {name}, {}: {lengths}; PA-MPJPE {:.0}% of the unscaled subjects' (target: at most \
         110%): {}\n",
        kind.name(),
        100.0 * ratio,
        mark(ratio <= 1.1)
    )
}

/// Measures the proportions test on the held-out `test` clips with `basis` (and `localizer`
/// for `hybrid`, and `lifter` for its lifted variants, when given); returns the markdown.
pub fn measure(
    basis: &PoseBasis,
    (localizer, lifter): (Option<&CameraLocalizer>, Option<&DepthLifter>),
    test: &[PoseSequence],
    options: &Options,
) -> Result<String, String> {
    let mut md = String::new();
    let singles = single_poses(test, 100.0, options.every);
    let sequences = windows(test, options.window, options.per_clip);
    let _ = writeln!(
        md,
        "Held-out subjects rescaled by known factors, one draw per subject: each limb type \
         (hip width, thigh, shin, torso, shoulder width, upper arm, forearm; left and right \
         alike) x U({}, {}), the neck-to-head distance x U({}, {}) (where detectors put the \
         head). {} single poses (every {}th selected by pose at 100 mm) and {} windows of {} \
         consecutive frames (about 30 frames a second) of their clips, each filmed by one \
         camera: `jittered` (near a random Table-1 viewpoint, 3-8 m, f = 1000 px, 3% noise) or \
         `rig` (a tripod camera of the studio, distortion, detector noise), noise drawn per \
         frame. PA-MPJPE = MPJPE after similarity alignment, mm, all / walking / other motions; \
         length errors are each limb's relative error after one common scale (sizes cannot be \
         told from one camera), the mean over limbs and the largest limb, averaged over \
         persons (single poses: over poses; sequences: over windows); \"within 5%\": the \
         share whose every limb is within 5%. `hybrid` rows of the variants after the \
         pursuit-only ones start the refinement from the depth lifter's depths of the classified \
         camera (docs/conventions.md section 6), as `camloc reconstruct` does. The localizer \
         of `hybrid` weighs the camera heights by their shares among all the views of the \
         table row's test set, estimated before any is localized (`--camera-height \
         from-input`, `camloc reconstruct`'s default, each test set one input). Time: wall \
         time per frame on the machine's cores.\n",
        LIMB_FACTOR.0,
        LIMB_FACTOR.1,
        HEAD_FACTOR.0,
        HEAD_FACTOR.1,
        singles.len(),
        options.every,
        sequences.len(),
        options.window
    );
    let (single_variants, sequence_variants) = variants();
    let mut kinds = vec![ModeKind::Opt];
    if localizer.is_some() {
        kinds.push(ModeKind::Hybrid);
    }
    for studio in [Studio::Jittered, Studio::Rig] {
        eprintln!("proportions: {} views", studio.name());
        let single_scaled = film_all(&singles, studio, Skeletons::Random, options.seed)?;
        let single_plain = film_all(&singles, studio, Skeletons::Own, options.seed)?;
        let seq_scaled = film_all(&sequences, studio, Skeletons::Random, options.seed)?;
        let seq_plain = film_all(&sequences, studio, Skeletons::Own, options.seed)?;
        let (tm, tw, template_limbs) = template_errors(basis, &seq_scaled)?;
        let (single_tm, _, _) = template_errors(basis, &single_scaled)?;
        let (plain_tm, plain_tw, _) = template_errors(basis, &seq_plain)?;
        let _ = writeln!(
            md,
            "`{}` (template lengths against the rescaled people: mean error {:.1}%, largest \
             limb {:.1}%; against the same subjects unscaled: {:.1}%, {:.1}%):\n\n| variant | camera | frames | PA-MPJPE | walking / other | length \
             error | largest limb | within 5% | failed | time per frame |\n|---|---|---|---|---|---|---|---|---|---|",
            studio.name(),
            100.0 * tm,
            100.0 * tw,
            100.0 * plain_tm,
            100.0 * plain_tw
        );
        let mut limbs = limb_row("template (windows)", &template_limbs);
        let mut checks = String::new();
        for (variants, scaled, plain, sequence) in [
            (&single_variants, &single_scaled, &single_plain, false),
            (&sequence_variants, &seq_scaled, &seq_plain, true),
        ] {
            for variant in variants {
                // Lifting needs the classified camera: `hybrid`, with a lifter. A lifted
                // variant's `opt` row is its pursuit-only twin's, when it has one.
                let lifts = |kind: ModeKind| kind == ModeKind::Hybrid && lifter.is_some();
                let twin = variants.iter().any(|o| {
                    !o.lifted
                        && o.config == variant.config
                        && o.lengths == variant.lengths
                        && o.focal == variant.focal
                });
                for &kind in kinds
                    .iter()
                    .filter(|&&k| !(variant.lifted && twin) || lifts(k))
                {
                    eprintln!(
                        "proportions: {} {} {}",
                        studio.name(),
                        variant.name,
                        kind.name()
                    );
                    let s = run(basis, variant, kind, (localizer, lifter), scaled, sequence)?;
                    let _ = writeln!(md, "| {} | {} | {} |", variant.name, kind.name(), s.cells());
                    // What `camloc reconstruct` does with this camera.
                    if !variant.is_default(false, lifts(kind)) {
                        continue;
                    }
                    let u = run(basis, variant, kind, (localizer, lifter), plain, sequence)?;
                    let _ = writeln!(
                        md,
                        "| {}, same subjects unscaled | {} | {} |",
                        variant.name,
                        kind.name(),
                        u.cells()
                    );
                    limbs.push_str(&limb_row(
                        &format!("{}, {}", variant.name, kind.name()),
                        &s.limb_means(),
                    ));
                    let template = if sequence { tm } else { single_tm };
                    checks.push_str(&target_line(variant.name, kind, sequence, &s, &u, template));
                }
            }
        }
        let _ = writeln!(
            md,
            "\nMean absolute length error of each limb (%, after one common scale):\n\n| \
             variant | {} |\n|---|{}\n{limbs}\nIssue 23's targets (`{}`):\n\n{checks}",
            camloc::reconstruct::BONE_KEYS.join(" | "),
            "---|".repeat(NUM_LIMBS),
            studio.name()
        );
    }
    md.push_str(&labs_section(
        basis,
        (localizer, lifter),
        (&singles, &sequences),
        options.seed,
    )?);
    if let Some(localizer) = localizer {
        md.push_str(&missing::section(
            basis,
            (localizer, lifter),
            &singles,
            options.seed,
        )?);
        md.push_str(&gaps::section(
            basis,
            (localizer, lifter),
            &sequences,
            options.seed,
        )?);
    }
    Ok(md)
}

/// The labs section's row group of the held-out people's own skeletons with the landmarks
/// placed as detectors place them ([`Skeletons::Annotated`]).
const DETECTOR_PLACEMENT: &str = "own limbs, landmarks placed as detectors place them (neck at the mid-shoulder point, pelvis at the mid-hip point)";

/// Skeletons like those of the recorded labs issue 23 quotes (their limbs relative to
/// camloc's template), as factors of the held-out people's own limbs.
const LAB_SKELETONS: [(&str, [f64; NUM_LIMBS]); 2] = [
    (
        "first lab (torso x 1.30, hip half-width x 0.83, neck-to-head x 0.57, forearms x 1.17)",
        [
            0.83, 1.0, 1.0, 0.83, 1.0, 1.0, 1.30, 0.57, 1.0, 1.0, 1.17, 1.0, 1.0, 1.17,
        ],
    ),
    (
        "second lab (neck-to-head x 1.64, hip half-width x 0.46)",
        [
            0.46, 1.0, 1.0, 0.46, 1.0, 1.0, 1.0, 1.64, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0,
        ],
    ),
];

/// The command line's defaults (lengths estimated; `hybrid` with the lifter when there is a
/// localizer and a lifter, else `opt`) and the same with the true lengths given, on the
/// held-out `singles` and `sequences` with the [`LAB_SKELETONS`], filmed by the `rig`.
fn labs_section(
    basis: &PoseBasis,
    (localizer, lifter): (Option<&CameraLocalizer>, Option<&DepthLifter>),
    (singles, sequences): (&[Frames], &[Frames]),
    seed: u64,
) -> Result<String, String> {
    let (kind, lifted) = match (localizer, lifter) {
        (Some(_), Some(_)) => (ModeKind::Hybrid, true),
        _ => (ModeKind::Opt, false),
    };
    let (single_variants, sequence_variants) = variants();
    let chosen: Vec<(&Variant, bool)> = [
        (&single_variants, false, false),
        (&single_variants, true, false),
        (&sequence_variants, false, true),
    ]
    .into_iter()
    .filter_map(|(variants, lengths, sequence)| {
        variants
            .iter()
            .find(|v| v.is_default(lengths, lifted))
            .map(|v| (v, sequence))
    })
    .collect();
    let mut md = format!(
        "\nSkeletons like the recorded labs' that issue 23 quotes: the held-out people's own \
         limbs times the labs' ratios to camloc's template, every subject alike, filmed by \
         the `rig` (the labs' are studio cameras), camera `{}`:\n\n| skeletons | variant | \
         frames | PA-MPJPE | walking / other | length error | largest limb | within 5% | \
         failed | time per frame |\n|---|---|---|---|---|---|---|---|---|---|\n",
        kind.name()
    );
    let groups = LAB_SKELETONS
        .iter()
        .map(|&(name, factors)| (name, Skeletons::Fixed(factors)))
        .chain([(DETECTOR_PLACEMENT, Skeletons::Annotated)]);
    for (name, skeletons) in groups {
        eprintln!("proportions: {name}");
        let filmed = [
            film_all(singles, Studio::Rig, skeletons, seed)?,
            film_all(sequences, Studio::Rig, skeletons, seed)?,
        ];
        for (variant, sequence) in &chosen {
            let items = &filmed[usize::from(*sequence)];
            let s = run(basis, variant, kind, (localizer, lifter), items, *sequence)?;
            let _ = writeln!(md, "| {name} | {} | {} |", variant.name, s.cells());
        }
    }
    Ok(md)
}
