//! Landmarks far off the body ([`without_far_off_landmarks`]): a detection misplaced by most
//! of the image (a wrist on another person, on the background) is no view of this body, and
//! fitted as one it turned the whole pose (a simulated reviewer's wrist 1,000 px off a 190 px
//! person: the other joints moved 0.9 m, the focal length estimated at 1.6e5 px). Such a
//! landmark is read as missing, and filled in as missing landmarks are.

use camloc_skeleton::{LIMBS, Landmark, NUM_LIMBS, PartialPose2};

/// A landmark is far off when every limb it ends (of those present) is longer in the image,
/// over its typical length, than this many times the median of that ratio over the present
/// limbs. Projection only shortens a limb, so the ratio of a limb is at most the person's
/// scale: on a simulated user's 28,388 lab views with a detector's 15-45 px outliers it
/// reached 5.0 times the median, on LSP's 373 annotated photos 3.7, on CMU poses seen from
/// straight above (the torso and legs foreshortened to nothing, the arms spread) 5.7.
pub const FAR_OFF_RATIO: f64 = 8.0;

/// The fewest limbs present for the test: fewer tell no scale.
const MIN_LIMBS: usize = 6;

/// Typical limb lengths, metres, in [`LIMBS`] order (the medians of the lengths camloc
/// estimated on LSP's 400 photos): only their proportions matter.
const TYPICAL_LIMB_M: [f64; NUM_LIMBS] = [
    0.13, 0.41, 0.42, 0.13, 0.41, 0.42, 0.45, 0.22, 0.20, 0.30, 0.22, 0.20, 0.30, 0.22,
];

/// `1 / TYPICAL_LIMB_M[k]^2`, per limb.
const INVERSE_SQUARED_LIMB: [f64; NUM_LIMBS] = {
    let mut inverse = [0.0; NUM_LIMBS];
    let mut k = 0;
    while k < NUM_LIMBS {
        inverse[k] = 1.0 / (TYPICAL_LIMB_M[k] * TYPICAL_LIMB_M[k]);
        k += 1;
    }
    inverse
};

/// `pose` with its landmarks far off the others ([`FAR_OFF_RATIO`]) removed, and those
/// landmarks in landmark order (none for a pose with fewer than 6 limbs present).
pub fn without_far_off_landmarks(pose: &PartialPose2) -> (PartialPose2, Vec<Landmark>) {
    // Squared ratios (the order is the same, and no square root is taken: this runs for
    // every pose localized), on the stack.
    let mut ratios = [None; NUM_LIMBS];
    let mut present = [0.0; NUM_LIMBS];
    let mut count = 0;
    for (k, &(a, b)) in LIMBS.iter().enumerate() {
        if let (Some(p), Some(q)) = (pose.points[a.index()], pose.points[b.index()]) {
            let (du, dv) = (p[0] - q[0], p[1] - q[1]);
            let squared = (du * du + dv * dv) * INVERSE_SQUARED_LIMB[k];
            // (A square that overflows is a limb longer than any: kept, as infinity.)
            if !squared.is_nan() {
                ratios[k] = Some(squared);
                present[count] = squared;
                count += 1;
            }
        }
    }
    if count < MIN_LIMBS {
        return (*pose, Vec::new());
    }
    let (_, median, _) = present[..count].select_nth_unstable_by(count / 2, f64::total_cmp);
    let bound = FAR_OFF_RATIO * FAR_OFF_RATIO * *median;
    let longest = present[..count].iter().copied().fold(0.0, f64::max);
    if !(bound > 0.0) || longest <= bound {
        return (*pose, Vec::new());
    }
    // The present limbs each landmark ends, and whether all of them are long.
    let ends = |landmark: Landmark| {
        LIMBS
            .iter()
            .zip(&ratios)
            .filter(move |((a, b), _)| *a == landmark || *b == landmark)
            .filter_map(move |((a, b), r)| Some((if *a == landmark { *b } else { *a }, (*r)?)))
    };
    let all_long = |landmark: Landmark| {
        let mut limbs = ends(landmark).peekable();
        limbs.peek().is_some() && limbs.all(|(_, r)| r > bound)
    };
    // A landmark whose one limb is long because the landmark at its other end is off (a
    // wrist beyond an elbow off) stays.
    let far: Vec<Landmark> = Landmark::ALL
        .into_iter()
        .filter(|&landmark| all_long(landmark))
        .filter(|&landmark| {
            let limbs: Vec<(Landmark, f64)> = ends(landmark).collect();
            !(limbs.len() == 1 && all_long(limbs[0].0) && ends(limbs[0].0).count() > 1)
        })
        .collect();
    let mut cleaned = *pose;
    for landmark in &far {
        cleaned.points[landmark.index()] = None;
    }
    (cleaned, far)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A standing person facing the camera, about 180 px tall (image coordinates, v down).
    fn standing() -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        let points = [
            [100.0, 100.0], // pelvis
            [110.0, 100.0],
            [112.0, 140.0],
            [113.0, 180.0],
            [90.0, 100.0],
            [88.0, 140.0],
            [87.0, 180.0],
            [100.0, 55.0], // neck
            [100.0, 33.0],
            [118.0, 57.0],
            [124.0, 84.0],
            [127.0, 106.0],
            [82.0, 57.0],
            [76.0, 84.0],
            [73.0, 106.0],
        ];
        for (slot, p) in pose.points.iter_mut().zip(points) {
            *slot = Some(p);
        }
        pose
    }

    #[test]
    fn a_landmark_far_off_is_removed_and_a_body_kept() {
        let pose = standing();
        assert_eq!(without_far_off_landmarks(&pose), (pose, Vec::new()));
        let mut glitch = pose;
        glitch.points[Landmark::RightWrist.index()] = Some([900.0, 700.0]);
        let (cleaned, far) = without_far_off_landmarks(&glitch);
        assert_eq!(far, vec![Landmark::RightWrist]);
        assert_eq!(cleaned.points[Landmark::RightWrist.index()], None);
        // An elbow off makes both its limbs long; the wrist beyond it, whose one limb is long
        // because of the elbow, stays.
        let mut elbow = pose;
        elbow.points[Landmark::LeftElbow.index()] = Some([-800.0, 84.0]);
        assert_eq!(
            without_far_off_landmarks(&elbow).1,
            vec![Landmark::LeftElbow]
        );
        // Arms spread seen from above, the rest foreshortened: kept.
        let mut above = pose;
        for (l, p) in [
            (Landmark::LeftKnee, [111.0, 104.0]),
            (Landmark::LeftAnkle, [112.0, 108.0]),
            (Landmark::RightKnee, [89.0, 104.0]),
            (Landmark::RightAnkle, [88.0, 108.0]),
            (Landmark::Neck, [100.0, 88.0]),
            (Landmark::Head, [100.0, 84.0]),
            (Landmark::LeftShoulder, [118.0, 88.0]),
            (Landmark::LeftElbow, [148.0, 88.0]),
            (Landmark::LeftWrist, [173.0, 88.0]),
            (Landmark::RightShoulder, [82.0, 88.0]),
            (Landmark::RightElbow, [52.0, 88.0]),
            (Landmark::RightWrist, [27.0, 88.0]),
        ] {
            above.points[l.index()] = Some(p);
        }
        assert_eq!(without_far_off_landmarks(&above).1, Vec::new());
    }
}
