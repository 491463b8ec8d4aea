//! [`ImageAnkles`]: the ankles where each frame's camera sees them, averaged over nearby
//! frames, for the feet's stillness in the image (where a depth the scale got wrong does not
//! move a still foot): the planted feet's and the floor contact's.

use camloc_skeleton::{Landmark, NUM_LANDMARKS};

use super::centred::centred_means;

/// The ankles' image positions (each frame's reprojection) averaged over the frames within
/// `half` on each side where they are known, and the legs' median length in the
/// image (hip to knee to ankle, the left leg): where a depth the scale got wrong does not
/// move a still foot.
pub(super) struct ImageAnkles {
    /// Per frame, the averaged left and right ankle, image units.
    smooth: Vec<Option<[[f64; 2]; 2]>>,
    /// The legs' median length, image units (0 without images).
    legs: f64,
}

impl ImageAnkles {
    /// The averaged ankles of `images` (`n` frames; `None` where unknown).
    pub(super) fn of(
        images: &[Option<[[f64; 2]; NUM_LANDMARKS]>],
        n: usize,
        half: usize,
    ) -> ImageAnkles {
        let image = |t: usize| images.get(t).copied().flatten();
        let length = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
        let mut legs: Vec<f64> = (0..n)
            .filter_map(image)
            .map(|p| {
                let [hip, knee, ankle] =
                    [Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle]
                        .map(|l| p[l.index()]);
                length(hip, knee) + length(knee, ankle)
            })
            .filter(|l| l.is_finite())
            .collect();
        legs.sort_by(f64::total_cmp);
        let [left, right] = [Landmark::LeftAnkle, Landmark::RightAnkle].map(Landmark::index);
        let ankles: Vec<Option<[f64; 4]>> = (0..n)
            .map(|t| image(t).map(|p| [p[left][0], p[left][1], p[right][0], p[right][1]]))
            .collect();
        let smooth = centred_means(&ankles, half)
            .into_iter()
            .map(|a| a.map(|[lu, lv, ru, rv]| [[lu, lv], [ru, rv]]))
            .collect();
        ImageAnkles {
            smooth,
            legs: legs.get(legs.len() / 2).copied().unwrap_or(0.0),
        }
    }

    /// How far `foot`'s averaged image place at frame `b` is from frame `a`'s, in legs'
    /// lengths; `None` where either is unknown.
    pub(super) fn apart(&self, a: usize, b: usize, foot: usize) -> Option<f64> {
        let (p, q) = (self.smooth.get(a).copied()??, self.smooth.get(b).copied()??);
        let d = (p[foot][0] - q[foot][0]).hypot(p[foot][1] - q[foot][1]) / self.legs;
        d.is_finite().then_some(d)
    }
}
