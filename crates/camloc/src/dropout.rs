//! The landmark-dropout augmentation of training: which samples get a copy with landmarks
//! dropped, and which landmarks ([`DropoutPlan`], drawn from the seed), and the descriptor
//! rows of those copies, made straight into the training rows.

use camloc_features::Descriptor;
use camloc_skeleton::{Landmark, NUM_LANDMARKS, PartialPose2, mirror_landmark_index};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::rows::impute_rows;
use crate::{CamlocError, LandmarkDropout};

/// The copies of a landmark dropout: per copy, the sample it copies and the landmarks it
/// loses.
pub(crate) struct DropoutPlan {
    /// The index of each copy's sample among the originals.
    chosen: Vec<usize>,
    /// Each copy's dropped landmarks, bit `i` for landmark index `i`.
    dropped: Vec<u16>,
}

impl DropoutPlan {
    /// Draws the copies of `originals` samples from `dropout`'s seed: `floor(copies)` copies
    /// of every sample, then one more of each with probability the fractional part; each copy
    /// loses 1 to `max_missing` landmarks other than the pelvis and neck, drawn without
    /// replacement.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for invalid settings ([`LandmarkDropout::validate`]).
    pub(crate) fn draw(dropout: &LandmarkDropout, originals: usize) -> Result<Self, CamlocError> {
        dropout.validate()?;
        let mut rng = ChaCha8Rng::seed_from_u64(dropout.seed);
        let whole = dropout.copies.floor() as usize;
        let mut chosen: Vec<usize> = (0..whole).flat_map(|_| 0..originals).collect();
        let part = (dropout.copies - whole as f64).clamp(0.0, 1.0);
        chosen.extend((0..originals).filter(|_| rng.random_bool(part)));
        let droppable: Vec<usize> = (0..NUM_LANDMARKS)
            .filter(|&i| i != Landmark::Pelvis.index() && i != Landmark::Neck.index())
            .collect();
        let mut candidates = Vec::with_capacity(droppable.len());
        let dropped = chosen
            .iter()
            .map(|_| {
                candidates.clone_from(&droppable);
                (0..rng.random_range(1..=dropout.max_missing)).fold(0u16, |mask, _| {
                    let landmark = candidates.swap_remove(rng.random_range(0..candidates.len()));
                    mask | 1 << landmark
                })
            })
            .collect();
        Ok(Self { chosen, dropped })
    }

    /// The number of copies of each image (see [`add_rows`](Self::add_rows)).
    pub(crate) fn len(&self) -> usize {
        self.chosen.len()
    }

    /// Appends to `x` the imputed descriptor rows of the copies of `poses`, and gives their
    /// labels. `poses` (and `labels`) are `images` equal parts, part 2 (when 2) the mirror
    /// images of part 1 in its order; the copies are made of each part in turn, a copy in part
    /// 2 losing the mirror landmarks of its part-1 copy, so that the copies are mirror images
    /// of each other as the poses are. Reserve room in `x` for `images * len()` rows to
    /// append without moving it.
    ///
    /// # Errors
    /// [`CamlocError::Feature`] naming the copy (`sample i`, counting the copies) whose
    /// descriptor fails.
    pub(crate) fn add_rows(
        &self,
        descriptor: &Descriptor,
        poses: &[PartialPose2],
        labels: &[usize],
        imputation: &[f64],
        images: usize,
        x: &mut Vec<f64>,
    ) -> Result<Vec<usize>, CamlocError> {
        let d = descriptor.len();
        let (originals, copies) = (poses.len() / images, self.chosen.len());
        let start = x.len();
        x.resize(start + images * copies * d, 0.0);
        x[start..].par_chunks_mut(d).enumerate().try_for_each_init(
            || vec![false; d],
            |undefined, (r, row)| {
                let (image, c) = (r / copies, r % copies);
                let mut pose = poses[image * originals + self.chosen[c]];
                for landmark in (0..NUM_LANDMARKS).filter(|&l| self.dropped[c] & 1 << l != 0) {
                    let landmark = if image == 1 {
                        mirror_landmark_index(landmark)
                    } else {
                        landmark
                    };
                    pose.points[landmark] = None;
                }
                descriptor
                    .extract_partial_into(&pose, row, undefined)
                    .map_err(|source| CamlocError::Feature {
                        context: format!("sample {r}"),
                        source,
                    })?;
                impute_rows(row, undefined, imputation);
                Ok::<(), CamlocError>(())
            },
        )?;
        Ok((0..images)
            .flat_map(|image| {
                self.chosen
                    .iter()
                    .map(move |&i| labels[image * originals + i])
            })
            .collect())
    }
}
