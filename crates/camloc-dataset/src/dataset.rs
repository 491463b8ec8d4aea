//! The dataset file: header, samples, subject splits, save/load.

use std::collections::BTreeMap;

use camloc_geometry::{CameraSet, Matrix3};
use camloc_skeleton::{NUM_LANDMARKS, Pose2, Pose3};
use camloc_store::{FileKind, Persist, Validate};
use serde::{Deserialize, Serialize};

use crate::{Augmentation, DatasetError, Jitter, MotionCategory, PostureLimits, Protocol, Rig};

/// One clip of motion capture that samples were drawn from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClipInfo {
    /// Subject id (CMU file-name prefix, e.g. `"35"` for `35_02.bvh`).
    pub subject: String,
    /// Clip name (file stem, e.g. `"35_02"`).
    pub name: String,
    /// What the person does in the clip (from the CMU index; [`MotionCategory::Other`] when
    /// unknown).
    pub category: MotionCategory,
}

impl ClipInfo {
    /// A clip of `subject` called `name`, of category [`MotionCategory::Other`].
    pub fn new(subject: impl Into<String>, name: impl Into<String>) -> ClipInfo {
        ClipInfo {
            subject: subject.into(),
            name: name.into(),
            category: MotionCategory::Other,
        }
    }
}

/// The most clips a dataset file may list (CMU has about 2,600): an empty clip takes 3 bytes
/// of a file and about 80 of memory, so a forged file listing millions would have held 20
/// times its size. Refused while the file is decoded.
pub const MAX_CLIPS: usize = 1 << 20;

/// Decodes a dataset's clips, refusing more than [`MAX_CLIPS`] before holding them.
fn at_most_max_clips<'de, D: serde::Deserializer<'de>>(
    decoder: D,
) -> Result<Vec<ClipInfo>, D::Error> {
    struct Clips;
    impl<'de> serde::de::Visitor<'de> for Clips {
        type Value = Vec<ClipInfo>;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "at most {MAX_CLIPS} clips")
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(
            self,
            mut seq: A,
        ) -> Result<Self::Value, A::Error> {
            let too_many = || serde::de::Error::custom(format!("more than {MAX_CLIPS} clips"));
            if seq.size_hint().is_some_and(|n| n > MAX_CLIPS) {
                return Err(too_many());
            }
            let mut clips = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(4096));
            while let Some(clip) = seq.next_element()? {
                if clips.len() == MAX_CLIPS {
                    return Err(too_many());
                }
                clips.push(clip);
            }
            Ok(clips)
        }
    }
    decoder.deserialize_seq(Clips)
}

/// How a dataset was made.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DatasetHeader {
    /// Version of camloc that wrote the file.
    pub camloc_version: String,
    /// Projection protocol.
    pub protocol: Protocol,
    /// The camera classes (labels 1..=n).
    pub cameras: CameraSet,
    /// Random seed (jitter, noise).
    pub seed: u64,
    /// Frame stride: every `stride`-th mocap frame was considered.
    pub stride: usize,
    /// Frame selection by pose: a strided frame was kept when its maximum per-joint distance
    /// to every frame kept before it in its clip was more than this (mm); 0 for none.
    pub min_pose_distance_mm: f64,
    /// The 3D pose augmentation applied per sample.
    pub augmentation: Augmentation,
    /// Camera jitter, roll and distance of the perspective protocols: the azimuth and
    /// elevation bounds the views were drawn within (a finer sphere's, half its spacing, are
    /// narrower than the configured ones; files written before this was so record the
    /// configured ones).
    pub jitter: Jitter,
    /// The studio of the `rig` protocol.
    pub rig: Rig,
    /// The joint-angle limits [`Augmentation::posture`] drew within, learned from the poses
    /// the dataset was made from.
    pub posture_limits: PostureLimits,
    /// Views left out because no descriptor could describe them: their 2D torso (hip to
    /// shoulder midpoints, or pelvis to neck) is degenerate, as when a camera looks along it
    /// (`camloc_features::Descriptor::describable_by_all`).
    pub undescribable_views: usize,
    /// 2D noise standard deviation as a fraction of the 2D torso length (0 for none).
    pub noise_fraction: f64,
    /// Clips the samples come from, indexed by [`Sample::clip`] (at most [`MAX_CLIPS`]).
    #[serde(deserialize_with = "at_most_max_clips")]
    pub clips: Vec<ClipInfo>,
}

/// One labelled 2D projection of a 3D pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Projected landmarks: orthographic metres for `canonical`, focal-length-scaled image
    /// units (v down) for the perspective protocols (`rig`: pixels from the principal point,
    /// distorted).
    pub landmarks: Pose2,
    /// Bit `i` set when landmark `i` was dropped (treat as missing); 0 for complete poses.
    pub missing_mask: u16,
    /// Camera class label (1-based, in [`DatasetHeader::cameras`]); under `sphere` and `rig` the
    /// camera of the direction's elevation ring and azimuth quadrant.
    pub label: u16,
    /// Whether the camera direction lies in the label's class box (azimuth and elevation
    /// within the jitter bounds of its centre): always under `canonical` and `jittered`.
    pub in_class_box: bool,
    /// The exact camera rotation used (rows: camera axes in world coordinates); equals the
    /// class rotation under `canonical`, a jittered one otherwise; under `rig`, the camera
    /// seen from the person (looking from its centre at the pelvis, [`crate::RigView`]).
    pub rotation: Matrix3,
    /// Index into [`DatasetHeader::clips`].
    pub clip: u32,
    /// Frame index in the clip (0-based, before striding).
    pub frame: u32,
    /// The canonical 3D pose, metres (pelvis at origin, facing -x, z up).
    pub pose3: Pose3,
}

/// Number of samples seen by one camera.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CameraCount {
    /// Camera label.
    pub label: u16,
    /// Number of samples.
    pub samples: usize,
}

/// A labelled dataset: header and samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dataset {
    /// How the dataset was made.
    pub header: DatasetHeader,
    /// The samples.
    pub samples: Vec<Sample>,
}

impl Validate for Dataset {
    type Invalid = DatasetError;

    /// Checks the header (a valid camera set, stride at least 1, a finite non-negative noise
    /// fraction) and every sample (clip index and label within the header, a mask naming only
    /// the 15 landmarks, finite landmarks, rotation and 3D pose).
    ///
    /// # Errors
    /// [`DatasetError::Cameras`], [`DatasetError::BadHeader`], then for the first bad sample
    /// [`DatasetError::BadClipIndex`], [`DatasetError::BadLabel`],
    /// [`DatasetError::BadMissingMask`] or [`DatasetError::NonFinite`].
    fn validate(&self) -> Result<(), DatasetError> {
        let header = &self.header;
        header.cameras.validate().map_err(DatasetError::Cameras)?;
        if header.stride == 0 {
            return Err(DatasetError::BadHeader {
                field: "stride",
                value: "0".into(),
                reason: "must be at least 1",
            });
        }
        if !(header.noise_fraction >= 0.0 && header.noise_fraction.is_finite()) {
            return Err(DatasetError::BadHeader {
                field: "noise_fraction",
                value: header.noise_fraction.to_string(),
                reason: "must be finite and >= 0",
            });
        }
        let clips = header.clips.len();
        let cameras = header.cameras.len();
        for (i, s) in self.samples.iter().enumerate() {
            if s.clip as usize >= clips {
                return Err(DatasetError::BadClipIndex {
                    sample: i,
                    clip: s.clip,
                    clips,
                });
            }
            if s.label == 0 || s.label as usize > cameras {
                return Err(DatasetError::BadLabel {
                    sample: i,
                    label: s.label,
                    cameras,
                });
            }
            if s.missing_mask >> NUM_LANDMARKS != 0 {
                return Err(DatasetError::BadMissingMask {
                    sample: i,
                    mask: s.missing_mask,
                });
            }
            let non_finite = |what| DatasetError::NonFinite { sample: i, what };
            if !s.landmarks.is_finite() {
                return Err(non_finite("2D landmarks"));
            }
            if !s.rotation.iter().all(|v| v.is_finite()) {
                return Err(non_finite("rotation"));
            }
            if !s.pose3.is_finite() {
                return Err(non_finite("3D pose"));
            }
        }
        Ok(())
    }
}

/// Dataset files: [`camloc_store::DATASET_KIND`] (magic `CAMLOCDS`); load with
/// [`Persist::load`], write with [`Persist::save`] (no overwrite unless asked).
impl Persist for Dataset {
    const KIND: FileKind = camloc_store::DATASET_KIND;
}

impl Dataset {
    /// Subject of a sample.
    pub fn subject_of(&self, sample: &Sample) -> &str {
        self.header
            .clips
            .get(sample.clip as usize)
            .map_or("?", |c| c.subject.as_str())
    }

    /// Motion category of a sample's clip.
    pub fn category_of(&self, sample: &Sample) -> MotionCategory {
        self.header
            .clips
            .get(sample.clip as usize)
            .map_or(MotionCategory::Other, |c| c.category)
    }

    /// Samples per motion category, for every category that has any, in
    /// [`MotionCategory::ALL`] order.
    pub fn samples_per_category(&self) -> Vec<(MotionCategory, usize)> {
        let mut counts = [0usize; MotionCategory::ALL.len()];
        for s in &self.samples {
            let c = self.category_of(s);
            if let Some(i) = MotionCategory::ALL.iter().position(|&a| a == c) {
                counts[i] += 1;
            }
        }
        MotionCategory::ALL
            .into_iter()
            .zip(counts)
            .filter(|(_, n)| *n > 0)
            .collect()
    }

    /// Splits by motion category: samples of clips of `category` go to the second dataset,
    /// all others to the first (leave-one-category-out). Both keep the full header.
    pub fn split_by_category(&self, category: MotionCategory) -> (Dataset, Dataset) {
        self.split_where(|s| self.category_of(s) == category)
    }

    /// Splits into the samples for which `is_test` is false (first) and true (second), both
    /// with the full header.
    fn split_where(&self, is_test: impl Fn(&Sample) -> bool) -> (Dataset, Dataset) {
        let (test, train): (Vec<Sample>, Vec<Sample>) =
            self.samples.iter().cloned().partition(|s| is_test(s));
        (
            Dataset {
                header: self.header.clone(),
                samples: train,
            },
            Dataset {
                header: self.header.clone(),
                samples: test,
            },
        )
    }

    /// Clip name of a sample.
    pub fn clip_of(&self, sample: &Sample) -> &str {
        self.header
            .clips
            .get(sample.clip as usize)
            .map_or("?", |c| c.name.as_str())
    }

    /// Distinct subjects with their number of samples, sorted by subject id (numerically when
    /// ids are numbers).
    pub fn subjects(&self) -> Vec<(String, usize)> {
        let mut counts: BTreeMap<SubjectKey, usize> = BTreeMap::new();
        for s in &self.samples {
            *counts
                .entry(SubjectKey(self.subject_of(s).to_string()))
                .or_default() += 1;
        }
        counts.into_iter().map(|(k, n)| (k.0, n)).collect()
    }

    /// Samples per camera label, for every camera of the set (zero counts included).
    pub fn samples_per_camera(&self) -> Vec<CameraCount> {
        let mut counts = vec![0usize; self.header.cameras.len()];
        for s in &self.samples {
            if let Some(c) = (s.label as usize)
                .checked_sub(1)
                .and_then(|i| counts.get_mut(i))
            {
                *c += 1;
            }
        }
        counts
            .into_iter()
            .enumerate()
            .map(|(i, samples)| CameraCount {
                label: i as u16 + 1,
                samples,
            })
            .collect()
    }

    /// The distinct canonical 3D poses of the dataset (one per clip and frame, in sample
    /// order): what a reconstruction basis is built from.
    pub fn unique_poses(&self) -> Vec<Pose3> {
        let mut seen = std::collections::HashSet::new();
        self.samples
            .iter()
            .filter(|s| seen.insert((s.clip, s.frame)))
            .map(|s| s.pose3)
            .collect()
    }

    /// Appends the samples of `other` (views of other protocols or seeds, trained on
    /// together): its clips join this one's list (a clip listed by both, the same
    /// [`ClipInfo`], once) and its samples' clip indices follow them; its undescribable views
    /// are added, the rest of the header stays this one's.
    ///
    /// # Errors
    /// [`DatasetError::Incompatible`] when `other` has another camera set (labels would mean
    /// other cameras) or the clips would be more than [`MAX_CLIPS`].
    pub fn append(&mut self, other: Dataset) -> Result<(), DatasetError> {
        if other.header.cameras != self.header.cameras {
            return Err(DatasetError::Incompatible(format!(
                "one has {} cameras ({} azimuths at {:?} deg), the other {} ({} at {:?} deg)",
                self.header.cameras.len(),
                self.header.cameras.azimuths(),
                self.header.cameras.elevations_deg(),
                other.header.cameras.len(),
                other.header.cameras.azimuths(),
                other.header.cameras.elevations_deg()
            )));
        }
        let index: BTreeMap<(&str, &str), usize> = (self.header.clips.iter().enumerate())
            .map(|(i, c)| ((c.subject.as_str(), c.name.as_str()), i))
            .collect();
        let mut moved = Vec::with_capacity(other.header.clips.len());
        let mut added = Vec::new();
        for clip in other.header.clips {
            let known = index
                .get(&(clip.subject.as_str(), clip.name.as_str()))
                .filter(|&&i| self.header.clips[i] == clip);
            moved.push(match known {
                Some(&i) => i,
                None => {
                    added.push(clip);
                    self.header.clips.len() + added.len() - 1
                }
            });
        }
        if self.header.clips.len() + added.len() > MAX_CLIPS {
            return Err(DatasetError::Incompatible(format!(
                "together they list more than {MAX_CLIPS} clips"
            )));
        }
        self.header.clips.extend(added);
        self.header.undescribable_views =
            (self.header.undescribable_views).saturating_add(other.header.undescribable_views);
        let clip_of = |s: &Sample| moved.get(s.clip as usize).copied();
        for mut sample in other.samples {
            // A sample of a clip its dataset does not list keeps an index past the list,
            // which validation refuses.
            sample.clip = clip_of(&sample).map_or(u32::MAX, |c| c as u32);
            self.samples.push(sample);
        }
        Ok(())
    }

    /// Splits by subject: samples whose subject is in `test_subjects` go to the second dataset,
    /// all others to the first. Both keep the full header. Never splits a subject.
    pub fn split_by_subjects(&self, test_subjects: &[String]) -> (Dataset, Dataset) {
        self.split_where(|s| test_subjects.iter().any(|t| t == self.subject_of(s)))
    }
}

/// The subjects held out for testing by default: every fourth subject in sorted order,
/// starting with the second, so that about a quarter of subjects (and no frame of theirs) are
/// unseen in training. Deterministic for a given subject list.
pub fn default_test_subjects(subjects: &[(String, usize)]) -> Vec<String> {
    subjects
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 4 == 1)
        .map(|(_, (s, _))| s.clone())
        .collect()
}

/// Orders subject ids numerically when both are numbers, else as text.
#[derive(Clone, Debug, PartialEq, Eq)]
struct SubjectKey(String);

impl Ord for SubjectKey {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        match (self.0.parse::<u64>(), other.0.parse::<u64>()) {
            (Ok(a), Ok(b)) => a.cmp(&b).then_with(|| self.0.cmp(&other.0)),
            _ => self.0.cmp(&other.0),
        }
    }
}

impl PartialOrd for SubjectKey {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
