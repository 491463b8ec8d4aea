//! The warning that `--image-size` is the wrong way round for pixel keypoints whose principal
//! point it sets ([`OutsideImage`]): a portrait video's size given landscape (1920,1080 for
//! 1080,1920) puts the principal point, the image's centre, off the true one, which no other
//! check sees (a simulated user's squats: PA-MPJPE 28 -> 40 mm, without a word).

use camloc::PartialPose2;
use camloc::keypoints::ImageSize;
use camloc::reconstruct::Intrinsics;

/// How far beyond an image side, as a share of it, a landmark counts as outside the image
/// (detectors clip to the image or reach a little past it).
pub const OUTSIDE_MARGIN: f64 = 0.05;

/// The share of the poses with a landmark outside the image from which [`OutsideImage`]
/// warns (with the input's landmarks all inside the image turned the other way): a portrait
/// video's person given a landscape size reaches past it in most frames, one who leaves a
/// frame of the right size now and then in few (a simulated reviewer's feet below the frame in
/// 10% of the frames had been warned of at 5%).
pub const OUTSIDE_SHARE: f64 = 0.5;

/// Counts the poses with a landmark outside the image of `--image-size` (by more than
/// [`OUTSIDE_MARGIN`] of its side), and the landmarks' extent, for [`OutsideImage::warning`].
#[derive(Debug, Default)]
pub struct OutsideImage {
    /// The image size, when it sets the principal point (nothing is counted otherwise).
    size: Option<ImageSize>,
    /// Poses with a landmark.
    poses: u64,
    /// Of those, the poses with a landmark outside the image.
    outside: u64,
    /// The smallest and largest `u` and `v` of the landmarks, pixels: `[[u_min, u_max],
    /// [v_min, v_max]]`.
    extent: [[f64; 2]; 2],
}

impl OutsideImage {
    /// A count for keypoints read with the image size `size` and the camera's intrinsics
    /// `aim`: counted when the principal point is that image's centre (`--focal-px` without
    /// `--principal-point`, or with the centre), the only use of the size for keypoints in
    /// pixels; otherwise nothing is (the size then changes nothing, or scales normalised
    /// coordinates into the image, which `ImageSizeCheck` checks).
    pub fn new(size: Option<ImageSize>, aim: Option<Intrinsics>) -> OutsideImage {
        let centre = |s: &ImageSize| Some([0.5 * s.width, 0.5 * s.height]);
        OutsideImage {
            size: size.filter(|s| aim.and_then(|i| i.principal_point) == centre(s)),
            extent: [[f64::INFINITY, f64::NEG_INFINITY]; 2],
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
                    self.extent[k] = [
                        self.extent[k][0].min(point[k]),
                        self.extent[k][1].max(point[k]),
                    ];
                    outside |= !within(point[k], sides[k]);
                }
            }
        }
        self.poses += u64::from(any);
        self.outside += u64::from(outside);
    }

    /// The warning when [`OUTSIDE_SHARE`] or more of the poses have a landmark outside the
    /// image and every landmark lies within the image turned the other way (a portrait
    /// video's size given landscape, or the reverse); `None` otherwise (people partly out of
    /// a frame of the right size do not fit the other way round either).
    pub fn warning(&self) -> Option<String> {
        let size = self.size?;
        let [u, v] = self.extent;
        let fits_turned = within(u[0], size.height)
            && within(u[1], size.height)
            && within(v[0], size.width)
            && within(v[1], size.width);
        let many = self.outside > 0 && self.outside as f64 >= OUTSIDE_SHARE * self.poses as f64;
        (many && fits_turned).then(|| {
            format!(
                "{} of {} poses reach past the {}x{} image of --image-size (the landmarks span u \
                 = {} to {}, v = {} to {}), and all fit a {}x{} one: is the size width first (a \
                 portrait video is 1080,1920)? The principal point is taken at its centre",
                self.outside,
                self.poses,
                size.width,
                size.height,
                pixels(u[0]),
                pixels(u[1]),
                pixels(v[0]),
                pixels(v[1]),
                size.height,
                size.width
            )
        })
    }
}

/// Whether `x` (pixels) lies on a side `side` pixels long, within [`OUTSIDE_MARGIN`] of it.
fn within(x: f64, side: f64) -> bool {
    let margin = OUTSIDE_MARGIN * side;
    (-margin..=side + margin).contains(&x)
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

    fn size(width: f64, height: f64) -> Option<ImageSize> {
        Some(ImageSize { width, height })
    }

    /// `--focal-px 1000` with the principal point at the centre of `size`.
    fn centred(size: Option<ImageSize>) -> Option<Intrinsics> {
        size.map(|s| Intrinsics {
            focal_px: 1000.0,
            principal_point: Some([0.5 * s.width, 0.5 * s.height]),
        })
    }

    fn counted(size: Option<ImageSize>, poses: &[PartialPose2]) -> OutsideImage {
        let mut count = OutsideImage::new(size, centred(size));
        for p in poses {
            count.add(p);
        }
        count
    }

    #[test]
    fn a_portrait_video_given_landscape_is_warned_of_and_the_right_size_is_not() {
        // A person 1700 px tall in a 1080 x 1920 frame.
        let person = pose(&[[540.0, 150.0], [560.0, 1000.0], [520.0, 1850.0]]);
        let said = counted(size(1920.0, 1080.0), &[person; 10])
            .warning()
            .expect("no warning");
        assert!(said.starts_with("10 of 10 poses"), "{said}");
        assert!(said.contains("u = 520 to 560, v = 150 to 1850"), "{said}");
        assert!(said.contains("all fit a 1080x1920 one"), "{said}");
        assert_eq!(counted(size(1080.0, 1920.0), &[person; 10]).warning(), None);
        // Without a size, or with the principal point given elsewhere, nothing is counted.
        assert_eq!(counted(None, &[person]).warning(), None);
        let mut elsewhere = OutsideImage::new(
            size(1920.0, 1080.0),
            Some(Intrinsics {
                focal_px: 1000.0,
                principal_point: Some([540.0, 960.0]),
            }),
        );
        elsewhere.add(&person);
        assert_eq!(elsewhere.warning(), None);
        assert_eq!(
            OutsideImage::new(size(1920.0, 1080.0), None).warning(),
            None
        );
    }

    #[test]
    fn people_partly_out_of_a_frame_of_the_right_size_are_not_said() {
        // Feet 80 px below a landscape frame in every pose, the people spread across it: they
        // do not fit the frame turned either.
        let poses: Vec<PartialPose2> = (0..10)
            .map(|i| {
                let u = 150.0 * f64::from(i) + 100.0;
                pose(&[[u, 300.0], [u, 1160.0]])
            })
            .collect();
        assert_eq!(counted(size(1920.0, 1080.0), &poses).warning(), None);
        // A person near the middle of the frame with the feet below it in 1 of 10 poses fits
        // the frame turned, but is under half: not said; in 5 of 10, said.
        let inside = pose(&[[900.0, 300.0], [1000.0, 1000.0]]);
        let feet_out = pose(&[[900.0, 300.0], [1000.0, 1160.0]]);
        let mut few = vec![feet_out];
        few.extend([inside; 9]);
        assert_eq!(counted(size(1920.0, 1080.0), &few).warning(), None);
        let half: Vec<PartialPose2> = (0..10)
            .map(|i| if i % 2 == 0 { feet_out } else { inside })
            .collect();
        assert!(counted(size(1920.0, 1080.0), &half).warning().is_some());
        assert_eq!(
            counted(size(1000.0, 1000.0), &[pose(&[[1040.0, -40.0]])]).warning(),
            None
        );
    }

    #[test]
    fn huge_coordinates_are_quoted_short() {
        assert_eq!(pixels(1e300), "1.000e300");
        assert_eq!(pixels(499.6), "500");
    }
}
