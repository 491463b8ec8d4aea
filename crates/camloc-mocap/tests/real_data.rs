//! Every CMU file in the shared data folder parses to plausible human poses.
//! Skipped (with a message) when the data folder is absent; `CAMLOC_DATA` overrides its path.
//!
//! Nothing here assumes which folder holds which motion: files are counted over the whole
//! tree, and what a clip shows (a walk, a sit, ...) comes from the CMU index text beside them.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Instant;

use camloc_mocap::{
    CanonicaliseError, MocapClip, MocapIndex, MocapSource, MotionCategory, canonicalise, discover,
};
use camloc_skeleton::{LIMB_NAMES, LIMBS, Landmark, NUM_LIMBS};

/// The CMU folder; `None` (and a visible `SKIPPED` line naming `test`) when it is absent.
fn cmu_dir(test: &str) -> Option<PathBuf> {
    camloc_skeleton::data::data_path_or_skip("cmu", test)
}

/// Every clip under `cmu/`, read once per test binary; `None` (and a visible `SKIPPED` line
/// naming `test`) when the data is absent.
fn clips(test: &str) -> Option<&'static [(MocapSource, MocapClip)]> {
    static CLIPS: OnceLock<Vec<(MocapSource, MocapClip)>> = OnceLock::new();
    let dir = cmu_dir(test)?;
    let clips = CLIPS.get_or_init(|| {
        let start = Instant::now();
        let clips: Vec<_> = discover(&dir)
            .unwrap()
            .into_iter()
            .map(|source| {
                let clip = source.read().unwrap_or_else(|e| panic!("{e}"));
                (source, clip)
            })
            .collect();
        let frames: usize = clips.iter().map(|(_, c)| c.frames.len()).sum();
        eprintln!(
            "read {} clips, {frames} frames from {} in {:.2?} (single thread)",
            clips.len(),
            dir.display(),
            start.elapsed()
        );
        clips
    });
    Some(clips)
}

fn is_bvh(source: &MocapSource) -> bool {
    matches!(source, MocapSource::Bvh { .. })
}

/// The clips' categories from the CMU index beside them: `None` (and a visible `SKIPPED` line
/// naming `test`) when the index is absent.
fn categories(test: &str) -> Option<Vec<MotionCategory>> {
    let index_path =
        camloc_skeleton::data::data_path_or_skip("cmu/cmu-mocap-index-text.txt", test)?;
    let index = MocapIndex::load(&index_path).unwrap();
    let clips = clips(test)?;
    Some(
        clips
            .iter()
            .map(|(_, c)| index.category(&c.subject, &c.clip).0)
            .collect(),
    )
}

/// Files under `dir` (recursively, every folder) whose extension is `ext`, ignoring ASCII
/// case; counted here independently of [`discover`].
fn count_files(dir: &Path, ext: &str) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|path| {
            if path.is_dir() {
                count_files(&path, ext)
            } else {
                usize::from(
                    path.extension()
                        .is_some_and(|x| x.eq_ignore_ascii_case(ext)),
                )
            }
        })
        .sum()
}

#[test]
fn every_bvh_and_amc_file_is_found_and_parses() {
    let Some(clips) = clips("camloc-mocap::every_bvh_and_amc_file_is_found_and_parses") else {
        return;
    };
    let dir = cmu_dir("camloc-mocap::every_bvh_and_amc_file_is_found_and_parses").unwrap();
    let bvh = clips.iter().filter(|(s, _)| is_bvh(s)).count();
    assert_eq!(bvh, count_files(&dir, "bvh"));
    assert_eq!(clips.len() - bvh, count_files(&dir, "amc"));
    for (source, clip) in clips {
        assert!(!clip.frames.is_empty(), "{}", clip.clip);
        assert!(clip.frame_time_s > 0.0 && clip.frame_time_s < 0.1);
        assert!(clip.frames.iter().all(|f| f.is_finite()), "{}", clip.clip);
        assert_eq!(clip.subject, source.subject());
        assert!(clip.clip.starts_with(&format!("{}_", clip.subject)));
    }
}

/// Mean and relative standard deviation of one limb's length over a clip.
fn length_stats(clip: &MocapClip, limb: usize) -> (f64, f64) {
    let n = clip.frames.len() as f64;
    let lengths: Vec<f64> = clip.frames.iter().map(|f| f.limb_length(limb)).collect();
    let mean = lengths.iter().sum::<f64>() / n;
    let var = lengths.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt() / mean)
}

#[test]
fn bone_lengths_are_constant_and_human() {
    let Some(clips) = clips("camloc-mocap::bone_lengths_are_constant_and_human") else {
        return;
    };
    // Torso (pelvis-neck) and neck-head span several jointed bones in both formats; every other
    // limb is one rigid bone.
    let multi_joint = [6, 7];
    let mut worst = [0.0f64; NUM_LIMBS];
    for (_, clip) in clips {
        for limb in 0..NUM_LIMBS {
            let (mean, rel_std) = length_stats(clip, limb);
            worst[limb] = worst[limb].max(rel_std);
            let tolerance = if multi_joint.contains(&limb) {
                0.05
            } else {
                1e-9
            };
            assert!(
                rel_std < tolerance,
                "{}: {} length varies by {rel_std}",
                clip.clip,
                LIMB_NAMES[limb]
            );
            assert!(
                mean > 0.05 && mean < 0.6,
                "{}: {} is {mean} m",
                clip.clip,
                LIMB_NAMES[limb]
            );
        }
        for thigh in [1, 4] {
            let (mean, _) = length_stats(clip, thigh);
            assert!((0.3..0.6).contains(&mean), "{}: thigh {mean} m", clip.clip);
        }
    }
    for (limb, w) in worst.iter().enumerate() {
        eprintln!(
            "{:>16}: largest relative std over clips {w:.2e}",
            LIMB_NAMES[limb]
        );
    }
}

/// Share of frames (over all clips) whose head is above the pelvis, and the clips the CMU index
/// calls walks one by one: every frame of a walk is upright.
#[test]
fn real_motion_is_mostly_upright_and_walks_are_always_upright() {
    let test = "camloc-mocap::real_motion_is_mostly_upright_and_walks_are_always_upright";
    let (Some(clips), Some(categories)) = (clips(test), categories(test)) else {
        return;
    };
    let z = |f: &camloc_skeleton::Pose3, l: Landmark| f.get(l)[2];
    let (mut frames, mut head_up, mut walks) = (0usize, 0usize, 0usize);
    for ((_, clip), category) in clips.iter().zip(&categories) {
        walks += usize::from(*category == MotionCategory::Walk);
        for f in &clip.frames {
            frames += 1;
            head_up += usize::from(z(f, Landmark::Head) > z(f, Landmark::Pelvis));
            if *category == MotionCategory::Walk {
                let ankle = z(f, Landmark::LeftAnkle).min(z(f, Landmark::RightAnkle));
                assert!(
                    z(f, Landmark::Head) > z(f, Landmark::Pelvis) + 0.3
                        && z(f, Landmark::Pelvis) > ankle + 0.5,
                    "{}: a walking frame is not upright",
                    clip.clip
                );
            }
        }
    }
    let share = head_up as f64 / frames as f64;
    eprintln!(
        "head above pelvis in {head_up} of {frames} frames ({:.2}%); {walks} walks upright",
        100.0 * share
    );
    assert!(walks > 0, "the index calls no clip a walk");
    // Dives, rolls and handstand-like moves turn a few frames upside down; most motion is upright.
    assert!(
        share > 0.95,
        "head above pelvis in only {:.2}%",
        100.0 * share
    );
}

/// Every frame that can be canonicalised satisfies the canonical frame's definition: pelvis at
/// the origin, the horizontal lateral direction (hips plus shoulders) along +y, heights above
/// the pelvis and limb lengths kept; the others have no horizontal lateral direction. Over the
/// clips the CMU index calls walks, the body faces -x: knees, which only bend forwards, lie
/// ahead.
#[test]
fn canonical_frames_satisfy_the_definition_and_walks_face_minus_x() {
    let test = "camloc-mocap::canonical_frames_satisfy_the_definition_and_walks_face_minus_x";
    let (Some(clips), Some(categories)) = (clips(test), categories(test)) else {
        return;
    };
    let (mut frames, mut degenerate) = (0usize, 0usize);
    let (mut knee_forward, mut walk_frames) = (0.0, 0usize);
    for ((_, clip), category) in clips.iter().zip(&categories) {
        for pose in &clip.frames {
            frames += 1;
            let c = match canonicalise(pose) {
                Ok(c) => c,
                Err(e @ CanonicaliseError::NoLateralDirection { .. }) => {
                    degenerate += 1;
                    eprintln!("{}: {e}", clip.clip);
                    continue;
                }
                Err(e) => panic!("{}: {e}", clip.clip),
            };
            assert!(c.get(Landmark::Pelvis).iter().all(|v| *v == 0.0));
            let lateral = |r: Landmark, l: Landmark| {
                let (r, l) = (c.get(r), c.get(l));
                [r[0] - l[0], r[1] - l[1]]
            };
            let (h, s) = (
                lateral(Landmark::RightHip, Landmark::LeftHip),
                lateral(Landmark::RightShoulder, Landmark::LeftShoulder),
            );
            let (x, y) = (h[0] + s[0], h[1] + s[1]);
            assert!(
                y > 0.0 && x.abs() <= 1e-9 * y.max(1.0),
                "{}: lateral ({x}, {y})",
                clip.clip
            );
            let pelvis_z = pose.get(Landmark::Pelvis)[2];
            for l in Landmark::ALL {
                assert!((c.get(l)[2] - (pose.get(l)[2] - pelvis_z)).abs() < 1e-9);
            }
            for limb in 0..LIMBS.len() {
                assert!((c.limb_length(limb) - pose.limb_length(limb)).abs() < 1e-9);
            }
            if *category == MotionCategory::Walk {
                walk_frames += 1;
                for (hip, knee, ankle) in [
                    (Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle),
                    (
                        Landmark::RightHip,
                        Landmark::RightKnee,
                        Landmark::RightAnkle,
                    ),
                ] {
                    knee_forward += c.get(knee)[0] - 0.5 * (c.get(hip)[0] + c.get(ankle)[0]);
                }
            }
        }
    }
    let mean = knee_forward / (2.0 * walk_frames as f64);
    eprintln!(
        "{degenerate} of {frames} frames without a lateral direction; walking knees {:.1} mm ahead",
        -1000.0 * mean
    );
    assert!(
        degenerate * 1000 < frames,
        "{degenerate} of {frames} frames degenerate"
    );
    assert!(mean < -0.05, "walking knees {mean} m ahead");
}

#[test]
fn bvh_and_asf_of_one_subject_agree_except_for_the_thorax() {
    let Some(clips) = clips("camloc-mocap::bvh_and_asf_of_one_subject_agree_except_for_the_thorax")
    else {
        return;
    };
    // Subject 16 is in both folders (BVH walks, ASF/AMC jumps) with the same skeleton.
    let first = |bvh: bool| {
        clips
            .iter()
            .find(|(s, c)| c.subject == "16" && is_bvh(s) == bvh)
            .map(|(_, c)| c)
    };
    let (Some(bvh), Some(amc)) = (first(true), first(false)) else {
        let line = "\nSKIPPED: camloc-mocap::bvh_and_asf_of_one_subject_agree_except_for_the_thorax: \
                    subject 16 is not in both formats\n";
        let _ = std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes());
        return;
    };
    for limb in (0..NUM_LIMBS).filter(|l| *l != 6 && *l != 7) {
        let (b, a) = (length_stats(bvh, limb).0, length_stats(amc, limb).0);
        assert!(
            (a - b).abs() < 1e-4,
            "{}: BVH {b} m, ASF {a} m",
            LIMB_NAMES[limb]
        );
    }
    // The BVH has no thorax bone (2.17 units, 0.123 m, in 16.asf): its torso is that much
    // shorter, up to spine bending.
    let (b, a) = (length_stats(bvh, 6).0, length_stats(amc, 6).0);
    assert!((a - b - 0.123).abs() < 0.02, "torso: BVH {b} m, ASF {a} m");
}
