//! The hand-made fixtures in `fixtures/mocap/` read to the joint positions computed by hand
//! (see `fixtures/mocap/README.md` for the geometry).

use std::path::{Path, PathBuf};

use camloc_mocap::{
    CMU_FRAME_TIME_S, CMU_UNIT_M, MocapError, MocapSource, canonicalise, discover, parse_bvh,
    read_amc, read_asf, read_bvh,
};
use camloc_skeleton::{LIMBS, Landmark, NUM_LANDMARKS, Pose3};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/mocap")
        .join(name)
}

/// A point given in CMU units in the y-up file frame, in metres in the z-up world
/// (docs/conventions.md section 1: (x, y, z) -> (x, -z, y)).
fn world(p: [f64; 3]) -> [f64; 3] {
    [p[0] * CMU_UNIT_M, -p[2] * CMU_UNIT_M, p[1] * CMU_UNIT_M]
}

fn assert_pose(actual: &Pose3, expected_file_units: [[f64; 3]; NUM_LANDMARKS], what: &str) {
    for (landmark, expected) in Landmark::ALL.iter().zip(expected_file_units) {
        let (a, e) = (actual.get(*landmark), world(expected));
        let err = a
            .iter()
            .zip(&e)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(
            err < 1e-12,
            "{what}: {} at {a:?}, expected {e:?}",
            landmark.name()
        );
    }
}

/// The rest pose shared by both fixtures (file units, landmark order): legs 8 + 8 units
/// below hips 1 unit either side of the pelvis at height 16, neck 7 above the pelvis, head 3
/// above the neck, shoulders 3, elbows 8, wrists 12 units either side of the neck.
const REST: [[f64; 3]; NUM_LANDMARKS] = [
    [0.0, 16.0, 0.0],
    [1.0, 16.0, 0.0],
    [1.0, 8.0, 0.0],
    [1.0, 0.0, 0.0],
    [-1.0, 16.0, 0.0],
    [-1.0, 8.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 23.0, 0.0],
    [0.0, 26.0, 0.0],
    [3.0, 23.0, 0.0],
    [8.0, 23.0, 0.0],
    [12.0, 23.0, 0.0],
    [-3.0, 23.0, 0.0],
    [-8.0, 23.0, 0.0],
    [-12.0, 23.0, 0.0],
];

#[test]
fn bvh_rest_frame_is_the_sum_of_offsets() {
    let clip = read_bvh(fixture("98_01.bvh")).unwrap();
    assert_eq!(clip.subject, "98");
    assert_eq!(clip.clip, "98_01");
    assert_eq!(clip.frame_time_s, 0.0083333);
    assert_eq!(clip.frames.len(), 2);
    // Frame 1 sets LeftShoulder's position channels to its OFFSET: no change.
    assert_pose(&clip.frames[0], REST, "98_01 frame 1");
}

#[test]
fn bvh_rotations_compose_in_channel_order_and_positions_replace_offsets() {
    let clip = read_bvh(fixture("98_01.bvh")).unwrap();
    // Root at (2, 16, -1) turned by Ry(90): (x, y, z) -> (z, y, -x).
    // LeftKnee `Zrotation Xrotation Yrotation` = 90 90 0 is Rz(90) Rx(90): the shin (0, -8, 0)
    // becomes (0, 0, -8) (Rx(90) Rz(90) would give (8, 0, 0)); Ry(90) makes it (-8, 0, 0).
    // Chest `Yrotation Xrotation Zrotation` = 90 90 0 is Ry(90) Rx(90); with the root that is
    // Ry(180) Rx(90): (x, y, z) -> (-x, -z, -y), so the neck offset (0, 3, 0) becomes (0, 0, -3).
    // LeftShoulder's position channels (3, 4, 0) replace its OFFSET (3, 3, 0).
    let expected = [
        [2.0, 16.0, -1.0],
        [2.0, 16.0, -2.0],
        [2.0, 8.0, -2.0],
        [-6.0, 8.0, -2.0],
        [2.0, 16.0, 0.0],
        [2.0, 8.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 20.0, -4.0],
        [2.0, 20.0, -7.0],
        [-1.0, 20.0, -5.0],
        [-6.0, 20.0, -5.0],
        [-10.0, 20.0, -5.0],
        [5.0, 20.0, -4.0],
        [10.0, 20.0, -4.0],
        [14.0, 20.0, -4.0],
    ];
    assert_pose(&clip.frames[1], expected, "98_01 frame 2");
}

#[test]
fn bvh_motionbuilder_naming_uses_arm_and_upleg_joints() {
    let clip = read_bvh(fixture("97_01.bvh")).unwrap();
    assert_eq!(clip.frame_time_s, 0.04);
    // LeftShoulder here is the collar at the neck, turned Rz(90): LeftArm (the shoulder
    // landmark) goes from 3 units left of the neck to 3 units above it, the arm points up.
    let mut expected = REST;
    expected[Landmark::LeftShoulder.index()] = [0.0, 26.0, 0.0];
    expected[Landmark::LeftElbow.index()] = [0.0, 31.0, 0.0];
    expected[Landmark::LeftWrist.index()] = [0.0, 35.0, 0.0];
    assert_pose(&clip.frames[0], expected, "97_01");
}

#[test]
fn asf_skeleton_metadata_and_rest_pose() {
    let skeleton = read_asf(fixture("99.asf")).unwrap();
    assert_eq!(skeleton.metres_per_unit(), 0.0254 / 0.45);
    assert_eq!(skeleton.bone_names().count(), 16);
    // Parents come before children.
    let names: Vec<_> = skeleton.bone_names().collect();
    let at = |n: &str| names.iter().position(|b| *b == n).unwrap();
    assert!(at("lfemur") < at("ltibia") && at("thorax") < at("lclavicle"));
    // The rest pose has the root at `position` (0, 0, 0) rather than 16 units up.
    let lowered = REST.map(|[x, y, z]| [x, y - 16.0, z]);
    assert_pose(&skeleton.rest_pose(), lowered, "99.asf rest pose");
}

#[test]
fn amc_frames_match_hand_computation() {
    let skeleton = read_asf(fixture("99.asf")).unwrap();
    let clip = read_amc(fixture("99_01.amc"), &skeleton).unwrap();
    assert_eq!((clip.subject.as_str(), clip.clip.as_str()), ("99", "99_01"));
    assert_eq!(clip.frame_time_s, CMU_FRAME_TIME_S);
    assert_eq!(clip.frames.len(), 2);
    assert_pose(&clip.frames[0], REST, "99_01 frame 1");
    // Root at (2, 16, -1); order RZ RY RX with rz = rx = 90 applies Rz first:
    // W = Rx(90) Rz(90), (x, y, z) -> (-y, -z, x).
    // ltibia (axis 0 90 0, C = Ry(90)) rx = 90: C Rx(90) C^-1 = Rz(-90) turns (0, -8, 0) into
    // (-8, 0, 0), W makes it (0, 0, -8).
    // rfemur rx = rz = 90: M = Rz(90) Rx(90) turns (0, -8, 0) into (0, 0, -8), W into (0, 8, 0).
    // lhumerus rz = -90 turns (5, 0, 0) into (0, -5, 0), W into (5, 0, 0).
    let expected = [
        [2.0, 16.0, -1.0],
        [2.0, 16.0, 0.0],
        [10.0, 16.0, 0.0],
        [10.0, 16.0, -8.0],
        [2.0, 16.0, -2.0],
        [2.0, 24.0, -2.0],
        [2.0, 32.0, -2.0],
        [-5.0, 16.0, -1.0],
        [-8.0, 16.0, -1.0],
        [-5.0, 16.0, 2.0],
        [0.0, 16.0, 2.0],
        [4.0, 16.0, 2.0],
        [-5.0, 16.0, -4.0],
        [-5.0, 16.0, -9.0],
        [-5.0, 16.0, -13.0],
    ];
    assert_pose(&clip.frames[1], expected, "99_01 frame 2");
}

#[test]
fn discover_pairs_amc_with_its_subject_asf() {
    let sources = discover(fixture("")).unwrap();
    let expected = vec![
        MocapSource::Bvh {
            path: fixture("97_01.bvh"),
        },
        MocapSource::Bvh {
            path: fixture("98_01.bvh"),
        },
        MocapSource::AsfAmc {
            asf: fixture("99.asf"),
            amc: fixture("99_01.amc"),
        },
    ];
    assert_eq!(sources, expected);
    let ids: Vec<_> = sources.iter().map(|s| (s.subject(), s.clip())).collect();
    assert_eq!(
        ids,
        [("97", "97_01"), ("98", "98_01"), ("99", "99_01")].map(|(s, c)| (s.into(), c.into()))
    );
    for source in &sources {
        let clip = source.read().unwrap();
        assert_eq!(clip.clip, source.clip());
        assert!(!clip.frames.is_empty());
    }
}

/// A fresh empty folder under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("camloc-mocap-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn discover_lists_an_amc_without_its_asf_whose_read_fails_and_recurses_into_folders() {
    let dir = TempDir::new("orphan");
    let nested = dir.0.join("a/b");
    std::fs::create_dir_all(&nested).unwrap();
    std::fs::copy(fixture("98_01.bvh"), nested.join("98_01.BVH")).unwrap();
    let found = discover(&dir.0).unwrap();
    assert_eq!(
        found,
        vec![MocapSource::Bvh {
            path: nested.join("98_01.BVH")
        }]
    );
    std::fs::copy(fixture("99_01.amc"), nested.join("99_01.amc")).unwrap();
    // The orphan motion is listed (the BVH beside it is still found); reading it names the
    // missing skeleton.
    let found = discover(&dir.0).unwrap();
    assert_eq!(found.len(), 2);
    let orphan = found
        .iter()
        .find(|s| s.motion_path() == nested.join("99_01.amc"))
        .unwrap();
    match orphan.read() {
        Err(MocapError::MissingSkeleton { amc, asf }) => {
            assert_eq!(amc, nested.join("99_01.amc"));
            assert_eq!(asf, nested.join("99.asf"));
        }
        other => panic!("expected MissingSkeleton, got {other:?}"),
    }
    let err = discover(dir.0.join("does-not-exist")).unwrap_err();
    assert!(matches!(err, MocapError::Io { .. }), "{err}");
}

/// The 98_01 hierarchy with one frame: root at (5, 16, 3) turned `yaw` degrees about y, left
/// knee flexed 90 degrees (`Xrotation`), everything else at rest.
fn bvh_with_flexed_knee(yaw: f64) -> String {
    let text = std::fs::read_to_string(fixture("98_01.bvh")).unwrap();
    let hierarchy = text.split("MOTION").next().unwrap();
    let mut values = vec![0.0; 51];
    values[..6].copy_from_slice(&[5.0, 16.0, 3.0, 0.0, 0.0, yaw]);
    values[10] = 90.0; // LeftKnee: Zrotation Xrotation Yrotation at 9..12.
    values[30..33].copy_from_slice(&[3.0, 3.0, 0.0]); // LeftShoulder position = OFFSET.
    let line: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    format!(
        "{hierarchy}MOTION\nFrames: 1\nFrame Time: 0.01\n{}\n",
        line.join(" ")
    )
}

#[test]
fn canonicalised_fixture_faces_minus_x_with_right_side_on_plus_y() {
    for yaw in [0.0, 37.0, 180.0, -100.0] {
        let pose = parse_bvh(&bvh_with_flexed_knee(yaw), "knee.bvh")
            .unwrap()
            .frames[0];
        let c = canonicalise(&pose).unwrap();
        let u = CMU_UNIT_M;
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(c.get(Landmark::Pelvis), [0.0; 3]));
        assert!(close(c.get(Landmark::RightHip), [0.0, u, 0.0]), "yaw {yaw}");
        assert!(close(c.get(Landmark::LeftHip), [0.0, -u, 0.0]));
        assert!(close(c.get(Landmark::Head), [0.0, 0.0, 10.0 * u]));
        // A flexed knee sends the foot backwards: behind the body is +x when it faces -x.
        let (knee, ankle) = (c.get(Landmark::LeftKnee), c.get(Landmark::LeftAnkle));
        assert!(close(
            [ankle[0] - knee[0], ankle[1] - knee[1], ankle[2] - knee[2]],
            [8.0 * u, 0.0, 0.0]
        ));
        for limb in 0..LIMBS.len() {
            assert!((c.limb_length(limb) - pose.limb_length(limb)).abs() < 1e-12);
        }
    }
}
