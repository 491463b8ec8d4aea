//! [`centred_means`]: each frame's value averaged over the frames around it, as many on each
//! side (the pelvis's coarse path, the feet's averaged places).

/// Per frame of `values` (`None`: a frame without one), the mean of the values present within
/// `half` frames of it, as many frames on each side (fewer near the ends, where there are
/// fewer on one side); `None` where the frame has no value.
pub(super) fn centred_means<const N: usize>(
    values: &[Option<[f64; N]>],
    half: usize,
) -> Vec<Option<[f64; N]>> {
    let n = values.len();
    (0..n)
        .map(|t| {
            values[t]?;
            let half = half.min(t).min(n - 1 - t);
            let near: Vec<[f64; N]> = values[t - half..=t + half]
                .iter()
                .flatten()
                .copied()
                .collect();
            let m = near.len() as f64;
            Some(std::array::from_fn(|k| {
                near.iter().map(|p| p[k]).sum::<f64>() / m
            }))
        })
        .collect()
}
