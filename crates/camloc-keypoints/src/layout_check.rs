//! Telling the two 17-joint layouts apart by what their first five joints are: COCO-17's are
//! the face (nose, eyes, ears), a cluster the size of a head; Human3.6M's are the pelvis, the
//! right leg and the left hip, spread over half the body. Declaring one for the other gives a
//! pose that is no body (the nose read as the pelvis, the eyes as hips) and a confident wrong
//! camera, so the readers refuse a pose whose first five joints clearly contradict its layout.
//! A detector's misplaced face point must not make a COCO-17 pose look like Human3.6M's, so
//! the test of a COCO-17 pose leaves out the face point that spreads the face most. And
//! [`layout_applies`]: a layout given for a format that fixes its own.

use crate::error::KeypointError;
use crate::layout::Layout;
use crate::{KeypointFormat, ReadOptions};

/// A pose declared COCO-17 is refused when its face points, the one that spreads them most
/// left out, spread over more than this share of the other twelve joints' spread (root mean
/// square distances from their centroids). On tripod views of CMU walks and of seated people
/// (COCO-17 and Human3.6M landmarks of the same poses, 2 px noise): COCO-17 0.04-0.22, and
/// with one face point moved by 80-400 px at most 0.33; the same poses' Human3.6M first five
/// joints, read so, were above it in 95% of the poses (all but people sitting on the ground,
/// whose folded legs gather the pelvis, hips and knee).
pub const COCO_FACE_SPREAD_MAX: f64 = 0.35;

/// A pose declared Human3.6M-17 is refused when its first five joints, all present, spread
/// over less than this share of the other twelve joints' spread. On the same views Human3.6M
/// 0.45-1.37 and the COCO-17 faces read so 0.10-0.30; on a simulated user's lab (28,388
/// ground-truth Human3.6M views of CMU people walking, sitting down, squatting and bending,
/// four tripods) Human3.6M from 0.237 (deep squats and low sits seen from the side or the
/// front: 18 under 0.3, refused at 0.3), and on another's tripod clips of people sitting,
/// kneeling, squatting and picking up (5,363 COCO-17 views, 2 px noise) the faces read so
/// 0.07-0.28: 97.0% of them below 0.22, 100% below 0.3. A COCO-17 file declared Human3.6M
/// still has nearly every pose refused; a correct pose is not.
pub const H36M_HIPS_SPREAD_MIN: f64 = 0.22;

/// At least this many of the first five joints, and of the other twelve, must be present for
/// [`contradicted`] to tell.
const MIN_PRESENT: usize = 4;

/// Joints scored below this are left out of [`contradicted`]'s test (not out of the pose):
/// detectors place the joints they barely see (an occluded ear) anywhere.
pub const LAYOUT_CHECK_MIN_SCORE: f64 = 0.3;

/// The layout the joints `points` of a pose declared `layout` look like and the spread that
/// tells, when that is the other 17-joint layout: a COCO-17 pose whose face points without
/// the one that spreads them most spread over more than [`COCO_FACE_SPREAD_MAX`] of the other
/// joints', a Human3.6M pose whose first five joints, all present, spread over less than
/// [`H36M_HIPS_SPREAD_MIN`] of them; `None` otherwise, for other layouts, and when too few
/// joints are present or the other joints coincide. With `scores` (one per joint), joints
/// scored below [`LAYOUT_CHECK_MIN_SCORE`] are left out.
pub fn contradicted(
    layout: Layout,
    points: &[Option<[f64; 2]>],
    scores: Option<&[f64]>,
) -> Option<(Layout, f64)> {
    if points.len() != 17 || !matches!(layout, Layout::Coco17 | Layout::H36m17) {
        return None;
    }
    // The sure joints of `range`, on the stack (this runs for every 17-joint pose read).
    let sure = |range: std::ops::Range<usize>| {
        let mut kept = [[0.0; 2]; 12];
        let mut n = 0;
        for j in range {
            let scored =
                scores.is_none_or(|s| s.get(j).is_some_and(|&c| c >= LAYOUT_CHECK_MIN_SCORE));
            if let (true, Some(p)) = (scored, points[j]) {
                kept[n] = p;
                n += 1;
            }
        }
        (kept, n)
    };
    let ((first, n_first), (rest, n_rest)) = (sure(0..5), sure(5..17));
    let (first, rest) = (&first[..n_first], &rest[..n_rest]);
    if first.len() < MIN_PRESENT || rest.len() < MIN_PRESENT {
        return None;
    }
    let size = rms_radius(rest);
    if !(size.is_finite() && size > 0.0) {
        return None;
    }
    if layout == Layout::Coco17 {
        let face = (0..first.len())
            .map(|left_out| {
                let mut others = [[0.0; 2]; 4];
                for (slot, i) in others
                    .iter_mut()
                    .zip((0..first.len()).filter(|&i| i != left_out))
                {
                    *slot = first[i];
                }
                rms_radius(&others[..first.len() - 1])
            })
            .fold(f64::INFINITY, f64::min);
        let spread = face / size;
        (spread > COCO_FACE_SPREAD_MAX).then_some((Layout::H36m17, spread))
    } else if first.len() == 5 {
        let spread = rms_radius(first) / size;
        (spread < H36M_HIPS_SPREAD_MIN).then_some((Layout::Coco17, spread))
    } else {
        // Without one of them (an ankle or knee a desk hides), a seated person's pelvis, hips
        // and knee gather as a face does: 70 of 2,200 tripod views of people sitting and
        // walking (66 of 644 seated) fell under the bound with the right ankle left out.
        None
    }
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
    let (measured, side, limit) = if layout == Layout::Coco17 {
        (
            "face points, leaving out the most spread one,",
            "over",
            COCO_FACE_SPREAD_MAX,
        )
    } else {
        ("first five joints", "under", H36M_HIPS_SPREAD_MIN)
    };
    format!(
        "the {measured} spread over {spread:.3} of the other joints' size ({side} {limit}), as \
         {likely}'s {} do, not {layout}'s {}: the layout is likely {likely}, not {layout} (if \
         the layout is right, joints 0-4 of this pose are misplaced: --min-score, Python min_score=, drops weak ones)",
        first_five(likely),
        first_five(layout),
    )
}

/// The root mean square distance of `points` from their centroid, computed on the distances
/// over the largest one so that coordinates near the ends of f64's range (1e154 squared
/// overflows, 1e-300 squared underflows) give the same spreads as any other scale.
fn rms_radius(points: &[[f64; 2]]) -> f64 {
    let n = points.len() as f64;
    let mean = points
        .iter()
        .fold([0.0, 0.0], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    let offsets = points.iter().map(|p| [p[0] - mean[0], p[1] - mean[1]]);
    let largest = offsets
        .clone()
        .map(|[x, y]| x.abs().max(y.abs()))
        .fold(0.0, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return largest;
    }
    let squares: f64 = offsets
        .map(|[x, y]| (x / largest).powi(2) + (y / largest).powi(2))
        .sum();
    largest * (squares / n).sqrt()
}

/// [`KeypointError::LayoutNotUsed`] when [`ReadOptions::layout`] is given for a `format` that does
/// not take one (only `.npy` arrays and MMPose keypoints do) and is not the format's own layout
/// (COCO's and YOLO's `coco17`, LSP's `lsp14`, MPII's `mpii16`, camloc's `camloc15`, OpenPose's
/// `body25`, MediaPipe's `mediapipe33`).
pub(crate) fn layout_applies(
    format: KeypointFormat,
    options: &ReadOptions,
    file: &str,
) -> Result<(), KeypointError> {
    let Some(layout) = options.layout else {
        return Ok(());
    };
    let own = match format {
        KeypointFormat::Npy | KeypointFormat::MmPose => return Ok(()),
        KeypointFormat::Coco => Some(Layout::Coco17),
        KeypointFormat::Lsp => Some(Layout::Lsp14),
        KeypointFormat::Mpii => Some(Layout::Mpii16),
        KeypointFormat::Camloc => Some(Layout::Camloc15),
        KeypointFormat::OpenPose => Some(Layout::Body25),
        KeypointFormat::Yolo => Some(Layout::Coco17),
        KeypointFormat::MediaPipe => Some(Layout::Mediapipe33),
    };
    if own == Some(layout) {
        return Ok(());
    }
    Err(KeypointError::LayoutNotUsed {
        file: file.to_owned(),
        format: format.name(),
        layout: layout.name(),
    })
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
        let coco = COCO_STANDING.map(Some);
        let h36m = h36m_standing().map(Some);
        assert_eq!(contradicted(Layout::Coco17, &coco, None), None);
        assert_eq!(contradicted(Layout::H36m17, &h36m, None), None);
        let (likely, _) = contradicted(Layout::Coco17, &h36m, None).unwrap();
        assert_eq!(likely, Layout::H36m17);
        let (likely, _) = contradicted(Layout::H36m17, &coco, None).unwrap();
        assert_eq!(likely, Layout::Coco17);
        // One face point misplaced by a body's height is still a face.
        let mut misplaced = coco;
        misplaced[3] = Some([300.0, 200.0]);
        assert_eq!(contradicted(Layout::Coco17, &misplaced, None), None);
        // Two are not, unless the detector scored them low.
        misplaced[4] = Some([-100.0, 200.0]);
        assert!(contradicted(Layout::Coco17, &misplaced, None).is_some());
        let mut scores = [0.9; 17];
        scores[3] = 0.1;
        assert_eq!(
            contradicted(Layout::Coco17, &misplaced, Some(&scores)),
            None
        );
        // A seated person seen from the front, the right ankle hidden: the pelvis, hips and
        // the knee in front of the hip gather as a face does, but are not told.
        let mut seated = h36m;
        seated[2] = Some([87.0, 140.0]);
        seated[3] = None;
        assert_eq!(contradicted(Layout::H36m17, &seated, None), None);
        seated[3] = Some([87.0, 142.0]);
        assert!(contradicted(Layout::H36m17, &seated, None).is_some());
        // A deep squat's right leg folded under the hip (first five spread 0.29): a body, not
        // a face (refused under the bound of 0.3 it replaced).
        let mut squat = h36m;
        squat[2] = Some([87.0, 150.0]);
        squat[3] = Some([87.0, 170.0]);
        assert_eq!(contradicted(Layout::H36m17, &squat, None), None);
        // Any scale tells alike, up to the ends of f64's range.
        for scale in [1e-300, 1e154, 1e300] {
            let scaled = COCO_STANDING.map(|[x, y]| Some([x * scale, y * scale]));
            let (likely, _) = contradicted(Layout::H36m17, &scaled, None).unwrap();
            assert_eq!(likely, Layout::Coco17, "{scale}");
        }
        // Too few joints: no answer; other layouts are not checked.
        let mut few = h36m;
        few[..2].fill(None);
        assert_eq!(contradicted(Layout::Coco17, &few, None), None);
        assert_eq!(contradicted(Layout::Mpii16, &coco[..16], None), None);
    }
}
