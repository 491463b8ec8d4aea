//! Whether the frames of one sequence show one person: [`identity_jumps`] finds the steps at
//! which the pose jumps across the image or changes size as no person moves in a frame, which is
//! what a detector's order of people does when it changes (OpenPose's `people[i]` is that
//! order, not a tracked identity) or when two people share one id.

use camloc_reconstruct::FrameRate;
use camloc_skeleton::{Landmark, PartialPose2};

/// The distance, in 2D torso lengths (pelvis to neck) per frame elapsed, that a pelvis may move
/// between two frames of one person before [`identity_jumps`] reports the step. A person
/// running past a camera at 30 frames a second moves the pelvis about a third of a torso a
/// frame.
pub const IDENTITY_JUMP_TORSOS: f64 = 1.0;

/// How far beyond where it is expected (carried on at its own velocity) a person's pelvis is
/// taken to move in 1/30 s, in 2D torso lengths, when a frame's poses are told apart
/// ([`left_out_of_sequence`]). After the person was missed for a while, a pose is the
/// person's only within [`IDENTITY_JUMP_TORSOS`] (a detector's slack) plus this for every
/// further 1/30 s: a reach of a whole torso per frame from the last pose had taken another
/// person 2.8 torsos away for the person after 3 missed frames, and kept them (a simulated
/// user's three untracked walkers).
pub const PERSON_STEP_TORSOS: f64 = 0.4;

/// The ratio of two consecutive frames' 2D torso lengths above which [`identity_jumps`]
/// reports the step: a person walking towards a camera grows by a few percent a frame.
pub const IDENTITY_SIZE_RATIO: f64 = 2.0;

/// Where one frame's person is in the image: the pelvis (the mean of the pelvis and hips
/// present) and the 2D torso length (from there to the mean of the neck and shoulders
/// present), in the input's image units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsoAnchor {
    /// The mean of the pelvis and hips present.
    pub pelvis: [f64; 2],
    /// The distance from `pelvis` to the mean of the neck and shoulders present (positive).
    pub torso: f64,
}

impl TorsoAnchor {
    /// The anchor of `pose`: the mean of its pelvis and hips present, and of its neck and
    /// shoulders present, so that a detector's error on one of them moves the anchor by a
    /// third of it (from the pelvis and neck alone, such single errors left correct frames out
    /// of their sequences as another person's: 18 of a simulated user's 10,560 poses with 3%
    /// of the landmarks 20 px off, 16 of another's 600 frames from a high camera, whose
    /// foreshortened torso made 30 px a torso length; none with the means). `None` when it
    /// has neither pelvis nor hip, or neither neck nor shoulder, or the two points coincide or
    /// are not finite.
    pub fn of(pose: &PartialPose2) -> Option<TorsoAnchor> {
        let point = |centre: Landmark, pair: [Landmark; 2]| {
            let (sum, n) = std::iter::once(centre)
                .chain(pair)
                .filter_map(|l| pose.points[l.index()])
                .fold(([0.0, 0.0], 0.0), |(s, n), p| {
                    ([s[0] + p[0], s[1] + p[1]], n + 1.0)
                });
            (n > 0.0).then(|| sum.map(|v| v / n))
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
/// [`IDENTITY_JUMP_TORSOS`] torso lengths (their mean) per frame elapsed, from where it was
/// and from where the step before would have carried it (a steady runner moves more than a
/// torso length every frame), or, between consecutive frame numbers, the torso length changes
/// by more than [`IDENTITY_SIZE_RATIO`].
/// The anchors are compared after a median of three (each with the frames with anchors before
/// and after it), so that one frame whose hips or shoulders a detector misplaced is not a jump
/// while a change of person that lasts two frames or more is.
///
/// `frames[k]` is frame `k`'s number (`None`: one frame after the previous one) and
/// `anchors[k]` its [`TorsoAnchor`] (`None`: skipped, as a frame without a torso).
pub fn identity_jumps(frames: &[Option<u64>], anchors: &[Option<TorsoAnchor>]) -> Vec<usize> {
    let present = present(anchors);
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
    let filtered: Vec<(usize, TorsoAnchor)> = filtered.collect();
    // Where the steady motion from the frame at `from` to the one at `to` (positions in
    // `filtered`) carries the person at the frame at `at`: a steady runner (or a jogger seen
    // from above, the torso foreshortened) moves more than a torso length every frame without
    // jumping.
    let carried = |from: usize, to: usize, at: usize| TorsoAnchor {
        pelvis: pelvis_along(frames, filtered[to], filtered[from], filtered[at].0),
        torso: filtered[to].1.torso,
    };
    let mut found = Vec::new();
    let mut jumped_before = false;
    for m in 1..filtered.len() {
        let ((j, before), (k, anchor)) = (filtered[m - 1], filtered[m]);
        let span = elapsed(frames, j, k);
        // The steady motion of the step before (when it was no jump), or else (the first
        // step, the step after a jump) that of the step after, carried back.
        let steady = if m >= 2 && !jumped_before {
            Some(jumps(&carried(m - 2, m - 1, m), &anchor, span))
        } else if m + 1 < filtered.len() {
            Some(jumps(&carried(m + 1, m, m - 1), &before, span))
        } else {
            None
        };
        let jumped = jumps(&before, &anchor, span) && steady.unwrap_or(true);
        if jumped {
            found.push(k);
        }
        jumped_before = jumped;
    }
    found
}

/// The frames of `anchors` that have one, with their positions.
fn present(anchors: &[Option<TorsoAnchor>]) -> Vec<(usize, TorsoAnchor)> {
    anchors
        .iter()
        .enumerate()
        .filter_map(|(k, a)| a.map(|a| (k, a)))
        .collect()
}

/// Whether the step from `before` to `after` (`elapsed` frames apart) is not one person
/// moving: the pelvis moves more than [`IDENTITY_JUMP_TORSOS`] torso lengths (their mean) per
/// frame elapsed, or, over one frame, the torso length changes by more than
/// [`IDENTITY_SIZE_RATIO`].
fn jumps(before: &TorsoAnchor, after: &TorsoAnchor, elapsed: f64) -> bool {
    let (moved, ratio) = torso_step(before, after);
    moved > IDENTITY_JUMP_TORSOS * elapsed || (elapsed <= 1.0 && ratio > IDENTITY_SIZE_RATIO)
}

/// How far the pelvis moves from `before` to `after`, in their mean torso length, and the
/// ratio of the larger torso to the smaller.
pub(crate) fn torso_step(before: &TorsoAnchor, after: &TorsoAnchor) -> (f64, f64) {
    let moved = (after.pelvis[0] - before.pelvis[0]).hypot(after.pelvis[1] - before.pelvis[1]);
    let torso = 0.5 * (after.torso + before.torso);
    let ratio = after.torso.max(before.torso) / after.torso.min(before.torso);
    (moved / torso, ratio)
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

/// Frames elapsed from position `j` to position `k` of one person's frames ([`elapsed`]),
/// negative when `k` comes before `j`.
fn signed_elapsed(frames: &[Option<u64>], j: usize, k: usize) -> f64 {
    if j <= k {
        elapsed(frames, j, k)
    } else {
        -elapsed(frames, k, j)
    }
}

/// Where the line through the pelvises of two of a person's frames, `base` and `other` (their
/// positions and anchors), puts the pelvis at the time of the frame at position `at`: between
/// them, or beyond either (the steady motion carried on).
fn pelvis_along(
    frames: &[Option<u64>],
    (j, base): (usize, TorsoAnchor),
    (k, other): (usize, TorsoAnchor),
    at: usize,
) -> [f64; 2] {
    let share = signed_elapsed(frames, j, at) / signed_elapsed(frames, j, k);
    [0, 1].map(|d| base.pelvis[d] + share * (other.pelvis[d] - base.pelvis[d]))
}

/// The most frames in a row that [`outlier_frames`] leaves out as another person's: a tracker
/// that gave one person's id to another for a third of a second at 30 frames a second (an
/// occluder passing by). A longer stretch is a change of person ([`identity_jumps`] warns).
pub const OUTLIER_RUN_FRAMES: usize = 10;

/// The positions of one person's frames (in time order; `frames` and `anchors` as for
/// [`identity_jumps`]) whose pose is not where the frames before and after them put the person
/// while those agree with each other: up to [`OUTLIER_RUN_FRAMES`] frames in a row that hold
/// another person's detection (two tracked people's ids swapped for a few frames) or a
/// detection a detector misplaced. The median of [`identity_jumps`] does not count such frames
/// as a change of person; their poses are still not this person's. A stretch counts only when
/// each of its frames lies more than a torso length off the line through the person's frames
/// on each side of it (a steady runner's frames may each be more than a torso length apart).
/// The first (last) frame of a track is judged by the two frames after (before) it; a longer
/// stretch at an end only where the frame numbers say it follows the rest of the track within
/// [`OUTLIER_END_GAP_FRAMES`] frames. When more than a third of the frames would be left
/// out, none is: such frames are not a tracker's swap but a track of several people, or
/// frames sampled far apart and numbered one after another ([`identity_jumps`] warns). The
/// frame counts are at 30 frames a second, [`FrameRate::step`] times as many at `rate`'s
/// faster ones (as long in time).
pub fn outlier_frames(
    frames: &[Option<u64>],
    anchors: &[Option<TorsoAnchor>],
    rate: FrameRate,
) -> Vec<usize> {
    let run = OUTLIER_RUN_FRAMES * rate.step();
    let end_gap = OUTLIER_END_GAP_FRAMES * rate.step() as u64;
    let present = present(anchors);
    let n = present.len();
    // Whether the frames at positions `x` and `y` of `present` are too far apart for one
    // person.
    let apart = |x: usize, y: usize| {
        let (a, b) = (x.min(y), x.max(y));
        jumps(
            &present[a].1,
            &present[b].1,
            elapsed(frames, present[a].0, present[b].0),
        )
    };
    // Whether the frame at position `k` lies more than a torso length (of the frames at `a`
    // and `b`) off where the line through the frames at positions `a` and `b` (`a != b`) puts
    // the person at its time, between them or beyond them, or differs from their size by
    // more than IDENTITY_SIZE_RATIO.
    let off_line = |k: usize, a: usize, b: usize| {
        let (pa, pb, pk) = (present[a].1, present[b].1, present[k].1);
        let on_line = pelvis_along(frames, present[a], present[b], present[k].0);
        let size = 0.5 * (pa.torso + pb.torso);
        let off = [0, 1].map(|i| pk.pelvis[i] - on_line[i]);
        off[0].hypot(off[1]) > IDENTITY_JUMP_TORSOS * size
            || pk.torso.max(size) / pk.torso.min(size) > IDENTITY_SIZE_RATIO
    };
    let mut out = vec![false; n];
    // The ends: the first (last) frame apart from the two frames after (before) it, which
    // agree, when the track does not come back to its person within OUTLIER_RUN_FRAMES + 1
    // frames. Without frame numbers, a longer stretch at an end is not told from a person who
    // moved fast between sparse frames (two of a simulated user's 12 clips of 25 frames
    // spread over long takes).
    let first = n >= 3
        && apart(0, 1)
        && !apart(1, 2)
        && off_line(0, 1, 2)
        && !(2..(3 + run).min(n)).any(|f| apart(f - 1, f) && !apart(0, f));
    let last_frame = n >= 3
        && apart(n - 2, n - 1)
        && !apart(n - 3, n - 2)
        && off_line(n - 1, n - 2, n - 3)
        && !((n - 2).saturating_sub(run + 1).max(1)..n - 2)
            .any(|f| apart(f - 1, f) && !apart(f - 1, n - 1));
    // Longer stretches at an end where the frame numbers say that the stretch begins (ends)
    // within OUTLIER_END_GAP_FRAMES of the rest of the track.
    let numbered_near = |x: usize, y: usize| {
        let (a, b) = (x.min(y), x.max(y));
        let number = |m: usize| frames.get(present[m].0).copied().flatten();
        matches!((number(a), number(b)), (Some(p), Some(q)) if q > p && q - p <= end_gap)
    };
    let end = EndJudges {
        run,
        apart,
        off_line,
        numbered_near,
    };
    let head = if first { 1 } else { end.stretch(n, |e| e) };
    let tail = if last_frame {
        1
    } else {
        end.stretch(n, |e| n - 1 - e)
    };
    out[..head].fill(true);
    out[n - tail..].fill(true);
    // In between: a stretch that leaves the person's last agreeing frame and comes back.
    let mut last = head;
    let mut m = last + 1;
    while m + 1 < n && !out[m] {
        let back = apart(last, m)
            .then(|| (m..(m + run).min(n - 1)).find(|&e| apart(e, e + 1) && !apart(last, e + 1)))
            .flatten()
            .filter(|&e| (m..=e).all(|k| off_line(k, last, e + 1)));
        match back {
            Some(e) => {
                out[m..=e].fill(true);
                last = e + 1;
                m = e + 2;
            }
            None => {
                last = m;
                m += 1;
            }
        }
    }
    let left_out: Vec<usize> = (0..n).filter(|&m| out[m]).map(|m| present[m].0).collect();
    if 3 * left_out.len() > n {
        return Vec::new();
    }
    left_out
}

/// The most frame numbers between a stretch at an end of a track and the rest of the track
/// for [`outlier_frames`] to judge the stretch (a detector that missed a frame or two where
/// the tracker swapped two people's ids).
pub const OUTLIER_END_GAP_FRAMES: u64 = 3;

/// The tests [`outlier_frames`] judges a stretch at an end of a track with, on positions of
/// the track's frames: two frames too far apart for one person, a frame off the line through
/// two others, two frames numbered at most [`OUTLIER_END_GAP_FRAMES`] apart.
struct EndJudges<A, O, N> {
    /// The longest stretch ([`OUTLIER_RUN_FRAMES`] at the sequence's rate).
    run: usize,
    apart: A,
    off_line: O,
    numbered_near: N,
}

impl<A, O, N> EndJudges<A, O, N>
where
    A: Fn(usize, usize) -> bool,
    O: Fn(usize, usize, usize) -> bool,
    N: Fn(usize, usize) -> bool,
{
    /// The length (2 to [`run`](Self::run)) of a stretch of frames at one end of a track
    /// of `n` frames that holds another person: it jumps in from the rest of the track within
    /// a few numbered frames, its frames agree with each other and lie off the line through
    /// the rest's two nearest frames, and the rest (at least twice as long, and 3 frames) has
    /// no jump within `run` + 1 frames of it (else the stretch may be the
    /// person and the rest's start another's). `at(e)` is the position of the `e`-th frame
    /// from that end; 0 when there is no such stretch.
    fn stretch(&self, n: usize, at: impl Fn(usize) -> usize) -> usize {
        let apart = &self.apart;
        (2..=self.run)
            .take_while(|&len| n >= 2 * len + 3)
            .find(|&len| {
                let (inside, outside) = (at(len - 1), at(len));
                apart(inside, outside)
                    && (self.numbered_near)(inside, outside)
                    && (0..len - 1).all(|e| !apart(at(e), at(e + 1)))
                    && (0..len).all(|e| (self.off_line)(at(e), outside, at(len + 1)))
                    && (len..(len + self.run + 1).min(n - 1)).all(|e| !apart(at(e), at(e + 1)))
            })
            .unwrap_or(0)
    }
}

/// The person's chosen poses [`other_poses_of_frames`] carries the velocity over: at most
/// this many, newest last, spanning at most [`TRACK_SPAN_STEPS`].
pub(crate) const TRACK_POSES: usize = 4;

/// The longest time, in 1/30 s, over which the person's velocity is measured and carried on.
const TRACK_SPAN_STEPS: f64 = 8.0;

/// Where the person's pelvis is expected at position `m` of the person's frames (`frames`
/// numbers, at `rate`), from `track` (the person's last chosen poses, newest last): the
/// newest's, carried on for at most [`TRACK_SPAN_STEPS`] at the velocity from the oldest to
/// the newest (when they span at most that); with the newest's torso, and the time elapsed
/// since it in 1/30 s.
fn expected(
    track: &[(usize, TorsoAnchor)],
    frames: &[Option<u64>],
    m: usize,
    rate: FrameRate,
) -> Option<(TorsoAnchor, f64)> {
    let step = rate.step() as f64;
    let &(at, newest) = track.last()?;
    let steps = elapsed(frames, at, m) / step;
    let &(first_at, oldest) = track.first()?;
    let span = elapsed(frames, first_at, at) / step;
    let mut pelvis = newest.pelvis;
    if first_at != at && span <= TRACK_SPAN_STEPS {
        let carried = steps.min(TRACK_SPAN_STEPS) / span;
        for (p, (n, o)) in pelvis
            .iter_mut()
            .zip(newest.pelvis.iter().zip(&oldest.pelvis))
        {
            *p += (n - o) * carried;
        }
    }
    let anchor = TorsoAnchor {
        pelvis,
        torso: newest.torso,
    };
    Some((anchor, steps))
}

/// How far a pose at position `m` of `frames` (numbers, at `rate`), where `anchor` is, lies
/// from where the person of `track` (its last chosen poses, positions in `frames`, newest
/// last) is expected ([`expected`]): the pelvis's distance in torso lengths plus the log of the
/// torsos' size ratio, when within reach (a torso length, [`IDENTITY_JUMP_TORSOS`], and
/// [`PERSON_STEP_TORSOS`] for every further 1/30 s; a size change of at most
/// [`IDENTITY_SIZE_RATIO`] from one frame to the next); `None` beyond it.
pub(crate) fn within_reach(
    track: &[(usize, TorsoAnchor)],
    frames: &[Option<u64>],
    m: usize,
    anchor: TorsoAnchor,
    rate: FrameRate,
) -> Option<f64> {
    let (moved, ratio, steps) = expected_step(track, frames, m, anchor, rate)?;
    (moved <= reach_torsos(steps) && (steps > 1.0 || ratio <= IDENTITY_SIZE_RATIO))
        .then(|| step_cost(moved, ratio))
}

/// The cost of a pose as a person's next one, the lower the likelier: `moved` (the pelvis's
/// distance from where the person is expected, torso lengths) plus the log of `ratio` (the
/// torsos' size ratio, at least 1).
pub(crate) fn step_cost(moved: f64, ratio: f64) -> f64 {
    moved + ratio.ln()
}

/// How far from where a person is expected its pose may lie, in torso lengths, `steps` 1/30 s
/// after its last pose: [`IDENTITY_JUMP_TORSOS`] (a detector's slack) and
/// [`PERSON_STEP_TORSOS`] for every further 1/30 s.
pub(crate) fn reach_torsos(steps: f64) -> f64 {
    IDENTITY_JUMP_TORSOS + PERSON_STEP_TORSOS * (steps - 1.0).max(0.0)
}

/// How far `anchor`, at position `m` of `frames`, lies from where the person of `track` is
/// expected ([`within_reach`]'s terms, without the reach): the pelvis's distance in torso
/// lengths, the size ratio, and the time since the track's newest pose in 1/30 s.
pub(crate) fn expected_step(
    track: &[(usize, TorsoAnchor)],
    frames: &[Option<u64>],
    m: usize,
    anchor: TorsoAnchor,
    rate: FrameRate,
) -> Option<(f64, f64, f64)> {
    let (there, steps) = expected(track, frames, m, rate)?;
    let (moved, ratio) = torso_step(&there, &anchor);
    Some((moved, ratio, steps))
}

/// The positions of the poses of one person's frames (`frames` numbers and `anchors` as for
/// [`left_out_of_sequence`]) that share a frame number with another pose and are not the
/// person's. Of each frame's poses the person's is, of those within reach of where the
/// person is expected (the last chosen pose carried on at the person's velocity over the last
/// few: [`expected`]; the reach a torso length and [`PERSON_STEP_TORSOS`] for every further
/// 1/30 s at `rate`), the nearest it (pelvis distance in torso lengths, and the torsos' size
/// ratio), or none when none is (the person was not detected there); before the person's
/// first pose with a torso, the first in the input. The person's poses are the chosen ones, a
/// frame of one pose counting only when within reach (another person detected alone where
/// the person was missed is left to [`outlier_frames`]). The first in the input had been the
/// person's: an untracked second person listed first in some frames was taken for the person
/// there (a simulated user's animation jumped 4 m for 15 frames); then a reach of a torso per
/// frame from the last pose took a bystander 2.8 torsos away for a walker missed for 3
/// frames, and a reach in time without the velocity lost a sprinter passing a walker.
pub(crate) fn other_poses_of_frames(
    frames: &[Option<u64>],
    anchors: &[Option<TorsoAnchor>],
    rate: FrameRate,
) -> Vec<usize> {
    let n = frames.len();
    let same = |a: usize, b: usize| frames[a].is_some() && frames[a] == frames[b];
    let anchor = |m: usize| anchors.get(m).copied().flatten();
    let distance =
        |track: &[(usize, TorsoAnchor)], m: usize| within_reach(track, frames, m, anchor(m)?, rate);
    let mut others = Vec::new();
    // The person's last chosen poses with a torso: position and anchor, newest last.
    let mut track: Vec<(usize, TorsoAnchor)> = Vec::new();
    let mut start = 0;
    while start < n {
        let end = (start + 1..n).find(|&m| !same(start, m)).unwrap_or(n);
        let chosen = if end - start == 1 || track.is_empty() {
            Some(start)
        } else {
            (start..end)
                .filter_map(|m| distance(&track, m).map(|d| (m, d)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(m, _)| m)
        };
        others.extend((start..end).filter(|&m| Some(m) != chosen));
        if let Some(m) = chosen
            && let Some(a) = anchor(m)
            && (end - start > 1 || track.is_empty() || distance(&track, m).is_some())
        {
            track.push((m, a));
            if track.len() > TRACK_POSES {
                track.remove(0);
            }
        }
        start = end;
    }
    others
}

/// The frames of one person that are not the person's frame of the sequence
/// ([`left_out_of_sequence`]), as positions in the person's frames.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LeftOut {
    /// The poses of a frame number that another pose has too (a tracker's duplicate, an
    /// untracked second person) other than the person's: the one nearest the person's
    /// track (see [`left_out_of_sequence`]); ascending.
    pub second_poses: Vec<usize>,
    /// Poses apart from the frames before and after them ([`outlier_frames`]).
    pub outliers: Vec<usize>,
}

impl LeftOut {
    /// Per position of the person's `n` frames, whether it is left out.
    pub fn mask(&self, n: usize) -> Vec<bool> {
        let mut mask = vec![false; n];
        for &m in self.second_poses.iter().chain(&self.outliers) {
            if let Some(left) = mask.get_mut(m) {
                *left = true;
            }
        }
        mask
    }

    /// `anchors` (one per frame of the person) with the left-out frames' taken away (`None`),
    /// for [`identity_jumps`] among the frames kept.
    pub fn kept_anchors(&self, anchors: &[Option<TorsoAnchor>]) -> Vec<Option<TorsoAnchor>> {
        anchors
            .iter()
            .zip(self.mask(anchors.len()))
            .map(|(a, left)| a.filter(|_| !left))
            .collect()
    }
}

/// The frames of one person (their `frames` numbers, `None` where unknown, and `anchors`, in
/// time order; a frame's poses in input order) to leave out of the person's sequence: the
/// poses of a frame other than the person's (the one nearest where the person is expected),
/// and the poses that lie apart from the frames around them
/// ([`outlier_frames`], judged without the second poses). `camloc reconstruct --sequence`
/// reconstructs them on their own
/// ([`PoseReconstructor::reconstruct_sequence_at_frames`](crate::PoseReconstructor::reconstruct_sequence_at_frames))
/// and `camloc localize --sequence` leaves them out of the smoothing. `rate`: the frames a
/// second, as [`outlier_frames`] takes it.
pub fn left_out_of_sequence(
    frames: &[Option<u64>],
    anchors: &[Option<TorsoAnchor>],
    rate: FrameRate,
) -> LeftOut {
    let second_poses = other_poses_of_frames(frames, anchors, rate);
    let mut left_out = LeftOut {
        second_poses,
        outliers: Vec::new(),
    };
    left_out.outliers = outlier_frames(frames, &left_out.kept_anchors(anchors), rate);
    left_out
}

#[cfg(test)]
mod tests;
