//! Where a 2D pose's pelvis and neck sit on its torso: at the hip and shoulder midpoints, as
//! detectors and photo annotations place them, or where a skeleton's own joints are, as
//! motion capture places them (docs/conventions.md section 6).
//!
//! CMU's pelvis is about a quarter of the way from the mid-hip point up to the mid-shoulder
//! point, a tenth of that off it towards the back, and its neck about a sixth of the way
//! below the mid-shoulder point; a view cannot tell the two placements apart by the torso's
//! depth, so the depth lifter has one set of heads per placement ([`crate::DepthLifter`])
//! and reads a pose's placement from its image.

use camloc_skeleton::{Landmark, PartialPose2, Pose2};

/// Pelvis and neck within this share of the mid-hip to mid-shoulder distance of the
/// midpoints (both): the midpoint placement alone. Landmarks derived as midpoints are there
/// exactly; held-out CMU poses placed so and seen with 3% noise (`jittered`) were within it
/// in 82% of 6,210 views, in their own placement in 0.08% of 12,420.
pub const MIDPOINT_PLACEMENT: f64 = 0.08;

/// Pelvis or neck beyond this share: the skeleton's own placement alone (CMU's own with 3%
/// noise: 95.5% of those views, `rig` 98.6-99.3%; midpoints: 0.03%). Between the two bounds
/// the placements' depths are blended linearly, so that a pose near one bound is not read
/// one way in one frame and the other in the next.
pub const OWN_PLACEMENT: f64 = 0.16;

/// The pelvis, the neck, the hips and the shoulders: the landmarks a placement is read from.
pub(crate) const TORSO: [Landmark; 6] = [
    Landmark::Pelvis,
    Landmark::Neck,
    Landmark::LeftHip,
    Landmark::RightHip,
    Landmark::LeftShoulder,
    Landmark::RightShoulder,
];

/// The quantile of its poses' weights that a sequence's poses are all lifted with
/// ([`sequence_own_placement_weight`]).
pub const SEQUENCE_PLACEMENT_QUANTILE: f64 = 0.9;

/// The weight of the skeleton's own placement for every pose of one person's sequence: the
/// [`SEQUENCE_PLACEMENT_QUANTILE`] of [`own_placement_weight`] over its poses that have the
/// pelvis, the neck, both hips and both shoulders (none without such a pose). A person's
/// landmarks keep one placement, which a view from above and behind can hide: CMU's pelvis,
/// 0.23 of the torso above the mid-hip point and 0.09 behind it, shows 0.12-0.13 above it at
/// 55 deg of elevation (a simulated user's subject 14, whose frames were read as midpoints in
/// 84-94% of frames), while a detector's midpoints are there in every frame.
pub fn sequence_own_placement_weight(poses: &[PartialPose2]) -> Option<f64> {
    let mut weights: Vec<f64> = poses
        .iter()
        .filter_map(|p| {
            let mut pose = Pose2 {
                points: [[0.0; 2]; camloc_skeleton::NUM_LANDMARKS],
            };
            for l in TORSO {
                pose.points[l.index()] = p.points[l.index()]?;
            }
            Some(own_placement_weight(&pose))
        })
        .collect();
    if weights.is_empty() {
        return None;
    }
    weights.sort_by(f64::total_cmp);
    let at = ((weights.len() - 1) as f64 * SEQUENCE_PLACEMENT_QUANTILE).round() as usize;
    Some(weights[at])
}

/// The weight (0 to 1) of the skeleton's own placement for `pose`: 0 when its pelvis and
/// neck both lie within [`MIDPOINT_PLACEMENT`] of the hip and shoulder midpoints (in
/// units of the distance between those midpoints), 1 when either lies beyond
/// [`OWN_PLACEMENT`], linear between; 1 for a torso of no length or non-finite points.
pub fn own_placement_weight(pose: &Pose2) -> f64 {
    let mid = |a: Landmark, b: Landmark| {
        let (p, q) = (pose.get(a), pose.get(b));
        [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]
    };
    let distance = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
    let hips = mid(Landmark::LeftHip, Landmark::RightHip);
    let shoulders = mid(Landmark::LeftShoulder, Landmark::RightShoulder);
    let torso = distance(hips, shoulders);
    let (pelvis, neck) = (
        distance(pose.get(Landmark::Pelvis), hips) / torso,
        distance(pose.get(Landmark::Neck), shoulders) / torso,
    );
    // (`f64::max` would pass over a NaN.)
    if !(pelvis.is_finite() && neck.is_finite()) {
        return 1.0;
    }
    let off = pelvis.max(neck);
    ((off - MIDPOINT_PLACEMENT) / (OWN_PLACEMENT - MIDPOINT_PLACEMENT)).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A front view (x right, y up) of a standing torso: hips at +-0.1 m, shoulders at
    /// +-0.18 m and 0.5 m up, the pelvis and the neck where `pelvis_up` and `neck_up` put
    /// them on the axis between the midpoints (0: the mid-hip point, 1: the mid-shoulder
    /// point).
    fn torso(pelvis_up: f64, neck_up: f64) -> Pose2 {
        let mut points = [[0.0, -0.5]; camloc_skeleton::NUM_LANDMARKS];
        let mut set = |l: Landmark, p: [f64; 2]| points[l.index()] = p;
        set(Landmark::LeftHip, [0.1, 0.0]);
        set(Landmark::RightHip, [-0.1, 0.0]);
        set(Landmark::LeftShoulder, [0.18, 0.5]);
        set(Landmark::RightShoulder, [-0.18, 0.5]);
        set(Landmark::Pelvis, [0.0, 0.5 * pelvis_up]);
        set(Landmark::Neck, [0.0, 0.5 * neck_up]);
        Pose2 { points }
    }

    #[test]
    fn midpoints_weigh_nothing_and_a_skeletons_own_placement_everything() {
        assert_eq!(own_placement_weight(&torso(0.0, 1.0)), 0.0);
        // CMU's: the pelvis a quarter of the way up, the neck a sixth below the shoulders.
        assert_eq!(own_placement_weight(&torso(0.25, 0.85)), 1.0);
        // Either one off is enough.
        assert_eq!(own_placement_weight(&torso(0.0, 0.8)), 1.0);
        // Between the bounds, linear.
        let halfway = 0.5 * (MIDPOINT_PLACEMENT + OWN_PLACEMENT);
        assert!((own_placement_weight(&torso(halfway, 1.0)) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_weight_does_not_depend_on_where_or_how_large_the_pose_is() {
        let pose = torso(0.11, 0.95);
        let mut moved = pose;
        for p in &mut moved.points {
            *p = [3.0 * p[0] + 400.0, 3.0 * p[1] - 250.0];
        }
        let (a, b) = (own_placement_weight(&pose), own_placement_weight(&moved));
        assert!(a > 0.0 && a < 1.0, "{a}");
        assert!((a - b).abs() < 1e-9, "{a} {b}");
    }

    #[test]
    fn a_sequence_takes_the_placement_its_clearest_frames_show() {
        let partial = |p: Pose2| PartialPose2::from(p);
        // A view from above and behind hides CMU's placement in most frames, not in all.
        let mut frames = vec![partial(torso(0.12, 0.95)); 8];
        frames.extend([partial(torso(0.25, 0.85)); 2]);
        assert_eq!(sequence_own_placement_weight(&frames), Some(1.0));
        assert!(own_placement_weight(&torso(0.12, 0.95)) < 1.0);
        // A detector's midpoints, with one noisy frame.
        let mut frames = vec![partial(torso(0.0, 1.0)); 19];
        frames.push(partial(torso(0.2, 1.0)));
        assert_eq!(sequence_own_placement_weight(&frames), Some(0.0));
        // Frames without a whole torso say nothing.
        let mut headless = torso(0.0, 1.0).into();
        let PartialPose2 { points } = &mut headless;
        points[Landmark::Neck.index()] = None;
        assert_eq!(sequence_own_placement_weight(&[headless]), None);
        assert_eq!(sequence_own_placement_weight(&[]), None);
    }

    #[test]
    fn a_torso_of_no_length_or_a_non_finite_one_is_read_as_its_own() {
        let mut flat = torso(0.0, 1.0);
        flat.points[Landmark::LeftShoulder.index()] = [0.1, 0.0];
        flat.points[Landmark::RightShoulder.index()] = [-0.1, 0.0];
        assert_eq!(own_placement_weight(&flat), 1.0);
        let mut nan = torso(0.0, 1.0);
        nan.points[Landmark::Neck.index()] = [f64::NAN, 0.0];
        assert_eq!(own_placement_weight(&nan), 1.0);
    }
}
