//! How spread out a set of 2D points is: their centroid and their root-mean-square distance
//! from it, the size a pose is measured in (the pursuit's normalisation, the view weights,
//! the landmark smoothing).

/// The mean of `points` (their units); NaN for no points.
pub fn centroid(points: &[[f64; 2]]) -> [f64; 2] {
    let n = points.len() as f64;
    points
        .iter()
        .fold([0.0; 2], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n])
}

/// The root-mean-square distance of `points` from `centre` (their units); NaN for no points.
pub fn rms_radius_about(points: &[[f64; 2]], centre: [f64; 2]) -> f64 {
    let n = points.len() as f64;
    let sum: f64 = points
        .iter()
        .map(|p| (p[0] - centre[0]).powi(2) + (p[1] - centre[1]).powi(2))
        .sum();
    (sum / n).sqrt()
}

/// The root-mean-square distance of `points` from their [`centroid`] (their units); NaN for
/// no points.
pub fn rms_radius(points: &[[f64; 2]]) -> f64 {
    rms_radius_about(points, centroid(points))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_spreads_by_its_half_diagonal() {
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert_eq!(centroid(&square), [1.0, 1.0]);
        assert!((rms_radius(&square) - 2f64.sqrt()).abs() < 1e-12);
        assert!((rms_radius_about(&square, [0.0, 0.0]) - 2.0).abs() < 1e-12);
        assert!(rms_radius(&[]).is_nan());
    }
}
