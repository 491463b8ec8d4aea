//! A landmark missing for a few frames of a sequence is filled in from the frames around it
//! (`PoseReconstructor::with_gap_fill`, on by default): its 3D follows the complete
//! sequence's, where each frame's fill from the pose basis can only guess; the frames still
//! name it as filled in.

mod common;
#[path = "common/hybrid.rs"]
mod hybrid;
#[path = "common/moving.rs"]
mod moving;

use camloc::reconstruct::mpjpe_after_similarity;
use camloc::{CamlocError, Landmark, PoseReconstructor};

/// The frames of the gap.
const GAP: std::ops::Range<usize> = 4..8;

/// Each frame's 3D (mm after similarity alignment) from the complete sequence's, with the
/// left knee and ankle missing in the frames of [`GAP`].
fn apart_from_complete(reconstructor: &PoseReconstructor) -> Vec<f64> {
    let complete = moving::frames(12);
    let mut hidden = complete.clone();
    for t in GAP {
        hidden[t].points[Landmark::LeftKnee.index()] = None;
        hidden[t].points[Landmark::LeftAnkle.index()] = None;
    }
    let whole = reconstructor.reconstruct_sequence(&complete).unwrap();
    let gapped = reconstructor.reconstruct_sequence(&hidden).unwrap();
    whole
        .frames
        .iter()
        .zip(&gapped.frames)
        .enumerate()
        .map(|(t, (w, g))| {
            let (w, g) = (w.as_ref().unwrap(), g.as_ref().unwrap());
            let named = if GAP.contains(&t) {
                vec![Landmark::LeftKnee, Landmark::LeftAnkle]
            } else {
                Vec::new()
            };
            assert_eq!(g.imputed, named, "frame {t}");
            mpjpe_after_similarity(&g.reconstruction.pose, &w.reconstruction.pose)
        })
        .collect()
}

#[test]
fn a_short_gap_is_filled_in_from_the_frames_around_it() {
    let reconstructor = hybrid::hybrid_reconstructor();
    let filled = apart_from_complete(&reconstructor);
    let per_frame = apart_from_complete(&reconstructor.clone().with_gap_fill(0.0).unwrap());
    let mean = |d: &[f64]| GAP.map(|t| d[t]).sum::<f64>() / GAP.len() as f64;
    eprintln!(
        "gap frames from the complete sequence's 3D: {:.1} mm filled from the frames around, \
         {:.1} mm filled per frame",
        mean(&filled),
        mean(&per_frame)
    );
    assert!(mean(&filled) < 10.0, "{filled:?}");
    assert!(mean(&filled) < mean(&per_frame), "{filled:?} {per_frame:?}");
}

#[test]
fn a_gap_fill_time_must_be_a_number_of_seconds() {
    let reconstructor = hybrid::hybrid_reconstructor();
    for bad in [-0.1, f64::NAN, f64::INFINITY] {
        let err = reconstructor.clone().with_gap_fill(bad).unwrap_err();
        assert!(
            matches!(
                err,
                CamlocError::InvalidOption {
                    name: "gap fill",
                    ..
                }
            ),
            "{err}"
        );
    }
}
