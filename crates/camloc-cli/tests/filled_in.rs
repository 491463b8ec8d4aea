//! The warnings of landmarks filled in, not seen: per person in a sequence (often, or over
//! half a second), and counted frame by frame.

mod common;
#[path = "common/walk.rs"]
mod walk;

use common::{TempDir, camloc};
use serde_json::Value;
use walk::walk_document;

/// A landmark filled in, not seen, in a quarter or more of a person's frames, or over half a
/// second of frame numbers, is named in a warning with its count (its 3D is the basis's guess); one
/// filled in now and then is not. Frame by frame, the poses with landmarks filled in are
/// counted.
#[test]
fn landmarks_filled_in_most_of_a_sequence_are_warned_of() {
    let dir = TempDir::new("filled-warning");
    let mut document = walk_document(0..16);
    for (t, pose) in document["poses"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .enumerate()
    {
        pose["landmarks"]["left_wrist"] = Value::Null;
        if t % 8 == 0 {
            pose["landmarks"]["right_ankle"] = Value::Null;
        }
    }
    let input = dir.file("hidden.json", &document.to_string());
    let out = camloc(&["reconstruct", "--input", &input, "--sequence", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "of its 16 reconstructed frames: left_wrist in 16 (for 16 frames from frame 0)"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("right_ankle"), "{stderr}");
    let out = camloc(&["reconstruct", "--input", &input, "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("16 of 16 poses have landmarks filled in, not seen"),
        "{stderr}"
    );
    // 16 frames in a row of 80 (a fifth): named at 30 frames a second (half a second is 15
    // frames), not at 60 (30).
    let mut document = walk_document(0..80);
    let poses = document["poses"].as_array_mut().unwrap();
    for pose in &mut poses[30..46] {
        pose["landmarks"]["right_knee"] = Value::Null;
    }
    let input = dir.file("knee.json", &document.to_string());
    let warned = |fps: &str| {
        let out = camloc(&[
            "reconstruct",
            "--input",
            &input,
            "--sequence",
            "--quiet",
            "--fps",
            fps,
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{stderr}");
        stderr.contains("right_knee in 16 (for 16 frames from frame 30)")
    };
    assert!(warned("30"));
    assert!(!warned("60"));
    // 16 frames split by the person missing for 90 frames: not a run (nor a quarter).
    let mut document = walk_document((0..40).chain(130..170));
    let poses = document["poses"].as_array_mut().unwrap();
    for pose in &mut poses[30..46] {
        pose["landmarks"]["right_knee"] = Value::Null;
    }
    let input = dir.file("apart.json", &document.to_string());
    let out = camloc(&["reconstruct", "--input", &input, "--sequence", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("right_knee"), "{stderr}");
}
