//! How many of an input's landmarks a detector scored weakly ([`WeakScores`]): read at
//! [`ReadOptions::min_score`](crate::ReadOptions::min_score) 0, such landmarks are used as
//! detected although a detector writes coordinates for joints it cannot see.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use camloc_skeleton::{Landmark, PartialPose2};

use crate::{KeypointFormat, KeypointRecord, ReadOptions, sample_records};

/// The landmarks of some poses that are present when read at a minimum score of 0 and missing at
/// [`WeakScores::THRESHOLD`]: the joints a detector scored weakly (often misplaced, or guessed
/// behind the body). Landmarks derived from other joints (pelvis, neck, COCO's head) are not
/// counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WeakScores {
    /// Poses compared.
    pub poses: u64,
    /// Landmarks read (not derived) in those poses at a minimum score of 0.
    pub landmarks: u64,
    /// Of those, the landmarks scored below [`WeakScores::threshold`].
    pub weak: u64,
    /// Whether the input's scores are on a scale of 0-100 (a score above
    /// [`SCORE_SCALE_LIMIT`](crate::SCORE_SCALE_LIMIT)), so that the landmarks were read again
    /// at [`WeakScores::PERCENT_THRESHOLD`] instead of [`WeakScores::THRESHOLD`].
    pub percent_scale: bool,
}

impl WeakScores {
    /// The score below which a landmark counts as weak: the minimum score the documentation
    /// recommends for a detector's output (docs/keypoints.md).
    pub const THRESHOLD: f64 = 0.3;

    /// [`WeakScores::THRESHOLD`] for scores of 0-100 (some exports write percentages).
    pub const PERCENT_THRESHOLD: f64 = 30.0;

    /// The share of weak landmarks ([`WeakScores::weak`] over [`WeakScores::landmarks`]) from
    /// which [`WeakScores::worth_saying`] holds: 1%.
    pub const SAY_FROM_SHARE: f64 = 0.01;

    /// The poses read from the start of an input that [`WeakScores::of_input`] compares
    /// (about 30,000 landmarks: the share is known to a fraction of a percent).
    pub const SAMPLE_POSES: usize = 2_000;

    /// Reads the first [`WeakScores::SAMPLE_POSES`] poses of the file or folder at `path`
    /// ([`sample_records`], with `format`, `options` and `recursive` as its reader takes them)
    /// at a minimum score of 0 and again at [`WeakScores::THRESHOLD`], and
    /// [compares](WeakScores::compare) them. `None` unless `path` is a regular file or a folder
    /// (standard input or a named pipe cannot be read again).
    pub fn of_input(
        path: &Path,
        format: Option<KeypointFormat>,
        options: &ReadOptions,
        recursive: bool,
    ) -> Option<WeakScores> {
        let read = sample_at(0.0, path, format, options, recursive)?;
        WeakScores::against(&read, path, format, options, recursive)
    }

    /// [Compares](WeakScores::compare) `read`, the poses of the file or folder at `path` read
    /// already at a minimum score of 0, with its first [`WeakScores::SAMPLE_POSES`] poses read
    /// again at [`WeakScores::THRESHOLD`] ([`sample_records`], with `format`, `options` and
    /// `recursive` as its reader takes them), or at [`WeakScores::PERCENT_THRESHOLD`] when
    /// every pose is refused at the first (scores of 0-100). `None` unless `path` is a regular
    /// file or a folder.
    pub fn against(
        read: &[KeypointRecord],
        path: &Path,
        format: Option<KeypointFormat>,
        options: &ReadOptions,
        recursive: bool,
    ) -> Option<WeakScores> {
        let strong = sample_at(WeakScores::THRESHOLD, path, format, options, recursive)?;
        if !strong.is_empty() || read.is_empty() {
            return Some(WeakScores::compare(read, &strong));
        }
        // Every pose refused at 0.3: scores of 0-100 (`KeypointError::ScoreScale`), read again
        // on their own scale.
        let strong = sample_at(
            WeakScores::PERCENT_THRESHOLD,
            path,
            format,
            options,
            recursive,
        )?;
        Some(WeakScores {
            percent_scale: !strong.is_empty(),
            ..WeakScores::compare(read, &strong)
        })
    }

    /// The score below which [`WeakScores::weak`] counted a landmark:
    /// [`WeakScores::PERCENT_THRESHOLD`] for scores of 0-100, else [`WeakScores::THRESHOLD`];
    /// the `--min-score` to suggest.
    pub fn threshold(&self) -> f64 {
        if self.percent_scale {
            WeakScores::PERCENT_THRESHOLD
        } else {
            WeakScores::THRESHOLD
        }
    }

    /// Compares the same poses read at a minimum score of 0 (`all`) and at
    /// [`WeakScores::THRESHOLD`] (`strong`), pose by pose ([`WeakScores::add`]), each of `all`
    /// with the pose of `strong` of the same source and id; poses that only one of them has (a
    /// pose refused in one reading, a reading cut short) are not counted.
    pub fn compare<'a>(
        all: impl IntoIterator<Item = &'a KeypointRecord>,
        strong: impl IntoIterator<Item = &'a KeypointRecord>,
    ) -> WeakScores {
        let strong: HashMap<(&str, &str), &KeypointRecord> = strong
            .into_iter()
            .map(|r| ((r.source.as_str(), r.id.as_str()), r))
            .collect();
        let mut counts = WeakScores::default();
        for read in all {
            if let Some(kept) = strong.get(&(read.source.as_str(), read.id.as_str())) {
                counts.add(&read.pose, &read.derived, &kept.pose);
            }
        }
        counts
    }

    /// Counts one pose: `read` at a minimum score of 0 (with the landmarks `derived` from
    /// other joints, which are not counted) and the same pose `strong`, read at
    /// [`WeakScores::THRESHOLD`].
    pub fn add(&mut self, read: &PartialPose2, derived: &[Landmark], strong: &PartialPose2) {
        self.poses += 1;
        for landmark in Landmark::ALL {
            let i = landmark.index();
            if read.points[i].is_none() || derived.contains(&landmark) {
                continue;
            }
            self.landmarks += 1;
            self.weak += u64::from(strong.points[i].is_none());
        }
    }

    /// The share of the landmarks read that are weak (0 when none was read).
    pub fn share(&self) -> f64 {
        if self.landmarks == 0 {
            0.0
        } else {
            self.weak as f64 / self.landmarks as f64
        }
    }

    /// Whether a reader at a minimum score of 0 should be told: at least
    /// [`WeakScores::SAY_FROM_SHARE`] of the landmarks are weak.
    pub fn worth_saying(&self) -> bool {
        self.weak > 0 && self.share() >= WeakScores::SAY_FROM_SHARE
    }
}

/// The first [`WeakScores::SAMPLE_POSES`] records of the file or folder at `path`
/// ([`sample_records`]) read with `options` but at a minimum score of `min_score`.
fn sample_at(
    min_score: f64,
    path: &Path,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
    recursive: bool,
) -> Option<Vec<KeypointRecord>> {
    let options = ReadOptions {
        min_score,
        ..*options
    };
    sample_records(path, format, &options, recursive, WeakScores::SAMPLE_POSES)
}

/// What was counted, for a warning: `85 of the 3240 landmarks (2.6%) of the first 270 poses
/// score below 0.3 and are used as detected`.
impl fmt::Display for WeakScores {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let poses = match self.poses {
            1 => "pose".to_owned(),
            n => format!("{n} poses"),
        };
        write!(
            f,
            "{} of the {} landmarks ({:.1}%) of the first {poses} score below {} and are used \
             as detected",
            self.weak,
            self.landmarks,
            100.0 * self.share(),
            self.threshold()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(
        source: &str,
        points: &[(Landmark, [f64; 2])],
        derived: &[Landmark],
    ) -> KeypointRecord {
        let mut pose = PartialPose2::empty();
        for &(landmark, uv) in points {
            pose.points[landmark.index()] = Some(uv);
        }
        KeypointRecord {
            id: source.to_owned(),
            pose,
            derived: derived.to_vec(),
            source: source.to_owned(),
            frame: None,
            person: None,
            person_is_position: false,
        }
    }

    #[test]
    fn counts_landmarks_dropped_at_the_threshold_but_not_derived_ones() {
        let full = [
            (Landmark::Pelvis, [0.0, 0.0]),
            (Landmark::LeftKnee, [1.0, 2.0]),
            (Landmark::RightWrist, [3.0, 4.0]),
        ];
        let all = [
            record("a", &full, &[Landmark::Pelvis]),
            record("b", &full, &[]),
        ];
        let strong = [
            // The derived pelvis is lost with a weak hip: not counted.
            record("a", &full[1..], &[]),
            record("b", &full[..2], &[]),
        ];
        let counts = WeakScores::compare(&all, &strong);
        assert_eq!(
            counts,
            WeakScores {
                poses: 2,
                landmarks: 5,
                weak: 1,
                percent_scale: false
            }
        );
        assert!(counts.worth_saying());
        assert_eq!(
            counts.to_string(),
            "1 of the 5 landmarks (20.0%) of the first 2 poses score below 0.3 and are used as \
             detected"
        );
    }

    #[test]
    fn poses_are_paired_by_their_source_and_the_unpaired_left_out() {
        let point = [(Landmark::Head, [0.0, 0.0])];
        // "a" refused in the strong reading, "c" cut off from it: only "b" is compared.
        let all = [
            record("a", &point, &[]),
            record("b", &point, &[]),
            record("c", &point, &[]),
        ];
        let strong = [record("b", &[], &[])];
        let counts = WeakScores::compare(&all, &strong);
        assert_eq!((counts.poses, counts.landmarks, counts.weak), (1, 1, 1));
    }

    #[test]
    fn under_one_percent_is_not_said() {
        let mut full = PartialPose2::empty();
        full.points = [Some([0.0, 0.0]); 15];
        let mut one_weak = full;
        one_weak.points[3] = None;
        let mut counts = WeakScores::default();
        // 1 weak landmark in 6 x 15 = 90 (1.1%): said; in 7 x 15 = 105 (0.95%): not.
        counts.add(&full, &[], &one_weak);
        for _ in 0..5 {
            counts.add(&full, &[], &full);
        }
        assert!(counts.worth_saying());
        counts.add(&full, &[], &full);
        assert_eq!((counts.poses, counts.landmarks, counts.weak), (7, 105, 1));
        assert!(!counts.worth_saying());
    }
}
