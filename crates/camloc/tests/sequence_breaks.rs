//! A sequence with a gap (`PoseReconstructor::reconstruct_sequence_with_breaks`): the frames
//! on each side are solved as runs of their own, with the bone lengths of all frames.

mod common;
#[path = "common/hybrid.rs"]
mod hybrid;
#[path = "common/moving.rs"]
mod moving;

use camloc::{Landmark, PartialPose2, Pose3, PoseReconstructor};

/// The moving frames with the pelvis and the neck at the hip and shoulder midpoints, so that
/// every part of the sequence is lifted in the same placement as the whole (a sequence's
/// placement is its frames', `camloc::sequence_own_placement_weight`).
fn frames() -> Vec<PartialPose2> {
    moving::frames(10)
        .into_iter()
        .map(|f| {
            let mut p = f.complete().unwrap();
            let mid = |a: Landmark, b: Landmark| {
                let (a, b) = (p.get(a), p.get(b));
                [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
            };
            let (hips, shoulders) = (
                mid(Landmark::LeftHip, Landmark::RightHip),
                mid(Landmark::LeftShoulder, Landmark::RightShoulder),
            );
            p.points[Landmark::Pelvis.index()] = hips;
            p.points[Landmark::Neck.index()] = shoulders;
            PartialPose2::from(p)
        })
        .collect()
}

fn reconstructor() -> PoseReconstructor {
    hybrid::hybrid_reconstructor()
}

fn poses(result: &camloc::PoseSequenceReconstruction) -> Vec<Pose3> {
    result
        .frames
        .iter()
        .map(|f| f.as_ref().unwrap().reconstruction.pose)
        .collect()
}

#[test]
fn frames_after_a_gap_are_solved_apart_with_the_shared_lengths() {
    let frames = frames();
    let rec = reconstructor();
    let mut breaks = vec![false; frames.len()];
    breaks[5] = true;
    let split = rec
        .reconstruct_sequence_with_breaks(&frames, &breaks)
        .unwrap();
    let whole = rec.reconstruct_sequence(&frames).unwrap();
    // The lengths are those of all frames together (whose landmarks, smoothed over time
    // without the gap, differ a little): not either side's own.
    let close = |a: &camloc::reconstruct::BoneLengths, b: &camloc::reconstruct::BoneLengths| {
        a.relative_errors(b).iter().all(|e| e.abs() < 0.02)
    };
    assert!(close(&split.lengths, &whole.lengths));
    let first_alone = rec.reconstruct_sequence(&frames[..5]).unwrap().lengths;
    let second_alone = rec.reconstruct_sequence(&frames[5..]).unwrap().lengths;
    assert!(split.lengths != first_alone && split.lengths != second_alone);
    // Each side is what that side alone gives with those lengths.
    let given = rec.clone().with_bone_lengths(split.lengths);
    let first = given.reconstruct_sequence(&frames[..5]).unwrap();
    let second = given.reconstruct_sequence(&frames[5..]).unwrap();
    let expected: Vec<Pose3> = poses(&first).into_iter().chain(poses(&second)).collect();
    assert_eq!(poses(&split), expected);
    // Without the gap the smoothness ties the frames at the break to each other.
    assert_ne!(poses(&whole), expected);
}

#[test]
fn a_frame_or_two_that_fail_keep_their_neighbours_tied_and_three_split_them() {
    let frames = frames();
    let rec = reconstructor();
    let without = |gone: &[usize]| -> Vec<PartialPose2> {
        (0..frames.len())
            .filter(|t| !gone.contains(t))
            .map(|t| frames[t])
            .collect()
    };
    let failing = |gone: &[usize]| -> Vec<PartialPose2> {
        (0..frames.len())
            .map(|t| {
                if gone.contains(&t) {
                    PartialPose2::empty()
                } else {
                    frames[t]
                }
            })
            .collect()
    };
    // Two failed frames: the others stay one run, tied across them (not as split there).
    let gone = [4, 5];
    let result = rec.reconstruct_sequence(&failing(&gone)).unwrap();
    assert!(result.frames[4].is_err() && result.frames[5].is_err());
    let kept: Vec<Pose3> = result
        .frames
        .iter()
        .filter_map(|f| f.as_ref().ok().map(|r| r.reconstruction.pose))
        .collect();
    let mut at_the_gap = vec![false; 8];
    at_the_gap[4] = true;
    let apart = rec
        .reconstruct_sequence_with_breaks(&without(&gone), &at_the_gap)
        .unwrap();
    assert_eq!(kept.len(), 8);
    assert_ne!(kept, poses(&apart));
    // Three in a row split the frames into two runs.
    let gone = [4, 5, 6];
    let result = rec.reconstruct_sequence(&failing(&gone)).unwrap();
    let mut breaks = vec![false; 7];
    breaks[4] = true;
    let split = rec
        .reconstruct_sequence_with_breaks(&without(&gone), &breaks)
        .unwrap();
    let kept: Vec<Pose3> = result
        .frames
        .iter()
        .filter_map(|f| f.as_ref().ok().map(|r| r.reconstruction.pose))
        .collect();
    assert_eq!(kept, poses(&split));
}

#[test]
fn left_out_frames_are_reconstructed_alone_and_three_in_a_row_split_the_runs() {
    let frames = frames();
    let rec = reconstructor();
    let kept_poses = |result: &camloc::PoseSequenceReconstruction, gone: &[usize]| {
        (result.frames.iter().enumerate())
            .filter(|(t, _)| !gone.contains(t))
            .map(|(_, f)| f.as_ref().unwrap().reconstruction.pose)
            .collect::<Vec<Pose3>>()
    };
    let without = |gone: &[usize]| -> Vec<PartialPose2> {
        (0..frames.len())
            .filter(|t| !gone.contains(t))
            .map(|t| frames[t])
            .collect()
    };
    for (gone, split_at) in [(vec![4, 5], None), (vec![4, 5, 6], Some(4))] {
        let mut left_out = vec![false; frames.len()];
        for &t in &gone {
            left_out[t] = true;
        }
        // Consecutive frame numbers: the left-out frames count for frames the person is
        // missing from.
        let numbers: Vec<Option<u64>> = (0..frames.len() as u64).map(Some).collect();
        let result = rec
            .reconstruct_sequence_at_frames(&numbers, &frames, &left_out)
            .unwrap();
        // A left-out frame is its own reconstruction.
        for &t in &gone {
            assert_eq!(
                result.frames[t].as_ref().unwrap().reconstruction.pose,
                rec.reconstruct(&frames[t]).unwrap().reconstruction.pose
            );
        }
        // The others are the sequence of the person's other frames, which miss those frames
        // (their time passes in the landmarks' smoothing): two in a row keep their
        // neighbours tied, three split them as a gap.
        let kept_numbers: Vec<Option<u64>> = (0..frames.len() as u64)
            .filter(|t| !gone.contains(&(*t as usize)))
            .map(Some)
            .collect();
        let expected = rec
            .reconstruct_sequence_at_frames(
                &kept_numbers,
                &without(&gone),
                &vec![false; kept_numbers.len()],
            )
            .unwrap();
        assert_eq!(kept_poses(&result, &gone), poses(&expected));
        assert_eq!(result.lengths, expected.lengths);
        let mut breaks = vec![false; frames.len() - gone.len()];
        if let Some(t) = split_at {
            breaks[t] = true;
            // Split, each run's frames are consecutive: as runs given by their breaks.
            let split = rec
                .reconstruct_sequence_with_breaks(&without(&gone), &breaks)
                .unwrap();
            assert_eq!(poses(&split), poses(&expected));
        } else {
            let tied = rec
                .reconstruct_sequence_with_breaks(&without(&gone), &breaks)
                .unwrap();
            assert_ne!(
                poses(&tied),
                poses(&expected),
                "the missed frames' time counts"
            );
        }
    }
}
