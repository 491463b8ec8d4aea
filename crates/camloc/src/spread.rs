//! How spread out a set of 2D points is ([`centroid_and_spread`]): the size a pose is
//! measured in by the view weights and the landmark smoothing.

/// The centroid of `points` and the root mean square distance of the points from it (the
/// points' units); `None` with fewer than two points, or when they coincide or are not
/// finite.
pub(crate) fn centroid_and_spread(points: &[[f64; 2]]) -> Option<([f64; 2], f64)> {
    let n = points.len() as f64;
    let centre = points
        .iter()
        .fold([0.0, 0.0], |s, p| [s[0] + p[0] / n, s[1] + p[1] / n]);
    let spread = (points
        .iter()
        .map(|p| (p[0] - centre[0]).powi(2) + (p[1] - centre[1]).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
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
