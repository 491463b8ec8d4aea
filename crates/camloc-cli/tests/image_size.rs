//! `--image-size` the wrong way round: `reconstruct` says so when the poses of a normalised
//! input (YOLO, MediaPipe) fit a body clearly better with width and height swapped.

mod common;
use common::*;

use camloc::keypoints::{ReadOptions, read_keypoints};
use camloc::skeleton::Landmark;

/// COCO-17's joints as camloc landmarks (the five face points at the head).
const COCO17: [Landmark; 17] = [
    Landmark::Head,
    Landmark::Head,
    Landmark::Head,
    Landmark::Head,
    Landmark::Head,
    Landmark::LeftShoulder,
    Landmark::RightShoulder,
    Landmark::LeftElbow,
    Landmark::RightElbow,
    Landmark::LeftWrist,
    Landmark::RightWrist,
    Landmark::LeftHip,
    Landmark::RightHip,
    Landmark::LeftKnee,
    Landmark::RightKnee,
    Landmark::LeftAnkle,
    Landmark::RightAnkle,
];

/// A YOLO-pose folder of the example poses, 5 times each a little apart, filmed upright in a
/// portrait 1080 x 1920 video (coordinates normalised by its sides).
fn portrait_yolo(dir: &TempDir) -> String {
    let records = read_keypoints(
        fixture("keypoints/example.json"),
        None,
        &ReadOptions::default(),
    )
    .unwrap();
    let folder = dir.0.join("yolo");
    std::fs::create_dir(&folder).unwrap();
    let (w, h) = (1080.0, 1920.0);
    for (frame, (k, record)) in records.iter().cycle().take(15).enumerate().enumerate() {
        let shift = 4.0 * k as f64;
        let mut line = String::from("0 0.5 0.5 0.4 0.6");
        for landmark in COCO17 {
            match record.pose.points[landmark.index()] {
                Some([u, v]) => {
                    let (x, y) = (3.0 * (u - 320.0) + 540.0 + shift, 3.0 * (v - 270.0) + 960.0);
                    line.push_str(&format!(" {:.6} {:.6} 0.9", x / w, y / h));
                }
                None => line.push_str(" 0 0 0"),
            }
        }
        std::fs::write(folder.join(format!("clip_{}.txt", frame + 1)), line + "\n").unwrap();
    }
    folder.to_str().unwrap().to_owned()
}

#[test]
fn a_portrait_video_given_as_landscape_is_said() {
    let dir = TempDir::new("image-size");
    let folder = portrait_yolo(&dir);
    let warning = |size: &str| {
        let args = ["reconstruct", &folder, "--image-size", size, "-q", "--json"];
        warning_line(&args, "--image-size is width first")
    };
    let said = warning("1920,1080").expect("no warning of a swapped image size");
    assert!(
        said.contains("better with the image 1080x1920 than 1920x1080"),
        "{said}"
    );
    assert_eq!(warning("1080,1920"), None);
    // Pixels are not scaled by the size: nothing to say of them.
    let out = camloc(&[
        "reconstruct",
        fixture("keypoints/example.json").to_str().unwrap(),
        "--image-size",
        "1920,1080",
        "-q",
    ]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("width first"));
}
