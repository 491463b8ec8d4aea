//! Tests of [`super`]: identity jumps, outlier frames and the poses left out of a sequence.

use super::*;

fn at(x: f64, torso: f64) -> Option<TorsoAnchor> {
    Some(TorsoAnchor {
        pelvis: [x, 0.0],
        torso,
    })
}

#[test]
fn a_walk_has_no_jump_and_a_switch_of_people_has_one() {
    // 100 px torso, 20 px a frame: one person walking.
    let walk: Vec<_> = (0..10).map(|t| at(20.0 * f64::from(t), 100.0)).collect();
    let frames: Vec<Option<u64>> = (0..10).map(Some).collect();
    assert!(identity_jumps(&frames, &walk).is_empty());
    // Another person 300 px away from frame 6 on.
    let mut switched = walk.clone();
    for a in switched.iter_mut().skip(6) {
        a.as_mut().unwrap().pelvis[0] += 300.0;
    }
    assert_eq!(identity_jumps(&frames, &switched), vec![6]);
    // The same place, but two and a half times the size (a person nearer the camera)
    // from frame 4 on.
    let mut nearer = walk.clone();
    for a in nearer.iter_mut().skip(4) {
        a.as_mut().unwrap().torso = 250.0;
    }
    assert_eq!(identity_jumps(&frames, &nearer), vec![4]);
    // One frame whose hips a detector misplaced is not a jump, but an outlier.
    let mut misplaced = walk.clone();
    misplaced[5] = at(400.0, 40.0);
    assert!(identity_jumps(&frames, &misplaced).is_empty());
    assert_eq!(
        outlier_frames(&frames, &misplaced, FrameRate::default()),
        vec![5]
    );
    // Neither a walk nor a lasting switch has an outlier; two people's ids swapped for
    // one frame give one in each.
    assert!(outlier_frames(&frames, &walk, FrameRate::default()).is_empty());
    assert!(outlier_frames(&frames, &switched, FrameRate::default()).is_empty());
    let other: Vec<_> = (0..10)
        .map(|t| at(900.0 - 10.0 * f64::from(t), 100.0))
        .collect();
    let (mut a, mut b) = (walk.clone(), other.clone());
    std::mem::swap(&mut a[3], &mut b[3]);
    assert_eq!(outlier_frames(&frames, &a, FrameRate::default()), vec![3]);
    assert_eq!(outlier_frames(&frames, &b, FrameRate::default()), vec![3]);
    // Ids swapped at two frames with one between: the frame between is the person's.
    let (mut a, mut b) = (walk.clone(), other.clone());
    for t in [4, 6] {
        std::mem::swap(&mut a[t], &mut b[t]);
    }
    assert_eq!(
        outlier_frames(&frames, &a, FrameRate::default()),
        vec![4, 6]
    );
    assert_eq!(
        outlier_frames(&frames, &b, FrameRate::default()),
        vec![4, 6]
    );
    // At either end of a track.
    for end in [0, 9] {
        let (mut a, mut b) = (walk.clone(), other.clone());
        std::mem::swap(&mut a[end], &mut b[end]);
        assert_eq!(outlier_frames(&frames, &a, FrameRate::default()), vec![end]);
        assert_eq!(outlier_frames(&frames, &b, FrameRate::default()), vec![end]);
    }
    // Ids swapped for the first frame of the track and for three later: the frames of
    // the other person in each. A switch for the last four of ten frames is a change of
    // person, not an outlier.
    let frames: Vec<Option<u64>> = (0..20).map(Some).collect();
    let walk: Vec<_> = (0..20).map(|t| at(20.0 * f64::from(t), 100.0)).collect();
    let other: Vec<_> = (0..20)
        .map(|t| at(900.0 - 10.0 * f64::from(t), 100.0))
        .collect();
    let (mut a, mut b) = (walk.clone(), other.clone());
    for t in [0, 16, 17, 18] {
        std::mem::swap(&mut a[t], &mut b[t]);
    }
    assert_eq!(
        outlier_frames(&frames, &a, FrameRate::default()),
        vec![0, 16, 17, 18]
    );
    assert_eq!(
        outlier_frames(&frames, &b, FrameRate::default()),
        vec![0, 16, 17, 18]
    );
    let frames: Vec<Option<u64>> = (0..10).map(Some).collect();
    let walk: Vec<_> = (0..10).map(|t| at(20.0 * f64::from(t), 100.0)).collect();
    let other: Vec<_> = (0..10)
        .map(|t| at(900.0 - 10.0 * f64::from(t), 100.0))
        .collect();
    let (mut a, mut b) = (walk.clone(), other.clone());
    for t in 6..10 {
        std::mem::swap(&mut a[t], &mut b[t]);
    }
    assert!(outlier_frames(&frames, &a, FrameRate::default()).is_empty());
    assert!(outlier_frames(&frames, &b, FrameRate::default()).is_empty());
    // Away for longer than OUTLIER_RUN_FRAMES in a long track: a change of person (and the
    // frames before it are the person's, whom the track comes back to).
    let frames: Vec<Option<u64>> = (0..40).map(Some).collect();
    let long_walk: Vec<_> = (0..40).map(|t| at(20.0 * f64::from(t), 100.0)).collect();
    let mut away = long_walk.clone();
    for a in &mut away[10..10 + OUTLIER_RUN_FRAMES + 1] {
        a.as_mut().unwrap().pelvis[0] += 2000.0;
    }
    assert!(outlier_frames(&frames, &away, FrameRate::default()).is_empty());
    for a in &mut away[10 + OUTLIER_RUN_FRAMES..10 + OUTLIER_RUN_FRAMES + 1] {
        a.as_mut().unwrap().pelvis[0] -= 2000.0;
    }
    assert_eq!(
        outlier_frames(&frames, &away, FrameRate::default()),
        (10..10 + OUTLIER_RUN_FRAMES).collect::<Vec<_>>()
    );
    // At 120 frames a second another person's 0.1 s is 12 frames: left out told the
    // rate, a change of person not told.
    let frames: Vec<Option<u64>> = (0..120).map(Some).collect();
    let mut away: Vec<_> = (0..120).map(|t| at(5.0 * f64::from(t), 100.0)).collect();
    for a in &mut away[40..52] {
        a.as_mut().unwrap().pelvis[0] += 2000.0;
    }
    let rate = FrameRate::new(120.0).unwrap();
    assert_eq!(
        outlier_frames(&frames, &away, rate),
        (40..52).collect::<Vec<_>>()
    );
    assert!(outlier_frames(&frames, &away, FrameRate::default()).is_empty());
    let frames: Vec<Option<u64>> = (0..10).map(Some).collect();
    // A person running past a camera filmed at a low frame rate moves far every frame:
    // no outlier, as the frames before and after disagree too.
    let fast: Vec<_> = (0..10).map(|t| at(150.0 * f64::from(t), 100.0)).collect();
    assert!(outlier_frames(&frames, &fast, FrameRate::default()).is_empty());
}

#[test]
fn a_steady_runner_is_no_jump_and_a_switch_while_running_is_one() {
    // A torso and a half a frame: a sprint, or a jogger seen from steeply above (a
    // simulated user's such views were warned of 24-36 times).
    let frames: Vec<Option<u64>> = (0..30).map(Some).collect();
    let runner: Vec<_> = (0..30)
        .map(|t| at(150.0 * f64::from(t) + 10.0 * f64::from(t % 2), 100.0))
        .collect();
    assert!(identity_jumps(&frames, &runner).is_empty());
    // Starting to run from standing: the speed grows by a fifth of a torso a frame.
    let starting: Vec<_> = (0..30)
        .map(|t| at(10.0 * f64::from(t * t), 100.0))
        .collect();
    assert!(identity_jumps(&frames, &starting).is_empty());
    // Another person, 600 px away, from frame 12 on; and the runner stopping dead.
    let mut switched = runner.clone();
    for a in switched.iter_mut().skip(12) {
        a.as_mut().unwrap().pelvis[1] += 600.0;
    }
    assert_eq!(identity_jumps(&frames, &switched), vec![12]);
    let mut stopping = runner.clone();
    for a in stopping.iter_mut().skip(12) {
        a.as_mut().unwrap().pelvis[0] = 150.0 * 11.0;
    }
    assert!(identity_jumps(&frames, &stopping).is_empty());
}

#[test]
fn a_steady_runner_and_sparse_frames_numbered_in_a_row_lose_no_frame() {
    // A runner whose pelvis moves a little more than a torso length in some frames and a
    // little less in others (a simulated user's side view of a sprint lost 10 of 18).
    let frames: Vec<Option<u64>> = (0..18).map(Some).collect();
    let runner: Vec<_> = (0..18)
        .map(|t| {
            let step = if t % 2 == 0 { 1.15 } else { 0.9 };
            at(100.0 * f64::from(t) + 10.0 * step, 100.0)
        })
        .collect();
    assert!(outlier_frames(&frames, &runner, FrameRate::default()).is_empty());
    let uneven: Vec<_> = (0..18)
        .map(|t| at(104.0 * f64::from(t) + 12.0 * f64::from(t % 2), 100.0))
        .collect();
    assert!(outlier_frames(&frames, &uneven, FrameRate::default()).is_empty());
    // A person pacing back and forth, sampled once a second but numbered 0, 1, 2...:
    // most frames are far from their neighbours; none is left out as another person's.
    let pacing: Vec<_> = (0..35)
        .map(|t| at(800.0 * (0.7 * f64::from(t)).sin(), 100.0))
        .collect();
    let numbered: Vec<Option<u64>> = (0..35).map(Some).collect();
    assert!(outlier_frames(&numbered, &pacing, FrameRate::default()).is_empty());
}

#[test]
fn a_swap_at_an_end_of_a_numbered_track_is_left_out() {
    let walk: Vec<_> = (0..30).map(|t| at(20.0 * f64::from(t), 100.0)).collect();
    let other: Vec<_> = (0..30)
        .map(|t| at(1500.0 - 10.0 * f64::from(t), 100.0))
        .collect();
    let numbered: Vec<Option<u64>> = (0..30).map(|t| Some(1000 + t)).collect();
    for (swapped, len) in [(25..30, 5), (0..4, 4), (20..30, 10)] {
        let (mut a, mut b) = (walk.clone(), other.clone());
        for t in swapped.clone() {
            std::mem::swap(&mut a[t], &mut b[t]);
        }
        let expected: Vec<usize> = swapped.collect();
        assert_eq!(expected.len(), len);
        assert_eq!(
            outlier_frames(&numbered, &a, FrameRate::default()),
            expected
        );
        assert_eq!(
            outlier_frames(&numbered, &b, FrameRate::default()),
            expected
        );
        // Without frame numbers, or with frames far apart in time (a person may have
        // walked there), only the one-frame rule holds.
        let sparse: Vec<Option<u64>> = (0..30).map(|t| Some(100 * t)).collect();
        assert!(outlier_frames(&[], &a, FrameRate::default()).is_empty());
        assert!(outlier_frames(&sparse, &a, FrameRate::default()).is_empty());
    }
    // Where the detector also missed a frame next to the swap (numbers 2 apart).
    let (mut a, mut b) = (walk.clone(), other.clone());
    for t in 26..30 {
        std::mem::swap(&mut a[t], &mut b[t]);
    }
    let mut missed = numbered.clone();
    for number in &mut missed[26..] {
        *number = number.map(|f| f + 1);
    }
    assert_eq!(
        outlier_frames(&missed, &a, FrameRate::default()),
        vec![26, 27, 28, 29]
    );
    // Eleven frames are a change of person; so is a stretch that moves on its own.
    let (mut a, mut b) = (walk.clone(), other.clone());
    for t in 19..30 {
        std::mem::swap(&mut a[t], &mut b[t]);
    }
    assert!(outlier_frames(&numbered, &a, FrameRate::default()).is_empty());
    assert!(outlier_frames(&numbered, &b, FrameRate::default()).is_empty());
    let mut runs_off = walk.clone();
    for (k, a) in runs_off.iter_mut().enumerate().skip(26) {
        a.as_mut().unwrap().pelvis[0] += 500.0 * (k - 25) as f64;
    }
    assert!(outlier_frames(&numbered, &runs_off, FrameRate::default()).is_empty());
}

#[test]
fn a_missing_pelvis_or_neck_is_stood_in_for_by_hips_or_shoulders() {
    let mut pose = PartialPose2::empty();
    pose.points[Landmark::LeftHip.index()] = Some([-10.0, 0.0]);
    pose.points[Landmark::RightHip.index()] = Some([10.0, 0.0]);
    pose.points[Landmark::LeftShoulder.index()] = Some([-20.0, -100.0]);
    assert_eq!(
        TorsoAnchor::of(&pose),
        Some(TorsoAnchor {
            pelvis: [0.0, 0.0],
            torso: 20.0f64.hypot(100.0)
        })
    );
    pose.points[Landmark::LeftShoulder.index()] = None;
    assert_eq!(TorsoAnchor::of(&pose), None);
}

#[test]
fn gaps_allow_longer_moves_and_frames_without_a_torso_are_skipped() {
    let anchors = [
        at(0.0, 100.0),
        at(0.0, 100.0),
        None,
        at(250.0, 100.0),
        at(250.0, 100.0),
    ];
    // Frame numbers 1 and 4: 250 px in 3 frames is within a torso a frame.
    let gap = [Some(0), Some(1), Some(2), Some(4), Some(5)];
    assert!(identity_jumps(&gap, &anchors).is_empty());
    // Consecutive frame numbers around the frame without a torso: two frames elapsed.
    let frames: Vec<Option<u64>> = (0..5).map(Some).collect();
    assert_eq!(identity_jumps(&frames, &anchors), vec![3]);
    assert!(identity_jumps(&[None, None, None], &[at(0.0, 100.0), at(90.0, 100.0)]).is_empty());
}
