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
    /// The anchor of `pose`, `None` when its pelvis or neck is missing, or they coincide or
    /// are not finite.
    pub fn of(pose: &PartialPose2) -> Option<TorsoAnchor> {
        let pelvis = pose.points[Landmark::Pelvis.index()]?;
        let neck = pose.points[Landmark::Neck.index()]?;
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
    let mut jumps = Vec::new();
    let mut previous: Option<(usize, TorsoAnchor)> = None;
    for (k, anchor) in filtered {
        if let Some((j, before)) = previous {
            let elapsed = match (
                frames.get(j).copied().flatten(),
                frames.get(k).copied().flatten(),
            ) {
                (Some(a), Some(b)) if b > a => (b - a) as f64,
                _ => (k - j) as f64,
            };
            let moved =
                (anchor.pelvis[0] - before.pelvis[0]).hypot(anchor.pelvis[1] - before.pelvis[1]);
            let torso = 0.5 * (anchor.torso + before.torso);
            let ratio = anchor.torso.max(before.torso) / anchor.torso.min(before.torso);
            if moved > IDENTITY_JUMP_TORSOS * elapsed * torso
                || (elapsed <= 1.0 && ratio > IDENTITY_SIZE_RATIO)
            {
                jumps.push(k);
            }
        }
        previous = Some((k, anchor));
    }
    jumps
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
        // One frame whose hips a detector misplaced is not a jump.
        let mut misplaced = walk.clone();
        misplaced[5] = at(400.0, 40.0);
        assert!(identity_jumps(&frames, &misplaced).is_empty());
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
