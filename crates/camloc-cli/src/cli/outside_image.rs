//! The warning that the keypoints do not fit the image of `--image-size` ([`OutsideImage`]):
//! pixel keypoints of a portrait video given its size landscape (1920,1080 for 1080,1920) put
//! the principal point, the image's centre, off the true one, which no other check sees (a
//! simulated user's squats: PA-MPJPE 28 -> 40 mm, without a word).

use camloc::PartialPose2;
use camloc::keypoints::ImageSize;

/// How far beyond an image side, as a share of it, a landmark counts as outside the image
/// (detectors clip to the image or reach a little past it).
pub const OUTSIDE_MARGIN: f64 = 0.05;

/// The share of the poses with a landmark outside the image from which [`OutsideImage`]
/// warns: a player running out of the frame is a few.
pub const OUTSIDE_SHARE: f64 = 0.05;

/// Counts the poses with a landmark outside the image of `--image-size` (by more than
/// [`OUTSIDE_MARGIN`] of its side), for [`OutsideImage::warning`].
#[derive(Debug, Default)]
pub struct OutsideImage {
    /// The image size given (nothing is counted without one).
    size: Option<ImageSize>,
    /// Poses with a landmark.
    poses: u64,
    /// Of those, the poses with a landmark outside the image.
    outside: u64,
    /// The largest `u` and `v` of the landmarks, pixels.
    reach: [f64; 2],
}

impl OutsideImage {
    /// A count for keypoints in the pixels of an image of `size` (none: nothing to check).
    pub fn new(size: Option<ImageSize>) -> OutsideImage {
        OutsideImage {
            size,
            ..OutsideImage::default()
        }
    }

    /// Counts `pose` (its present landmarks, in pixels).
    pub fn add(&mut self, pose: &PartialPose2) {
        let Some(size) = self.size else {
            return;
        };
        let sides = [size.width, size.height];
        let mut any = false;
        let mut outside = false;
        for point in pose.points.iter().flatten() {
            any = true;
            for k in 0..2 {
                if point[k].is_finite() {
                    self.reach[k] = self.reach[k].max(point[k]);
                    let margin = OUTSIDE_MARGIN * sides[k];
                    outside |= point[k] < -margin || point[k] > sides[k] + margin;
                }
            }
        }
        self.poses += u64::from(any);
        self.outside += u64::from(outside);
    }

    /// The warning when [`OUTSIDE_SHARE`] or more of the poses have a landmark outside the
    /// image, `None` otherwise.
    pub fn warning(&self) -> Option<String> {
        let size = self.size?;
        (self.outside > 0 && self.outside as f64 >= OUTSIDE_SHARE * self.poses as f64).then(|| {
            format!(
                "{} of {} poses have landmarks outside the {}x{} image of --image-size (they \
                 reach u = {}, v = {}): is the size width first (a portrait video is \
                 1080,1920) and the keypoints in its pixels? The principal point is taken at \
                 its centre",
                self.outside,
                self.poses,
                size.width,
                size.height,
                pixels(self.reach[0]),
                pixels(self.reach[1])
            )
        })
    }
}

/// `value` (pixels) as a message quotes it: whole pixels, or in scientific notation from a
/// million on (a coordinate of 1e300 would be 301 digits).
fn pixels(value: f64) -> String {
    if value.abs() < 1e6 {
        format!("{value:.0}")
    } else {
        format!("{value:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(points: &[[f64; 2]]) -> PartialPose2 {
        let mut pose = PartialPose2::empty();
        for (slot, p) in pose.points.iter_mut().zip(points) {
            *slot = Some(*p);
        }
        pose
    }

    #[test]
    fn a_portrait_video_given_landscape_is_warned_of_and_the_right_size_is_not() {
        // A person 1700 px tall in a 1080 x 1920 frame.
        let person = pose(&[[540.0, 150.0], [560.0, 1000.0], [520.0, 1850.0]]);
        let mut wrong = OutsideImage::new(Some(ImageSize {
            width: 1920.0,
            height: 1080.0,
        }));
        let mut right = OutsideImage::new(Some(ImageSize {
            width: 1080.0,
            height: 1920.0,
        }));
        for _ in 0..10 {
            wrong.add(&person);
            right.add(&person);
        }
        let said = wrong.warning().expect("no warning");
        assert!(said.starts_with("10 of 10 poses"), "{said}");
        assert!(said.contains("v = 1850"), "{said}");
        assert_eq!(right.warning(), None);
        // Without a size nothing is counted.
        let mut none = OutsideImage::new(None);
        none.add(&person);
        assert_eq!(none.warning(), None);
    }

    #[test]
    fn a_few_poses_past_the_edge_are_not_said() {
        let size = Some(ImageSize {
            width: 1000.0,
            height: 1000.0,
        });
        let inside = pose(&[[500.0, 100.0], [500.0, 900.0]]);
        let past = pose(&[[500.0, 100.0], [1100.0, 900.0]]);
        let mut count = OutsideImage::new(size);
        count.add(&past);
        for _ in 0..20 {
            count.add(&inside);
        }
        // 1 of 21 (under 5%): not said; a landmark 4% past the side is inside.
        assert_eq!(count.warning(), None);
        let mut near = OutsideImage::new(size);
        near.add(&pose(&[[1040.0, -40.0]]));
        assert_eq!(near.warning(), None);
        // A huge coordinate is quoted short.
        let mut huge = OutsideImage::new(size);
        huge.add(&pose(&[[1e300, 500.0]]));
        let said = huge.warning().unwrap();
        assert!(said.contains("u = 1.000e300, v = 500"), "{said}");
    }
}
