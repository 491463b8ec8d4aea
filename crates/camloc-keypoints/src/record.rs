//! The reader output ([`KeypointRecord`]) and how the readers build it.

use camloc_skeleton::{Landmark, PartialPose2};

use crate::ReadOptions;
use crate::error::{KeypointError, Location, PosePlace};
use crate::layout::{Joint, map_joints};
use crate::torso::derive_torso;

/// One pose read from a keypoint file.
#[derive(Clone, Debug, PartialEq)]
pub struct KeypointRecord {
    /// Identifier of the pose: the camloc `id`, the LSP image name, or `"{image_id}/{id}"` for
    /// COCO (see the crate documentation).
    pub id: String,
    /// The 15 landmarks in the file's image coordinates (usually pixels, `v` down); `None` where
    /// a landmark is missing.
    pub pose: PartialPose2,
    /// Landmarks computed from other keypoints rather than read as one annotated point (pelvis
    /// and neck by [`derive_torso`], the COCO head from the face points), in landmark order.
    pub derived: Vec<Landmark>,
    /// Where the pose is in the input, e.g. `lsp.csv: line 17` or `poses.json: poses[3]`.
    pub source: String,
    /// The video frame of the pose (0-based), for inputs that have frames: the number in an
    /// OpenPose file name, MMPose's `frame_id`, an integer COCO `image_id`, the position in a
    /// MediaPipe list, the row of a `.npy` array. `None` otherwise.
    pub frame: Option<u64>,
    /// The person: a tracker's `track_id` (COCO, MMPose) when the detection has one, else the
    /// person's position among the poses of its frame (0-based: OpenPose `people`, MMPose
    /// `instances`); `None` for inputs with one pose per frame or no frames.
    pub person: Option<u64>,
    /// Whether `person` is the pose's position among its frame's poses (the detector's
    /// order, which may change from frame to frame), not a tracker's id.
    pub person_is_position: bool,
}

impl KeypointRecord {
    /// The record of the pose a reader refused with `error`
    /// ([`KeypointError::refused_pose`]): its place, no landmark, nothing derived; and why.
    /// `None` for other errors.
    pub fn of_refused_pose(error: &KeypointError) -> Option<(KeypointRecord, String)> {
        let (place, message) = error.refused_pose()?;
        let PosePlace {
            id,
            source,
            frame,
            person,
        } = place.clone();
        let record = KeypointRecord {
            id,
            pose: PartialPose2::empty(),
            derived: Vec::new(),
            source,
            frame,
            person,
            // A refused pose has no landmarks to follow a person by: its number stays.
            person_is_position: false,
        };
        Some((record, message))
    }

    /// `true` when `landmark` was derived rather than read (see [`KeypointRecord::derived`]).
    pub fn is_derived(&self, landmark: Landmark) -> bool {
        self.derived.contains(&landmark)
    }

    /// Checks that the pelvis and the neck, the torso every camloc descriptor is scaled by, are
    /// present; otherwise returns [`KeypointError::MissingTorso`] naming the pose.
    ///
    /// Readers do not reject such poses themselves: what to do with them is the caller's choice.
    pub fn require_torso(&self) -> Result<(), KeypointError> {
        let missing: Vec<Landmark> = [Landmark::Pelvis, Landmark::Neck]
            .into_iter()
            .filter(|l| self.pose.points[l.index()].is_none())
            .collect();
        if missing.is_empty() {
            Ok(())
        } else {
            Err(KeypointError::MissingTorso {
                id: self.id.clone(),
                origin: self.source.clone(),
                missing,
            })
        }
    }
}

/// The record of one detection read at JSON `path` of `file`: `points` (one per joint of
/// `table`, `None` for a joint not kept) mapped to camloc's landmarks ([`map_joints`]), then
/// [`finish`]ed as `id`.
pub(crate) fn from_joints(
    table: &[Joint],
    points: impl IntoIterator<Item = Option<[f64; 2]>>,
    id: String,
    file: &str,
    path: &str,
    options: &ReadOptions,
) -> KeypointRecord {
    let (pose, derived) = map_joints(table, points);
    let source = format!("{file}: {}", Location::Path(path.to_owned()));
    finish(id, pose, derived, source, options)
}

/// Builds a record: applies [`derive_torso`] when `options.derive_torso`, and records what was
/// derived (`derived` holds what the format-specific reader already computed).
pub(crate) fn finish(
    id: String,
    mut pose: PartialPose2,
    mut derived: Vec<Landmark>,
    source: String,
    options: &ReadOptions,
) -> KeypointRecord {
    if options.derive_torso {
        derived.extend(derive_torso(&mut pose));
    }
    derived.sort_unstable();
    derived.dedup();
    KeypointRecord {
        id,
        pose,
        derived,
        source,
        frame: None,
        person: None,
        person_is_position: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::torso::tests::with;

    #[test]
    fn require_torso_names_the_pose_and_what_is_missing() {
        let record = KeypointRecord {
            id: "im7".into(),
            pose: with(&[(Landmark::Neck, [1.0, 2.0])]),
            derived: vec![],
            source: "x.csv: line 9".into(),
            frame: None,
            person: None,
            person_is_position: false,
        };
        let err = record.require_torso().unwrap_err();
        assert!(
            matches!(&err, KeypointError::MissingTorso { id, missing, .. } if id == "im7" && missing == &[Landmark::Pelvis])
        );
        assert!(
            err.to_string()
                .starts_with("x.csv: line 9: pose \"im7\" has no pelvis"),
            "{err}"
        );
    }
}
