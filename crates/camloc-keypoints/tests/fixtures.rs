//! Each format reads its hand-made fixture to the coordinates written in the file.

mod common;

use camloc_keypoints::{
    COCO_KEYPOINTS, Invisible, KeypointError, KeypointFormat, LSP_JOINTS, Landmark, LspOptions,
    ReadOptions, parse_keypoints, read_keypoints, to_camloc_json,
};
use common::{fixture, fixture_text, mid, point, read};
use serde_json::Value;

/// `[u, v]` of a JSON array of two numbers, or `None` for null / absent.
fn json_point(value: Option<&Value>) -> Option<[f64; 2]> {
    let a = value?.as_array()?;
    Some([a[0].as_f64()?, a[1].as_f64()?])
}

#[test]
fn camloc_example_reads_the_file_coordinates() {
    let records = read("example.json");
    let doc: Value = serde_json::from_str(&fixture_text("example.json")).unwrap();
    let poses = doc["poses"].as_array().unwrap();
    assert_eq!(records.len(), poses.len());
    assert!(records.len() >= 2);
    for (i, (record, pose)) in records.iter().zip(poses).enumerate() {
        assert_eq!(record.id, pose["id"].as_str().unwrap());
        assert!(
            record
                .source
                .ends_with(&format!("example.json: poses[{i}]")),
            "{}",
            record.source
        );
        for l in Landmark::ALL {
            if record.is_derived(l) {
                continue;
            }
            assert_eq!(
                record.pose.points[l.index()],
                json_point(pose["landmarks"].get(l.name())),
                "{} {l:?}",
                record.id
            );
        }
        // The README's job needs a complete pose with a torso.
        record.require_torso().unwrap();
        assert!(record.pose.complete().is_some(), "{}", record.id);
    }
}

#[test]
fn camloc_example_poses_look_human() {
    for record in read("example.json") {
        let pose = record.pose.complete().unwrap();
        let vs: Vec<f64> = pose.points.iter().map(|p| p[1]).collect();
        let height = vs.iter().cloned().fold(f64::MIN, f64::max)
            - vs.iter().cloned().fold(f64::MAX, f64::min);
        assert!(
            (200.0..=350.0).contains(&height),
            "{}: {height} px tall",
            record.id
        );
        // Upright: head above neck above pelvis above knees above ankles (v grows downwards).
        let v = |l: Landmark| pose.get(l)[1];
        assert!(v(Landmark::Head) < v(Landmark::Neck), "{}", record.id);
        assert!(v(Landmark::Neck) < v(Landmark::Pelvis), "{}", record.id);
        for (knee, ankle) in [
            (Landmark::LeftKnee, Landmark::LeftAnkle),
            (Landmark::RightKnee, Landmark::RightAnkle),
        ] {
            assert!(
                v(Landmark::Pelvis) < v(knee) && v(knee) < v(ankle),
                "{}",
                record.id
            );
        }
        // Torso and thighs of human proportions (thigh / torso between 0.5 and 1.5).
        let thigh = pose.limb_length(1).max(pose.limb_length(4));
        let ratio = thigh / pose.torso_length();
        assert!(
            (0.5..1.5).contains(&ratio),
            "{}: thigh/torso {ratio}",
            record.id
        );
    }
}

#[test]
fn camloc_missing_pelvis_is_derived_and_recorded() {
    let records = read("example.json");
    let derived: Vec<_> = records.iter().filter(|r| !r.derived.is_empty()).collect();
    assert_eq!(derived.len(), 1, "the example shows derivation once");
    let r = derived[0];
    assert_eq!(r.derived, vec![Landmark::Pelvis]);
    assert_eq!(
        point(r, Landmark::Pelvis),
        mid(point(r, Landmark::LeftHip), point(r, Landmark::RightHip))
    );
}

#[test]
fn camloc_partial_poses_keep_missing_landmarks() {
    let records = read("partial.json");
    assert_eq!(records.len(), 2);
    let (a, b) = (&records[0], &records[1]);
    assert_eq!(a.id, "occluded-right-arm");
    assert_eq!(a.pose.points[Landmark::RightElbow.index()], None);
    assert_eq!(a.pose.points[Landmark::RightWrist.index()], None);
    assert_eq!(a.derived, vec![Landmark::Pelvis]);
    assert_eq!(
        point(a, Landmark::Pelvis),
        mid(point(a, Landmark::LeftHip), point(a, Landmark::RightHip))
    );
    a.require_torso().unwrap();

    // No id: named after its position. One hip only: no pelvis; both shoulders: derived neck.
    assert_eq!(b.id, "pose-1");
    assert_eq!(b.pose.points[Landmark::Pelvis.index()], None);
    assert_eq!(b.derived, vec![Landmark::Neck]);
    assert_eq!(
        point(b, Landmark::Neck),
        mid(
            point(b, Landmark::LeftShoulder),
            point(b, Landmark::RightShoulder)
        )
    );
    let err = b.require_torso().unwrap_err();
    assert!(
        matches!(&err, KeypointError::MissingTorso { id, missing, origin } if id == "pose-1" && missing == &[Landmark::Pelvis] && origin.ends_with("partial.json: poses[1]")),
        "{err:?}"
    );
}

#[test]
fn derivation_can_be_turned_off() {
    let options = ReadOptions {
        derive_torso: false,
        ..ReadOptions::default()
    };
    let records = read_keypoints(fixture("partial.json"), None, &options).unwrap();
    assert!(records.iter().all(|r| r.derived.is_empty()));
    assert_eq!(records[0].pose.points[Landmark::Pelvis.index()], None);
    assert!(records[0].require_torso().is_err());
}

#[test]
fn camloc_bare_pose_is_accepted() {
    let records = read("single_pose.json");
    assert_eq!(records.len(), 1);
    let r = &records[0];
    assert_eq!(r.id, "just-one");
    assert_eq!(r.pose.points[Landmark::Pelvis.index()], Some([10.0, 20.0]));
    assert_eq!(r.pose.points[Landmark::Neck.index()], Some([10.5, -30.25]));
    assert_eq!(r.pose.points[Landmark::Head.index()], None);
    assert_eq!(r.pose.missing().count(), 13);
    assert!(
        r.source.ends_with("single_pose.json: top level"),
        "{}",
        r.source
    );
}

/// The rows of an LSP CSV fixture, split independently of the reader:
/// (line, image, joint, [x, y], visible).
fn lsp_rows(name: &str) -> Vec<(usize, String, String, [f64; 2], bool)> {
    fixture_text(name)
        .lines()
        .enumerate()
        .skip(1)
        .map(|(i, line)| {
            let f: Vec<&str> = line.split(',').collect();
            (
                i + 1,
                f[0].to_owned(),
                f[1].to_owned(),
                [f[2].parse().unwrap(), f[3].parse().unwrap()],
                f[4] == "1",
            )
        })
        .collect()
}

fn lsp_landmark(joint: &str) -> Landmark {
    LSP_JOINTS.iter().find(|(n, _)| *n == joint).unwrap().1
}

#[test]
fn lsp_groups_rows_by_image_in_first_appearance_order() {
    let rows = lsp_rows("tiny_lsp.csv");
    let records = read("tiny_lsp.csv");
    let mut images: Vec<(&str, usize)> = Vec::new();
    for (line, image, ..) in &rows {
        if !images.iter().any(|(i, _)| i == image) {
            images.push((image, *line));
        }
    }
    let got: Vec<&str> = records.iter().map(|r| r.id.as_str()).collect();
    assert_eq!(got, images.iter().map(|(i, _)| *i).collect::<Vec<_>>());
    for (record, (_, line)) in records.iter().zip(&images) {
        assert!(
            record
                .source
                .ends_with(&format!("tiny_lsp.csv: line {line}")),
            "{}",
            record.source
        );
    }
    // The fixture splits one image's rows around another image.
    let firsts: Vec<usize> = images.iter().map(|(_, l)| *l).collect();
    assert!(
        rows.iter()
            .any(|(l, image, ..)| image == "im_b" && *l > firsts[2])
    );
}

#[test]
fn lsp_reads_visible_coordinates_and_drops_invisible_ones_by_default() {
    let rows = lsp_rows("tiny_lsp.csv");
    let records = read("tiny_lsp.csv");
    for (_, image, joint, xy, visible) in &rows {
        let r = records.iter().find(|r| &r.id == image).unwrap();
        let got = r.pose.points[lsp_landmark(joint).index()];
        if *visible {
            assert_eq!(got, Some(*xy), "{image} {joint}");
        } else if !r.is_derived(lsp_landmark(joint)) {
            assert_eq!(got, None, "{image} {joint}");
        }
    }
    for r in &records {
        let invisible: Vec<&str> = rows
            .iter()
            .filter(|x| x.1 == r.id && !x.4)
            .map(|x| x.2.as_str())
            .collect();
        let hips_visible = !invisible.contains(&"left_hip") && !invisible.contains(&"right_hip");
        let annotated = |joint: &str| {
            rows.iter()
                .find(|x| x.1 == r.id && x.2 == joint)
                .map(|x| x.3)
        };
        // LSP has no pelvis: it is always derived, from the visible hips when both are
        // visible, else from the annotated (invisible) hip coordinates.
        match (annotated("left_hip"), annotated("right_hip")) {
            (Some(l), Some(rh)) => {
                assert!(r.is_derived(Landmark::Pelvis), "{}", r.id);
                assert_eq!(r.pose.points[0], Some(mid(l, rh)), "{}", r.id);
            }
            _ => assert_eq!(r.pose.points[0], None, "{}", r.id),
        }
        if hips_visible {
            assert_eq!(
                point(r, Landmark::Pelvis),
                mid(point(r, Landmark::LeftHip), point(r, Landmark::RightHip))
            );
        }
        // The neck is derived exactly when it is invisible (the shoulders are visible here).
        assert_eq!(
            r.is_derived(Landmark::Neck),
            invisible.contains(&"neck"),
            "{}",
            r.id
        );
    }
    assert!(
        records.iter().any(|r| r.is_derived(Landmark::Neck)),
        "fixture exercises neck derivation"
    );
    assert!(
        records
            .iter()
            .any(|r| r.pose.points[0].is_some()
                && r.pose.points[Landmark::LeftHip.index()].is_none()),
        "fixture derives a pelvis from an invisible hip"
    );
}

#[test]
fn lsp_invisible_use_keeps_annotated_coordinates() {
    let options = ReadOptions {
        lsp: LspOptions {
            invisible: Invisible::Use,
        },
        ..ReadOptions::default()
    };
    let records =
        read_keypoints(fixture("tiny_lsp.csv"), Some(KeypointFormat::Lsp), &options).unwrap();
    for (_, image, joint, xy, _) in lsp_rows("tiny_lsp.csv") {
        let r = records.iter().find(|r| r.id == image).unwrap();
        assert_eq!(
            r.pose.points[lsp_landmark(&joint).index()],
            Some(xy),
            "{image} {joint}"
        );
    }
    for r in &records {
        assert_eq!(r.derived, vec![Landmark::Pelvis], "{}", r.id);
        assert!(r.pose.complete().is_some());
    }
}

/// `(image_id, id, keypoints)` of every entry of a COCO fixture, read independently.
fn coco_entries(name: &str) -> Vec<(String, Option<String>, Vec<f64>)> {
    let doc: Value = serde_json::from_str(&fixture_text(name)).unwrap();
    let list = doc
        .get("annotations")
        .unwrap_or(&doc)
        .as_array()
        .unwrap()
        .clone();
    list.iter()
        .map(|a| {
            (
                a["image_id"].to_string(),
                a.get("id").map(|v| v.to_string()),
                a["keypoints"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_f64().unwrap())
                    .collect(),
            )
        })
        .collect()
}

/// Checks COCO records against the file's keypoints, with `min_score`.
fn check_coco(name: &str, min_score: f64) {
    let options = ReadOptions {
        min_score,
        ..ReadOptions::default()
    };
    let records = read_keypoints(fixture(name), None, &options).unwrap();
    let entries = coco_entries(name);
    assert_eq!(records.len(), entries.len());
    for (i, (r, (image, id, kp))) in records.iter().zip(&entries).enumerate() {
        let suffix = id.clone().unwrap_or_else(|| i.to_string());
        assert_eq!(r.id, format!("{image}/{suffix}"));
        // Score 0 is missing; below min_score too.
        let present = |k: usize| {
            let v = kp[3 * k + 2];
            (v > 0.0 && v >= min_score).then(|| [kp[3 * k], kp[3 * k + 1]])
        };
        for (k, name) in COCO_KEYPOINTS.iter().enumerate() {
            if let Some(l) = Landmark::from_name(name) {
                assert_eq!(r.pose.points[l.index()], present(k), "{} {name}", r.id);
            }
        }
        let face: Vec<[f64; 2]> = (0..5).filter_map(present).collect();
        if face.is_empty() {
            assert_eq!(r.pose.points[Landmark::Head.index()], None);
            assert!(!r.is_derived(Landmark::Head));
        } else {
            let n = face.len() as f64;
            let mean = [
                face.iter().map(|p| p[0]).sum::<f64>() / n,
                face.iter().map(|p| p[1]).sum::<f64>() / n,
            ];
            let head = point(r, Landmark::Head);
            assert!(
                (head[0] - mean[0]).abs() < 1e-9 && (head[1] - mean[1]).abs() < 1e-9,
                "{}",
                r.id
            );
            assert!(r.is_derived(Landmark::Head));
        }
        for (target, a, b) in [
            (Landmark::Pelvis, Landmark::LeftHip, Landmark::RightHip),
            (
                Landmark::Neck,
                Landmark::LeftShoulder,
                Landmark::RightShoulder,
            ),
        ] {
            match (r.pose.points[a.index()], r.pose.points[b.index()]) {
                (Some(p), Some(q)) => {
                    assert_eq!(point(r, target), mid(p, q));
                    assert!(r.is_derived(target));
                }
                _ => assert_eq!(r.pose.points[target.index()], None),
            }
        }
    }
}

#[test]
fn coco_dataset_maps_keypoints_and_derives_head_neck_pelvis() {
    check_coco("tiny_coco.json", 0.0);
    let records = read("tiny_coco.json");
    // The fixture has a person without a left shoulder (no neck) and one without nose and eyes.
    assert!(
        records
            .iter()
            .any(|r| r.pose.points[Landmark::Neck.index()].is_none())
    );
    assert!(records.iter().all(|r| r.is_derived(Landmark::Head)));
    assert!(
        records[1]
            .source
            .ends_with("tiny_coco.json: annotations[1]"),
        "{}",
        records[1].source
    );
}

#[test]
fn coco_results_use_the_confidence_threshold() {
    check_coco("tiny_coco_results.json", 0.0);
    check_coco("tiny_coco_results.json", 0.85);
    let options = ReadOptions {
        min_score: 0.85,
        ..ReadOptions::default()
    };
    let strict = read_keypoints(fixture("tiny_coco_results.json"), None, &options).unwrap();
    assert!(
        strict[1].pose.missing().count() == 15,
        "confidences of 0.8 all drop out"
    );
    assert!(read("tiny_coco_results.json")[0].source.ends_with(": [0]"));
}

#[test]
fn detection_agrees_with_the_explicit_format() {
    for (name, format) in [
        ("example.json", KeypointFormat::Camloc),
        ("partial.json", KeypointFormat::Camloc),
        ("single_pose.json", KeypointFormat::Camloc),
        ("tiny_lsp.csv", KeypointFormat::Lsp),
        ("tiny_coco.json", KeypointFormat::Coco),
        ("tiny_coco_results.json", KeypointFormat::Coco),
    ] {
        let text = fixture_text(name);
        let ext = name.rsplit('.').next();
        assert_eq!(
            KeypointFormat::from_extension_and_content(ext, &text),
            Some(format),
            "{name}"
        );
        let explicit =
            read_keypoints(fixture(name), Some(format), &ReadOptions::default()).unwrap();
        assert_eq!(read(name), explicit, "{name}");
        // Without an extension the content alone decides.
        let anonymous = parse_keypoints(&text, "stdin", None, &ReadOptions::default()).unwrap();
        assert_eq!(anonymous.len(), explicit.len(), "{name}");
    }
}

#[test]
fn any_format_converts_to_camloc_json_and_back() {
    let options = ReadOptions {
        derive_torso: false,
        ..ReadOptions::default()
    };
    // The OpenPose frames have frame and person numbers, which come back too.
    for name in [
        "tiny_lsp.csv",
        "tiny_coco.json",
        "example.json",
        "samples/openpose_coco18_000000000007_keypoints.json",
    ] {
        let records = read(name);
        let keys = |r: &[camloc_keypoints::KeypointRecord]| -> Vec<_> {
            r.iter()
                .map(|r| (r.id.clone(), r.pose, r.frame, r.person))
                .collect()
        };
        let text = to_camloc_json(&records);
        let back = parse_keypoints(&text, "converted.json", None, &options).unwrap();
        assert_eq!(keys(&back), keys(&records), "{name}");
    }
}

#[test]
fn crlf_and_byte_order_mark_are_accepted() {
    let text = fixture_text("tiny_lsp.csv");
    let crlf = format!("\u{feff}{}", text.replace('\n', "\r\n"));
    let options = ReadOptions::default();
    assert_eq!(
        parse_keypoints(&crlf, "tiny_lsp.csv", None, &options).unwrap(),
        parse_keypoints(&text, "tiny_lsp.csv", None, &options).unwrap()
    );
    let json = fixture_text("example.json");
    assert_eq!(
        parse_keypoints(&format!("\u{feff}{json}"), "e.json", None, &options).unwrap(),
        parse_keypoints(&json, "e.json", None, &options).unwrap()
    );
}
