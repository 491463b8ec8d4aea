//! `--image-size` the wrong way round: `reconstruct` says so when the poses of a normalised
//! input (YOLO, MediaPipe) fit a body better with width and height swapped.

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

/// A YOLO-pose folder of the example's person seen from the left, 15 times a little apart,
/// filmed upright in a portrait 1080 x 1920 video (coordinates normalised by its sides).
fn portrait_yolo(dir: &TempDir) -> String {
    yolo_video(dir, "yolo", 1080.0, 1920.0)
}

/// A YOLO-pose folder `name` in `dir` of the example's person seen from the left (its second
/// pose: the check compares people seen from a side), 15 times a little apart, three times its
/// size at the centre of a `w` x `h` video (coordinates normalised by its sides).
fn yolo_video(dir: &TempDir, name: &str, w: f64, h: f64) -> String {
    let records = read_keypoints(
        fixture("keypoints/example.json"),
        None,
        &ReadOptions::default(),
    )
    .unwrap();
    let folder = dir.0.join(name);
    std::fs::create_dir(&folder).unwrap();
    for (frame, (k, record)) in std::iter::repeat_n(&records[1], 15).enumerate().enumerate() {
        let shift = 4.0 * k as f64;
        let mut line = String::from("0 0.5 0.5 0.4 0.6");
        for landmark in COCO17 {
            match record.pose.points[landmark.index()] {
                Some([u, v]) => {
                    let x = 3.0 * (u - 320.0) + 0.5 * w + shift;
                    let y = 3.0 * (v - 270.0) + 0.5 * h;
                    line.push_str(&format!(" {:.6} {:.6} 0.9", x / w, y / h));
                }
                None => line.push_str(" 0 0 0"),
            }
        }
        std::fs::write(folder.join(format!("clip_{}.txt", frame + 1)), line + "\n").unwrap();
    }
    folder.to_str().unwrap().to_owned()
}

/// Asserts that `reconstruct` of the normalised video `folder` (of the image `right`, `W,H`)
/// warns when given the image size swapped (`wrong`), naming the right one, and not when
/// given `right`.
fn swapped_size_is_said(folder: &str, right: &str, wrong: &str) {
    let warning = |size: &str| {
        let args = ["reconstruct", folder, "--image-size", size, "-q", "--json"];
        warning_line(&args, "--image-size is width first")
    };
    let said = warning(wrong).expect("no warning of a swapped image size");
    let [rw, rh] = [right, wrong].map(|s| s.replace(',', "x"));
    assert!(
        said.contains(&format!("better with the image {rw} than {rh}")),
        "{said}"
    );
    assert_eq!(warning(right), None);
}

#[test]
fn a_portrait_video_given_as_landscape_is_said() {
    let dir = TempDir::new("image-size");
    swapped_size_is_said(&portrait_yolo(&dir), "1080,1920", "1920,1080");
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

/// A landscape video given as portrait (its poses squeezed across, like side views) is said
/// too (the check's ratio of 0.6 had left it unsaid).
#[test]
fn a_landscape_video_given_as_portrait_is_said() {
    let dir = TempDir::new("image-size-landscape");
    let folder = yolo_video(&dir, "landscape", 1920.0, 1080.0);
    swapped_size_is_said(&folder, "1920,1080", "1080,1920");
}
