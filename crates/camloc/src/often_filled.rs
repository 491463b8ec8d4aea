//! The landmarks of a person's frames that were filled in, not seen, often enough to say so
//! ([`often_filled`]): their 3D is a guess, the pose basis's frame by frame or, over a short
//! gap of a sequence, interpolated from the frames around it.

use camloc_skeleton::{Landmark, NUM_LANDMARKS};

/// The share of a person's reconstructed frames from which a landmark filled in there is
/// named by [`often_filled`]: a simulated animator's walker had its far arm filled in 214 of
/// 232 frames, where it swung three times as far as the arm it stood for, without a word.
pub const OFTEN_FILLED_SHARE: f64 = 0.25;

/// The landmarks filled in, not seen, in [`OFTEN_FILLED_SHARE`] or more of a person's
/// reconstructed frames ([`often_filled`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OftenFilled {
    /// The person's reconstructed frames.
    pub frames: usize,
    /// Each landmark filled in that often, with the frames it was filled in, in index order.
    pub landmarks: Vec<(Landmark, usize)>,
}

impl OftenFilled {
    /// The landmarks as text, e.g. `left_elbow in 207, left_wrist in 214`.
    pub fn names(&self) -> String {
        (self.landmarks.iter())
            .map(|(l, n)| format!("{} in {n}", l.name()))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The landmarks filled in often among a person's reconstructed frames, `filled` holding each
/// frame's filled-in landmarks (`PoseReconstruction::imputed`); `None` when none was.
pub fn often_filled<'a>(filled: impl IntoIterator<Item = &'a [Landmark]>) -> Option<OftenFilled> {
    let mut counts = [0usize; NUM_LANDMARKS];
    let mut frames = 0;
    for imputed in filled {
        frames += 1;
        for l in imputed {
            counts[l.index()] += 1;
        }
    }
    let landmarks: Vec<(Landmark, usize)> = (Landmark::ALL.into_iter().zip(counts))
        .filter(|&(_, n)| n > 0 && n as f64 >= OFTEN_FILLED_SHARE * frames as f64)
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
        let found = often_filled(frames.iter().map(Vec::as_slice)).unwrap();
        assert_eq!(found.frames, 8);
        // In index order: the right ankle (6) before the left wrist (11).
        assert_eq!(found.landmarks, [(RightAnkle, 2), (LeftWrist, 3)]);
        assert_eq!(found.names(), "right_ankle in 2, left_wrist in 3");
        assert_eq!(often_filled(frames[3..].iter().map(Vec::as_slice)), None);
        // One frame of eight is not often.
        let once: Vec<Vec<Landmark>> = (0..8)
            .map(|t| if t == 0 { vec![Head] } else { vec![] })
            .collect();
        assert_eq!(often_filled(once.iter().map(Vec::as_slice)), None);
    }
}
