//! Readers that turn CMU motion capture (BVH, and ASF skeletons with AMC motions) into
//! sequences of 15-landmark [`Pose3`]s, plus [`canonicalise`] (docs/conventions.md sections 1 and
//! 3).
//!
//! # Conventions
//!
//! * **Output frame.** Poses are in metres in the right-handed z-up world of docs/conventions.md
//!   section 1. The files are y-up; a file point `(x, y, z)` becomes `(x, -z, y)` times the unit
//!   scale. CMU subjects face +z in the files, so read poses face -y; [`canonicalise`] turns them
//!   to face -x with the pelvis at the origin.
//! * **Units.** BVH files carry no unit: coordinates are taken to be CMU units,
//!   [`CMU_UNIT_M`] metres each. ASF files declare `:units length L`, meaning one unit is
//!   `1 / L` inch (CMU uses `L = 0.45`, i.e. [`CMU_UNIT_M`]).
//! * **Landmarks** are joint positions, located as in docs/conventions.md section 3:
//!   for BVH the joint's origin (see [`parse_bvh`] for the two joint namings), for ASF the end
//!   point of a bone (see [`parse_asf`]); the pelvis is the root position.
//! * **CMU BVH versus ASF.** The CMU BVH conversions drop the ASF `thorax` bone (`lowerneck`
//!   and the collars sit at the top of `Chest2`, the ASF `upperback`), so their torso
//!   (pelvis-neck) is shorter by the thorax length, about 0.12 m, than the torso of the same
//!   subject read from ASF/AMC; the other limbs agree.
//! * **Errors** name the file and the 1-based line ([`MocapError`]); no input makes a reader
//!   panic, allocate in proportion to a declared (rather than present) size, or recurse.
//!
//! # Example
//!
//! ```no_run
//! use camloc_skeleton::Landmark;
//! use camloc_mocap::{canonicalise, discover};
//!
//! for source in discover("../shared/data/cmu")? {
//!     let clip = source.read()?;
//!     for pose in &clip.frames {
//!         let canonical = canonicalise(pose)?; // pelvis at 0, facing -x
//!         assert!(canonical.get(Landmark::RightHip)[1] > 0.0);
//!     }
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod amc;
mod asf;
mod bvh;
mod bvh_gaps;
mod bvh_skeleton;
mod bvh_solve;
mod bvh_write;
mod canonical;
mod category;
mod discover;
mod error;
mod euler;
mod rotation;
mod text;

use std::path::Path;

pub use amc::{parse_amc, read_amc};
pub use asf::{AsfSkeleton, parse_asf, read_asf};
pub use bvh::{parse_bvh, parse_bvh_with_unit, read_bvh, read_bvh_with_unit};
pub use bvh_write::{
    BVH_CENTIMETRE, BVH_FRAME_TIME_RANGE_S, BVH_UNIT_RANGE_M, BvhOptions, BvhWriteError, write_bvh,
    write_person_bvh,
};
pub use canonical::canonicalise;
pub use category::{CATEGORY_RULES, CategorySource, MAX_INDEX_BYTES, MocapIndex, MotionCategory};
pub use discover::{MocapSource, discover};
pub use error::{CanonicaliseError, MocapError, ParseProblem};

use camloc_skeleton::Pose3;

/// Metres per CMU length unit: one unit is `1 / 0.45` inch (ASF `:units length 0.45`),
/// about 0.0564 m.
pub const CMU_UNIT_M: f64 = 0.0254 / 0.45;

/// Frame period of CMU AMC motions, in seconds (120 Hz). AMC files do not record it.
pub const CMU_FRAME_TIME_S: f64 = 1.0 / 120.0;

/// The largest motion-capture file (BVH, ASF, AMC) the readers take, bytes: 1 GiB, hundreds of
/// times the largest CMU clip (an hour at 120 frames a second is about 300 MiB of BVH).
pub const MAX_MOCAP_FILE_BYTES: u64 = 1 << 30;

/// One motion clip: a sequence of 3D poses with its subject and clip ids.
#[derive(Clone, Debug, PartialEq)]
pub struct MocapClip {
    /// Subject id: the file name up to its first `_` (`35` for `35_02.bvh`).
    pub subject: String,
    /// Clip id: the file stem (`35_02` for `35_02.bvh`).
    pub clip: String,
    /// Time between consecutive frames, in seconds.
    pub frame_time_s: f64,
    /// One pose per frame, in metres in the z-up world frame (not canonicalised); empty when
    /// the file declares no frames.
    pub frames: Vec<Pose3>,
}

/// Subject and clip ids of a file named `source_name` (a path or a bare file name):
/// the clip is the file stem, the subject the stem up to its first `_`.
fn subject_and_clip(source_name: &str) -> (String, String) {
    let stem = Path::new(source_name)
        .file_stem()
        .map_or_else(|| source_name.into(), |s| s.to_string_lossy());
    let subject = stem.split('_').next().unwrap_or_default().to_owned();
    (subject, stem.into_owned())
}

/// Reads a whole file, mapping failures to [`MocapError::Io`].
fn read_file(path: &Path) -> Result<Vec<u8>, MocapError> {
    read_capped(path, MAX_MOCAP_FILE_BYTES)
}

/// Bytes at the start of a motion-capture file looked at before the rest is read.
const TEXT_CHECK_BYTES: u64 = 1 << 16;

/// The bytes of the file at `path`, refused ([`MocapError::TooLarge`]) beyond `limit` bytes
/// without reading further, and refused after its first [`TEXT_CHECK_BYTES`] when they are not
/// text (a NUL byte or invalid UTF-8: `/dev/zero` or `/dev/urandom` had been read to the
/// limit, 1 GiB, before the parser refused them).
fn read_capped(path: &Path, limit: u64) -> Result<Vec<u8>, MocapError> {
    use std::io::Read;
    let io = |source| MocapError::Io {
        path: path.to_owned(),
        source,
    };
    let mut bytes = Vec::new();
    let mut file = std::fs::File::open(path).map_err(io)?;
    (&mut file)
        .take(TEXT_CHECK_BYTES.min(limit + 1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    let text_error = |line: usize| MocapError::Parse {
        file: path.display().to_string(),
        line,
        problem: ParseProblem::NotUtf8,
    };
    let line_at = |end: usize| 1 + bytes[..end].iter().filter(|&&b| b == b'\n').count();
    if let Some(nul) = bytes.iter().position(|&b| b == 0) {
        return Err(text_error(line_at(nul)));
    }
    if let Err(e) = std::str::from_utf8(&bytes)
        && e.error_len().is_some()
    {
        return Err(text_error(line_at(e.valid_up_to())));
    }
    let rest = (limit + 1).saturating_sub(bytes.len() as u64);
    file.take(rest).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(MocapError::TooLarge {
            path: path.to_owned(),
            limit,
        });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_come_from_the_file_name() {
        assert_eq!(
            subject_and_clip("data/cmu/35_02.bvh"),
            ("35".to_owned(), "35_02".to_owned())
        );
        assert_eq!(subject_and_clip("walk.amc"), ("walk".into(), "walk".into()));
        assert_eq!(
            subject_and_clip("118_3_b.amc"),
            ("118".into(), "118_3_b".into())
        );
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_or_long_file_is_refused_early() {
        // Not text: refused after its first 64 KiB.
        let path = Path::new("/dev/zero");
        match read_capped(path, MAX_MOCAP_FILE_BYTES) {
            Err(MocapError::Parse {
                line: 1, problem, ..
            }) => {
                assert_eq!(problem, ParseProblem::NotUtf8)
            }
            other => panic!("{other:?}"),
        }
        // Text beyond the limit: refused at the limit.
        let long = std::env::temp_dir().join(format!("camloc-long-{}.bvh", std::process::id()));
        std::fs::write(&long, "HIERARCHY\n".repeat(300)).unwrap();
        let read = read_capped(&long, 1000);
        std::fs::remove_file(&long).unwrap();
        match read {
            Err(MocapError::TooLarge { limit, .. }) => assert_eq!(limit, 1000),
            other => panic!("{other:?}"),
        }
        let message = MocapError::TooLarge {
            path: path.to_owned(),
            limit: MAX_MOCAP_FILE_BYTES,
        }
        .to_string();
        assert_eq!(
            message,
            "/dev/zero: larger than 1024 MiB, more than a motion-capture file holds; not read"
        );
    }

    #[test]
    fn cmu_unit_is_about_56_mm() {
        assert!((CMU_UNIT_M - 0.0564).abs() < 1e-4);
    }
}
