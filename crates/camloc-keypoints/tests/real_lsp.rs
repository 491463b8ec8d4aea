//! The real LSP annotations in `../shared/data/lsp/lsp400_joints.csv` (skipped when absent).

mod common;

use std::collections::HashMap;

use camloc_keypoints::{Invisible, LSP_JOINTS, Landmark, LspOptions, ReadOptions, read_keypoints};
use common::{mid, point};

#[test]
fn lsp400_gives_400_records_of_14_joints_with_derived_pelvis() {
    let Some(path) = camloc_skeleton::data::data_path_or_skip(
        "lsp/lsp400_joints.csv",
        "camloc-keypoints::lsp400_gives_400_records_of_14_joints_with_derived_pelvis",
    ) else {
        return;
    };
    // Count rows and visible rows per image independently of the reader.
    let text = std::fs::read_to_string(&path).unwrap();
    let mut order: Vec<String> = Vec::new();
    let mut visible: HashMap<String, Vec<String>> = HashMap::new();
    let mut rows: HashMap<String, usize> = HashMap::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if !rows.contains_key(f[0]) {
            order.push(f[0].to_owned());
        }
        *rows.entry(f[0].to_owned()).or_default() += 1;
        if f[4] == "1" {
            visible
                .entry(f[0].to_owned())
                .or_default()
                .push(f[1].to_owned());
        }
    }

    let use_all = ReadOptions {
        lsp: LspOptions {
            invisible: Invisible::Use,
        },
        ..ReadOptions::default()
    };
    let all = read_keypoints(&path, None, &use_all).unwrap();
    assert_eq!(all.len(), 400);
    assert_eq!(all.iter().map(|r| r.id.clone()).collect::<Vec<_>>(), order);
    for r in &all {
        assert_eq!(rows[&r.id], 14, "{}", r.id);
        assert_eq!(r.derived, vec![Landmark::Pelvis], "{}", r.id);
        assert!(r.pose.complete().is_some(), "{}", r.id);
        assert_eq!(
            point(r, Landmark::Pelvis),
            mid(point(r, Landmark::LeftHip), point(r, Landmark::RightHip))
        );
        r.require_torso().unwrap();
    }

    // By default invisible joints are missing; the torso is derived from what is visible, or
    // else from the annotated invisible joints (LSP annotates all 14 joints).
    let default = read_keypoints(&path, None, &ReadOptions::default()).unwrap();
    assert_eq!(default.len(), 400);
    let mut without_pelvis = 0;
    for r in &default {
        let seen = visible.get(&r.id).cloned().unwrap_or_default();
        let read = LSP_JOINTS
            .iter()
            .filter(|(_, l)| r.pose.points[l.index()].is_some() && !r.is_derived(*l))
            .count();
        assert_eq!(read, seen.len(), "{}", r.id);
        let has = |j: &str| seen.iter().any(|s| s == j);
        assert!(r.is_derived(Landmark::Pelvis), "{}", r.id);
        assert_eq!(r.is_derived(Landmark::Neck), !has("neck"), "{}", r.id);
        r.require_torso().unwrap();
        without_pelvis += usize::from(!(has("left_hip") && has("right_hip")));
    }
    println!(
        "lsp400, invisible = missing: {without_pelvis} of 400 poses take their pelvis from an invisible hip"
    );
}
