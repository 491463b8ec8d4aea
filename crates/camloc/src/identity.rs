//! Whether the frames of one sequence show one person: [`identity_jumps`] finds the steps at
//! which the pose jumps across the image or changes size as no person moves in a frame, which is
//! what a detector's order of people does when it changes (OpenPose's `people[i]` is that
//! order, not a tracked identity) or when two people share one id.

use camloc_skeleton::{Landmark, PartialPose2};

/// The distance, in 2D torso lengths (pelvis to neck) per frame elapsed, that a pelvis may move
/// between two frames of one person before [`identity_jumps`] reports the step. A person
/// running past a camera at 30 frames a second moves the pelvis about a third of a torso a
/// frame.
pub const IDENTITY_JUMP_TORSOS: f64 = 1.0;

/// The ratio of two consecutive frames' 2D torso lengths above which [`identity_jumps`]
/// reports the step: a person walking towards a camera grows by a few percent a frame.
pub const IDENTITY_SIZE_RATIO: f64 = 2.0;

/// Where one frame's person is in the image: the pelvis and the 2D torso length (pelvis to
/// neck), in the input's image units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsoAnchor {
    /// The pelvis.
    pub pelvis: [f64; 2],
    /// The distance from the pelvis to the neck (positive).
    pub torso: f64,
}

impl TorsoAnchor {
    /// The anchor of `pose`: its pelvis, else the midpoint of its hips, else the hip it has;
    /// its neck, else the midpoint of its shoulders, else the shoulder it has (a low-scored
    /// pelvis or neck is often where people occlude each other, which is where identities
    /// switch). `None` when it has neither hip nor shoulder, or the two points coincide or are
    /// not finite.
    pub fn of(pose: &PartialPose2) -> Option<TorsoAnchor> {
        let point = |centre: Landmark, pair: [Landmark; 2]| {
            pose.points[centre.index()].or_else(|| match pair.map(|l| pose.points[l.index()]) {
                [Some(a), Some(b)] => Some([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]),
                [a, b] => a.or(b),
            })
        };
        let pelvis = point(Landmark::Pelvis, [Landmark::LeftHip, Landmark::RightHip])?;
        let neck = point(
            Landmark::Neck,
            [Landmark::LeftShoulder, Landmark::RightShoulder],
        )?;
        let torso = (neck[0] - pelvis[0]).hypot(neck[1] - pelvis[1]);
        (torso.is_finite() && torso > 0.0 && pelvis.iter().all(|v| v.is_finite()))
            .then_some(TorsoAnchor { pelvis, torso })
    }
}

/// The positions `k` (from 1) of one person's frames, in time order, at which the step from
/// the previous frame with an anchor is not one person moving: the pelvis moves more than
/// [`IDENTITY_JUMP_TORSOS`] torso lengths (their mean) per frame elapsed, or, between
/// consecutive frame numbers, the torso length changes by more than [`IDENTITY_SIZE_RATIO`].
/// The anchors are compared after a median of three (each with the frames with anchors before
/// and after it), so that one frame whose hips or shoulders a detector misplaced is not a jump
/// while a change of person that lasts two frames or more is.
///
/// `frames[k]` is frame `k`'s number (`None`: one frame after the previous one) and
/// `anchors[k]` its [`TorsoAnchor`] (`None`: skipped, as a frame without a torso).
pub fn identity_jumps(frames: &[Option<u64>], anchors: &[Option<TorsoAnchor>]) -> Vec<usize> {
    let present: Vec<(usize, TorsoAnchor)> = anchors
        .iter()
        .enumerate()
        .filter_map(|(k, a)| a.map(|a| (k, a)))
        .collect();
    let median = |values: [f64; 3]| {
        let mut v = values;
        v.sort_by(f64::total_cmp);
        v[1]
    };
    let filtered = present.iter().enumerate().map(|(m, &(k, a))| {
        if m == 0 || m + 1 == present.len() {
            return (k, a);
        }
        let (b, c) = (present[m - 1].1, present[m + 1].1);
        let smoothed = TorsoAnchor {
            pelvis: [0, 1].map(|i| median([b.pelvis[i], a.pelvis[i], c.pelvis[i]])),
            torso: median([b.torso, a.torso, c.torso]),
        };
        (k, smoothed)
    });
    let mut found = Vec::new();
    let mut previous: Option<(usize, TorsoAnchor)> = None;
    for (k, anchor) in filtered {
        if let Some((j, before)) = previous {
            if jumps(&before, &anchor, elapsed(frames, j, k)) {
                found.push(k);
            }
        }
        previous = Some((k, anchor));
    }
    found
}

/// Whether the step from `before` to `after` (`elapsed` frames apart) is not one person
/// moving: the pelvis moves more than [`IDENTITY_JUMP_TORSOS`] torso lengths (their mean) per
/// frame elapsed, or, over one frame, the torso length changes by more than
/// [`IDENTITY_SIZE_RATIO`].
fn jumps(before: &TorsoAnchor, after: &TorsoAnchor, elapsed: f64) -> bool {
    let moved = (after.pelvis[0] - before.pelvis[0]).hypot(after.pelvis[1] - before.pelvis[1]);
    let torso = 0.5 * (after.torso + before.torso);
    let ratio = after.torso.max(before.torso) / after.torso.min(before.torso);
    moved > IDENTITY_JUMP_TORSOS * elapsed * torso
        || (elapsed <= 1.0 && ratio > IDENTITY_SIZE_RATIO)
}

/// Frames elapsed from position `j` to position `k` (`k > j`) of one person's frames: by their
/// frame numbers where both have one in that order, else by their positions.
fn elapsed(frames: &[Option<u64>], j: usize, k: usize) -> f64 {
    match (
        frames.get(j).copied().flatten(),
        frames.get(k).copied().flatten(),
    ) {
        (Some(a), Some(b)) if b > a => (b - a) as f64,
        _ => (k - j) as f64,
    }
}

/// The positions of one person's frames (in time order; `frames` and `anchors` as for
/// [`identity_jumps`]) whose pose is not where the frames before and after it put the person
/// while those two agree with each other: one frame that holds another person's detection (two
/// tracked people's ids swapped for one frame) or a detection a detector misplaced. The median
/// of [`identity_jumps`] does not count such a frame as a change of person; its pose is still
/// not this person's. The first (last) frame with an anchor is judged by the two after (before)
/// it: apart from both while they agree.
pub fn outlier_frames(frames: &[Option<u64>], anchors: &[Option<TorsoAnchor>]) -> Vec<usize> {
    let present: Vec<(usize, TorsoAnchor)> = anchors
        .iter()
        .enumerate()
        .filter_map(|(k, a)| a.map(|a| (k, a)))
        .collect();
    // Whether `b` lies apart from `a` and `c`, which agree (each an anchor and its position,
    // in time order or reversed).
    let apart = |(i, a): (usize, TorsoAnchor),
                 (k, b): (usize, TorsoAnchor),
                 (l, c): (usize, TorsoAnchor)| {
        let steps = |x: usize, y: usize| elapsed(frames, x.min(y), x.max(y));
        jumps(&a, &b, steps(i, k)) && jumps(&b, &c, steps(k, l)) && !jumps(&a, &c, steps(i, l))
    };
    // Positions in `present` of the frames apart from both neighbours; of three in a row, the
    // middle one is the person between two misplaced frames (ids swapped at frames 20 and 22
    // make 21 look apart from both), and stays.
    let candidates: Vec<usize> = (1..present.len().saturating_sub(1))
        .filter(|&m| apart(present[m - 1], present[m], present[m + 1]))
        .collect();
    let mut found: Vec<usize> = candidates
        .iter()
        .filter(|&&m| !(candidates.contains(&(m - 1)) && candidates.contains(&(m + 1))))
        .map(|&m| present[m].0)
        .collect();
    let n = present.len();
    if n >= 3 {
        // The ends: the first against the second and third (the second standing between),
        // the last against the two before it.
        if apart(present[2], present[0], present[1]) {
            found.insert(0, present[0].0);
        }
        if apart(present[n - 3], present[n - 1], present[n - 2]) {
            found.push(present[n - 1].0);
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, torso: f64) -> Option<TorsoAnchor> {
        Some(TorsoAnchor {
            pelvis: [x, 0.0],
            torso,
        })
    }

    #[test]
    fn a_walk_has_no_jump_and_a_switch_of_people_has_one() {
        // 100 px torso, 20 px a frame: one person walking.
        let walk: Vec<_> = (0..10).map(|t| at(20.0 * f64::from(t), 100.0)).collect();
        let frames: Vec<Option<u64>> = (0..10).map(Some).collect();
        assert!(identity_jumps(&frames, &walk).is_empty());
        // Another person 300 px away from frame 6 on.
        let mut switched = walk.clone();
        for a in switched.iter_mut().skip(6) {
            a.as_mut().unwrap().pelvis[0] += 300.0;
        }
        assert_eq!(identity_jumps(&frames, &switched), vec![6]);
        // The same place, but two and a half times the size (a person nearer the camera)
        // from frame 4 on.
        let mut nearer = walk.clone();
        for a in nearer.iter_mut().skip(4) {
            a.as_mut().unwrap().torso = 250.0;
        }
        assert_eq!(identity_jumps(&frames, &nearer), vec![4]);
        // One frame whose hips a detector misplaced is not a jump, but an outlier.
        let mut misplaced = walk.clone();
        misplaced[5] = at(400.0, 40.0);
        assert!(identity_jumps(&frames, &misplaced).is_empty());
        assert_eq!(outlier_frames(&frames, &misplaced), vec![5]);
        // Neither a walk nor a lasting switch has an outlier; two people's ids swapped for
        // one frame give one in each.
        assert!(outlier_frames(&frames, &walk).is_empty());
        assert!(outlier_frames(&frames, &switched).is_empty());
        let other: Vec<_> = (0..10)
            .map(|t| at(900.0 - 10.0 * f64::from(t), 100.0))
            .collect();
        let (mut a, mut b) = (walk.clone(), other.clone());
        std::mem::swap(&mut a[3], &mut b[3]);
        assert_eq!(outlier_frames(&frames, &a), vec![3]);
        assert_eq!(outlier_frames(&frames, &b), vec![3]);
        // Ids swapped at two frames with one between: the frame between is the person's.
        let (mut a, mut b) = (walk.clone(), other.clone());
        for t in [4, 6] {
            std::mem::swap(&mut a[t], &mut b[t]);
        }
        assert_eq!(outlier_frames(&frames, &a), vec![4, 6]);
        assert_eq!(outlier_frames(&frames, &b), vec![4, 6]);
        // At either end of a track.
        for end in [0, 9] {
            let (mut a, mut b) = (walk.clone(), other.clone());
            std::mem::swap(&mut a[end], &mut b[end]);
            assert_eq!(outlier_frames(&frames, &a), vec![end]);
            assert_eq!(outlier_frames(&frames, &b), vec![end]);
        }
        // A person running past a camera filmed at a low frame rate moves far every frame:
        // no outlier, as the frames before and after disagree too.
        let fast: Vec<_> = (0..10).map(|t| at(150.0 * f64::from(t), 100.0)).collect();
        assert!(outlier_frames(&frames, &fast).is_empty());
    }

    #[test]
    fn a_missing_pelvis_or_neck_is_stood_in_for_by_hips_or_shoulders() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::LeftHip.index()] = Some([-10.0, 0.0]);
        pose.points[Landmark::RightHip.index()] = Some([10.0, 0.0]);
        pose.points[Landmark::LeftShoulder.index()] = Some([-20.0, -100.0]);
        assert_eq!(
            TorsoAnchor::of(&pose),
            Some(TorsoAnchor {
                pelvis: [0.0, 0.0],
                torso: 20.0f64.hypot(100.0)
            })
        );
        pose.points[Landmark::LeftShoulder.index()] = None;
        assert_eq!(TorsoAnchor::of(&pose), None);
    }

    #[test]
    fn gaps_allow_longer_moves_and_frames_without_a_torso_are_skipped() {
        let anchors = [
            at(0.0, 100.0),
            at(0.0, 100.0),
            None,
            at(250.0, 100.0),
            at(250.0, 100.0),
        ];
        // Frame numbers 1 and 4: 250 px in 3 frames is within a torso a frame.
        let gap = [Some(0), Some(1), Some(2), Some(4), Some(5)];
        assert!(identity_jumps(&gap, &anchors).is_empty());
        // Consecutive frame numbers around the frame without a torso: two frames elapsed.
        let frames: Vec<Option<u64>> = (0..5).map(Some).collect();
        assert_eq!(identity_jumps(&frames, &anchors), vec![3]);
        assert!(identity_jumps(&[None, None, None], &[at(0.0, 100.0), at(90.0, 100.0)]).is_empty());
    }
}
