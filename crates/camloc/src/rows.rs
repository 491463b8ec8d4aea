//! Descriptor rows of many poses: extracted in parallel, undefined values flagged and imputed.

use camloc_features::Descriptor;
use camloc_skeleton::PartialPose2;
use rayon::prelude::*;

use crate::CamlocError;

/// The (possibly partial) 2D pose of a dataset sample.
pub(crate) fn sample_pose(sample: &camloc_dataset::Sample) -> PartialPose2 {
    let mut pose = PartialPose2::from(sample.landmarks);
    for (i, p) in pose.points.iter_mut().enumerate() {
        if sample.missing_mask & (1 << i) != 0 {
            *p = None;
        }
    }
    pose
}

/// Descriptors of `poses` (row-major) and the flags of undefined values, in parallel. Errors
/// name the pose as `sample {first + i}` (`first`: the index of `poses[0]` in the caller's
/// collection).
pub(crate) fn extract_rows(
    descriptor: &Descriptor,
    poses: &[PartialPose2],
    first: usize,
) -> Result<(Vec<f64>, Vec<bool>), CamlocError> {
    let mut x = Vec::new();
    let undefined = extract_rows_into(descriptor, poses, first, &mut x)?;
    Ok((x, undefined))
}

/// [`extract_rows`], the rows appended to `x` (which moves only if it lacks the room); gives
/// the flags of the appended rows.
pub(crate) fn extract_rows_into(
    descriptor: &Descriptor,
    poses: &[PartialPose2],
    first: usize,
    x: &mut Vec<f64>,
) -> Result<Vec<bool>, CamlocError> {
    let d = descriptor.len();
    let start = x.len();
    x.resize(start + poses.len() * d, 0.0);
    let mut undefined = vec![false; poses.len() * d];
    x[start..]
        .par_chunks_mut(d)
        .zip(undefined.par_chunks_mut(d))
        .zip(poses.par_iter())
        .enumerate()
        .try_for_each(|(i, ((row, flags), pose))| {
            descriptor
                .extract_partial_into(pose, row, flags)
                .map_err(|source| CamlocError::Feature {
                    context: format!("sample {}", first + i),
                    source,
                })
        })?;
    Ok(undefined)
}

/// Column means over defined values (0 where a column is never defined).
pub(crate) fn column_means(x: &[f64], undefined: &[bool], d: usize) -> Vec<f64> {
    let mut sums = vec![0.0; d];
    let mut counts = vec![0usize; d];
    for (row, flags) in x.chunks_exact(d).zip(undefined.chunks_exact(d)) {
        for j in 0..d {
            if !flags[j] {
                sums[j] += row[j];
                counts[j] += 1;
            }
        }
    }
    sums.iter()
        .zip(&counts)
        .map(|(s, &n)| if n > 0 { s / n as f64 } else { 0.0 })
        .collect()
}

/// Replaces undefined values by the imputation values (rows of `imputation.len()`).
pub(crate) fn impute_rows(x: &mut [f64], undefined: &[bool], imputation: &[f64]) {
    let d = imputation.len().max(1);
    for (row, flags) in x.chunks_exact_mut(d).zip(undefined.chunks_exact(d)) {
        for ((v, &u), m) in row.iter_mut().zip(flags).zip(imputation) {
            if u {
                *v = *m;
            }
        }
    }
}
