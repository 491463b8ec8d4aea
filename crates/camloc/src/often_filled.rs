//! The landmarks of a person's frames that were filled in, not seen, often or long enough to
//! say so ([`often_filled`]): their 3D is a guess, the pose basis's frame by frame or, over a
//! short gap of a sequence, interpolated from the frames around it.

use camloc_skeleton::{Landmark, NUM_LANDMARKS};

/// The share of a person's reconstructed frames from which a landmark filled in there is
/// named by [`often_filled`]: a simulated animator's walker had its far arm filled in 214 of
/// 232 frames, where it swung three times as far as the arm it stood for, without a word.
pub const OFTEN_FILLED_SHARE: f64 = 0.25;

/// The time, seconds, over which a landmark filled in in every frame in a row is named by
/// [`often_filled`] however few the person's frames it is of: a simulated physiotherapist's
/// squat with the legs unseen for 20 frames (0.67 s) at its bottom came out 20 deg short at
/// the knees (92 deg frame by frame) without a word.
pub const FILLED_RUN_S: f64 = 0.5;

/// The frames in a row that last [`FILLED_RUN_S`] at `fps` frames a second (at least 2).
pub fn filled_run_frames(fps: f64) -> usize {
    let frames = (FILLED_RUN_S * fps).ceil();
    if frames.is_finite() && frames >= 2.0 {
        frames.min(usize::MAX as f64) as usize
    } else {
        2
    }
}

/// A landmark named by [`often_filled`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FilledLandmark {
    /// The landmark.
    pub landmark: Landmark,
    /// The person's frames it was filled in.
    pub frames: usize,
    /// The most of them in a row.
    pub longest_run: usize,
}

/// The landmarks filled in, not seen, in [`OFTEN_FILLED_SHARE`] or more of a person's
/// reconstructed frames, or in every frame of a run of [`filled_run_frames`]
/// ([`often_filled`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OftenFilled {
    /// The person's reconstructed frames.
    pub frames: usize,
    /// Each landmark filled in that often or that long, in index order.
    pub landmarks: Vec<FilledLandmark>,
}

impl OftenFilled {
    /// The landmarks as text, e.g. `left_elbow in 207, left_wrist in 20 (all in a row)`, the
    /// longest run said when it is at least `run_frames`.
    pub fn names(&self, run_frames: usize) -> String {
        (self.landmarks.iter())
            .map(|f| {
                let run = match f.longest_run {
                    r if r == f.frames && r >= run_frames => " (all in a row)".to_owned(),
                    r if r >= run_frames => format!(" ({r} in a row)"),
                    _ => String::new(),
                };
                format!("{} in {}{run}", f.landmark.name(), f.frames)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The landmarks filled in often or long among a person's reconstructed frames, `filled`
/// holding each frame's filled-in landmarks (`PoseReconstruction::imputed`) in time order: in
/// [`OFTEN_FILLED_SHARE`] of them or more, or in `run_frames` of them in a row or more
/// ([`filled_run_frames`]); `None` when none was.
pub fn often_filled<'a>(
    filled: impl IntoIterator<Item = &'a [Landmark]>,
    run_frames: usize,
) -> Option<OftenFilled> {
    let mut counts = [0usize; NUM_LANDMARKS];
    let mut runs = [0usize; NUM_LANDMARKS];
    let mut longest = [0usize; NUM_LANDMARKS];
    let mut frames = 0;
    for imputed in filled {
        frames += 1;
        let mut here = [false; NUM_LANDMARKS];
        for l in imputed {
            here[l.index()] = true;
        }
        for i in 0..NUM_LANDMARKS {
            counts[i] += usize::from(here[i]);
            runs[i] = if here[i] { runs[i] + 1 } else { 0 };
            longest[i] = longest[i].max(runs[i]);
        }
    }
    let landmarks: Vec<FilledLandmark> = (Landmark::ALL.into_iter().enumerate())
        .map(|(i, landmark)| FilledLandmark {
            landmark,
            frames: counts[i],
            longest_run: longest[i],
        })
        .filter(|f| {
            f.frames > 0
                && (f.frames as f64 >= OFTEN_FILLED_SHARE * frames as f64
                    || f.longest_run >= run_frames)
        })
        .collect();
    (!landmarks.is_empty()).then_some(OftenFilled { frames, landmarks })
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let found = often_filled(frames.iter().map(Vec::as_slice), 100).unwrap();
        assert_eq!(found.frames, 8);
        // In index order: the right ankle (6) before the left wrist (11).
        let named: Vec<(Landmark, usize)> = found
            .landmarks
            .iter()
            .map(|f| (f.landmark, f.frames))
            .collect();
        assert_eq!(named, [(RightAnkle, 2), (LeftWrist, 3)]);
        assert_eq!(found.names(100), "right_ankle in 2, left_wrist in 3");
        assert_eq!(
            often_filled(frames[3..].iter().map(Vec::as_slice), 100),
            None
        );
        // One frame of eight is not often.
        let once: Vec<Vec<Landmark>> = (0..8)
            .map(|t| if t == 0 { vec![Head] } else { vec![] })
            .collect();
        assert_eq!(often_filled(once.iter().map(Vec::as_slice), 100), None);
    }

    #[test]
    fn a_landmark_filled_in_a_long_run_of_few_frames_is_named() {
        use Landmark::*;
        // 15 frames in a row of 200 (7.5%), and 14 frames in two runs.
        let frames: Vec<Vec<Landmark>> = (0..200)
            .map(|t| match t {
                50..65 => vec![LeftKnee],
                100..107 | 150..157 => vec![RightKnee],
                _ => vec![],
            })
            .collect();
        let run = filled_run_frames(30.0);
        assert_eq!(run, 15);
        let found = often_filled(frames.iter().map(Vec::as_slice), run).unwrap();
        assert_eq!(
            found.landmarks,
            [FilledLandmark {
                landmark: LeftKnee,
                frames: 15,
                longest_run: 15
            }]
        );
        assert_eq!(found.names(run), "left_knee in 15 (all in a row)");
        assert_eq!(often_filled(frames.iter().map(Vec::as_slice), 16), None);
        assert_eq!(filled_run_frames(120.0), 60);
        assert_eq!(filled_run_frames(1.0), 2);
        assert_eq!(filled_run_frames(f64::NAN), 2);
    }
}
