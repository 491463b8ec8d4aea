//! Left and right limbs that a 2D detector swapped for a few frames of a video: in a side or
//! back view a detector often labels the left leg right and the right leg left for a frame or
//! three. One frame so read is another pose (on held-out CMU views its 3D error was 143 mm
//! with the legs swapped and 115 mm with the arms, against 42), and a sequence's bone lengths
//! and smoothness take it in.

use camloc_reconstruct::FrameRate;
use camloc_skeleton::{Landmark, PartialPose2};

use crate::sequence::number_or_position;

/// A chain of landmarks whose left and right sides a detector can confuse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SideChain {
    /// Hips, knees and ankles.
    Legs,
    /// Shoulders, elbows and wrists.
    Arms,
}

impl SideChain {
    /// Every chain.
    pub const ALL: [SideChain; 2] = [SideChain::Legs, SideChain::Arms];

    /// The chain's (left, right) landmark pairs, from the torso out.
    pub const fn pairs(self) -> [(Landmark, Landmark); 3] {
        match self {
            SideChain::Legs => [
                (Landmark::LeftHip, Landmark::RightHip),
                (Landmark::LeftKnee, Landmark::RightKnee),
                (Landmark::LeftAnkle, Landmark::RightAnkle),
            ],
            SideChain::Arms => [
                (Landmark::LeftShoulder, Landmark::RightShoulder),
                (Landmark::LeftElbow, Landmark::RightElbow),
                (Landmark::LeftWrist, Landmark::RightWrist),
            ],
        }
    }

    /// The chain's name in messages: `legs`, `arms`.
    pub const fn name(self) -> &'static str {
        match self {
            SideChain::Legs => "legs",
            SideChain::Arms => "arms",
        }
    }
}

/// Which landmarks of a chain a frame read with its sides swapped has exchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SwappedPart {
    /// The whole chain: hips, knees and ankles (shoulders, elbows and wrists), a body read
    /// as seen from the other side.
    Whole,
    /// The limbs beyond the torso: knees and ankles (elbows and wrists), the hips (shoulders)
    /// as they are: a detector confusing crossing shins or forearms.
    Distal,
}

impl SwappedPart {
    /// Whether the chain's `pair`-th (left, right) pair ([`SideChain::pairs`], from the
    /// torso out) is exchanged.
    const fn exchanges(self, pair: usize) -> bool {
        match self {
            SwappedPart::Whole => true,
            SwappedPart::Distal => pair > 0,
        }
    }
}

/// The least cost of reading one frame's chain with its sides swapped, in squared torso
/// lengths: a swap must take away at least this much motion between the frames around it.
pub const SIDE_SWAP_PENALTY: f64 = 0.1;

/// The cost of a swapped frame is also at least this many times the median motion of the
/// chain from one frame to the next (squared torso lengths): a video of few frames a second
/// moves more between frames. With the other rules in place, 3 swapped back 3 real frames
/// of a simulated user's 16,192 (running and walking at 10-30 frames a second under detector
/// noise); 5 none.
pub const SIDE_SWAP_MOTION_FACTOR: f64 = 5.0;

/// At each end of a run swapped back, the motion into the run swapped must be at most this
/// share of the motion as read: a clear jump that the swap takes away, not noise.
pub const SIDE_SWAP_JOIN_RATIO: f64 = 0.25;

/// The most frames in a row that are swapped back: a detector's confusion of a moment. A
/// longer stretch read with the sides swapped (a back view a detector took for a front view)
/// is left as it is: which part of the track is right is not known.
pub const SIDE_SWAP_RUN_FRAMES: usize = 5;

/// Frames (with a torso) whose numbers are further apart than this do not constrain each
/// other's sides.
pub const SIDE_SWAP_GAP_FRAMES: u64 = 3;

/// `pose` with the left and right landmarks of `chain` exchanged.
pub fn with_sides_swapped(pose: &PartialPose2, chain: SideChain) -> PartialPose2 {
    with_part_swapped(pose, chain, SwappedPart::Whole)
}

/// `pose` with the left and right landmarks of `part` of `chain` exchanged.
pub fn with_part_swapped(pose: &PartialPose2, chain: SideChain, part: SwappedPart) -> PartialPose2 {
    let mut swapped = *pose;
    for (i, (left, right)) in chain.pairs().into_iter().enumerate() {
        if part.exchanges(i) {
            swapped.points.swap(left.index(), right.index());
        }
    }
    swapped
}

/// Per chain, the positions of one person's frames (`frames` their numbers, `None` for one
/// frame after the previous one; `poses` in time order) whose chain is read with its left and
/// right sides swapped against the frames around them, and the part swapped, to be swapped
/// back ([`with_part_swapped`]). The sides of the frames with a torso are chosen together (a
/// Viterbi path over as read, the whole chain swapped, or its limbs beyond the torso
/// swapped): the least motion of the chain relative to the pelvis
/// (in torso lengths, squared) between consecutive such frames, plus [`SIDE_SWAP_PENALTY`]
/// (or [`SIDE_SWAP_MOTION_FACTOR`] times the median motion) for each frame swapped, in runs
/// of at most [`SIDE_SWAP_RUN_FRAMES`] frames. A run is swapped back only between frames
/// of the track as read (not at its first or last frame), where at each end the frames as
/// read jump by more than the penalty and swapped join with at most
/// [`SIDE_SWAP_JOIN_RATIO`] of that. Frames more than [`SIDE_SWAP_GAP_FRAMES`] numbers apart
/// do not constrain each other; a frame without a torso is left as read and skipped. The
/// frame counts are at 30 frames a second: at `rate`'s faster ones the runs and gaps are
/// [`FrameRate::step`] times as many frames and a swapped frame costs the penalty divided by
/// it (a swap of 0.1 s is 3 frames at 30 a second, 12 at 120, and costs as much).
pub fn swapped_sides(
    frames: &[Option<u64>],
    poses: &[PartialPose2],
    rate: FrameRate,
) -> Vec<(SideChain, Vec<(usize, SwappedPart)>)> {
    let gap = SIDE_SWAP_GAP_FRAMES * rate.step() as u64;
    // The frames with a torso: their positions, pelvis and torso length (the landmarks are
    // taken relative to them as they are needed: a video of a million frames holds no copy).
    let present: Vec<Torso> = poses
        .iter()
        .enumerate()
        .filter_map(|(k, pose)| Torso::of(k, pose))
        .collect();
    let number = |k: usize| frames.get(k).copied().flatten();
    let linked: Vec<bool> = present
        .windows(2)
        .map(|w| {
            let (j, k) = (w[0].at, w[1].at);
            match (number(j), number(k)) {
                (Some(a), Some(b)) => b > a && b - a <= gap,
                _ => (k - j) as u64 <= gap,
            }
        })
        .collect();
    SideChain::ALL
        .into_iter()
        .map(|chain| {
            let swapped = swapped_frames(chain, poses, &present, &linked, rate.step())
                .into_iter()
                .map(|(m, part)| (present[m].at, part))
                .collect();
            (chain, swapped)
        })
        .collect()
}

/// [`swapped_sides`] of one person's frames (at `rate`), the parts found swapped back in
/// `poses` ([`with_part_swapped`]); returns, per chain, the positions swapped back. The frames
/// where `left_out` (missing entries: none; [`left_out_of_sequence`](crate::left_out_of_sequence):
/// another person's, a second pose of a frame) are neither judged nor neighbours of those
/// judged (another person's legs had been "swapped back" before the frame was left out).
pub fn swap_sides_back(
    frames: &[Option<u64>],
    poses: &mut [PartialPose2],
    left_out: &[bool],
    rate: FrameRate,
) -> Vec<(SideChain, Vec<usize>)> {
    let kept: Vec<usize> = (0..poses.len())
        .filter(|&m| !left_out.get(m).copied().unwrap_or(false))
        .collect();
    let kept_frames: Vec<Option<u64>> = kept
        .iter()
        .map(|&m| Some(number_or_position(frames, m)))
        .collect();
    let kept_poses: Vec<PartialPose2> = kept.iter().map(|&m| poses[m]).collect();
    swapped_sides(&kept_frames, &kept_poses, rate)
        .into_iter()
        .map(|(chain, swapped)| {
            for &(k, part) in &swapped {
                let m = kept[k];
                poses[m] = with_part_swapped(&poses[m], chain, part);
            }
            (chain, swapped.into_iter().map(|(k, _)| kept[k]).collect())
        })
        .collect()
}

/// A frame with a torso: its position among the person's frames, its pelvis and its torso
/// length (pelvis to neck, finite and non-zero).
#[derive(Clone, Copy)]
struct Torso {
    at: usize,
    pelvis: [f64; 2],
    length: f64,
}

impl Torso {
    /// The torso of `pose`, the frame at position `at`; `None` without a pelvis, a neck or a
    /// torso of finite, non-zero length.
    fn of(at: usize, pose: &PartialPose2) -> Option<Torso> {
        let pelvis = pose.points[Landmark::Pelvis.index()]?;
        let neck = pose.points[Landmark::Neck.index()]?;
        let length = (neck[0] - pelvis[0]).hypot(neck[1] - pelvis[1]);
        (length.is_finite() && length > 0.0).then_some(Torso { at, pelvis, length })
    }

    /// `landmark` of `pose` relative to the pelvis, in torso lengths.
    fn relative(&self, pose: &PartialPose2, landmark: Landmark) -> Option<[f64; 2]> {
        let [x, y] = pose.points[landmark.index()]?;
        Some([
            (x - self.pelvis[0]) / self.length,
            (y - self.pelvis[1]) / self.length,
        ])
    }
}

/// The positions (in `present`, the frames with a torso) of the frames whose `chain` is
/// swapped back and the part ([`swapped_sides`]); `linked[m - 1]`: frames `m - 1` and `m`
/// constrain each other; `step`: frames per frame at 30 frames a second
/// ([`FrameRate::step`]).
fn swapped_frames(
    chain: SideChain,
    poses: &[PartialPose2],
    present: &[Torso],
    linked: &[bool],
    step: usize,
) -> Vec<(usize, SwappedPart)> {
    let n = present.len();
    if n == 0 {
        return Vec::new();
    }
    // How a frame is read: as read (None) or with a part swapped.
    const READINGS: [Option<SwappedPart>; 3] =
        [None, Some(SwappedPart::Whole), Some(SwappedPart::Distal)];
    // The chain's squared motion from frame m - 1 (read `before`) to frame m (read `after`),
    // over the landmarks both have; 0 where the frames are not linked.
    let motion = |m: usize, before: Option<SwappedPart>, after: Option<SwappedPart>| -> f64 {
        if !linked[m - 1] {
            return 0.0;
        }
        let (a, b) = (&present[m - 1], &present[m]);
        // The left (or right) landmark of the `i`-th pair in a frame read so.
        let side = |i: usize, reading: Option<SwappedPart>, left: bool| {
            let (l, r) = chain.pairs()[i];
            let swapped = reading.is_some_and(|part| part.exchanges(i));
            if left != swapped { l } else { r }
        };
        (0..3)
            .flat_map(|i| [(i, true), (i, false)])
            .filter_map(|(i, left)| {
                let p = a.relative(&poses[a.at], side(i, before, left))?;
                let q = b.relative(&poses[b.at], side(i, after, left))?;
                Some((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2))
            })
            .sum()
    };
    // Each step's nine motions (each reading before and after), computed once.
    let steps: Vec<[f64; 9]> = (1..n)
        .map(|m| std::array::from_fn(|k| motion(m, READINGS[k / 3], READINGS[k % 3])))
        .collect();
    let index = |reading: Option<SwappedPart>| match reading {
        None => 0,
        Some(SwappedPart::Whole) => 1,
        Some(SwappedPart::Distal) => 2,
    };
    let motion = |m: usize, before: Option<SwappedPart>, after: Option<SwappedPart>| {
        steps[m - 1][3 * index(before) + index(after)]
    };
    let mut steady: Vec<f64> = (1..n)
        .filter(|&m| linked[m - 1])
        .map(|m| motion(m, None, None))
        .filter(|v| v.is_finite())
        .collect();
    steady.sort_by(f64::total_cmp);
    let median = steady.get(steady.len() / 2).copied().unwrap_or(0.0);
    let penalty = SIDE_SWAP_PENALTY.max(SIDE_SWAP_MOTION_FACTOR * median);
    // Each swapped frame costs the penalty per 30th of a second: a swap as long in time costs
    // as much at any rate (the noise between frames, which sets the penalty, does not shrink
    // with them).
    let per_frame = penalty / step as f64;
    // Viterbi over the states of a frame: 0 as read; r in 1..=SIDE_SWAP_RUN_FRAMES the r-th
    // frame of a run with the whole chain swapped, SIDE_SWAP_RUN_FRAMES + r of a run with
    // the limbs beyond the torso swapped; a track starts as read or at a run's first frame.
    let run = SIDE_SWAP_RUN_FRAMES * step;
    let states = 2 * run + 1;
    let reading = |state: usize| match state {
        0 => None,
        s if s <= run => Some(SwappedPart::Whole),
        _ => Some(SwappedPart::Distal),
    };
    let first_of_run = |state: usize| state == 1 || state == run + 1;
    // A frame is read swapped only where each pair it exchanges has both sides or neither:
    // with one side missing a swapped reading has fewer landmarks to move and looked cheap (a
    // simulated user's misplaced left wrist beside a missing right arm had the left arm
    // "swapped back" onto the right).
    let lopsided = |m: usize, part: SwappedPart| {
        let pose = &poses[present[m].at];
        (0..3).any(|i| {
            let (l, r) = chain.pairs()[i];
            part.exchanges(i)
                && pose.points[l.index()].is_some() != pose.points[r.index()].is_some()
        })
    };
    let own = |m: usize, state: usize| match reading(state) {
        None => 0.0,
        Some(part) if lopsided(m, part) => f64::INFINITY,
        Some(_) => per_frame,
    };
    let mut cost: Vec<f64> = (0..states)
        .map(|state| {
            if state == 0 || first_of_run(state) {
                own(0, state)
            } else {
                f64::INFINITY
            }
        })
        .collect();
    // The state each frame's state came from (`states` entries per step; at most 10,001
    // states, FrameRate::step being at most 1,000).
    let mut back: Vec<u16> = Vec::with_capacity((n - 1) * states);
    for m in 1..n {
        let mut next = vec![f64::INFINITY; states];
        let mut from = vec![0u16; states];
        for state in 0..states {
            // The states a frame in `state` can follow: any (as read), as read (a run's first
            // frame), the run's frame before.
            let before = match state {
                0 => 0..states,
                s if first_of_run(s) => 0..1,
                s => s - 1..s,
            };
            for b in before {
                let total = cost[b] + motion(m, reading(b), reading(state));
                if total < next[state] {
                    next[state] = total;
                    from[state] = b as u16;
                }
            }
            next[state] += own(m, state);
        }
        cost = next;
        back.extend(from);
    }
    let mut state = (0..states)
        .min_by(|&a, &b| cost[a].total_cmp(&cost[b]))
        .unwrap_or(0);
    let mut path = vec![None; n];
    for m in (0..n).rev() {
        path[m] = reading(state);
        if m > 0 {
            state = usize::from(back[(m - 1) * states + state]);
        }
    }
    // A run is kept only inside the track, where at each end the frames as read jump by more
    // than the penalty and swapped join with at most SIDE_SWAP_JOIN_RATIO of it. The path may
    // also move the ends of a longer stretch read swapped to where the limbs cross (a walk's
    // legs, twice a stride), or follow noise at a track's end (a simulated user's runners at
    // 10 frames a second), and such a run is left as read.
    let mends = |at: usize, part: SwappedPart, into: bool| {
        let jump = motion(at, None, None);
        let join = if into {
            motion(at, None, Some(part))
        } else {
            motion(at, Some(part), None)
        };
        linked[at - 1] && jump > penalty && join <= SIDE_SWAP_JOIN_RATIO * jump
    };
    let mut swapped = Vec::new();
    let mut m = 0;
    while m < n {
        let Some(part) = path[m] else {
            m += 1;
            continue;
        };
        let end = (m..n).find(|&e| path[e] != Some(part)).unwrap_or(n);
        if m > 0 && end < n && mends(m, part, true) && mends(end, part, false) {
            swapped.extend((m..end).map(|k| (k, part)));
        }
        m = end;
    }
    swapped
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A side view of a walk: the legs swing in opposite phases, the arms too.
    fn walk(frames: usize) -> Vec<PartialPose2> {
        walk_at(frames, 1.0)
    }

    /// [`walk`] filmed `faster` times as many frames a second.
    fn walk_at(frames: usize, faster: f64) -> Vec<PartialPose2> {
        (0..frames)
            .map(|t| {
                let phase = 0.35 * t as f64 / faster + 1.2;
                let x0 = 6.0 * t as f64 / faster;
                let mut pose = PartialPose2::empty();
                let mut set =
                    |l: Landmark, x: f64, y: f64| pose.points[l.index()] = Some([x0 + x, y]);
                set(Landmark::Pelvis, 0.0, 0.0);
                set(Landmark::Neck, 0.0, -100.0);
                set(Landmark::Head, 5.0, -130.0);
                let swing = 40.0 * phase.sin();
                set(Landmark::LeftHip, 3.0, 0.0);
                set(Landmark::RightHip, -3.0, 0.0);
                set(Landmark::LeftKnee, 0.5 * swing, 50.0);
                set(Landmark::RightKnee, -0.5 * swing, 50.0);
                set(Landmark::LeftAnkle, swing, 100.0);
                set(Landmark::RightAnkle, -swing, 100.0);
                set(Landmark::LeftShoulder, 4.0, -95.0);
                set(Landmark::RightShoulder, -4.0, -95.0);
                set(Landmark::LeftElbow, -0.4 * swing, -60.0);
                set(Landmark::RightElbow, 0.4 * swing, -60.0);
                set(Landmark::LeftWrist, -0.7 * swing, -30.0);
                set(Landmark::RightWrist, 0.7 * swing, -30.0);
                pose
            })
            .collect()
    }

    /// The frames of `chain` found swapped, whatever the part.
    fn found(frames: &[Option<u64>], poses: &[PartialPose2], chain: SideChain) -> Vec<usize> {
        found_parts(frames, poses, chain)
            .into_iter()
            .map(|(m, _)| m)
            .collect()
    }

    fn found_parts(
        frames: &[Option<u64>],
        poses: &[PartialPose2],
        chain: SideChain,
    ) -> Vec<(usize, SwappedPart)> {
        swapped_sides(frames, poses, FrameRate::default())
            .into_iter()
            .find(|(c, _)| *c == chain)
            .map(|(_, f)| f)
            .unwrap()
    }

    #[test]
    fn shins_or_forearms_swapped_alone_are_swapped_back_alone() {
        let clean = walk(60);
        let numbers: Vec<Option<u64>> = (0..60).map(Some).collect();
        let mut read = clean.clone();
        // A detector's crossing shins (knees and ankles, the hips right) for two frames, and
        // a forearm swap for one.
        for k in [27, 28] {
            read[k] = with_part_swapped(&read[k], SideChain::Legs, SwappedPart::Distal);
        }
        read[37] = with_part_swapped(&read[37], SideChain::Arms, SwappedPart::Distal);
        // The whole legs of another frame.
        read[10] = with_sides_swapped(&read[10], SideChain::Legs);
        assert_eq!(
            found_parts(&numbers, &read, SideChain::Legs),
            vec![
                (10, SwappedPart::Whole),
                (27, SwappedPart::Distal),
                (28, SwappedPart::Distal)
            ]
        );
        assert_eq!(
            found_parts(&numbers, &read, SideChain::Arms),
            vec![(37, SwappedPart::Distal)]
        );
        let mut repaired = read.clone();
        swap_sides_back(&numbers, &mut repaired, &[], FrameRate::default());
        assert_eq!(repaired, clean);
    }

    #[test]
    fn an_arm_missing_on_one_side_is_not_swapped_onto_it() {
        // The right arm missing for frames 20-34, and at frame 27 the left wrist misplaced
        // onto where the right one would be: nothing is swapped (the left arm had been put on
        // the right side).
        let clean = walk(60);
        let numbers: Vec<Option<u64>> = (0..60).map(Some).collect();
        let mut read = clean.clone();
        for pose in &mut read[20..35] {
            pose.points[Landmark::RightElbow.index()] = None;
            pose.points[Landmark::RightWrist.index()] = None;
        }
        read[27].points[Landmark::LeftWrist.index()] =
            clean[27].points[Landmark::RightWrist.index()];
        assert_eq!(found_parts(&numbers, &read, SideChain::Arms), vec![]);
    }

    #[test]
    fn frames_left_out_are_neither_judged_nor_neighbours() {
        // The walk with its legs swapped at frames 20-22, and another person (the same walk
        // 450 px away, its legs swapped at every frame) beside it at frames 15-29, each of
        // whose rows is left out of the person's sequence.
        let clean = walk(60);
        let mut poses = Vec::new();
        let mut numbers = Vec::new();
        let mut left_out = Vec::new();
        let mut person = Vec::new();
        for (t, pose) in clean.iter().enumerate() {
            if (15..30).contains(&t) {
                let other = PartialPose2 {
                    points: pose.points.map(|p| p.map(|[x, y]| [x + 450.0, y])),
                };
                poses.push(with_sides_swapped(&other, SideChain::Legs));
                numbers.push(Some(t as u64));
                left_out.push(true);
            }
            let read = if (20..23).contains(&t) {
                with_sides_swapped(pose, SideChain::Legs)
            } else {
                *pose
            };
            person.push(poses.len());
            poses.push(read);
            numbers.push(Some(t as u64));
            left_out.push(false);
        }
        let mut repaired = poses.clone();
        let swapped = swap_sides_back(&numbers, &mut repaired, &left_out, FrameRate::default());
        let legs = &swapped[0].1;
        assert_eq!(legs, &[person[20], person[21], person[22]]);
        for (t, &m) in person.iter().enumerate() {
            assert_eq!(repaired[m], clean[t], "frame {t}");
        }
        // The other person's rows are as read.
        for m in (0..poses.len()).filter(|&m| left_out[m]) {
            assert_eq!(repaired[m], poses[m]);
        }
    }

    #[test]
    fn a_few_frames_with_swapped_legs_are_found_and_a_clean_walk_has_none() {
        let clean = walk(60);
        let numbers: Vec<Option<u64>> = (0..60).map(Some).collect();
        for chain in SideChain::ALL {
            assert!(found(&numbers, &clean, chain).is_empty(), "{chain:?}");
            assert!(found(&[], &clean, chain).is_empty(), "{chain:?}");
        }
        let mut read = clean.clone();
        // Frames where the legs are apart (a swap where they cross changes nothing); a run at
        // the track's start is left as read (a track's end is judged by one side only).
        let legs: Vec<usize> = vec![10, 27, 28, 29, 55];
        for &k in legs.iter().chain(&[0, 1]) {
            read[k] = with_sides_swapped(&read[k], SideChain::Legs);
        }
        read[37] = with_sides_swapped(&read[37], SideChain::Arms);
        assert_eq!(found(&numbers, &read, SideChain::Legs), legs);
        assert_eq!(found(&numbers, &read, SideChain::Arms), vec![37]);
        // Swapping back gives the clean walk.
        for &k in &legs {
            assert_eq!(with_sides_swapped(&read[k], SideChain::Legs), clean[k]);
        }
        // A stretch longer than SIDE_SWAP_RUN_FRAMES read swapped is left: there is no
        // telling which part of the track is right.
        let mut long = clean.clone();
        for pose in &mut long[26..26 + SIDE_SWAP_RUN_FRAMES + 1] {
            *pose = with_sides_swapped(pose, SideChain::Legs);
        }
        assert_eq!(found(&numbers, &long, SideChain::Legs), Vec::<usize>::new());
        // Frames far apart in time, or without a torso, do not constrain each other.
        let sparse: Vec<Option<u64>> = (0..60).map(|t| Some(10 * t)).collect();
        assert!(found(&sparse, &read, SideChain::Legs).is_empty());
        // A frame without a torso is left as read, and the frames on each side of it are
        // judged together (a NaN row of Python, a missing frame number of the command line).
        let mut headless = read.clone();
        headless[10].points[Landmark::Neck.index()] = None;
        headless[29].points[Landmark::Neck.index()] = None;
        assert_eq!(
            found(&numbers, &headless, SideChain::Legs),
            vec![27, 28, 55]
        );
        assert!(
            swapped_sides(&[], &[], FrameRate::default())
                .iter()
                .all(|(_, f)| f.is_empty())
        );
    }

    #[test]
    fn a_swap_of_a_tenth_of_a_second_is_found_at_120_frames_a_second_told_the_rate() {
        let clean = walk_at(240, 4.0);
        let numbers: Vec<Option<u64>> = (0..240).map(Some).collect();
        let rate = FrameRate::new(120.0).unwrap();
        let legs = |poses: &[PartialPose2], rate: FrameRate| -> Vec<usize> {
            swapped_sides(&numbers, poses, rate)
                .into_iter()
                .find(|(c, _)| *c == SideChain::Legs)
                .map(|(_, f)| f.into_iter().map(|(m, _)| m).collect())
                .unwrap_or_default()
        };
        assert!(legs(&clean, rate).is_empty());
        // 12 frames (0.1 s) where the legs are apart: more than SIDE_SWAP_RUN_FRAMES frames,
        // as many in time as 3 at 30 frames a second.
        let mut read = clean.clone();
        let swapped: Vec<usize> = (70..82).collect();
        for &k in &swapped {
            read[k] = with_sides_swapped(&read[k], SideChain::Legs);
        }
        assert_eq!(legs(&read, rate), swapped);
        assert!(legs(&read, FrameRate::default()).is_empty());
    }
}
