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

/// A YOLO-pose folder of the example poses, 5 times each a little apart, filmed upright in a
/// portrait 1080 x 1920 video (coordinates normalised by its sides).
fn portrait_yolo(dir: &TempDir) -> String {
    yolo_video(dir, "yolo", 1080.0, 1920.0)
}

/// A YOLO-pose folder `name` in `dir` of the example poses, 5 times each a little apart, three
/// times their size at the centre of a `w` x `h` video (coordinates normalised by its sides).
fn yolo_video(dir: &TempDir, name: &str, w: f64, h: f64) -> String {
    let records = read_keypoints(
        fixture("keypoints/example.json"),
        None,
        &ReadOptions::default(),
    )
    .unwrap();
    let folder = dir.0.join(name);
    std::fs::create_dir(&folder).unwrap();
    for (frame, (k, record)) in records.iter().cycle().take(15).enumerate().enumerate() {
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

/// A landscape video given as portrait (its poses squeezed across, like side views) is said
/// too.
#[test]
fn a_landscape_video_given_as_portrait_is_said() {
    let dir = TempDir::new("image-size-landscape");
    let folder = yolo_video(&dir, "landscape", 1920.0, 1080.0);
    let warning = |size: &str| {
        let args = ["reconstruct", &folder, "--image-size", size, "-q", "--json"];
        warning_line(&args, "--image-size is width first")
    };
    let said = warning("1080,1920").expect("no warning of a swapped image size");
    assert!(
        said.contains("better with the image 1920x1080 than 1080x1920"),
        "{said}"
    );
    assert_eq!(warning("1920,1080"), None);
}
