//! Smoothing the viewpoint of one person over the frames of a video: [`SequenceModel`], a hidden
//! Markov model over the cameras, and [`sequences`], which groups records by person and frame.

use std::ops::Range;

use camloc_geometry::{CameraLabel, CameraSet};

use crate::CamlocError;

/// Default probability that the camera changes between two consecutive frames.
pub const DEFAULT_SWITCH_PROBABILITY: f64 = 0.05;

/// Share of the switching probability that goes to the neighbouring viewpoints (same level and
/// adjacent side, same side and adjacent level); the rest goes to the other cameras.
pub const NEIGHBOUR_SHARE: f64 = 0.8;

/// Weight of the flat distribution mixed into every frame's probabilities (robustness to
/// confidently wrong frames).
pub const OUTLIER_SHARE: f64 = 0.1;

/// The smoothed viewpoint of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothedFrame {
    /// The camera of this frame on the most probable path (Viterbi).
    pub label: CameraLabel,
    /// Posterior probability of `label` at this frame given all frames (forward-backward).
    pub probability: f64,
    /// Posterior probability of every camera at this frame, index [`CameraLabel::index`];
    /// sums to 1.
    pub probabilities: Vec<f64>,
}

/// A hidden Markov model over the cameras of a [`CameraSet`] that smooths the viewpoint of one
/// person over the frames of a video: its hidden states are the cameras, its emissions the
/// per-frame class probabilities of a [`CameraLocalizer`](crate::CameraLocalizer).
///
/// - **Transitions.** Between two consecutive frames the camera stays with probability
///   `1 - switch_probability` ([`DEFAULT_SWITCH_PROBABILITY`] = 0.05: on average a change of
///   viewpoint every 20 frames at most). The switching mass goes for the share
///   [`NEIGHBOUR_SHARE`] (0.8) to the neighbouring viewpoints (same level and adjacent side,
///   or same side and adjacent level), split equally, and the rest equally to every other
///   camera: a person turning moves through neighbours, a far jump is possible but costly.
/// - **Emissions.** A frame's probabilities are mixed with a flat distribution,
///   `(1 - OUTLIER_SHARE) p + OUTLIER_SHARE / K` ([`OUTLIER_SHARE`] = 0.1): a single frame,
///   however confident, can only outweigh a few transitions, so a few bad frames do not pull
///   the sequence away; a frame that could not be localized (`None`) is flat (it carries no
///   evidence, the neighbouring frames decide).
/// - **Results.** [`SequenceModel::smooth`] gives per frame the Viterbi label (the most
///   probable sequence of cameras as a whole) and the forward-backward posterior of every
///   camera given all frames.
///
/// A frame's probabilities are the classifier's `p(camera | pose)`; with the cameras equally
/// likely a priori they are proportional to the likelihood `p(pose | camera)` the model needs.
#[derive(Clone, Debug, PartialEq)]
pub struct SequenceModel {
    /// Number of cameras K.
    cameras: usize,
    /// Row-stochastic K x K transition matrix, row-major: `transition[i * K + j]` is the
    /// probability of camera j at frame t + 1 given camera i at frame t.
    transition: Vec<f64>,
}

/// The grid neighbours of camera `index` of `cameras`: adjacent azimuth on the same elevation
/// ring, adjacent ring at the same azimuth (labels run ring by ring, see [`CameraSet`]).
fn neighbours(cameras: &CameraSet, index: usize) -> Vec<usize> {
    let azimuths = cameras.azimuths();
    let rings = cameras.elevations_deg().len();
    let (ring, az) = (index / azimuths, index % azimuths);
    let mut out = Vec::with_capacity(4);
    if azimuths > 1 {
        out.push(ring * azimuths + (az + 1) % azimuths);
        out.push(ring * azimuths + (az + azimuths - 1) % azimuths);
    }
    if ring > 0 {
        out.push((ring - 1) * azimuths + az);
    }
    if ring + 1 < rings {
        out.push((ring + 1) * azimuths + az);
    }
    out.sort_unstable();
    out.dedup();
    out.retain(|&j| j != index);
    out
}

impl SequenceModel {
    /// The model for `cameras` with the given probability (in [0, 1)) that the camera changes
    /// between consecutive frames.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] when `switch_probability` is not in [0, 1).
    pub fn new(cameras: &CameraSet, switch_probability: f64) -> Result<SequenceModel, CamlocError> {
        if !(0.0..1.0).contains(&switch_probability) {
            return Err(CamlocError::InvalidOption {
                name: "switch probability",
                detail: format!("{switch_probability} is not in [0, 1)"),
            });
        }
        let k = cameras.len();
        let mut transition = vec![0.0; k * k];
        for i in 0..k {
            let row = &mut transition[i * k..(i + 1) * k];
            if k == 1 {
                row[0] = 1.0;
                continue;
            }
            let near = neighbours(cameras, i);
            let far = k - 1 - near.len();
            // Without far cameras (or without neighbours) the whole switching mass goes to the
            // other group, so every row sums to 1.
            let (near_mass, far_mass) = match (near.is_empty(), far == 0) {
                (true, _) => (0.0, switch_probability),
                (_, true) => (switch_probability, 0.0),
                _ => (
                    NEIGHBOUR_SHARE * switch_probability,
                    (1.0 - NEIGHBOUR_SHARE) * switch_probability,
                ),
            };
            for (j, value) in row.iter_mut().enumerate() {
                *value = if j == i {
                    1.0 - switch_probability
                } else if near.contains(&j) {
                    near_mass / near.len() as f64
                } else {
                    far_mass / far as f64
                };
            }
        }
        Ok(SequenceModel {
            cameras: k,
            transition,
        })
    }

    /// The model for `cameras` with [`DEFAULT_SWITCH_PROBABILITY`].
    pub fn with_default_switch(cameras: &CameraSet) -> SequenceModel {
        SequenceModel::new(cameras, DEFAULT_SWITCH_PROBABILITY)
            .unwrap_or_else(|_| unreachable!("the default switch probability is in [0, 1)"))
    }

    /// Probability of camera index `to` at a frame given camera index `from` at the previous.
    ///
    /// # Panics
    /// When `from` or `to` is not below the number of cameras.
    pub fn transition(&self, from: usize, to: usize) -> f64 {
        self.transition[from * self.cameras + to]
    }

    /// The emission weights of one frame: the probabilities mixed with a flat distribution,
    /// flat for `None`.
    fn emission(&self, frame: Option<&[f64]>, at: usize) -> Result<Vec<f64>, CamlocError> {
        let k = self.cameras;
        let flat = 1.0 / k as f64;
        match frame {
            None => Ok(vec![flat; k]),
            Some(p) => {
                if p.len() != k {
                    return Err(CamlocError::Inconsistent {
                        what: "sequence",
                        detail: format!("frame {at}: {} probabilities for {k} cameras", p.len()),
                    });
                }
                if let Some(bad) = p.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                    return Err(CamlocError::Inconsistent {
                        what: "sequence",
                        detail: format!(
                            "frame {at}: probability {bad} is not a finite number >= 0"
                        ),
                    });
                }
                let total: f64 = p.iter().sum();
                if !(total > 0.0) {
                    return Ok(vec![flat; k]);
                }
                Ok(p.iter()
                    .map(|v| (1.0 - OUTLIER_SHARE) * v / total + OUTLIER_SHARE * flat)
                    .collect())
            }
        }
    }

    /// Smooths one person's frames, in order: `frames[t]` is the probability of every camera
    /// (index [`CameraLabel::index`]) at frame t, `None` for a frame that could not be
    /// localized. Gives one [`SmoothedFrame`] per frame (none for no frames).
    ///
    /// # Errors
    /// [`CamlocError::Inconsistent`] for a frame whose length is not the number of cameras or
    /// that holds a negative or non-finite value.
    pub fn smooth(&self, frames: &[Option<&[f64]>]) -> Result<Vec<SmoothedFrame>, CamlocError> {
        let k = self.cameras;
        let n = frames.len();
        if n == 0 {
            return Ok(Vec::new());
        }
        // Memory per frame: the emissions, the scaled forward probabilities and the Viterbi
        // back-pointers (12 + 12 numbers and 12 small indices for 12 cameras), and the output.
        let mut emissions = Vec::with_capacity(n * k);
        for (t, frame) in frames.iter().enumerate() {
            emissions.extend(self.emission(*frame, t)?);
        }
        let emission = |t: usize| &emissions[t * k..(t + 1) * k];
        // Forward (scaled).
        let mut alpha = vec![0.0; n * k];
        for (value, e) in alpha.iter_mut().zip(emission(0)) {
            *value = e / k as f64;
        }
        normalise(&mut alpha[..k]);
        for t in 1..n {
            let (done, rest) = alpha.split_at_mut(t * k);
            let previous = &done[(t - 1) * k..];
            let current = &mut rest[..k];
            for (j, value) in current.iter_mut().enumerate() {
                let into: f64 = (0..k).map(|i| previous[i] * self.transition(i, j)).sum();
                *value = into * emission(t)[j];
            }
            normalise(current);
        }
        // Viterbi in logarithms (camera indices fit 16 bits: labels are 16-bit numbers).
        let log_transition: Vec<f64> = self.transition.iter().map(|p| p.ln()).collect();
        let mut score: Vec<f64> = emission(0).iter().map(|e| e.ln()).collect();
        let mut back = vec![0u16; n * k];
        for t in 1..n {
            let mut next = vec![f64::NEG_INFINITY; k];
            for (j, slot) in next.iter_mut().enumerate() {
                let (best, from) = (0..k)
                    .map(|i| (score[i] + log_transition[i * k + j], i))
                    .fold((f64::NEG_INFINITY, 0), |a, b| if b.0 > a.0 { b } else { a });
                *slot = best + emission(t)[j].ln();
                back[t * k + j] = u16::try_from(from).unwrap_or(u16::MAX);
            }
            score = next;
        }
        let mut state = argmax(&score);
        // Backward (scaled with the same factors), one step held at a time, each frame's
        // posterior and Viterbi state made as it comes; the frames come out last first.
        let mut beta = vec![1.0; k];
        let mut smoothed = Vec::with_capacity(n);
        for t in (0..n).rev() {
            if t + 1 < n {
                let next = std::mem::replace(&mut beta, vec![0.0; k]);
                for (i, value) in beta.iter_mut().enumerate() {
                    *value = (0..k)
                        .map(|j| self.transition(i, j) * emission(t + 1)[j] * next[j])
                        .sum();
                }
                normalise(&mut beta);
                state = usize::from(back[(t + 1) * k + state]);
            }
            let mut posterior: Vec<f64> = (0..k).map(|j| alpha[t * k + j] * beta[j]).collect();
            normalise(&mut posterior);
            smoothed.push(SmoothedFrame {
                label: CameraLabel::from_index(state)?,
                probability: posterior.get(state).copied().unwrap_or(0.0),
                probabilities: posterior,
            });
        }
        smoothed.reverse();
        Ok(smoothed)
    }
}

/// Scales `values` to sum 1 (left alone when they sum to 0).
fn normalise(values: &mut [f64]) {
    let total: f64 = values.iter().sum();
    if total > 0.0 {
        values.iter_mut().for_each(|v| *v /= total);
    }
}

/// Index of the largest value (the first of equal ones).
fn argmax(values: &[f64]) -> usize {
    values
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (i, &v)| {
            if v > best.1 { (i, v) } else { best }
        })
        .0
}

/// The frame number of position `t` of one person's frames (`numbers`, `None` where
/// unknown): its own, or, without one, its position (as [`sequences`] counts a record without
/// a frame), so that frames left out of a sequence still count as time passing.
pub(crate) fn number_or_position(numbers: &[Option<u64>], t: usize) -> u64 {
    numbers.get(t).copied().flatten().unwrap_or(t as u64)
}

/// The time of position `t` of one person's frames, in frames: its number in `frames` when
/// given, else its position (consecutive frames).
pub(crate) fn frame_time(frames: Option<&[u64]>, t: usize) -> f64 {
    frames
        .and_then(|f| f.get(t))
        .map_or(t as f64, |&n| n as f64)
}

/// Each frame's run among `len` frames: 0 for the first, one more at each frame that `breaks`
/// marks (beyond its end: no break).
pub(crate) fn run_ids(len: usize, breaks: &[bool]) -> Vec<usize> {
    let mut run = Vec::with_capacity(len);
    for t in 0..len {
        let starts = t > 0 && breaks.get(t).copied().unwrap_or(false);
        run.push(run.last().copied().unwrap_or(0) + usize::from(starts));
    }
    run
}

/// The positions of the frames about position `k` of `len` frames in time order that `near`
/// accepts: the run of them around `k` (`k` itself included), which is all of them, as frames
/// near in time are consecutive.
pub(crate) fn window_around(len: usize, k: usize, near: impl Fn(usize) -> bool) -> Range<usize> {
    let start = (0..k).rev().take_while(|&j| near(j)).last().unwrap_or(k);
    let end = (k + 1..len)
        .take_while(|&j| near(j))
        .last()
        .map_or(k + 1, |j| j + 1);
    start..end
}

/// The sequences of an input: the positions of the records of each person, ordered by frame.
///
/// `keys[n]` is the `(frame, person)` of the n-th record (see
/// [`KeypointRecord`](crate::keypoints::KeypointRecord)); a record without a frame counts as
/// frame n, one without a person as person 0 (inputs with one pose per frame). Persons come in
/// increasing order; records of the same person and frame keep their input order. The person
/// is a tracker's id where the input has one (`track_id` of COCO and MMPose), else the
/// detector's position of the pose in its frame (OpenPose `people[i]`), which is not a tracked
/// identity ([`identity_jumps`](crate::identity_jumps) finds where it changes).
pub fn sequences(keys: &[(Option<u64>, Option<u64>)]) -> Vec<(u64, Vec<usize>)> {
    let mut order: Vec<(u64, u64, usize)> = keys
        .iter()
        .enumerate()
        .map(|(n, (frame, person))| (person.unwrap_or(0), frame.unwrap_or(n as u64), n))
        .collect();
    order.sort_unstable();
    let mut out: Vec<(u64, Vec<usize>)> = Vec::new();
    for (person, _, n) in order {
        match out.last_mut() {
            Some((p, list)) if *p == person => list.push(n),
            _ => out.push((person, vec![n])),
        }
    }
    out
}

/// The video timeline of one sequence of [`sequences`] (`members`, ordered by frame, and the
/// `keys` of the records as there): slot `f - first` holds the position in `members` of the
/// record of frame `f`, `None` for a frame of which no record holds that person (not
/// detected), so that outputs keep the video's timing across such gaps; of members with the
/// same frame number the first for which `kept(position)` holds the slot, else the first (the
/// others are off the timeline: one duplicated detection used to cost the whole sequence its
/// timing, and an untracked second person listed first took the person's frame). `None` when
/// a member has no frame number, they are out of frame order, or the frames span more than
/// `max_slots`.
pub fn frame_slots(
    keys: &[(Option<u64>, Option<u64>)],
    members: &[usize],
    max_slots: usize,
    kept: impl Fn(usize) -> bool,
) -> Option<Vec<Option<usize>>> {
    let numbers: Vec<Option<u64>> = members
        .iter()
        .map(|&i| keys.get(i).and_then(|k| k.0))
        .collect();
    timeline_slots(&numbers, max_slots, kept)
}

/// [`frame_slots`] of one person's frames given by their frame `numbers` (in time order):
/// slot `f - first` holds the position of a frame numbered `f` (of several, the first for
/// which `kept(position)`, else the first), `None` where the person has no frame. `None` when
/// a frame has no number, they are out of order, or they span more than `max_slots`.
pub fn timeline_slots(
    numbers: &[Option<u64>],
    max_slots: usize,
    kept: impl Fn(usize) -> bool,
) -> Option<Vec<Option<usize>>> {
    let frames: Vec<u64> = numbers.iter().copied().collect::<Option<_>>()?;
    let (&first, &last) = (frames.first()?, frames.last()?);
    let span = usize::try_from(last.checked_sub(first)?)
        .ok()?
        .checked_add(1)?;
    if span > max_slots {
        return None;
    }
    let mut slots: Vec<Option<usize>> = vec![None; span];
    for (position, frame) in frames.iter().enumerate() {
        // (Out of order, a frame before the first has no slot.)
        let offset = usize::try_from(frame.checked_sub(first)?).ok()?;
        let slot = slots.get_mut(offset)?;
        if slot.is_none_or(|held| !kept(held) && kept(position)) {
            *slot = Some(position);
        }
    }
    Some(slots)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn frame_slots_keep_the_gaps_of_a_video() {
        let keys = [(Some(7), Some(0)), (Some(3), Some(0)), (Some(4), Some(0))];
        let members = &sequences(&keys)[0].1;
        assert_eq!(members, &vec![1, 2, 0]);
        assert_eq!(
            frame_slots(&keys, members, 10, |_| true),
            Some(vec![Some(0), Some(1), None, None, Some(2)])
        );
        // A repeated frame: the first record holds it.
        let repeated = [(Some(3), None), (Some(3), None), (Some(4), None)];
        assert_eq!(
            frame_slots(&repeated, &[0, 1, 2], 10, |_| true),
            Some(vec![Some(0), Some(2)])
        );
        // ... unless it is not kept (an untracked second person listed first, left out of
        // the sequence) and a later one is.
        assert_eq!(
            frame_slots(&repeated, &[0, 1, 2], 10, |m| m != 0),
            Some(vec![Some(1), Some(2)])
        );
        // Too long a span, a record without a frame: no timeline.
        assert_eq!(frame_slots(&keys, members, 4, |_| true), None);
        let unnumbered = [(Some(3), None), (None, None)];
        assert_eq!(frame_slots(&unnumbered, &[0, 1], 10, |_| true), None);
        let far = [(Some(0), None), (Some(u64::MAX), None)];
        assert_eq!(frame_slots(&far, &[0, 1], 100_000, |_| true), None);
        // Members out of frame order have no timeline either.
        assert_eq!(frame_slots(&keys, &[2, 1, 0], 10, |_| true), None);
        assert_eq!(frame_slots(&keys, &[0, 1, 2], 10, |_| true), None);
    }

    /// Confident probabilities of camera index `c` (0.9 there, the rest shared).
    fn confident(c: usize) -> Vec<f64> {
        let mut p = vec![0.1 / 11.0; 12];
        p[c] = 0.9;
        p
    }

    fn smooth(frames: &[Option<Vec<f64>>]) -> Vec<SmoothedFrame> {
        let model = SequenceModel::with_default_switch(&CameraSet::table1());
        let views: Vec<Option<&[f64]>> = frames.iter().map(|f| f.as_deref()).collect();
        model.smooth(&views).unwrap()
    }

    #[test]
    fn transitions_prefer_staying_then_neighbours() {
        let model = SequenceModel::with_default_switch(&CameraSet::table1());
        for i in 0..12 {
            let row: f64 = (0..12).map(|j| model.transition(i, j)).sum();
            assert!((row - 1.0).abs() < 1e-12);
        }
        // Camera 05 (index 4, middle front): 06 (middle left) and 01 (lower front) are
        // neighbours, 07 (middle back) is not.
        assert!(model.transition(4, 4) > model.transition(4, 5));
        assert!(model.transition(4, 5) > model.transition(4, 6));
        assert_eq!(model.transition(4, 5), model.transition(4, 0));
        assert!(SequenceModel::new(&CameraSet::table1(), 1.0).is_err());
        assert!(SequenceModel::new(&CameraSet::table1(), f64::NAN).is_err());
    }

    #[test]
    fn wrong_lengths_are_errors() {
        let model = SequenceModel::with_default_switch(&CameraSet::table1());
        let short = [0.5, 0.5];
        assert!(model.smooth(&[Some(&short[..])]).is_err());
        let negative = [-1.0; 12];
        assert!(model.smooth(&[Some(&negative[..])]).is_err());
        assert!(model.smooth(&[]).unwrap().is_empty());
    }

    #[test]
    fn a_turn_is_followed() {
        // Front (05) -> left (06) -> back (07), 20 frames each, one bad frame in each part.
        let mut frames: Vec<Option<Vec<f64>>> =
            (0..60).map(|t| Some(confident(4 + t / 20))).collect();
        frames[7] = Some(confident(10));
        frames[27] = None;
        frames[47] = Some(confident(0));
        let smoothed = smooth(&frames);
        for (t, s) in smoothed.iter().enumerate() {
            assert_eq!(s.label.index(), 4 + t / 20, "frame {t}");
            assert!((s.probabilities.iter().sum::<f64>() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn sequences_split_persons_and_order_frames() {
        let keys = [
            (Some(3), Some(0)),
            (Some(3), Some(1)),
            (Some(1), Some(1)),
            (Some(1), Some(0)),
            (Some(2), Some(0)),
        ];
        assert_eq!(sequences(&keys), vec![(0, vec![3, 4, 0]), (1, vec![2, 1])]);
        assert_eq!(
            sequences(&[(None, None), (None, None)]),
            vec![(0, vec![0, 1])]
        );
    }

    proptest! {
        /// A constant sequence with a few isolated corrupted frames (confidently another
        /// camera, or failed) is smoothed back to the constant camera.
        #[test]
        fn corrupted_frames_are_smoothed_back(
            camera in 0usize..12,
            len in 10usize..80,
            bad in proptest::collection::vec((0usize..80, 0usize..13), 0..4),
        ) {
            let mut frames: Vec<Option<Vec<f64>>> = vec![Some(confident(camera)); len];
            for (at, what) in bad {
                // 12 stands for a frame that failed to localize.
                frames[at % len] = (what < 12).then(|| confident(what));
            }
            // Isolated: no two corrupted frames next to each other.
            let corrupted: Vec<bool> = frames.iter().map(|f| f.as_deref() != Some(&confident(camera)[..])).collect();
            prop_assume!(corrupted.windows(2).all(|w| !(w[0] && w[1])));
            for s in smooth(&frames) {
                prop_assert_eq!(s.label.index(), camera);
            }
        }
    }
}
