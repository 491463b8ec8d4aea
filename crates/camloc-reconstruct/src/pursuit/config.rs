//! The options of [`Reconstructor`](crate::Reconstructor): sparsity, alternation, priors.

use serde::{Deserialize, Serialize};

use crate::Refinement;

/// Which sum of squared limb lengths the reconstructed pose must have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LengthTarget {
    /// The basis's anthropometric target,
    /// [`PoseBasis::anthropometric_target`](crate::PoseBasis::anthropometric_target): the
    /// value every normalised training pose has.
    TrainingAverage,
    /// The value of the mean pose `mu` (as the pursuit's constraint is usually written; smaller
    /// than the training average, because averaging poses shortens limbs).
    Mean,
}

/// Options of [`Reconstructor`](crate::Reconstructor).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReconstructConfig {
    /// Maximum number of basis poses in a reconstruction (`k`, the sparsity); at least 1.
    pub max_basis: usize,
    /// The anthropometric constraint's right-hand side.
    pub length_target: LengthTarget,
    /// Maximum coefficient/camera alternations after each basis pose is added; at least 1.
    pub max_alternations: usize,
    /// The alternation stops when an alternation lowers the squared reprojection error by less
    /// than this fraction; in `[0, 1)`.
    pub alternation_tolerance: f64,
    /// A basis pose is kept only if it lowers the squared reprojection error by at least this
    /// fraction; in `[0, 1)`. The first basis pose is always kept (the mean pose alone need
    /// not satisfy the constraint).
    pub min_relative_decrease: f64,
    /// Also pursue the depth-reflected hypothesis (the pose mirrored in depth fits the 2D
    /// about as well): see [`Reconstructor::reconstruct_hypotheses`][hypotheses] for how one
    /// is chosen.
    ///
    /// [hypotheses]: crate::Reconstructor::reconstruct_hypotheses
    pub try_depth_reflection: bool,
    /// Prior on the coefficients: the pursuit minimises the squared reprojection error (in
    /// the normalised image units, the 2D input centred and scaled to unit RMS radius) plus
    /// `coefficient_prior * sum_j w_j^2 / var_j`, `var_j` the training poses' variance along
    /// basis pose `j` (a Gaussian prior on the coefficients, MAP instead of least squares);
    /// `>= 0`, 0 is the plain pursuit.
    pub coefficient_prior: f64,
    /// Prior: bring left and right limb lengths to their mean after the pursuit
    /// ([`symmetrise`](crate::symmetrise)), then refit the camera.
    pub symmetry: bool,
    /// Prior: turn limb bones outside the basis's learned joint-angle limits onto their border
    /// after the pursuit ([`JointLimits::project`](crate::JointLimits::project)), then refit
    /// the camera; prefer, between hypotheses that fit the 2D about equally, the one the
    /// limits like better; and flip limbs read the wrong way in depth into the limits
    /// ([`JointLimits::flip_depths`](crate::JointLimits::flip_depths)) in the lifted pose
    /// the refinement starts from and after the refinement (refined again from the flip,
    /// single poses and sequences alike).
    pub joint_limits: bool,
    /// The final skeleton refinement: the pose rebuilt with the person's own bone lengths
    /// (given, or estimated under the length prior) and fitted to the 2D again, in sequences
    /// with shared lengths, smoothness and depths chosen consistently over time (see
    /// [`Refinement`]).
    pub refinement: Refinement,
}

/// Default [`ReconstructConfig::coefficient_prior`], chosen by cross-validation grouped by
/// subject on the CMU data (`cargo xtask reconstruction`, docs/RESULTS.md).
pub const DEFAULT_COEFFICIENT_PRIOR: f64 = 0.01;

/// Two hypotheses fit the 2D "about equally" when their RMS reprojection errors are within
/// this fraction of each other; the joint-angle prior then chooses between them.
pub const EQUAL_FIT_TOLERANCE: f64 = 0.1;

impl Default for ReconstructConfig {
    /// `max_basis` 12 with the training-average length target, depth reflection on, both
    /// priors on and the default [`Refinement`] (measured by `cargo xtask reconstruction`,
    /// docs/RESULTS.md).
    /// Measured on held-out CMU subjects (`examples/compare_modes.rs`), `max_basis` from 8 to 16
    /// changes the mean MPJPE by less than 3 mm, and larger values overfit the 2D noise; the
    /// [`LengthTarget::Mean`] target is 6-16 mm worse there. The alternation and
    /// stopping tolerances are unit-free (the 2D input is normalised internally).
    fn default() -> Self {
        ReconstructConfig {
            max_basis: 12,
            length_target: LengthTarget::TrainingAverage,
            max_alternations: 10,
            alternation_tolerance: 1e-4,
            min_relative_decrease: 1e-3,
            try_depth_reflection: true,
            coefficient_prior: DEFAULT_COEFFICIENT_PRIOR,
            symmetry: true,
            joint_limits: true,
            refinement: Refinement::default(),
        }
    }
}
