//! The landmarks of a person's frames that were filled in, not seen, often or long enough to
//! say so ([`often_filled`]): their 3D is a guess, the pose basis's frame by frame or, over a
//! short gap of a sequence, interpolated from the frames around it.

use camloc_reconstruct::FrameRate;
use camloc_skeleton::{LIMB_NAMES, LIMBS, Landmark, NUM_LANDMARKS};

use crate::PoseReconstruction;

/// The share of a person's reconstructed frames from which a landmark filled in there is
/// named by [`often_filled`]: a simulated animator's walker had its far arm filled in 214 of
/// 232 frames, where it swung three times as far as the arm it stood for, without a word.
pub const OFTEN_FILLED_SHARE: f64 = 0.25;

/// The time, seconds, over which a landmark filled in in every frame of a run is named by
/// [`often_filled`] however few the person's frames it is of: a simulated physiotherapist's
/// squat with the legs unseen for 20 frames (0.67 s) at its bottom came out 20 deg short at
/// the knees (92 deg frame by frame) without a word.
pub const FILLED_RUN_S: f64 = 0.5;

/// The most frame numbers between two frames of one run of [`often_filled`] (times
/// [`FrameRate::step`] above 30 frames a second): frames the person is missing from for longer
/// end the run, as they split a sequence.
pub const FILLED_RUN_GAP_FRAMES: u64 = 3;

/// A landmark named by [`often_filled`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FilledLandmark {
    /// The landmark.
    pub landmark: Landmark,
    /// The person's frames it was filled in.
    pub frames: usize,
    /// The frame numbers its longest run of filled-in frames spans (first to last, both
    /// counted).
    pub longest_run: u64,
    /// The frame number that run starts at.
    pub longest_run_from: u64,
}

/// The landmarks filled in, not seen, in [`OFTEN_FILLED_SHARE`] or more of a person's
/// reconstructed frames, or over a run of [`FILLED_RUN_S`] ([`often_filled`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OftenFilled {
    /// The person's reconstructed frames.
    pub frames: usize,
    /// The frame numbers a run must span to be named ([`FILLED_RUN_S`] at the frame rate).
    pub run_frames: u64,
    /// Each landmark filled in that often or that long, in index order.
    pub landmarks: Vec<FilledLandmark>,
}

impl OftenFilled {
    /// The landmarks as text, e.g. `left_elbow in 207, left_wrist in 20 (for 20 frames from
    /// frame 50)`, the longest run said when it spans [`run_frames`](Self::run_frames).
    pub fn names(&self) -> String {
        (self.landmarks.iter())
            .map(|f| {
                let run = if f.longest_run >= self.run_frames {
                    format!(
                        " (for {} frames from frame {})",
                        f.longest_run, f.longest_run_from
                    )
                } else {
                    String::new()
                };
                format!("{} in {}{run}", f.landmark.name(), f.frames)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The limbs ([`LIMB_NAMES`]) with an end filled in in every frame, in limb order: with
    /// no frame that shows them, their lengths are the length prior's guess, not the
    /// person's (a simulated animator's actor whose legs never entered the frame got a thigh
    /// 7% long, and its lengths file looked like a measured one).
    pub fn unseen_limbs(&self) -> Vec<&'static str> {
        let always = |l: Landmark| {
            self.landmarks
                .iter()
                .any(|f| f.landmark == l && f.frames == self.frames)
        };
        (LIMBS.iter().zip(LIMB_NAMES))
            .filter(|((a, b), _)| always(*a) || always(*b))
            .map(|(_, name)| name)
            .collect()
    }

    /// [`names`](Self::names), then, unless the person's lengths were given
    /// (`lengths_given`), the [`unseen_limbs`](Self::unseen_limbs) when there are some:
    /// `left_ankle in 90 (for 90 frames from frame 0); seen in no frame, the lengths of the
    /// left shin are the length prior's guess`.
    pub fn summary(&self, lengths_given: bool) -> String {
        let unseen = self.unseen_limbs();
        if unseen.is_empty() || lengths_given {
            return self.names();
        }
        format!(
            "{}; seen in no frame, the lengths of the {} are the length prior's guess",
            self.names(),
            unseen.join(", ")
        )
    }
}

/// The landmarks filled in often or long among a person's reconstructed frames at `rate`,
/// `filled` holding each frame's number and filled-in landmarks (`PoseReconstruction::imputed`)
/// in time order: in [`OFTEN_FILLED_SHARE`] of the frames or more, or in every frame of a run
/// spanning [`FILLED_RUN_S`] of frame numbers or more (a run ends where the numbers jump by
/// more than [`FILLED_RUN_GAP_FRAMES`]); `None` when none was.
pub fn often_filled<'a>(
    filled: impl IntoIterator<Item = (u64, &'a [Landmark])>,
    rate: FrameRate,
) -> Option<OftenFilled> {
    let run_frames = ((FILLED_RUN_S * rate.hz()).ceil() as u64).max(2);
    let gap = FILLED_RUN_GAP_FRAMES * rate.step() as u64;
    let mut counts = [0usize; NUM_LANDMARKS];
    // Per landmark, the current run's first and last frame numbers, and the longest run.
    let mut runs: [Option<(u64, u64)>; NUM_LANDMARKS] = [None; NUM_LANDMARKS];
    let mut longest = [(0u64, 0u64); NUM_LANDMARKS];
    let mut frames = 0;
    for (number, imputed) in filled {
        frames += 1;
        let mut filled_here = [false; NUM_LANDMARKS];
        for l in imputed {
            filled_here[l.index()] = true;
        }
        for (i, &here) in filled_here.iter().enumerate() {
            counts[i] += usize::from(here);
            runs[i] = match (here, runs[i]) {
                (false, _) => None,
                (true, Some((first, last))) if number.saturating_sub(last) <= gap => {
                    Some((first, number))
                }
                (true, _) => Some((number, number)),
            };
            if let Some((first, last)) = runs[i] {
                let span = last.saturating_sub(first) + 1;
                if span > longest[i].0 {
                    longest[i] = (span, first);
                }
            }
        }
    }
    let landmarks: Vec<FilledLandmark> = (Landmark::ALL.into_iter().enumerate())
        .map(|(i, landmark)| FilledLandmark {
            landmark,
            frames: counts[i],
            longest_run: longest[i].0,
            longest_run_from: longest[i].1,
        })
        .filter(|f| {
            f.frames > 0
                && (f.frames as f64 >= OFTEN_FILLED_SHARE * frames as f64
                    || f.longest_run >= run_frames)
        })
        .collect();
    (!landmarks.is_empty()).then_some(OftenFilled {
        frames,
        run_frames,
        landmarks,
    })
}

/// [`often_filled`] of a person's reconstructed `frames` (the failed ones left out) at `rate`,
/// `numbers` their frame numbers (a frame without one is numbered by its position: rows
/// without frame numbers are consecutive frames), as `camloc reconstruct --sequence` and
/// Python's `reconstruct(sequence=True)` warn of them.
pub fn often_filled_frames<E>(
    frames: &[Result<PoseReconstruction, E>],
    numbers: &[Option<u64>],
    rate: FrameRate,
) -> Option<OftenFilled> {
    let filled = (frames.iter().zip(numbers).enumerate()).filter_map(|(i, (r, number))| {
        let r = r.as_ref().ok()?;
        Some((number.unwrap_or(i as u64), r.imputed.as_slice()))
    });
    often_filled(filled, rate)
}

/// The poses of a run reconstructed one by one that had landmarks filled in, not seen, and
/// which landmarks ([`FilledCount::summary`]): frame by frame their 3D is the pose basis's guess
/// (a simulated physiotherapist's squat with the legs unseen for 20 frames came out 92 deg off
/// at the knees there, without a word).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FilledCount {
    /// Poses counted.
    pub poses: u64,
    /// Of those, the poses with a landmark filled in.
    pub filled: u64,
    /// Per landmark (index order), the poses it was filled in.
    pub per_landmark: [u64; NUM_LANDMARKS],
}

impl FilledCount {
    /// Counts a pose whose filled-in landmarks are `imputed`.
    pub fn add(&mut self, imputed: &[Landmark]) {
        self.poses += 1;
        self.filled += u64::from(!imputed.is_empty());
        for l in imputed {
            self.per_landmark[l.index()] += 1;
        }
    }

    /// `None` when no pose had a landmark filled in, else e.g. `12 of 86 poses have landmarks
    /// filled in, not seen (most often left_ankle in 9, right_ankle in 7, left_knee in 3)`.
    pub fn summary(&self) -> Option<String> {
        if self.filled == 0 {
            return None;
        }
        let mut most: Vec<(u64, Landmark)> = (self.per_landmark.iter().zip(Landmark::ALL))
            .filter(|(n, _)| **n > 0)
            .map(|(n, l)| (*n, l))
            .collect();
        // The most filled first, ties in index order.
        most.sort_by_key(|m| std::cmp::Reverse(m.0));
        let named: Vec<String> = (most.iter().take(3))
            .map(|(n, l)| format!("{} in {n}", l.name()))
            .collect();
        Some(format!(
            "{} of {} poses have landmarks filled in, not seen (most often {})",
            self.filled,
            self.poses,
            named.join(", ")
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `frames` numbered from 0 in order.
    fn numbered(frames: &[Vec<Landmark>]) -> impl Iterator<Item = (u64, &[Landmark])> {
        frames
            .iter()
            .enumerate()
            .map(|(i, f)| (i as u64, f.as_slice()))
    }

    fn at(hz: f64) -> FrameRate {
        FrameRate::new(hz).unwrap()
    }

    #[test]
    fn a_landmark_filled_in_a_quarter_of_the_frames_is_named() {
        use Landmark::*;
        let frames: Vec<Vec<Landmark>> = (0..8)
            .map(|t| match t {
                0 | 1 => vec![LeftWrist, RightAnkle],
                2 => vec![LeftWrist],
                _ => vec![],
            })
            .collect();
        let found = often_filled(numbered(&frames), at(30.0)).unwrap();
        assert_eq!(found.frames, 8);
        // In index order: the right ankle (6) before the left wrist (11).
        let named: Vec<(Landmark, usize)> = found
            .landmarks
            .iter()
            .map(|f| (f.landmark, f.frames))
            .collect();
        assert_eq!(named, [(RightAnkle, 2), (LeftWrist, 3)]);
        assert_eq!(found.names(), "right_ankle in 2, left_wrist in 3");
        assert_eq!(often_filled(numbered(&frames[3..]), at(30.0)), None);
        // One frame of eight is not often.
        let once: Vec<Vec<Landmark>> = (0..8)
            .map(|t| if t == 0 { vec![Head] } else { vec![] })
            .collect();
        assert_eq!(often_filled(numbered(&once), at(30.0)), None);
    }

    #[test]
    fn single_poses_with_landmarks_filled_in_are_counted_with_the_most_filled() {
        use Landmark::*;
        let mut count = FilledCount::default();
        assert_eq!(count.summary(), None);
        for imputed in [
            vec![LeftAnkle, RightAnkle],
            vec![LeftAnkle],
            vec![],
            vec![Head, LeftAnkle, RightWrist],
        ] {
            count.add(&imputed);
        }
        assert_eq!(
            count.summary().unwrap(),
            "3 of 4 poses have landmarks filled in, not seen (most often left_ankle in 3, \
             right_ankle in 1, head in 1)"
        );
    }

    #[test]
    fn a_landmark_filled_in_over_half_a_second_is_named_in_frame_numbers() {
        use Landmark::*;
        // 15 frames in a row of 200 (7.5%), and 14 frames in two runs.
        let frames: Vec<Vec<Landmark>> = (0..200)
            .map(|t| match t {
                50..65 => vec![LeftKnee],
                100..107 | 150..157 => vec![RightKnee],
                _ => vec![],
            })
            .collect();
        let found = often_filled(numbered(&frames), at(30.0)).unwrap();
        assert_eq!(found.run_frames, 15);
        assert_eq!(
            found.landmarks,
            [FilledLandmark {
                landmark: LeftKnee,
                frames: 15,
                longest_run: 15,
                longest_run_from: 50
            }]
        );
        assert_eq!(
            found.names(),
            "left_knee in 15 (for 15 frames from frame 50)"
        );
        assert_eq!(often_filled(numbered(&frames), at(32.0)), None);
        // Every other frame numbered (the rest not detected): 8 frames over 15 numbers are a
        // run; 8 frames of a run broken by the person missing for 90 frames are not.
        let sparse: Vec<(u64, Vec<Landmark>)> = (0..100u64)
            .map(|i| {
                (
                    2 * i,
                    if (40..48).contains(&i) {
                        vec![Head]
                    } else {
                        vec![]
                    },
                )
            })
            .collect();
        let found = often_filled(sparse.iter().map(|(n, l)| (*n, l.as_slice())), at(30.0));
        assert_eq!(
            found.unwrap().names(),
            "head in 8 (for 15 frames from frame 80)"
        );
        let apart: Vec<(u64, Vec<Landmark>)> = (0..100u64)
            .map(|i| {
                let number = if i < 50 { i } else { i + 90 };
                (
                    number,
                    if (46..54).contains(&i) {
                        vec![Head]
                    } else {
                        vec![]
                    },
                )
            })
            .collect();
        assert_eq!(
            often_filled(apart.iter().map(|(n, l)| (*n, l.as_slice())), at(30.0)),
            None
        );
    }

    #[test]
    fn limbs_with_an_end_filled_in_every_frame_are_the_priors_guess() {
        use Landmark::*;
        // The left ankle in every frame, the right knee in half of them.
        let frames: Vec<Vec<Landmark>> = (0..10)
            .map(|t| match t % 2 {
                0 => vec![LeftAnkle, RightKnee],
                _ => vec![LeftAnkle],
            })
            .collect();
        let found = often_filled(numbered(&frames), at(30.0)).unwrap();
        assert_eq!(found.unseen_limbs(), ["left shin"]);
        assert!(
            found.summary(false).ends_with(
                "; seen in no frame, the lengths of the left shin are the length prior's guess"
            ),
            "{}",
            found.summary(false)
        );
        // Given lengths are not the prior's.
        assert_eq!(found.summary(true), found.names());
        let mut some: Vec<Vec<Landmark>> = vec![vec![RightKnee]; 4];
        some.extend(vec![vec![]; 4]);
        let found = often_filled(numbered(&some), at(30.0)).unwrap();
        assert!(found.unseen_limbs().is_empty());
        assert_eq!(found.summary(false), found.names());
    }
}
