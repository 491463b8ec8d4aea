//! The default reconstruction of real photos (LSP, skipped without ../shared/data) is a human
//! body: few knees bent backwards, no head folded into the chest, measured in each pose's own
//! body frame (not with the joint limits the reconstruction uses).

use camloc::keypoints::{ReadOptions, read_keypoints};
use camloc::{Landmark, Pose3, PoseReconstructor};
use nalgebra::{Rotation3, Vector3};

/// A landmark of `pose` as a vector (metres).
fn at(pose: &Pose3, l: Landmark) -> Vector3<f64> {
    Vector3::from(pose.get(l))
}

/// The body's own up (pelvis to neck, made orthogonal to the hips' axis) and forward
/// (up x the left-to-right hip axis) directions.
fn body_axes(pose: &Pose3) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let right = (at(pose, Landmark::RightHip) - at(pose, Landmark::LeftHip)).try_normalize(1e-9)?;
    let torso = at(pose, Landmark::Neck) - at(pose, Landmark::Pelvis);
    let up = (torso - right * right.dot(&torso)).try_normalize(1e-9)?;
    Some((up, up.cross(&right)))
}

/// How far (degrees) the knee of the leg `hip`-`knee`-`ankle` is bent backwards: the shin's
/// turn from the thigh's line towards the body's front as the thigh carries it (the front
/// turned by the smallest rotation from hanging down to the thigh), for a thigh within 90
/// degrees of hanging; 0 for a knee bent the human way.
fn knee_bent_backwards_deg(pose: &Pose3, [hip, knee, ankle]: [Landmark; 3]) -> f64 {
    let Some((up, forward)) = body_axes(pose) else {
        return 0.0;
    };
    let (Some(thigh), Some(shin)) = (
        (at(pose, knee) - at(pose, hip)).try_normalize(1e-9),
        (at(pose, ankle) - at(pose, knee)).try_normalize(1e-9),
    ) else {
        return 0.0;
    };
    let Some(swing) = Rotation3::rotation_between(&-up, &thigh).filter(|_| thigh.dot(&-up) > 0.0)
    else {
        return 0.0;
    };
    let across = shin - thigh * thigh.dot(&shin);
    let ahead = across.dot(&(swing * forward));
    if ahead <= 0.0 {
        return 0.0;
    }
    ahead.atan2(thigh.dot(&shin)).to_degrees()
}

/// The angle (degrees) between the neck-to-head and the pelvis-to-neck bones.
fn head_tilt_deg(pose: &Pose3) -> f64 {
    let head = at(pose, Landmark::Head) - at(pose, Landmark::Neck);
    let torso = at(pose, Landmark::Neck) - at(pose, Landmark::Pelvis);
    head.angle(&torso).to_degrees()
}

/// On the 400 LSP photos, of the poses `camloc reconstruct` gives by default (all but the 8
/// without a torso to find or fill in, no torso 2.5 times the median): before the
/// limbs' depths were flipped towards the joint limits and the head held back (stop 54), 30
/// knees were bent backwards by more than 45 degrees and 16 heads tilted more than 90
/// degrees from the torso's line by these measures (20 and 0 after); the motion capture's
/// heads lie within 47 degrees.
#[test]
fn reconstructed_lsp_photos_have_few_knees_bent_backwards_and_no_folded_heads() {
    let Some(file) = camloc::skeleton::data::data_path_or_skip(
        "lsp/lsp400_joints.csv",
        "camloc::reconstructed_lsp_photos_have_few_knees_bent_backwards_and_no_folded_heads",
    ) else {
        return;
    };
    let records = read_keypoints(&file, None, &ReadOptions::default()).unwrap();
    // As `camloc reconstruct` does it: the camera heights estimated from the input's poses.
    let read: Vec<_> = records.iter().map(|r| r.pose).collect();
    let reconstructor = PoseReconstructor::default_reconstructor()
        .unwrap()
        .with_camera_height_from(&read);
    let poses: Vec<Pose3> = records
        .iter()
        .filter_map(|r| reconstructor.reconstruct(&r.pose).ok())
        .map(|r| r.reconstruction.pose)
        .collect();
    let legs = [
        [Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle],
        [
            Landmark::RightHip,
            Landmark::RightKnee,
            Landmark::RightAnkle,
        ],
    ];
    let knees = poses
        .iter()
        .filter(|p| {
            legs.iter()
                .any(|&leg| knee_bent_backwards_deg(p, leg) > 45.0)
        })
        .count();
    let heads = poses.iter().filter(|p| head_tilt_deg(p) > 90.0).count();
    eprintln!(
        "LSP reconstructions: {} poses, {knees} with a knee bent backwards by more than 45 deg, \
         {heads} with the head tilted more than 90 deg from the torso",
        poses.len()
    );
    // Every photo whose torso can be found or filled in (8 have too few landmarks): an
    // upside-down gymnast's lifted depths made a torso of 1.9 m, refused as implausible,
    // before such a reading was solved again from the pursuit's pose.
    assert!(
        poses.len() >= 392,
        "{} LSP poses reconstructed",
        poses.len()
    );
    // No torso 2.5 times the photos' median (before that, 3.0 times: 1.34 m).
    let torso = camloc::skeleton::LIMB_NAMES
        .iter()
        .position(|&n| n == "torso")
        .unwrap();
    let mut torsos: Vec<f64> = poses.iter().map(|p| p.limb_length(torso)).collect();
    torsos.sort_by(f64::total_cmp);
    let longest = torsos[torsos.len() - 1] / torsos[torsos.len() / 2];
    eprintln!("longest torso {longest:.2} times the median");
    assert!(longest < 2.5, "a torso {longest:.2} times the median");
    assert!(
        knees <= 24,
        "{knees} knees bent backwards by more than 45 deg"
    );
    assert!(heads <= 4, "{heads} heads tilted more than 90 deg");
}
