//! [`centred_means`]: each frame's value averaged over the frames around it, as many on each
//! side (the pelvis's coarse path, the feet's averaged places); [`centred_lines`]: the
//! straight line through them, taken at the frame (the pelvis's smoothed place, the ankles'
//! steps), which a missing frame on one side does not pull.

/// Per frame of `values` (`None`: a frame without one), the values present within `half`
/// frames of it, as many frames on each side (fewer near the ends, where there are fewer on
/// one side), each with its frame's offset from it; `None` where the frame has no value.
fn windows<const N: usize>(
    values: &[Option<[f64; N]>],
    half: usize,
) -> impl Iterator<Item = Option<Vec<(f64, [f64; N])>>> + '_ {
    let n = values.len();
    (0..n).map(move |t| {
        values[t]?;
        let half = half.min(t).min(n - 1 - t);
        Some(
            (t - half..=t + half)
                .filter_map(|u| values[u].map(|q| (u as f64 - t as f64, q)))
                .collect(),
        )
    })
}

/// The mean of the values of `near` (as [`windows`] gives them), per coordinate.
fn mean<const N: usize>(near: &[(f64, [f64; N])]) -> [f64; N] {
    let m = near.len() as f64;
    std::array::from_fn(|k| near.iter().map(|(_, q)| q[k]).sum::<f64>() / m)
}

/// Per frame of `values` (`None`: a frame without one), the mean of the values present within
/// `half` frames of it, as many frames on each side (fewer near the ends, where there are
/// fewer on one side); `None` where the frame has no value.
pub(super) fn centred_means<const N: usize>(
    values: &[Option<[f64; N]>],
    half: usize,
) -> Vec<Option<[f64; N]>> {
    windows(values, half)
        .map(|near| near.map(|near| mean(&near)))
        .collect()
}

/// Per frame of `values` (`None`: a frame without one), the straight line (least squares, per
/// coordinate, against the frame number) through the values present within `half` frames of
/// it, as many frames on each side, taken at the frame: their mean where none is missing, and
/// where some are, the frames on one side do not draw it towards the other; `None` where the
/// frame has no value.
pub(super) fn centred_lines<const N: usize>(
    values: &[Option<[f64; N]>],
    half: usize,
) -> Vec<Option<[f64; N]>> {
    windows(values, half)
        .map(|near| {
            let near = near?;
            let m = near.len() as f64;
            let mean_dt = near.iter().map(|(dt, _)| dt).sum::<f64>() / m;
            let mean = mean(&near);
            let spread: f64 = near.iter().map(|(dt, _)| (dt - mean_dt).powi(2)).sum();
            if spread == 0.0 {
                return Some(mean);
            }
            Some(std::array::from_fn(|k| {
                let slope = near
                    .iter()
                    .map(|(dt, q)| (q[k] - mean[k]) * (dt - mean_dt))
                    .sum::<f64>()
                    / spread;
                mean[k] - slope * mean_dt
            }))
        })
        .collect()
}
