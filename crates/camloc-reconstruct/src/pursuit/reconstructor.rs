//! [`Reconstructor`]: a basis, its options and the anthropometric constraint's quadratic form
//! in basis coordinates, precomputed.

use nalgebra::{DMatrix, DVector};

use super::config::{LengthTarget, ReconstructConfig};
use crate::basis::{LIMB_DIM, limb_vectors};
use crate::length_prior::LimbMatrix;
use crate::{BoneLengths, FrameRate, PoseBasis, ReconstructError};

/// Reconstructs 3D poses from 2D landmarks with a [`PoseBasis`].
#[derive(Clone, Debug)]
pub struct Reconstructor {
    pub(super) basis: PoseBasis,
    pub(super) config: ReconstructConfig,
    /// `K x K` Gram matrix of the components' limb vectors: the constraint's `Q`.
    pub(super) gram: DMatrix<f64>,
    /// Components' limb vectors dotted with the mean's: the constraint's `c`.
    pub(super) cross: DVector<f64>,
    /// Mean's sum of squared limb lengths minus the target: the constraint's `e`.
    pub(super) offset: f64,
    /// Per component, the trace of the 3 x 3 scatter `C_j = sum_i (b_ji - mean_i b_ji)(...)^T`
    /// of its 15 landmark vectors, and `C_j` itself (`xx, xy, xz, yy, yz, zz`): the squared
    /// norm of its centred projection by `s [I2 0] R` is `s^2 (tr C_j - r3^T C_j r3)`.
    pub(super) scatter: Vec<(f64, [f64; 6])>,
    /// The whitening matrix of the basis's length prior widened by the refinement's
    /// widening.
    pub(super) whitening: LimbMatrix,
}

impl Reconstructor {
    /// Prepares a reconstructor (precomputes the constraint's quadratic form in basis
    /// coordinates).
    ///
    /// # Errors
    /// [`ReconstructError::InvalidConfig`] for `max_basis = 0`, `max_alternations = 0`, a
    /// tolerance outside `[0, 1)` or a refinement setting out of range;
    /// [`ReconstructError::Numerical`] when the widened length prior has no inverse.
    pub fn new(
        basis: PoseBasis,
        config: ReconstructConfig,
    ) -> Result<Reconstructor, ReconstructError> {
        let invalid = |field, value: String, reason| ReconstructError::InvalidConfig {
            field,
            value,
            reason,
        };
        if config.max_basis == 0 {
            return Err(invalid(
                "ReconstructConfig::max_basis",
                "0".into(),
                "at least one basis pose is needed",
            ));
        }
        if config.max_alternations == 0 {
            return Err(invalid(
                "ReconstructConfig::max_alternations",
                "0".into(),
                "at least one alternation is needed",
            ));
        }
        if !(config.coefficient_prior >= 0.0 && config.coefficient_prior.is_finite()) {
            return Err(invalid(
                "ReconstructConfig::coefficient_prior",
                config.coefficient_prior.to_string(),
                "must be finite and >= 0",
            ));
        }
        for (field, value) in [
            (
                "ReconstructConfig::alternation_tolerance",
                config.alternation_tolerance,
            ),
            (
                "ReconstructConfig::min_relative_decrease",
                config.min_relative_decrease,
            ),
        ] {
            if !(0.0..1.0).contains(&value) {
                return Err(invalid(field, value.to_string(), "must lie in [0, 1)"));
            }
        }
        config.refinement.check()?;
        let whitening = basis
            .length_prior()
            .whitening(&config.refinement.widening)?;
        let k = basis.n_components();
        let mut limbs = DMatrix::zeros(LIMB_DIM, k);
        for j in 0..k {
            limbs.set_column(j, &limb_vectors(&basis.components().column(j).into_owned()));
        }
        let mean_limbs = limb_vectors(basis.mean_vector());
        let mean_sum = mean_limbs.norm_squared();
        let target = match config.length_target {
            LengthTarget::TrainingAverage => basis.anthropometric_target(),
            LengthTarget::Mean => mean_sum,
        };
        let scatter = (0..k)
            .map(|j| {
                let column = basis.components().column(j);
                let points: Vec<[f64; 3]> = column
                    .as_slice()
                    .chunks_exact(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect();
                let n = points.len() as f64;
                let mean: [f64; 3] =
                    std::array::from_fn(|a| points.iter().map(|p| p[a]).sum::<f64>() / n);
                let entry = |a: usize, b: usize| {
                    points
                        .iter()
                        .map(|p| (p[a] - mean[a]) * (p[b] - mean[b]))
                        .sum::<f64>()
                };
                let c = [
                    entry(0, 0),
                    entry(0, 1),
                    entry(0, 2),
                    entry(1, 1),
                    entry(1, 2),
                    entry(2, 2),
                ];
                (c[0] + c[3] + c[5], c)
            })
            .collect();
        Ok(Reconstructor {
            gram: limbs.transpose() * &limbs,
            cross: limbs.transpose() * mean_limbs,
            offset: mean_sum - target,
            scatter,
            whitening,
            basis,
            config,
        })
    }

    /// The basis.
    pub fn basis(&self) -> &PoseBasis {
        &self.basis
    }

    /// The configuration.
    pub fn config(&self) -> &ReconstructConfig {
        &self.config
    }

    /// The reconstructor with its sequences' frame rate set
    /// ([`Refinement::frame_rate`](crate::Refinement::frame_rate)).
    pub fn with_frame_rate(mut self, rate: FrameRate) -> Reconstructor {
        self.config.refinement.frame_rate = rate;
        self
    }

    /// The bone lengths a reconstruction has without given or estimated lengths: the length
    /// prior's template (the geometric mean of the training skeletons, metres).
    ///
    /// # Errors
    /// As [`LengthPrior::template`](crate::LengthPrior::template).
    pub fn template_lengths(&self) -> Result<BoneLengths, ReconstructError> {
        self.basis.length_prior().template()
    }

    /// The sum of squared limb lengths every pursuit pose has, m^2 (the refinement then
    /// gives the pose its own lengths).
    pub fn length_target(&self) -> f64 {
        limb_vectors(self.basis.mean_vector()).norm_squared() - self.offset
    }
}
