//! The real LSP annotations in `../shared/data/lsp/lsp400_joints.csv` (skipped when absent).

mod common;

use std::collections::HashMap;

use camloc_keypoints::{Invisible, LSP_JOINTS, Landmark, LspOptions, ReadOptions, read_keypoints};
use common::{mid, point};

#[test]
fn lsp400_gives_400_records_whose_torso_comes_from_visible_joints() {
    let Some(path) = camloc_skeleton::data::data_path_or_skip(
        "lsp/lsp400_joints.csv",
        "camloc-keypoints::lsp400_gives_400_records_whose_torso_comes_from_visible_joints",
    ) else {
        return;
    };
    // Count rows, visible rows and invisible rows with a position (both coordinates > 0) per
    // image independently of the reader.
    let text = std::fs::read_to_string(&path).unwrap();
    let mut order: Vec<String> = Vec::new();
    let mut visible: HashMap<String, Vec<String>> = HashMap::new();
    let mut placed: HashMap<String, Vec<String>> = HashMap::new();
    let mut rows: HashMap<String, usize> = HashMap::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if !rows.contains_key(f[0]) {
            order.push(f[0].to_owned());
        }
        *rows.entry(f[0].to_owned()).or_default() += 1;
        let (x, y): (f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        if f[4] == "1" {
            visible
                .entry(f[0].to_owned())
                .or_default()
                .push(f[1].to_owned());
        } else if x > 0.0 && y > 0.0 {
            placed
                .entry(f[0].to_owned())
                .or_default()
                .push(f[1].to_owned());
        }
    }
    // In this file every invisible joint is a placeholder at the image's top or left edge.
    assert!(placed.is_empty(), "{placed:?}");

    // With invisible joints used, the placeholders stay missing: what is read is what is
    // visible, and the pelvis is derived from two hips or not at all.
    let use_all = ReadOptions {
        lsp: LspOptions {
            invisible: Invisible::Use,
        },
        ..ReadOptions::default()
    };
    let all = read_keypoints(&path, None, &use_all).unwrap();
    assert_eq!(all.len(), 400);
    assert_eq!(all.iter().map(|r| r.id.clone()).collect::<Vec<_>>(), order);
    let default = read_keypoints(&path, None, &ReadOptions::default()).unwrap();
    assert_eq!(default.len(), 400);
    let (mut without_pelvis, mut without_torso) = (0, 0);
    for (r, u) in default.iter().zip(&all) {
        assert_eq!(rows[&r.id], 14, "{}", r.id);
        assert_eq!(r.pose, u.pose, "{}", r.id);
        let seen = visible.get(&r.id).cloned().unwrap_or_default();
        let read = LSP_JOINTS
            .iter()
            .filter(|(_, l)| r.pose.points[l.index()].is_some() && !r.is_derived(*l))
            .count();
        assert_eq!(read, seen.len(), "{}", r.id);
        let has = |j: &str| seen.iter().any(|s| s == j);
        let hips = has("left_hip") && has("right_hip");
        assert_eq!(r.is_derived(Landmark::Pelvis), hips, "{}", r.id);
        assert_eq!(r.pose.points[Landmark::Pelvis.index()].is_some(), hips);
        if hips {
            assert_eq!(
                point(r, Landmark::Pelvis),
                mid(point(r, Landmark::LeftHip), point(r, Landmark::RightHip))
            );
        }
        let shoulders = has("left_shoulder") && has("right_shoulder");
        assert_eq!(
            r.is_derived(Landmark::Neck),
            !has("neck") && shoulders,
            "{}",
            r.id
        );
        let torso = hips && (has("neck") || shoulders);
        assert_eq!(r.require_torso().is_ok(), torso, "{}", r.id);
        without_pelvis += usize::from(!hips);
        without_torso += usize::from(!torso);
    }
    println!(
        "lsp400: {without_pelvis} of 400 poses lack a visible hip, {without_torso} have no torso"
    );
}
