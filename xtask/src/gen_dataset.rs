//! `cargo xtask gen-dataset`.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use camloc::store::Persist;
use camloc_dataset::{
    Augmentation, DEFAULT_MIN_POSE_DISTANCE_MM, GenerateConfig, Protocol, default_test_subjects,
};
use camloc_geometry::CameraSet;

use crate::mocap_data::{categorise, load_sequences, project};

/// Arguments of `gen-dataset`.
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  cargo xtask gen-dataset --mocap ../shared/data/cmu --out d.bin --protocol jittered --seed 1"
)]
pub struct Args {
    /// Folder of motion capture, walked recursively for .bvh and .asf/.amc files (repeatable).
    /// Default: ../shared/data/cmu (or $CAMLOC_DATA/cmu).
    #[arg(long = "mocap", value_name = "DIR")]
    pub mocap: Vec<PathBuf>,
    /// Output dataset file (refuses to overwrite unless --force).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Projection protocol: canonical (Table-1 cameras exactly, orthographic), jittered
    /// (jittered cameras, perspective from 3-8 m, 2D noise), sphere (camera directions
    /// uniform over |elevation| <= 67.5 deg, labelled with the camera of their elevation ring and
    /// azimuth quadrant) or rig (tripod
    /// cameras 1.0-2.2 m high around a capture area, aimed at its centre, lens distortion,
    /// detector-like noise; the pelvis-to-camera direction labelled as under sphere).
    #[arg(long, default_value = "canonical", value_parser = parse_protocol)]
    pub protocol: Protocol,
    /// Consider every N-th mocap frame only (before selection by pose).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub stride: usize,
    /// Selection by pose: keep a frame when the largest distance of any joint to the same
    /// joint of every frame already kept for its clip is more than MM millimetres (canonical
    /// poses); 0 keeps every (strided) frame.
    #[arg(long, default_value_t = DEFAULT_MIN_POSE_DISTANCE_MM, value_name = "MM")]
    pub min_pose_distance: f64,
    /// The CMU index text giving each clip's motion category
    /// [default: cmu-mocap-index-text.txt in the first --mocap folder, or in the default one].
    #[arg(long, value_name = "FILE")]
    pub index: Option<PathBuf>,
    /// Augment each sample with the training augmentation (docs/conventions.md section 7):
    /// bone lengths +-10% per limb, hip and shoulder widths, limb rotations up to 25 deg, the
    /// upper body of another pose for half of the samples, photo-annotation placements of
    /// neck, pelvis and head for half of the samples (the default model's classifier puts
    /// every sample in them).
    #[arg(long)]
    pub augment: bool,
    /// Put this share of the samples in a posture (seated, squatting, kneeling, sitting on
    /// the floor) within joint-angle limits learned from the poses (docs/conventions.md
    /// section 7) [default: the training augmentation's with --augment, else 0].
    #[arg(long, value_name = "P")]
    pub posture: Option<f64>,
    /// Camera roll bound about the optical axis, degrees, at most 180 (jittered and sphere) [default: 5].
    #[arg(long, value_name = "DEG")]
    pub roll: Option<f64>,
    /// Camera distance range from the pelvis, metres, as NEAR,FAR (jittered and sphere)
    /// [default: 3,8].
    #[arg(long, value_name = "NEAR,FAR", value_parser = parse_distance)]
    pub distance: Option<(f64, f64)>,
    /// 2D Gaussian noise sigma as a fraction of the 2D torso length
    /// [default: 0 for canonical, 0.03 for jittered].
    #[arg(long, value_name = "F")]
    pub noise: Option<f64>,
    /// Random seed (camera jitter, noise, dropped landmarks).
    #[arg(long, default_value_t = 0, value_name = "S")]
    pub seed: u64,
    /// Camera sphere: "table1" (the paper's 12 cameras) or "N:E1,E2,..." for N azimuths at
    /// the given elevations in degrees, e.g. "8:-30,0,30".
    #[arg(long, default_value = "table1", value_name = "SPHERE", value_parser = parse_sphere)]
    pub sphere: CameraSet,
    /// Mark this many random non-torso landmarks per sample as missing.
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub drop_landmarks: usize,
    /// Also split by subject: write the held-out subjects' samples to this file and only
    /// the other subjects' samples to --out.
    #[arg(long, value_name = "FILE")]
    pub test_out: Option<PathBuf>,
    /// Subjects held out with --test-out, comma-separated [default: every fourth subject in
    /// sorted order, starting with the second].
    #[arg(long, value_name = "IDS", value_delimiter = ',', requires = "test_out")]
    pub test_subjects: Vec<String>,
    /// Overwrite --out (and --test-out) if they exist.
    #[arg(long)]
    pub force: bool,
}

/// Reads `--distance` "NEAR,FAR": two finite numbers of metres, `0 < NEAR <= FAR`.
fn parse_distance(s: &str) -> Result<(f64, f64), String> {
    let values: Vec<f64> = s
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected NEAR,FAR in metres (e.g. 3,8), got {s:?}"))?;
    match values[..] {
        [near, far] if near.is_finite() && far.is_finite() && 0.0 < near && near <= far => {
            Ok((near, far))
        }
        [_, _] => Err(format!("need 0 < NEAR <= FAR (finite metres), got {s:?}")),
        _ => Err(format!("expected two values NEAR,FAR, got {s:?}")),
    }
}

fn parse_protocol(s: &str) -> Result<Protocol, String> {
    s.parse()
}

/// Parses `table1` or `N:E1,E2,...`.
pub fn parse_sphere(s: &str) -> Result<CameraSet, String> {
    if s == "table1" {
        return Ok(CameraSet::table1());
    }
    let (n, elevations) = s
        .split_once(':')
        .ok_or_else(|| format!("expected 'table1' or 'N:E1,E2,...', got '{s}'"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("'{n}' is not a number of azimuths"))?;
    let elevations = elevations
        .split(',')
        .map(|e| {
            e.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{e}' is not an elevation in degrees"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    CameraSet::sphere(n, &elevations).map_err(|e| e.to_string())
}

/// Runs `gen-dataset`.
pub fn run(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    for out in std::iter::once(&args.out).chain(&args.test_out) {
        if out.exists() && !args.force {
            return Err(format!(
                "{}: already exists (pass --force to overwrite it)",
                out.display()
            ));
        }
    }
    let (mut sequences, summary, mut warnings) = load_sequences(&args.mocap)?;
    warnings += categorise(&mut sequences, &args.mocap, args.index.as_ref())?;
    let mut config = GenerateConfig::new(args.protocol);
    config.cameras = args.sphere.clone();
    config.stride = args.stride;
    config.min_pose_distance_mm = args.min_pose_distance;
    if args.augment {
        config.augmentation = Augmentation::TRAINING;
    }
    if let Some(posture) = args.posture {
        config.augmentation.posture = posture;
    }
    if let Some(roll) = args.roll {
        config.jitter.roll_deg = roll;
    }
    if let Some(range) = args.distance {
        config.jitter.distance_m = range;
    }
    config.noise_fraction = args.noise.unwrap_or(args.protocol.default_noise_fraction());
    config.seed = args.seed;
    config.drop_landmarks = args.drop_landmarks;
    let dataset = project(&sequences, &config)?;
    let dataset = match &args.test_out {
        None => dataset,
        Some(test_out) => {
            let test_subjects = if args.test_subjects.is_empty() {
                default_test_subjects(&dataset.subjects())
            } else {
                args.test_subjects.clone()
            };
            let known = dataset.subjects();
            if let Some(unknown) = test_subjects
                .iter()
                .find(|t| !known.iter().any(|(s, _)| s == *t))
            {
                // Subjects are named as their files are: `09`, not `9`.
                let padded = format!("{unknown:0>2}");
                let hint = if &padded != unknown && known.iter().any(|(s, _)| *s == padded) {
                    format!(" (did you mean '{padded}'? subjects are named as their files)")
                } else {
                    String::new()
                };
                return Err(format!(
                    "--test-subjects: no subject '{}' in the data{hint}",
                    camloc::store::quoted(unknown)
                ));
            }
            let (train, test) = dataset.split_by_subjects(&test_subjects);
            test.save(test_out, args.force).map_err(|e| e.to_string())?;
            println!(
                "wrote {} ({} samples of held-out subjects {})",
                test_out.display(),
                test.samples.len(),
                test_subjects.join(", ")
            );
            train
        }
    };
    dataset
        .save(&args.out, args.force)
        .map_err(|e| e.to_string())?;

    let subjects = dataset.subjects();
    println!(
        "wrote {} ({} samples, protocol {}, {} cameras, stride {}, min pose distance {} mm, noise {}, seed {}) in {:.1} s",
        args.out.display(),
        dataset.samples.len(),
        config.protocol,
        config.cameras.len(),
        config.stride,
        config.min_pose_distance_mm,
        // The rig adds its own detector-like noise besides.
        if config.protocol == Protocol::Rig {
            format!(
                "{} and the rig's detector-like noise",
                config.noise_fraction
            )
        } else {
            config.noise_fraction.to_string()
        },
        config.seed,
        start.elapsed().as_secs_f64()
    );
    println!(
        "files: {} read, {} skipped; frames: {} read, {} degenerate dropped, {} used after stride and selection",
        summary.files_read,
        summary.skipped.len(),
        summary.frames,
        summary.degenerate_frames,
        dataset.samples.len() / config.cameras.len().max(1)
    );
    let mut clips_per_subject: BTreeMap<&str, usize> = BTreeMap::new();
    for c in &dataset.header.clips {
        *clips_per_subject.entry(c.subject.as_str()).or_default() += 1;
    }
    println!("subjects ({}):", subjects.len());
    for (s, n) in &subjects {
        println!(
            "  {s:>6}: {:>3} clips, {n:>7} samples",
            clips_per_subject.get(s.as_str()).copied().unwrap_or(0)
        );
    }
    println!("samples per motion category:");
    for (category, n) in dataset.samples_per_category() {
        let clips = dataset
            .samples
            .iter()
            .filter(|s| dataset.category_of(s) == category)
            .map(|s| s.clip)
            .collect::<std::collections::BTreeSet<_>>()
            .len();
        println!("  {:<10} {clips:>3} clips, {n:>7} samples", category.name());
    }
    if config.protocol == Protocol::Sphere {
        let inside = dataset.samples.iter().filter(|s| s.in_class_box).count();
        println!(
            "inside the class boxes: {inside} of {} samples",
            dataset.samples.len()
        );
    }
    if dataset.header.undescribable_views > 0 {
        println!(
            "left out {} views that no descriptor can describe (a degenerate 2D torso)",
            dataset.header.undescribable_views
        );
    }
    if config.augmentation.posture > 0.0 {
        let l = &dataset.header.posture_limits;
        println!(
            "posture limits learned from the poses: hip flexion <= {:.1} deg, knee flexion <= {:.1} deg, torso pitch {:.1} to {:.1} deg",
            l.hip_flexion_max_deg, l.knee_flexion_max_deg, l.torso_pitch_deg.0, l.torso_pitch_deg.1
        );
    }
    println!("samples per camera:");
    // A finer sphere's level and side names repeat: its cameras' angles tell them apart.
    let repeat = dataset.header.cameras.names_repeat();
    for c in dataset.samples_per_camera() {
        if let Some(v) = dataset.header.cameras.get(c.label) {
            let angles = if repeat {
                format!(" {:<16}", format!("({})", v.angles_text()))
            } else {
                String::new()
            };
            println!(
                "  {} {:<6} {:<5}{angles} {:>8}",
                v.label_text(),
                v.level.name(),
                v.side.name(),
                c.samples
            );
        }
    }
    if warnings > 0 {
        println!("{warnings} warning(s) above");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_distance;

    #[test]
    fn distance_reads_near_comma_far_and_refuses_the_rest() {
        assert_eq!(parse_distance("3,8"), Ok((3.0, 8.0)));
        assert_eq!(parse_distance("2.5, 2.5"), Ok((2.5, 2.5)));
        for bad in ["3", "3,8,9", "8,3", "0,3", "-1,3", "3,inf", "a,b", ""] {
            assert!(parse_distance(bad).is_err(), "{bad:?}");
        }
    }
}
