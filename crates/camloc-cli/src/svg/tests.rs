//! Tests of the drawings: what they show and where.

use super::*;

#[test]
fn the_skeleton_views_are_what_their_cameras_see_unmirrored() {
    let cameras = CameraSet::table1();
    for ((name, view), label) in SKELETON_VIEWS.iter().zip([5u16, 6]) {
        let r = cameras.get(label).unwrap().rotation;
        for p in [[0.3, -0.2, 0.5], [-0.1, 0.4, -0.7], [1.0, 0.0, 0.0]] {
            let v = Vector3::from(p);
            let want = [r.row(0).dot(&v.transpose()), r.row(1).dot(&v.transpose())];
            let got = view(p);
            assert!(
                (got[0] - want[0]).abs() < 1e-12 && (got[1] - want[1]).abs() < 1e-12,
                "{name}: {got:?} against camera {label}'s {want:?}"
            );
        }
    }
    // From above with the front (-x) up: the person's right (+y) on the right.
    let top = SKELETON_VIEWS[2].1;
    assert!(top([0.0, 1.0, 0.0])[0] > 0.0 && top([-1.0, 0.0, 0.0])[1] < 0.0);
}

/// The `(cx, cy)` texts of the circles of `fill` with radius `r` in `svg`.
fn circles(svg: &str, r: &str, fill: &str) -> Vec<String> {
    let tail = format!(r#"" r="{r}" fill="{fill}"/>"#);
    svg.lines()
        .filter_map(|line| line.split("<circle cx=\"").nth(1))
        .filter(|rest| rest.contains(&tail))
        .map(|rest| rest.split(&tail).next().unwrap_or("").to_owned())
        .collect()
}

/// Width of the bounding box of the uncertainty path (the path in the direction colour).
fn uncertainty_width(svg: &str) -> f64 {
    let line = svg
        .lines()
        .find(|l| l.starts_with("<path") && l.contains(DIRECTION))
        .unwrap_or("");
    let d = line.split("d=\"").nth(1).and_then(|r| r.split('"').next());
    let xs: Vec<f64> = d
        .unwrap_or("")
        .split_whitespace()
        .filter_map(|p| p.trim_start_matches(['M', 'L']).split(',').next())
        .filter_map(|x| x.parse().ok())
        .collect();
    assert_eq!(xs.len(), 49, "{line}");
    xs.iter().copied().fold(f64::MIN, f64::max) - xs.iter().copied().fold(f64::MAX, f64::min)
}

#[test]
fn the_sphere_draws_the_direction_at_its_point_with_its_uncertainty() {
    let pose = PartialPose2::from(Pose2::new([[0.0; 2]; 15]));
    let cameras = CameraSet::table1();
    let label = CameraLabel::new(5).unwrap();
    let front = |uncertainty_deg| Direction {
        azimuth_deg: 180.0,
        elevation_deg: 0.0,
        uncertainty_deg,
    };
    let mut probabilities = [0.0; 12];
    probabilities[4] = 0.9;
    probabilities[5] = 0.1;
    let svg = localization_svg(
        &pose,
        &cameras,
        &probabilities,
        label,
        Some(front(10.0)),
        "c",
    );
    // Camera 5 is the middle front camera: the direction's dot is drawn on it.
    let chosen = circles(&svg, "9.6", RIGHT);
    assert_eq!(chosen.len(), 1);
    assert_eq!(circles(&svg, "4.5", DIRECTION), chosen);
    assert!(svg.contains("direction: azimuth 180, elevation 0, +- 10 deg"));
    // Each camera's probability: the chosen one's and the next one's percentages, the
    // next one's dot larger than the others'.
    assert!(svg.contains(">05 90%</text>") && svg.contains(">06 10%</text>"));
    assert!(svg.contains(">07</text>"));
    assert_eq!(circles(&svg, "5.2", "#777777").len(), 1);
    // The ten others, those on the far side paler.
    let small = |tail: &str| {
        svg.lines()
            .filter(|l| l.contains(&format!(r##"r="3.0" fill="#777777"{tail}"##)))
            .count()
    };
    assert_eq!(small("/>") + small(r#" opacity="0.45"/>"#), 10);
    assert!(small(r#" opacity="0.45"/>"#) >= 4);
    let wider = localization_svg(
        &pose,
        &cameras,
        &probabilities,
        label,
        Some(front(30.0)),
        "c",
    );
    assert!(uncertainty_width(&wider) > 2.0 * uncertainty_width(&svg));
    let without = localization_svg(&pose, &cameras, &probabilities, label, None, "c");
    assert!(!without.contains(DIRECTION));
}

#[test]
fn a_long_caption_is_broken_into_lines_inside_the_drawing() {
    let missing = "pelvis, right_hip, neck, right_shoulder, right_elbow, right_wrist";
    let caption = format!("im00011: camera 08 (middle right), p = 0.95; missing: {missing}");
    let pose = PartialPose2::from(Pose2::new([[0.0; 2]; 15]));
    let (cameras, label) = (CameraSet::table1(), CameraLabel::new(8).unwrap());
    let probabilities = [1.0 / 12.0; 12];
    let short = localization_svg(&pose, &cameras, &probabilities, label, None, "im00011");
    let long = localization_svg(
        &pose,
        &cameras,
        &probabilities,
        label,
        None,
        &caption.repeat(2),
    );
    assert!(short.contains(r#"height="360""#));
    let rows = caption_lines(&caption.repeat(2), 620.0).len();
    assert!(rows > 1);
    let height = 360.0 + CAPTION_LINE_PX * (rows - 1) as f64;
    assert!(long.contains(&format!(r#"height="{height}""#)), "{long}");
    let last_baseline = 346.0 + CAPTION_LINE_PX * (rows - 1) as f64;
    assert!(long.contains(&format!(r#"y="{last_baseline}""#)));
    assert!(last_baseline < height);
}

#[test]
fn a_long_title_gets_lines_above_the_drawing() {
    let title = "cameras of /tmp/a-very-long-folder-name-for-a-video-project/and-another-nested-folder-of-frames/poses.json";
    let svg = begin_titled(300.0, 100.0, title);
    let rows = caption_lines(title, 280.0).len();
    assert!(rows > 1);
    let above = CAPTION_LINE_PX * (rows - 1) as f64;
    assert!(svg.contains(&format!(r#"viewBox="0 {} 300 {}""#, -above, 100.0 + above)));
    assert!(svg.contains(&format!(r#"y="{}""#, 20.0 - above)));
    assert!(begin_titled(300.0, 100.0, "short").contains(r#"viewBox="0 0 300 100""#));
}

#[test]
fn filled_in_joints_are_rings_in_the_reprojection_and_every_3d_view() {
    let points: [[f64; 2]; 15] = std::array::from_fn(|i| [i as f64, (i * i) as f64]);
    let reprojection = Pose2::new(points);
    let pose = Pose3::new(std::array::from_fn(|i| {
        [0.1 * i as f64, 0.0, 0.05 * i as f64]
    }));
    let mut input = PartialPose2::from(reprojection);
    let complete = reconstruction_svg(&input, &reprojection, &pose, "c");
    input.points[Landmark::RightWrist.index()] = None;
    let partial = reconstruction_svg(&input, &reprojection, &pose, "c");
    let rings = |svg: &str| svg.matches(r#"r="3.5" fill="white""#).count();
    assert_eq!(rings(&complete), 0);
    // The reprojection and the three 3D views: one ring each.
    assert_eq!(rings(&partial), 4, "{partial}");
    assert!(partial.contains("hollow rings: joints filled in") && !complete.contains("hollow"));
}

#[test]
fn a_lopsided_pose_stays_inside_its_3d_panels() {
    // Fourteen landmarks near the pelvis and one far out: centred on the points' mean, the far
    // one had been drawn past the panel's edge.
    let mut points = [[0.0, 0.0, 0.0]; 15];
    for (i, p) in points.iter_mut().enumerate() {
        *p = [
            0.01 * i as f64,
            0.02 * (i % 3) as f64,
            0.03 * (i % 5) as f64,
        ];
    }
    points[Landmark::RightWrist.index()] = [0.9, -0.8, 0.7];
    let pose = Pose3::new(points);
    let flat = Pose2::new(std::array::from_fn(|i| [points[i][1], -points[i][2]]));
    let svg = reconstruction_svg(&PartialPose2::from(flat), &flat, &pose, "c");
    for line in svg.lines().filter(|l| l.starts_with("<line")) {
        for key in ["y1", "y2"] {
            let value: f64 = line
                .split(&format!("{key}=\""))
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!((20.0..=240.0).contains(&value), "{key} {value}: {line}");
        }
    }
}

/// The confusion matrix and the timeline name Table 1's cameras by level and side, a finer
/// sphere's by their angles (its names repeat: two "middle left" cameras of 8 azimuths), and
/// the matrix shows every count.
#[test]
fn the_confusion_matrix_names_cameras_apart() {
    let table1 = CameraSet::table1();
    let mut counts = vec![vec![0usize; 12]; 12];
    counts[4][5] = 37;
    let svg = confusion_svg(&table1, &counts, "t");
    assert!(
        svg.contains(">05 middle front<") && svg.contains(">37<"),
        "{svg}"
    );
    let fine = CameraSet::sphere(8, &[-20.0, 0.0, 20.0, 40.0]).unwrap();
    let svg = confusion_svg(&fine, &vec![vec![1usize; 32]; 32], "t");
    assert!(svg.contains(">02 az 225, el -20<") && svg.contains(">03 az 270, el -20<"));
    assert!(!svg.contains("middle left"));
    // The timeline of `localize --sequence` names its rows by the same rule.
    let timeline = timeline_svg(&fine, &[None], &[], [0, 0], "t");
    assert!(timeline.contains(">02 az 225, el -20<") && !timeline.contains("middle left"));
    let timeline = timeline_svg(&table1, &[None], &[], [0, 0], "t");
    assert!(timeline.contains(">06 middle left<"), "{timeline}");
}
