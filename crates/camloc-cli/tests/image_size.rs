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

/// The first 200 frames of the first CMU clip the index describes as a walk, seen from the side
/// of the clip's y axis (the first walk goes along it) by a fixed camera 4 m from its mean
/// pelvis at eye level (1000 px focal length), in pixels with x times `stretch`, as a `.npy`
/// array (200, 15, 2) in `dir`; `None` without the data (a visible `SKIPPED` line).
fn walk_npy(dir: &TempDir, name: &str, stretch: f64) -> Option<String> {
    use camloc::mocap::{MocapIndex, read_bvh};
    let what = "camloc-cli::pixels_stretched_across_are_said";
    let skip = camloc::skeleton::data::data_path_or_skip;
    let index = skip("cmu/cmu-mocap-index-text.txt", what)?;
    let folder = skip("cmu/bvh", what)?;
    let index = MocapIndex::load(&index).unwrap();
    let mut files: Vec<_> = std::fs::read_dir(folder).unwrap().flatten().collect();
    files.sort_by_key(|e| e.file_name());
    let walk = files
        .iter()
        .find(|e| {
            let stem = e.path().file_stem().unwrap().to_string_lossy().into_owned();
            index.trial_description(&stem).map(str::trim) == Some("walk")
        })
        .expect("the CMU index describes a clip of cmu/bvh as a walk");
    let frames = read_bvh(walk.path()).unwrap().frames;
    let frames = &frames[..200];
    let n = frames.len() as f64;
    let mean: [f64; 3] =
        std::array::from_fn(|a| frames.iter().map(|p| p.points[0][a]).sum::<f64>() / n);
    // The camera on the clip's -x side of the mean pelvis, looking along +x (its right is -y,
    // its up +z).
    let mut bytes = Vec::new();
    let poses: Vec<camloc::skeleton::PartialPose2> = frames
        .iter()
        .map(|pose| camloc::skeleton::PartialPose2 {
            points: pose.points.map(|p| {
                let depth = p[0] - mean[0] + 4.0;
                Some([
                    -stretch * 1000.0 * (p[1] - mean[1]) / depth + 960.0,
                    -1000.0 * (p[2] - mean[2]) / depth + 540.0,
                ])
            }),
        })
        .collect();
    camloc::keypoints::write_npy(&mut bytes, &poses).unwrap();
    let path = dir.0.join(name);
    std::fs::write(&path, bytes).unwrap();
    Some(path.to_string_lossy().into_owned())
}

/// Pixels of a walk seen from the side stretched across by (16/9)^2 (normalised coordinates
/// multiplied by a portrait video's size given as landscape) or squeezed as much (a landscape
/// one's given as portrait) are said by `localize` and `reconstruct`, naming the way that
/// fits; the walk as it is says nothing. Skipped (visibly) without the shared data.
#[test]
fn pixels_stretched_across_are_said() {
    let dir = TempDir::new("stretched");
    let Some(right) = walk_npy(&dir, "right.npy", 1.0) else {
        return;
    };
    let wide = walk_npy(&dir, "wide.npy", camloc::VIDEO_STRETCH).unwrap();
    let narrow = walk_npy(&dir, "narrow.npy", 1.0 / camloc::VIDEO_STRETCH).unwrap();
    let said = |command: &str, input: &str| {
        warning_line(
            &[command, input, "--json", "-q"],
            "fit a body better with x",
        )
    };
    for command in ["localize", "reconstruct"] {
        let warning = said(command, &wide).expect("no warning of stretched pixels");
        assert!(warning.contains("with x divided by 3.16"), "{warning}");
        let warning = said(command, &narrow).expect("no warning of squeezed pixels");
        assert!(warning.contains("with x multiplied by 3.16"), "{warning}");
        assert_eq!(said(command, &right), None, "{command}");
    }
}
