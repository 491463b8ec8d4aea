//! The camera's intrinsics options of `localize` and `reconstruct` (`--focal-px`,
//! `--principal-point`).

use camloc::keypoints::ImageSize;
use camloc::reconstruct::{Intrinsics, MIN_FOCAL_PX};

/// The camera's focal length and principal point, when the user knows them.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct IntrinsicsArgs {
    /// The camera's focal length in pixels (the keypoints must be in pixels too).
    ///
    /// Each pose is localized as the camera turned to aim at the person would see it (a person near
    /// the edge of a wide-angle image is otherwise drawn out by the perspective); `reconstruct`
    /// also ends with a full-perspective refinement with it (close cameras, wide lenses). Without
    /// it `reconstruct` estimates the camera's distance (and so a focal length).
    #[arg(long, value_name = "F", value_parser = parse_focal, allow_hyphen_values = true)]
    pub focal_px: Option<f64>,
    /// With --focal-px: the principal point in pixels [default: the centre of --image-size
    /// if given, else of the bounding box of each pose's given landmarks, which leaves the
    /// localization as it is].
    #[arg(long, value_name = "U,V", requires = "focal_px", value_parser = parse_point,
          allow_hyphen_values = true)]
    pub principal_point: Option<[f64; 2]>,
}

impl IntrinsicsArgs {
    /// The intrinsics given, the principal point defaulting to the centre of `image_size`;
    /// `None` without `--focal-px`.
    pub fn intrinsics(&self, image_size: Option<ImageSize>) -> Option<Intrinsics> {
        let centre = image_size.map(|size| [0.5 * size.width, 0.5 * size.height]);
        self.focal_px.map(|focal_px| Intrinsics {
            focal_px,
            principal_point: self.principal_point.or(centre),
        })
    }
}

/// Parses `--focal-px`: a finite number of at least [`MIN_FOCAL_PX`] pixels.
fn parse_focal(text: &str) -> Result<f64, String> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|f| f.is_finite() && *f >= MIN_FOCAL_PX)
        .ok_or_else(|| format!("not a finite number of pixels >= {MIN_FOCAL_PX}: {text:?}"))
}

/// Parses `--principal-point`: `U,V`, two finite numbers.
fn parse_point(text: &str) -> Result<[f64; 2], String> {
    let numbers: Vec<f64> = text
        .split(',')
        .filter_map(|t| t.trim().parse::<f64>().ok())
        .filter(|v| v.is_finite())
        .collect();
    match (numbers.as_slice(), text.split(',').count()) {
        (&[u, v], 2) => Ok([u, v]),
        _ => Err(format!(
            "not U,V with two finite numbers of pixels: {text:?}"
        )),
    }
}
