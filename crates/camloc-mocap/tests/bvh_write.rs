//! The BVH writer: what it writes reads back (camloc's reader) to the poses it was given, with
//! their limb directions and the given lengths; channels stay smooth; bad input is an error.

use std::path::Path;

use camloc_mocap::{
    BVH_CENTIMETRE, BvhOptions, BvhWriteError, parse_bvh_with_unit, read_bvh, write_bvh,
    write_person_bvh,
};
use camloc_skeleton::{LIMBS, Landmark, NUM_LIMBS, Pose3, mean_limb_lengths};
use proptest::prelude::*;

/// Largest distance between corresponding landmarks, metres.
fn max_distance(a: &[Pose3], b: &[Pose3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(p, q)| {
            p.points.iter().zip(&q.points).map(|(u, v)| {
                ((u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2) + (u[2] - v[2]).powi(2)).sqrt()
            })
        })
        .fold(0.0, f64::max)
}

/// Writes `frames` with `lengths` and reads them back in metres.
fn round_trip(frames: &[Pose3], lengths: &[f64; NUM_LIMBS], fps: f64) -> Vec<Pose3> {
    let text = write_bvh(frames, lengths, &BvhOptions::at_fps(fps)).unwrap();
    let clip = parse_bvh_with_unit(&text, "written.bvh", BVH_CENTIMETRE).unwrap();
    assert!((clip.frame_time_s - 1.0 / fps).abs() < 1e-9);
    clip.frames
}

/// The CMU fixture's frames: real joint angles, root translation and turning.
fn fixture_frames() -> Vec<Pose3> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/mocap/98_01.bvh");
    read_bvh(path).unwrap().frames
}

#[test]
fn motion_capture_reads_back_with_the_given_lengths_and_directions() {
    let frames = fixture_frames();
    let lengths = frames[0].limb_lengths();
    let expected: Vec<Pose3> = frames
        .iter()
        .map(|f| f.with_limb_lengths(&lengths).unwrap())
        .collect();
    let back = round_trip(&frames, &lengths, 120.0);
    let error = max_distance(&back, &expected);
    assert!(error < 1e-6, "largest landmark error {error} m");
    // The root moves with the pelvis.
    for (b, f) in back.iter().zip(&frames) {
        let (p, q) = (b.get(Landmark::Pelvis), f.get(Landmark::Pelvis));
        assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-7));
    }
}

#[test]
fn a_pose_with_the_given_lengths_reads_back_as_itself() {
    let pose = fixture_frames()[0];
    let back = round_trip(&[pose], &pose.limb_lengths(), 30.0);
    assert!(max_distance(&back, &[pose]) < 1e-6);
}

#[test]
fn a_person_s_missing_frames_are_filled_with_the_given_or_mean_lengths() {
    let frames = fixture_frames();
    let (a, b) = (frames[0], frames[frames.len() - 1]);
    let options = BvhOptions::at_fps(30.0);
    let gappy = [None, Some(a), None, Some(b), None];
    let given = a.limb_lengths().map(|l| 1.1 * l);
    let text = write_person_bvh(&gappy, Some(&given), &options).unwrap();
    let back = parse_bvh_with_unit(&text, "gappy.bvh", BVH_CENTIMETRE)
        .unwrap()
        .frames;
    // The ends hold the first and last poses (with the given lengths).
    let (a1, b1) = (
        a.with_limb_lengths(&given).unwrap(),
        b.with_limb_lengths(&given).unwrap(),
    );
    assert!(max_distance(&back[..2], &[a1, a1]) < 1e-6);
    assert!(max_distance(&back[3..], &[b1, b1]) < 1e-6);
    // The frame between them: the pelvis half way, each limb half way along the great circle
    // between its directions in the two poses (the fixture's left upper arm points opposite
    // ways in them).
    let direction = |p: &Pose3, (from, to): (Landmark, Landmark)| -> [f64; 3] {
        let (u, v) = (p.get(from), p.get(to));
        let d = [v[0] - u[0], v[1] - u[1], v[2] - u[2]];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d.map(|c| c / n)
    };
    let angle = |u: [f64; 3], v: [f64; 3]| {
        (u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
            .clamp(-1.0, 1.0)
            .acos()
    };
    let (pa, pb, pm) = (
        a.get(Landmark::Pelvis),
        b.get(Landmark::Pelvis),
        back[2].get(Landmark::Pelvis),
    );
    assert!((0..3).all(|k| (pm[k] - 0.5 * (pa[k] + pb[k])).abs() < 1e-7));
    for limb in LIMBS {
        let (u, v, m) = (
            direction(&a, limb),
            direction(&b, limb),
            direction(&back[2], limb),
        );
        let whole = angle(u, v);
        if whole > 3.1 {
            // Opposite directions have no one great circle: the limb switches half way.
            assert!(angle(m, v) < 1e-6, "{limb:?}");
            continue;
        }
        assert!(
            (angle(u, m) - 0.5 * whole).abs() < 1e-6 && (angle(m, v) - 0.5 * whole).abs() < 1e-6,
            "{limb:?}: {} and {} of {whole} rad",
            angle(u, m),
            angle(m, v)
        );
    }
    // Without lengths: the mean over the poses present (a and b once each, not as filled).
    let mean = mean_limb_lengths(&[a, b]).unwrap();
    let text = write_person_bvh(&gappy, None, &options).unwrap();
    let back = parse_bvh_with_unit(&text, "gappy.bvh", BVH_CENTIMETRE)
        .unwrap()
        .frames;
    assert!((back[1].limb_length(0) - mean[0]).abs() < 1e-7);
    assert_eq!(
        write_person_bvh(&[None, None], None, &options),
        Err(BvhWriteError::NoFrames)
    );
}

/// `pose` turned about the vertical by `yaw` radians around its pelvis and moved by `shift`.
fn turned(pose: &Pose3, yaw: f64, shift: [f64; 3]) -> Pose3 {
    let (s, c) = yaw.sin_cos();
    let o = pose.get(Landmark::Pelvis);
    Pose3::new(pose.points.map(|p| {
        let (x, y) = (p[0] - o[0], p[1] - o[1]);
        [
            o[0] + c * x - s * y + shift[0],
            o[1] + s * x + c * y + shift[1],
            p[2] + shift[2],
        ]
    }))
}

/// `pose` with the landmarks below `joint` (not `joint` itself) turned about the unit axis
/// `axis` through `joint` by `angle` radians (Rodrigues).
fn turn_below(pose: &Pose3, joint: Landmark, axis: [f64; 3], angle: f64) -> Pose3 {
    let (s, c) = angle.sin_cos();
    let o = pose.get(joint);
    let mut out = *pose;
    for l in joint.subtree().filter(|l| *l != joint) {
        let p = pose.get(l);
        let v = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
        let d = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
        let x = [
            axis[1] * v[2] - axis[2] * v[1],
            axis[2] * v[0] - axis[0] * v[2],
            axis[0] * v[1] - axis[1] * v[0],
        ];
        out.points[l.index()] =
            std::array::from_fn(|k| o[k] + v[k] * c + x[k] * s + axis[k] * d * (1.0 - c));
    }
    out
}

#[test]
fn channels_of_a_smooth_motion_have_no_jumps() {
    // The fixture's T-pose walking forward while turning twice around (3 degrees a frame),
    // legs and arms swinging by up to 60 degrees, elbows and knees bending up to 100 degrees:
    // no channel may move by more than a few degrees between frames.
    let rest = fixture_frames()[0];
    let lateral = [0.0, 1.0, 0.0];
    let sequence: Vec<Pose3> = (0..240)
        .map(|t| {
            let phase = (6.0 * t as f64).to_radians();
            let mut pose = rest;
            for (hip, knee, sign) in [
                (Landmark::LeftHip, Landmark::LeftKnee, 1.0),
                (Landmark::RightHip, Landmark::RightKnee, -1.0),
            ] {
                pose = turn_below(&pose, hip, lateral, sign * phase.sin());
                pose = turn_below(&pose, knee, lateral, 0.9 * (1.0 - phase.cos()));
            }
            for (shoulder, elbow) in [
                (Landmark::LeftShoulder, Landmark::LeftElbow),
                (Landmark::RightShoulder, Landmark::RightElbow),
            ] {
                pose = turn_below(&pose, shoulder, [1.0, 0.0, 0.0], 1.2 * phase.sin());
                pose = turn_below(&pose, elbow, [0.0, 0.0, 1.0], 0.9 * (1.0 - phase.cos()));
            }
            turned(
                &pose,
                (3.0 * t as f64).to_radians(),
                [0.01 * t as f64, 0.0, 0.0],
            )
        })
        .collect();
    let lengths = sequence[0].limb_lengths();
    let text = write_bvh(&sequence, &lengths, &BvhOptions::at_fps(30.0)).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip_while(|l| !l.starts_with("Frame Time"))
        .skip(1)
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 240);
    let (largest_step, at) = rows
        .windows(2)
        .enumerate()
        .flat_map(|(t, w)| {
            w[0].iter()
                .zip(&w[1])
                .enumerate()
                .skip(3)
                .map(move |(k, (a, b))| ((a - b).abs(), (t + 1, k)))
        })
        .fold((0.0, (0, 0)), |m, x| if x.0 > m.0 { x } else { m });
    // Every landmark moves by at most about 10 degrees a frame about its joint.
    assert!(
        largest_step < 15.0,
        "channel {} jumped by {largest_step} deg at frame {}",
        at.1,
        at.0
    );
    let back = round_trip(&sequence, &lengths, 30.0);
    let expected: Vec<Pose3> = sequence
        .iter()
        .map(|f| f.with_limb_lengths(&lengths).unwrap())
        .collect();
    assert!(max_distance(&back, &expected) < 1e-6);
}

#[test]
fn the_file_names_the_landmark_joints_and_the_unit_scales_it() {
    let pose = fixture_frames()[0];
    let lengths = pose.limb_lengths();
    let text = write_bvh(&[pose], &lengths, &BvhOptions::at_fps(25.0)).unwrap();
    for name in [
        "ROOT Hips",
        "JOINT LeftUpLeg",
        "JOINT RightForeArm",
        "JOINT Head",
        "Frames: 1",
        "Frame Time: 0.040000000",
    ] {
        assert!(text.contains(name), "{name} missing");
    }
    // In metres the same file has coordinates 100 times smaller.
    let metres = BvhOptions {
        metres_per_unit: 1.0,
        ..BvhOptions::at_fps(25.0)
    };
    let text_m = write_bvh(&[pose], &lengths, &metres).unwrap();
    let back = parse_bvh_with_unit(&text_m, "m.bvh", 1.0).unwrap().frames;
    // Six decimals of a metre.
    assert!(max_distance(&back, &[pose]) < 1e-5);
}

#[test]
fn bad_input_is_a_typed_error() {
    let pose = fixture_frames()[0];
    let lengths = pose.limb_lengths();
    let options = BvhOptions::at_fps(30.0);
    assert_eq!(
        write_bvh(&[], &lengths, &options),
        Err(BvhWriteError::NoFrames)
    );
    let mut zero = lengths;
    zero[4] = 0.0;
    assert!(matches!(
        write_bvh(&[pose], &zero, &options),
        Err(BvhWriteError::LimbLength { limb: 4, .. })
    ));
    // 1e10 frames a second would be written as `Frame Time: 0.000000000`.
    for fps in [0.0, -1.0, f64::NAN, 1e10, 1e-300] {
        assert!(matches!(
            write_bvh(&[pose], &lengths, &BvhOptions::at_fps(fps)),
            Err(BvhWriteError::Option { .. })
        ));
    }
    let mut nan = pose;
    nan.points[3][1] = f64::NAN;
    let mut folded = pose;
    folded.points[Landmark::LeftElbow.index()] = folded.get(Landmark::LeftShoulder);
    for (bad, what) in [(nan, "not finite"), (folded, "left upper arm")] {
        let err = write_bvh(&[pose, bad], &lengths, &options).unwrap_err();
        assert!(
            matches!(err, BvhWriteError::Frame { frame: 2, .. }),
            "{err}"
        );
        assert!(err.to_string().contains(what), "{err}");
    }
}

/// A pose of random limb directions and lengths (metres), built from the pelvis outwards.
fn random_pose() -> impl Strategy<Value = Pose3> {
    (
        prop::array::uniform3(-5.0f64..5.0),
        prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), NUM_LIMBS),
        prop::collection::vec(0.05f64..0.6, NUM_LIMBS),
    )
        .prop_filter_map("a limb without direction", |(root, dirs, lengths)| {
            let mut points = [root; 15];
            for ((parent, child), (d, l)) in LIMBS.iter().zip(dirs.iter().zip(&lengths)) {
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if n < 1e-3 {
                    return None;
                }
                let p = points[parent.index()];
                points[child.index()] = std::array::from_fn(|k| p[k] + d[k] * l / n);
            }
            Some(Pose3::new(points))
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn any_poses_read_back_with_their_directions_and_the_given_lengths(
        frames in prop::collection::vec(random_pose(), 1..6),
    ) {
        let lengths = frames[0].limb_lengths();
        let expected: Vec<Pose3> = frames
            .iter()
            .map(|f| f.with_limb_lengths(&lengths).unwrap())
            .collect();
        let back = round_trip(&frames, &lengths, 24.0);
        let error = max_distance(&back, &expected);
        prop_assert!(error < 1e-6, "largest landmark error {} m", error);
    }
}
