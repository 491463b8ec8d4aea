//! A sequence's frame rate (`PoseReconstructor::with_frame_rate`, `reconstruct --sequence
//! --fps`): a held-out CMU walk filmed from a tripod at the clip's own 120 frames a second with
//! detector-like noise, reconstructed as `camloc reconstruct --sequence` does and placed in the
//! camera's world, told its rate and not. Told it, the smoothing keeps its windows in time and
//! the animation moves as smoothly as at 30 frames a second; not told, every window is a
//! quarter as long and the noise of each frame shows as accelerations of hundreds of m/s^2.
//! Skipped, visibly, without the data.

mod tripod;

use camloc::reconstruct::mpjpe_after_similarity;
use camloc::skeleton::Pose2;
use camloc::{PartialPose2, Pose3, PoseReconstructor};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tripod::{held_out_walks, hybrid_reconstructor, tripod};

/// Frames of the walk, at its own 120 a second.
const FRAMES: usize = 480;
/// Frames a second of the clip.
const RATE_HZ: f64 = 120.0;
/// Deviation of the 2D noise, pixels (about 1.5% of the walker's height in the image).
const NOISE_PX: f64 = 4.0;

/// `keypoints` with independent Gaussian noise of [`NOISE_PX`] on every coordinate.
fn noisy(keypoints: &[Pose2], rng: &mut ChaCha8Rng) -> Vec<PartialPose2> {
    let mut gauss = || {
        let (u, v): (f64, f64) = (rng.random(), rng.random());
        (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    keypoints
        .iter()
        .map(|k| {
            PartialPose2::from(Pose2::new(
                k.points.map(|p| p.map(|c| c + NOISE_PX * gauss())),
            ))
        })
        .collect()
}

/// The mean magnitude of the landmarks' accelerations about the pelvis, m/s^2.
fn acceleration(poses: &[Pose3]) -> f64 {
    let about = |p: &Pose3, j: usize, k: usize| p.points[j][k] - p.points[0][k];
    let mut total = 0.0;
    for w in poses.windows(3) {
        for j in 1..15 {
            let second: f64 = (0..3)
                .map(|k| {
                    (about(&w[2], j, k) - 2.0 * about(&w[1], j, k) + about(&w[0], j, k)).powi(2)
                })
                .sum();
            total += second.sqrt() * RATE_HZ * RATE_HZ;
        }
    }
    total / (14 * (poses.len() - 2)) as f64
}

#[test]
fn a_walk_at_120_frames_a_second_told_its_rate_moves_as_smoothly_as_at_30() {
    let test = "frame rate of a held-out CMU walk";
    let Some(cmu) = camloc::skeleton::data::data_path_or_skip("cmu", test) else {
        return;
    };
    let walks = held_out_walks(&cmu);
    let clip = walks
        .iter()
        .map(|s| s.read().unwrap())
        .find(|c| c.frames.len() >= FRAMES)
        .expect("a held-out walk of 4 s");
    let truth = &clip.frames[..FRAMES];
    let keypoints = noisy(&tripod(truth), &mut ChaCha8Rng::seed_from_u64(7));
    let reconstructor = hybrid_reconstructor();
    let measure = |reconstructor: &PoseReconstructor| {
        let found = reconstructor.reconstruct_sequence(&keypoints).unwrap();
        let frames: Vec<_> = found.frames.iter().map(|f| f.as_ref().ok()).collect();
        let placed: Vec<Pose3> = reconstructor
            .place_in_world(&frames)
            .into_iter()
            .map(|p| p.expect("every frame is reconstructed"))
            .collect();
        let error = placed
            .iter()
            .zip(truth)
            .map(|(p, t)| mpjpe_after_similarity(p, t))
            .sum::<f64>()
            / FRAMES as f64;
        (acceleration(&placed), error)
    };
    let (untold, untold_error) = measure(&reconstructor);
    let told = reconstructor.with_frame_rate(RATE_HZ).unwrap();
    let (smooth, error) = measure(&told);
    let truth_acceleration = acceleration(truth);
    eprintln!(
        "{} at {RATE_HZ} frames a second, {NOISE_PX} px noise: landmarks' acceleration about \
         the pelvis {untold:.1} m/s^2 untold, {smooth:.1} told (the truth's {truth_acceleration:.1}); \
         PA-MPJPE {untold_error:.1} mm untold, {error:.1} told",
        clip.clip
    );
    assert!(smooth < untold / 4.0, "{smooth} against {untold} m/s^2");
    assert!(
        error < untold_error + 1.0,
        "{error} against {untold_error} mm"
    );
    assert!(hybrid_reconstructor().with_frame_rate(0.0).is_err());
}
