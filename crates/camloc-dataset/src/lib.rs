//! camloc datasets: 2D projections of real 3D poses, labelled with the camera that saw them.
//!
//! A [`Dataset`] is what `cargo xtask gen-dataset` writes and what training, evaluation and
//! reconstruction read. Each [`Sample`] holds the 15 projected landmarks, the camera's class
//! label and exact rotation, the subject, clip and frame it came from, and the canonical 3D pose
//! (metres, pelvis at the origin, facing -x). The [`DatasetHeader`] records the protocol, camera
//! set, seed and versions, so a file says how it was made.
//!
//! [`generate`] builds a dataset from canonical 3D poses under a [`Protocol`]
//! (SPEC.md section 7); `Dataset` implements [`camloc_store::Persist`] (save, load with validation) as a versioned,
//! checksummed file ([`camloc_store`]). Splits are by subject ([`Dataset::split_by_subjects`]).

mod dataset;
mod from_mocap;
mod generate;

pub use dataset::{
    CameraCount, ClipInfo, Dataset, DatasetError, DatasetHeader, Sample, default_test_subjects,
};
pub use from_mocap::{MocapSummary, default_cmu_folder, load_mocap_folders};
pub use generate::{GenerateConfig, Jitter, PoseSequence, Protocol, generate};
