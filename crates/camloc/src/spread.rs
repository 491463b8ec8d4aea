//! How spread out a set of 2D points is ([`centroid_and_spread`]): the size a pose is
//! measured in by the view weights and the landmark smoothing.

use camloc_skeleton::{centroid, rms_radius_about};

/// The centroid of `points` and the root mean square distance of the points from it (the
/// points' units); `None` with fewer than two points, or when they coincide or are not
/// finite.
pub(crate) fn centroid_and_spread(points: &[[f64; 2]]) -> Option<([f64; 2], f64)> {
    let centre = centroid(points);
    let spread = rms_radius_about(points, centre);
    (points.len() >= 2 && spread.is_finite() && spread > 0.0).then_some((centre, spread))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_spreads_by_its_half_diagonal() {
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        let (centre, spread) = centroid_and_spread(&square).unwrap();
        assert_eq!(centre, [1.0, 1.0]);
        assert!((spread - 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(centroid_and_spread(&[[1.0, 1.0], [1.0, 1.0]]), None);
        assert_eq!(centroid_and_spread(&[[1.0, 1.0]]), None);
        assert_eq!(centroid_and_spread(&[[f64::NAN, 1.0], [1.0, 1.0]]), None);
    }
}
