//! The held-out people of the proportions test: each subject's skeleton rescaled by known
//! random factors, and the frames taken from their clips (single poses and windows of
//! consecutive frames).

use camloc::Pose3;
use camloc::dataset::{MotionCategory, PoseSequence, select_by_pose};
use camloc::skeleton::{LIMBS, NUM_LIMBS};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Limb factor range of the rescaled people (each limb type, left and right alike).
pub const LIMB_FACTOR: (f64, f64) = (0.8, 1.2);
/// Neck-to-head factor range: where detectors put the head (the face of COCO-like detectors
/// is lower than CMU's head point, the head top of LSP and MPII higher).
pub const HEAD_FACTOR: (f64, f64) = (0.6, 1.6);

/// The limb type of each limb (left and right share a type and a factor).
const LIMB_TYPE: [usize; NUM_LIMBS] = [0, 1, 2, 0, 1, 2, 3, 4, 5, 6, 7, 5, 6, 7];

/// Per limb, the factor a subject's limbs are scaled by: one draw per limb type (hip width,
/// thigh, shin, torso, collar = shoulder width, upper arm, forearm) from [`LIMB_FACTOR`], the
/// neck-head limb from [`HEAD_FACTOR`]; seeded by the subject, so every frame of a subject
/// has one skeleton.
pub fn factors(subject: &str, seed: u64) -> [f64; NUM_LIMBS] {
    let key = subject.bytes().fold(seed ^ 0x9E37_79B9_7F4A_7C15, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
    });
    let mut rng = ChaCha8Rng::seed_from_u64(key);
    let types: [f64; 8] = std::array::from_fn(|_| rng.random_range(LIMB_FACTOR.0..=LIMB_FACTOR.1));
    let head = rng.random_range(HEAD_FACTOR.0..=HEAD_FACTOR.1);
    std::array::from_fn(|b| if b == 7 { head } else { types[LIMB_TYPE[b]] })
}

/// `pose` with each limb scaled by its factor, the limbs below following (the pelvis stays).
pub fn rescale(pose: &Pose3, factors: &[f64; NUM_LIMBS]) -> Pose3 {
    let mut out = *pose;
    for (b, (parent, child)) in LIMBS.iter().enumerate() {
        let (p, c) = (parent.index(), child.index());
        out.points[c] = std::array::from_fn(|k| {
            out.points[p][k] + factors[b] * (pose.points[c][k] - pose.points[p][k])
        });
    }
    out
}

/// A test pose (or window of consecutive poses) with its subject and motion category.
pub struct Frames {
    /// The subject.
    pub subject: String,
    /// Walking or another category.
    pub category: MotionCategory,
    /// The poses (canonical, metres).
    pub poses: Vec<Pose3>,
}

/// Median largest per-landmark move between consecutive frames below which a clip is taken
/// at every 4th frame (a 120 fps clip seen at 30 fps), metres.
const FAST_CLIP_STEP_M: f64 = 0.04;

/// The frame step that brings `clip` to about 30 frames a second: 4 for clips whose
/// consecutive frames move less than [`FAST_CLIP_STEP_M`] at the median (120 fps), else 1.
fn step_of(clip: &PoseSequence) -> usize {
    let mut moves: Vec<f64> = clip
        .frames
        .windows(2)
        .map(|w| {
            w[0].1
                .points
                .iter()
                .zip(&w[1].1.points)
                .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max)
        })
        .collect();
    moves.sort_by(f64::total_cmp);
    match moves.get(moves.len() / 2) {
        Some(&m) if m < FAST_CLIP_STEP_M => 4,
        _ => 1,
    }
}

/// Windows of `length` consecutive frames at about 30 frames a second (see [`step_of`]), at
/// most `per_clip` of them spread evenly over each clip long enough.
pub fn windows(clips: &[PoseSequence], length: usize, per_clip: usize) -> Vec<Frames> {
    let mut out = Vec::new();
    for clip in clips {
        let step = step_of(clip);
        let poses: Vec<Pose3> = clip.frames.iter().step_by(step).map(|(_, p)| *p).collect();
        if poses.len() < length {
            continue;
        }
        let room = poses.len() - length;
        let count = per_clip.min(room / length + 1).max(1);
        for k in 0..count {
            let start = if count == 1 {
                room / 2
            } else {
                k * room / (count - 1)
            };
            out.push(Frames {
                subject: clip.clip.subject.clone(),
                category: clip.clip.category,
                poses: poses[start..start + length].to_vec(),
            });
        }
    }
    out
}

/// The poses of `clips` selected by pose at `min_distance_mm`, every `every`-th of them,
/// each alone.
pub fn single_poses(clips: &[PoseSequence], min_distance_mm: f64, every: usize) -> Vec<Frames> {
    let mut out = Vec::new();
    for clip in clips {
        let poses: Vec<&Pose3> = clip.frames.iter().map(|(_, p)| p).collect();
        for k in select_by_pose(&poses, min_distance_mm) {
            out.push(Frames {
                subject: clip.clip.subject.clone(),
                category: clip.clip.category,
                poses: vec![*poses[k]],
            });
        }
    }
    out.into_iter().step_by(every.max(1)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rescaling_scales_each_limb_by_its_factor() {
        let mut pose = Pose3::new([[0.0; 3]; 15]);
        for (i, p) in pose.points.iter_mut().enumerate().skip(1) {
            let t = i as f64;
            *p = [(t * 0.7).sin() * 0.4, (t * 1.3).cos() * 0.3, t * 0.05 - 0.3];
        }
        let f = factors("35", 1);
        assert_eq!(f, factors("35", 1));
        assert_ne!(f, factors("36", 1));
        assert_eq!(f[1], f[4]);
        let scaled = rescale(&pose, &f);
        for (b, factor) in f.iter().enumerate() {
            let ratio = scaled.limb_length(b) / pose.limb_length(b);
            assert!(
                (ratio - factor).abs() < 1e-12,
                "limb {b}: {ratio} vs {factor}"
            );
        }
    }
}
