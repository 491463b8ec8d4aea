//! `localize --npz`: the localizations of a run as NumPy arrays in one `.npz` archive, row n
//! for the n-th pose read, written as the poses are done ([`super::npz`]).

use std::io;
use std::path::{Path, PathBuf};

use camloc::keypoints::KeypointRecord;
use camloc::skeleton::{Landmark, NUM_LANDMARKS};
use camloc::store::{StagedFiles, quoted};
use camloc::{CameraHeight, Localization};

use super::CliError;
use super::npz::{Column, stage_npz};
use super::output::{RowFile, io_error};

/// The arrays of a `localize --npz` archive, in the order they are written. N is the number of
/// poses read, K the number of cameras; a failed pose is a row of sentinels (0, NaN) marked in
/// `failed`.
pub struct LocalizationArrays {
    target: PathBuf,
    cameras: usize,
    /// (N,) uint16: the camera label 1..=K, 0 where the pose failed.
    label: Column<u16>,
    /// (N,) uint16: the label after mirror folding, 0 where the pose failed.
    folded_label: Column<u16>,
    /// (N, K) float64: the probability of camera k + 1 in column k, NaN where the pose failed.
    probabilities: Column<f64>,
    /// (N,) float64, degrees: the continuous viewpoint, NaN where the pose failed or the model
    /// has no direction heads.
    azimuth_deg: Column<f64>,
    elevation_deg: Column<f64>,
    uncertainty_deg: Column<f64>,
    /// (N,) bool: `true` where the pose could not be localized.
    failed: Column<bool>,
    /// (N, 15) bool: landmark i (camloc15 order) is missing from the pose read, or far off the
    /// others (read as missing and filled in) in a localized pose.
    missing: Column<bool>,
    /// (N, 15) bool: landmark i was derived rather than read.
    derived: Column<bool>,
    /// (N,) int64: the pose's frame and person, -1 where the input has none.
    frame: Column<i64>,
    person: Column<i64>,
    /// (total bytes,) uint8: the ids, UTF-8, one after the other.
    id_utf8: Column<u8>,
    /// (N,) uint64: where each id ends in `id_utf8` (it starts where the previous one ended).
    id_end: Column<u64>,
    /// (3,) float64: the shares of the lower, middle and upper cameras the run localized
    /// under (`--camera-height from-input`'s estimate), NaN when it used none.
    camera_height_shares: Column<f64>,
    /// (3,) float64: the mean elevation above the pelvis (degrees) of the cameras of each
    /// height in that estimate ([`HeightShares::elevations_deg`](camloc::HeightShares::elevations_deg)),
    /// NaN where it has none.
    camera_height_elevations_deg: Column<f64>,
    /// (1,) float64: the independent views the estimate counted its poses as worth
    /// ([`HeightEstimate::views`](camloc::HeightEstimate::views)), NaN without an estimate.
    camera_height_views: Column<f64>,
}

impl LocalizationArrays {
    /// Starts the arrays of the archive `target`, for `cameras` cameras, localized under the
    /// prior `height`, estimated from `views` independent views (NaN: not estimated).
    ///
    /// # Errors
    /// When the scratch files cannot be made beside `target`.
    pub fn new(
        target: &Path,
        cameras: usize,
        height: CameraHeight,
        views: f64,
    ) -> Result<LocalizationArrays, CliError> {
        let mut camera_height_shares = Column::new(target, "camera_height_shares", None)?;
        let (shares, elevations) = height.reported();
        camera_height_shares
            .extend(shares)
            .map_err(io_error(target))?;
        let mut camera_height_elevations_deg =
            Column::new(target, "camera_height_elevations_deg", None)?;
        camera_height_elevations_deg
            .extend(elevations)
            .map_err(io_error(target))?;
        let mut camera_height_views = Column::new(target, "camera_height_views", None)?;
        camera_height_views.push(views).map_err(io_error(target))?;
        Ok(LocalizationArrays {
            target: target.to_path_buf(),
            cameras,
            label: Column::new(target, "label", None)?,
            folded_label: Column::new(target, "folded_label", None)?,
            probabilities: Column::new(target, "probabilities", Some(cameras))?,
            azimuth_deg: Column::new(target, "azimuth_deg", None)?,
            elevation_deg: Column::new(target, "elevation_deg", None)?,
            uncertainty_deg: Column::new(target, "uncertainty_deg", None)?,
            failed: Column::new(target, "failed", None)?,
            missing: Column::new(target, "missing", Some(NUM_LANDMARKS))?,
            derived: Column::new(target, "derived", Some(NUM_LANDMARKS))?,
            frame: Column::new(target, "frame", None)?,
            person: Column::new(target, "person", None)?,
            id_utf8: Column::new(target, "id_utf8", None)?,
            id_end: Column::new(target, "id_end", None)?,
            camera_height_shares,
            camera_height_elevations_deg,
            camera_height_views,
        })
    }

    fn append(&mut self, record: &KeypointRecord, loc: Option<&Localization>) -> io::Result<()> {
        let label = |l: Option<u16>| l.unwrap_or(0);
        self.label.push(label(loc.map(|l| l.label.get())))?;
        self.folded_label
            .push(label(loc.map(|l| l.folded_label.get())))?;
        match loc {
            Some(loc) if loc.probabilities.len() == self.cameras => {
                self.probabilities
                    .extend(loc.probabilities.iter().copied())?;
            }
            Some(loc) => {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "pose {} has {} camera probabilities, not {}",
                        quoted(&record.id),
                        loc.probabilities.len(),
                        self.cameras
                    ),
                ));
            }
            None => self
                .probabilities
                .extend(std::iter::repeat_n(f64::NAN, self.cameras))?,
        }
        let degrees = |d: fn(&Localization) -> Option<f64>| loc.and_then(d).unwrap_or(f64::NAN);
        self.azimuth_deg.push(degrees(|l| l.azimuth_deg))?;
        self.elevation_deg.push(degrees(|l| l.elevation_deg))?;
        self.uncertainty_deg.push(degrees(|l| l.uncertainty_deg))?;
        self.failed.push(loc.is_none())?;
        // Missing as localized (a landmark far off the others too, as the JSON says).
        match loc {
            Some(l) => self.missing.extend(flags(l.missing.iter().copied()))?,
            None => self.missing.extend(flags(record.pose.missing()))?,
        }
        self.derived.extend(flags(record.derived.iter().copied()))?;
        let place = |n: Option<u64>| n.map_or(-1, |n| i64::try_from(n).unwrap_or(i64::MAX));
        self.frame.push(place(record.frame))?;
        self.person.push(place(record.person))?;
        self.id_utf8.extend_bytes(record.id.as_bytes())?;
        self.id_end.push(self.id_utf8.len())
    }
}

/// The landmarks as one flag per landmark of camloc15, in its order.
fn flags(landmarks: impl Iterator<Item = Landmark>) -> [bool; NUM_LANDMARKS] {
    let mut flags = [false; NUM_LANDMARKS];
    for landmark in landmarks {
        flags[landmark.index()] = true;
    }
    flags
}

impl RowFile<Localization> for LocalizationArrays {
    fn push(
        &mut self,
        record: &KeypointRecord,
        row: Option<&Localization>,
    ) -> Result<(), CliError> {
        self.append(record, row).map_err(io_error(&self.target))
    }

    fn finish(self: Box<Self>, staged: &mut StagedFiles) -> Result<(), CliError> {
        let a = *self;
        // The entries in the order of the fields.
        macro_rules! entries {
            ($($column:ident)*) => { [$(a.$column.entry()),*] };
        }
        let entries = entries!(label folded_label probabilities azimuth_deg elevation_deg
            uncertainty_deg failed missing derived frame person id_utf8 id_end
            camera_height_shares camera_height_elevations_deg camera_height_views)
        .into_iter()
        .collect::<io::Result<Vec<_>>>()
        .map_err(io_error(&a.target))?;
        stage_npz(staged, &a.target, entries)?;
        Ok(())
    }
}
