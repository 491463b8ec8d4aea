//! Property tests: canonicalisation invariances, rigid bones under any joint angles, and
//! parsers that never panic on corrupted input.

use std::path::Path;

use camloc_mocap::{CMU_UNIT_M, CanonicaliseError, canonicalise, parse_amc, parse_asf, parse_bvh};
use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, Pose3};
use proptest::prelude::*;

fn fixture_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/mocap")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

fn pose_strategy() -> impl Strategy<Value = Pose3> {
    prop::array::uniform15(prop::array::uniform3(-1.0f64..1.0)).prop_map(Pose3::new)
}

/// Horizontal length of the left-right vector canonicalise uses.
fn lateral_length(p: &Pose3) -> f64 {
    let d = |r: Landmark, l: Landmark| [p.get(r)[0] - p.get(l)[0], p.get(r)[1] - p.get(l)[1]];
    let (h, s) = (
        d(Landmark::RightHip, Landmark::LeftHip),
        d(Landmark::RightShoulder, Landmark::LeftShoulder),
    );
    (h[0] + s[0]).hypot(h[1] + s[1])
}

/// `R_z(yaw) p + t` for every landmark.
fn yaw_and_shift(pose: &Pose3, yaw: f64, t: [f64; 3]) -> Pose3 {
    let (s, c) = yaw.sin_cos();
    Pose3::new(pose.points.map(|p| {
        [
            c * p[0] - s * p[1] + t[0],
            s * p[0] + c * p[1] + t[1],
            p[2] + t[2],
        ]
    }))
}

fn max_difference(a: &Pose3, b: &Pose3) -> f64 {
    a.points
        .iter()
        .flatten()
        .zip(b.points.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Signed volume spanned by three landmarks around the pelvis (a reflection flips its sign).
fn signed_volume(p: &Pose3) -> f64 {
    let o = p.get(Landmark::Pelvis);
    let v = |l: Landmark| [p.get(l)[0] - o[0], p.get(l)[1] - o[1], p.get(l)[2] - o[2]];
    let (a, b, c) = (
        v(Landmark::LeftHip),
        v(Landmark::Head),
        v(Landmark::RightWrist),
    );
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

proptest! {
    #[test]
    fn canonicalise_is_a_yaw_and_shift_invariant_rigid_motion(
        pose in pose_strategy().prop_filter("lateral direction", |p| lateral_length(p) > 1e-3),
        yaw in -10.0f64..10.0,
        t in prop::array::uniform3(-5.0f64..5.0),
    ) {
        let c = canonicalise(&pose).unwrap();
        prop_assert!(c.get(Landmark::Pelvis).iter().all(|v| v.abs() < 1e-12));
        // The left-right vector lies along +y.
        let lateral = |q: &Pose3| {
            let d = |r: Landmark, l: Landmark| [q.get(r)[0] - q.get(l)[0], q.get(r)[1] - q.get(l)[1]];
            let (h, s) = (d(Landmark::RightHip, Landmark::LeftHip), d(Landmark::RightShoulder, Landmark::LeftShoulder));
            [h[0] + s[0], h[1] + s[1]]
        };
        let l = lateral(&c);
        prop_assert!(l[0].abs() < 1e-9 && l[1] > 0.0);
        for limb in 0..LIMBS.len() {
            prop_assert!((c.limb_length(limb) - pose.limb_length(limb)).abs() < 1e-12);
        }
        for i in 0..NUM_LANDMARKS {
            let height = pose.points[i][2] - pose.get(Landmark::Pelvis)[2];
            prop_assert!((c.points[i][2] - height).abs() < 1e-12);
        }
        prop_assert!((signed_volume(&c) - signed_volume(&pose)).abs() < 1e-9);
        let moved = canonicalise(&yaw_and_shift(&pose, yaw, t)).unwrap();
        prop_assert!(max_difference(&moved, &c) < 1e-9);
        prop_assert!(max_difference(&canonicalise(&c).unwrap(), &c) < 1e-12);
    }

    #[test]
    fn canonicalise_rejects_poses_without_a_horizontal_left_right_direction(
        pose in pose_strategy(),
        lift in -1.0f64..1.0,
    ) {
        // Put the hips and shoulders on vertical lines: no horizontal lateral vector.
        let mut p = pose;
        for (right, left) in [(Landmark::RightHip, Landmark::LeftHip), (Landmark::RightShoulder, Landmark::LeftShoulder)] {
            let l = p.get(left);
            p.points[right.index()] = [l[0], l[1], l[2] + lift];
        }
        let is_lateral_error = matches!(canonicalise(&p), Err(CanonicaliseError::NoLateralDirection { .. }));
        prop_assert!(is_lateral_error);
        p.points[Landmark::Head.index()][0] = f64::NAN;
        prop_assert_eq!(canonicalise(&p), Err(CanonicaliseError::NotFinite));
    }

    #[test]
    fn bvh_bones_stay_rigid_for_any_joint_angles(
        angles in prop::collection::vec(-360.0f64..360.0, 51),
        root in prop::array::uniform3(-50.0f64..50.0),
    ) {
        let text = fixture_text("98_01.bvh");
        let hierarchy = text.split("MOTION").next().unwrap();
        let mut values = angles;
        values[..3].copy_from_slice(&root);
        values[30..33].copy_from_slice(&[3.0, 3.0, 0.0]); // LeftShoulder position = OFFSET
        let line: Vec<String> = values.iter().map(|v| v.to_string()).collect();
        let text = format!("{hierarchy}MOTION\nFrames: 1\nFrame Time: 1\n{}\n", line.join(" "));
        let pose = parse_bvh(&text, "random.bvh").unwrap().frames[0];
        // Rest lengths in units, in LIMBS order; torso and neck-head (two joints each) vary.
        let rest = [1.0, 8.0, 8.0, 1.0, 8.0, 8.0, f64::NAN, f64::NAN, 3.0, 5.0, 4.0, 3.0, 5.0, 4.0];
        for (limb, length) in rest.iter().enumerate().filter(|(_, l)| l.is_finite()) {
            prop_assert!((pose.limb_length(limb) - length * CMU_UNIT_M).abs() < 1e-12, "limb {}", limb);
        }
        let root_world = [root[0], -root[2], root[1]].map(|c| c * CMU_UNIT_M);
        prop_assert!(pose.get(Landmark::Pelvis).iter().zip(&root_world).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    #[test]
    fn amc_bones_stay_rigid_for_any_dof_values(seed_values in prop::collection::vec(-360.0f64..360.0, 64)) {
        let skeleton = parse_asf(&fixture_text("99.asf"), "99.asf").unwrap();
        let rest = skeleton.rest_pose();
        let fixture = fixture_text("99_01.amc");
        // The header's three lines, then frame 1: its number and one line per bone.
        let frame_one: Vec<&str> = fixture.lines().skip(3).take_while(|l| *l != "2").collect();
        let mut values = seed_values.into_iter().cycle();
        let mut text = String::new();
        for line in frame_one {
            let mut tokens = line.split(' ');
            let name = tokens.next().unwrap();
            text.push_str(name);
            for _ in tokens {
                text.push_str(&format!(" {}", values.next().unwrap()));
            }
            text.push('\n');
        }
        let pose = parse_amc(&text, "random.amc", &skeleton).unwrap().frames[0];
        for limb in (0..LIMBS.len()).filter(|l| ![6, 7].contains(l)) {
            prop_assert!((pose.limb_length(limb) - rest.limb_length(limb)).abs() < 1e-12, "limb {}", limb);
        }
    }

    #[test]
    fn parsers_never_panic_on_arbitrary_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let skeleton = parse_asf(&fixture_text("99.asf"), "99.asf").unwrap();
        let results = [
            parse_bvh(&bytes, "x.bvh").map(|c| c.frames),
            parse_amc(&bytes, "x.amc", &skeleton).map(|c| c.frames),
        ];
        for frames in results.into_iter().flatten() {
            prop_assert!(frames.iter().all(Pose3::is_finite));
        }
        let _ = parse_asf(&bytes, "x.asf");
    }

    #[test]
    fn parsers_never_panic_on_corrupted_fixtures(
        file in 0usize..3,
        cut in 0.0f64..1.0,
        span in 0usize..40,
        insert in prop::sample::select(vec![
            "", "{", "}", "JOINT", "End Site", "ROOT", "MOTION", "Frames: 3", "CHANNELS 6",
            "-", "1e999", "nan", "\r\n", "\n", "begin", "end", ":hierarchy", ":bonedata", "root",
            "dof rx", "2", "é",
        ]),
    ) {
        let name = ["98_01.bvh", "99.asf", "99_01.amc"][file];
        let text = fixture_text(name);
        let mut at = (cut * text.len() as f64) as usize;
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        let mut end = (at + span).min(text.len());
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        let corrupted = format!("{}{insert}{}", &text[..at], &text[end..]);
        let skeleton = parse_asf(&fixture_text("99.asf"), "99.asf").unwrap();
        let frames = match file {
            0 => parse_bvh(&corrupted, name).map(|c| c.frames),
            1 => parse_asf(&corrupted, name).map(|s| vec![s.rest_pose()]),
            _ => parse_amc(&corrupted, name, &skeleton).map(|c| c.frames),
        };
        if let Ok(frames) = frames {
            prop_assert!(frames.iter().all(Pose3::is_finite));
        }
    }
}
