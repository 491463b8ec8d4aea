//! Telling the two 17-joint layouts apart by what their first five joints are: COCO-17's are
//! the face (nose, eyes, ears), a cluster the size of a head; Human3.6M's are the pelvis, the
//! right leg and the left hip, spread over half the body. Declaring one for the other gives a
//! pose that is no body (the nose read as the pelvis, the eyes as hips) and a confident wrong
//! camera, so the readers refuse a pose whose first five joints contradict its layout.

use crate::layout::Layout;

/// The spread of the first five joints of a 17-joint pose relative to the whole pose's (root
/// mean square distances from their centroids) that separates the layouts: below it, COCO-17's
/// face; above it, Human3.6M's pelvis and legs. On tripod views of CMU walks, seated people,
/// people sitting on the ground (COCO-17 and Human3.6M landmarks of the same poses) the
/// COCO-17 spreads were 0.09-0.28 and the Human3.6M ones 0.50-1.19.
pub const FIRST_FIVE_SPREAD_SPLIT: f64 = 0.4;

/// At least this many of the first five joints, and [`MIN_JOINTS`] of all, must be present
/// for [`seventeen_joint_layout`] to tell.
const MIN_FIRST_FIVE: usize = 3;

/// See [`MIN_FIRST_FIVE`].
const MIN_JOINTS: usize = 12;

/// The 17-joint layout `points` look like ([`Layout::Coco17`] or [`Layout::H36m17`]) and the
/// spread of their first five joints relative to all of theirs ([`FIRST_FIVE_SPREAD_SPLIT`]);
/// `None` when `points` are not 17, too few are present, or all present joints coincide.
pub fn seventeen_joint_layout(points: &[Option<[f64; 2]>]) -> Option<(Layout, f64)> {
    if points.len() != 17 {
        return None;
    }
    let first: Vec<[f64; 2]> = points[..5].iter().flatten().copied().collect();
    let all: Vec<[f64; 2]> = points.iter().flatten().copied().collect();
    if first.len() < MIN_FIRST_FIVE || all.len() < MIN_JOINTS {
        return None;
    }
    let spread = rms_radius(&first) / rms_radius(&all);
    if !spread.is_finite() {
        return None;
    }
    let layout = if spread < FIRST_FIVE_SPREAD_SPLIT {
        Layout::Coco17
    } else {
        Layout::H36m17
    };
    Some((layout, spread))
}

/// The layout the joints `points` of a pose declared `layout` look like, and the spread that
/// tells, when that is the other 17-joint layout ([`seventeen_joint_layout`]).
pub(crate) fn contradicted(layout: Layout, points: &[Option<[f64; 2]>]) -> Option<(Layout, f64)> {
    if layout.joint_count() != 17 {
        return None;
    }
    seventeen_joint_layout(points).filter(|(likely, _)| *likely != layout)
}

/// What the first five joints of a 17-joint layout are, for messages.
fn first_five(layout: Layout) -> &'static str {
    match layout {
        Layout::Coco17 => "face points (nose, eyes, ears)",
        _ => "pelvis, right leg and left hip",
    }
}

/// The message of a pose declared `layout` whose first five joints' `spread` says `likely`.
pub(crate) fn mismatch(layout: Layout, likely: Layout, spread: f64) -> String {
    let side = if likely == Layout::Coco17 {
        "under"
    } else {
        "over"
    };
    format!(
        "joints 0-4 spread over {spread:.2} of the pose's size, as {likely}'s {} do ({side} \
         {FIRST_FIVE_SPREAD_SPLIT}; {layout}'s {} spread {}): the layout is likely {likely}, not \
         {layout}",
        first_five(likely),
        first_five(layout),
        if side == "under" { "more" } else { "less" },
    )
}

/// The root mean square distance of `points` from their centroid.
fn rms_radius(points: &[[f64; 2]]) -> f64 {
    let n = points.len() as f64;
    let mean = points
        .iter()
        .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    let squares: f64 = points
        .iter()
        .map(|p| (p[0] - mean[0]).powi(2) + (p[1] - mean[1]).powi(2))
        .sum();
    (squares / n).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A standing person facing the camera, 17 joints in COCO-17 order (pixels, y down).
    const COCO_STANDING: [[f64; 2]; 17] = [
        [100.0, 20.0],
        [104.0, 16.0],
        [96.0, 16.0],
        [110.0, 18.0],
        [90.0, 18.0],
        [125.0, 50.0],
        [75.0, 50.0],
        [130.0, 90.0],
        [70.0, 90.0],
        [132.0, 125.0],
        [68.0, 125.0],
        [115.0, 130.0],
        [85.0, 130.0],
        [116.0, 185.0],
        [84.0, 185.0],
        [117.0, 240.0],
        [83.0, 240.0],
    ];

    /// [`COCO_STANDING`] in Human3.6M order (pelvis, right leg, left leg, spine, thorax,
    /// neck/nose, head top, left arm, right arm).
    fn h36m_standing() -> [[f64; 2]; 17] {
        let c = COCO_STANDING;
        let mid = |a: [f64; 2], b: [f64; 2]| [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let pelvis = mid(c[11], c[12]);
        let thorax = mid(c[5], c[6]);
        [
            pelvis,
            c[12],
            c[14],
            c[16],
            c[11],
            c[13],
            c[15],
            mid(pelvis, thorax),
            thorax,
            c[0],
            [100.0, 5.0],
            c[5],
            c[7],
            c[9],
            c[6],
            c[8],
            c[10],
        ]
    }

    #[test]
    fn the_first_five_joints_tell_the_layouts_apart() {
        let some = |p: [[f64; 2]; 17]| p.map(Some);
        let (coco, spread) = seventeen_joint_layout(&some(COCO_STANDING)).unwrap();
        assert_eq!(coco, Layout::Coco17, "{spread}");
        let (h36m, spread) = seventeen_joint_layout(&some(h36m_standing())).unwrap();
        assert_eq!(h36m, Layout::H36m17, "{spread}");
        // Too few joints: no answer.
        let mut few = some(COCO_STANDING);
        few[..3].fill(None);
        assert_eq!(seventeen_joint_layout(&few), None);
        assert_eq!(seventeen_joint_layout(&[Some([0.0, 0.0]); 17]), None);
    }
}
