//! The pose basis: mean pose, principal components (and, for a dictionary, cluster-centre
//! atoms), anthropometric target, joint-angle limits, storage.

use camloc_skeleton::{LIMBS, NUM_LANDMARKS, NUM_LIMBS, Pose3};
use camloc_store::{FileKind, Persist, Validate};
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::length_prior::LengthPrior;
use crate::prior::JointLimits;
use crate::{ReconstructError, is_positive};

/// Length of a pose vector: 15 landmarks x 3 coordinates, landmark-major
/// (`[x0, y0, z0, x1, ...]`), metres.
pub const POSE_DIM: usize = 3 * NUM_LANDMARKS;

/// Length of a limb-vector stack: 14 limbs x 3 coordinates (child minus parent), metres.
pub(crate) const LIMB_DIM: usize = 3 * NUM_LIMBS;

/// What the basis poses are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum BasisKind {
    /// The leading principal components (orthonormal).
    Pca,
    /// An over-complete dictionary for the pursuit to choose from: the principal components
    /// followed by `atoms` cluster centres of the training poses (k-means, deterministic),
    /// each as its unit-norm deviation from the mean.
    Dictionary {
        /// Number of cluster centres (at least 1, at most the number of training poses).
        atoms: usize,
    },
}

/// Options of [`PoseBasis::fit`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BasisConfig {
    /// Number of principal components kept (at least 1, at most the number of directions with
    /// non-zero variance: 42 for 15 pelvis-centred landmarks, fewer with few training poses).
    pub n_components: usize,
    /// Principal components only, or a dictionary with cluster centres.
    pub kind: BasisKind,
    /// Representative directions per limb bone of the learned joint-angle limits
    /// ([`JointLimits::fit`]); at least 1.
    pub limit_directions: usize,
}

/// Dictionary atoms of [`BasisConfig::default`].
pub const DEFAULT_ATOMS: usize = 256;

impl Default for BasisConfig {
    /// 16 principal components (chosen by cross-validation grouped by subject on the CMU
    /// data, `cargo xtask reconstruction`) and a dictionary of 256 cluster centres beside
    /// them (lower error on held-out subjects than PCA alone, docs/RESULTS.md), 256
    /// directions per bone.
    fn default() -> Self {
        BasisConfig {
            n_components: 16,
            kind: BasisKind::Dictionary {
                atoms: DEFAULT_ATOMS,
            },
            limit_directions: 256,
        }
    }
}

/// Lloyd iterations of the dictionary's k-means.
const KMEANS_ITERATIONS: usize = 20;

/// A linear model of canonical 3D poses, `X = mu + B w` (eq. 5).
///
/// Frame: the canonical body frame of docs/conventions.md section 1 (pelvis at the origin, facing
/// -x, right side towards +y, z up), metres. Every training pose is translated so that its pelvis
/// is at the origin and scaled so that its sum of squared limb lengths equals the training average
/// (the *anthropometric target*); `mu` is their mean and the columns of `B` are the leading
/// principal components (orthonormal, unit-free directions in pose space), followed, for a
/// dictionary ([`BasisKind::Dictionary`]), by unit-norm cluster-centre deviations. The basis
/// also holds the joint-angle limits and the prior on limb lengths ([`LengthPrior`], from the
/// poses before their scaling) learned from the same poses.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "StoredBasis")]
pub struct PoseBasis {
    mean: DVector<f64>,
    components: DMatrix<f64>,
    variances: Vec<f64>,
    total_variance: f64,
    anthropometric_target: f64,
    n_training: usize,
    /// Number of leading columns of `components` that are orthonormal principal components.
    n_principal: usize,
    limits: JointLimits,
    lengths: LengthPrior,
}

impl PoseBasis {
    /// Fits the basis to `poses` (canonical frame, metres), and the joint-angle limits.
    ///
    /// Variances are population variances (divided by the number of poses), in m^2 (for a
    /// dictionary atom: of the poses' projections on it).
    /// Component signs are fixed so that each component's largest-magnitude entry is positive,
    /// which makes the basis a deterministic function of the training set (the k-means of a
    /// dictionary starts from the poses farthest apart, so it is deterministic too).
    ///
    /// # Errors
    /// [`ReconstructError::EmptyTrainingSet`], [`ReconstructError::NonFiniteTrainingPose`],
    /// [`ReconstructError::DegenerateTrainingPose`] (zero total limb length),
    /// [`ReconstructError::InvalidConfig`] for `n_components = 0`,
    /// [`ReconstructError::TooManyComponents`] when the poses do not vary in that many
    /// directions.
    pub fn fit(poses: &[Pose3], config: &BasisConfig) -> Result<PoseBasis, ReconstructError> {
        if config.n_components == 0 {
            return Err(ReconstructError::InvalidConfig {
                field: "BasisConfig::n_components",
                value: "0".into(),
                reason: "at least one component is needed",
            });
        }
        if poses.is_empty() {
            return Err(ReconstructError::EmptyTrainingSet);
        }
        let mut vectors = Vec::with_capacity(poses.len());
        let mut sums = Vec::with_capacity(poses.len());
        for (index, pose) in poses.iter().enumerate() {
            if !pose.is_finite() {
                return Err(ReconstructError::NonFiniteTrainingPose { index });
            }
            let sum = sum_squared_limb_lengths(pose);
            if !is_positive(sum) {
                return Err(ReconstructError::DegenerateTrainingPose { index });
            }
            vectors.push(pelvis_centred_vector(pose));
            sums.push(sum);
        }
        let n = poses.len() as f64;
        let target = sums.iter().sum::<f64>() / n;
        let mut mean = DVector::zeros(POSE_DIM);
        for (v, sum) in vectors.iter_mut().zip(&sums) {
            *v *= (target / sum).sqrt();
            mean += &*v;
        }
        mean /= n;
        let mut covariance = DMatrix::zeros(POSE_DIM, POSE_DIM);
        for v in &vectors {
            let d = v - &mean;
            covariance.ger(1.0 / n, &d, &d, 1.0);
        }
        let total_variance = covariance.trace();
        let eig = SymmetricEigen::try_new(covariance, f64::EPSILON, 0).ok_or(
            ReconstructError::Numerical("eigen-decomposition of the pose covariance failed"),
        )?;
        let mut order: Vec<usize> = (0..POSE_DIM).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[j].total_cmp(&eig.eigenvalues[i]));
        let floor = 1e-12 * total_variance;
        let available = order
            .iter()
            .filter(|&&i| eig.eigenvalues[i] > floor)
            .count();
        if config.n_components > available {
            return Err(ReconstructError::TooManyComponents {
                requested: config.n_components,
                available,
                training: poses.len(),
            });
        }
        let k = config.n_components;
        let atoms = match config.kind {
            BasisKind::Pca => Vec::new(),
            BasisKind::Dictionary { atoms } => {
                if atoms == 0 || atoms > poses.len() {
                    return Err(ReconstructError::InvalidConfig {
                        field: "BasisKind::Dictionary::atoms",
                        value: atoms.to_string(),
                        reason: "must be from 1 to the number of training poses",
                    });
                }
                cluster_atoms(&vectors, &mean, atoms)
            }
        };
        let mut components = DMatrix::zeros(POSE_DIM, k + atoms.len());
        let mut variances = Vec::with_capacity(k);
        for (col, &i) in order.iter().take(k).enumerate() {
            let mut v = eig.eigenvectors.column(i).into_owned();
            let pivot = v.iamax();
            if v[pivot] < 0.0 {
                v = -v;
            }
            components.set_column(col, &v);
            variances.push(eig.eigenvalues[i]);
        }
        for (j, atom) in atoms.iter().enumerate() {
            components.set_column(k + j, atom);
            let variance = vectors
                .iter()
                .map(|v| (v - &mean).dot(atom).powi(2))
                .sum::<f64>()
                / n;
            variances.push(variance);
        }
        let limits = JointLimits::fit(poses, config.limit_directions)?;
        let lengths = LengthPrior::fit(poses)?;
        Ok(PoseBasis {
            mean,
            components,
            variances,
            total_variance,
            anthropometric_target: target,
            n_training: poses.len(),
            n_principal: k,
            limits,
            lengths,
        })
    }

    /// The joint-angle limits learned from the training poses.
    pub fn joint_limits(&self) -> &JointLimits {
        &self.limits
    }

    /// The prior on limb lengths learned from the training poses (before their scaling).
    pub fn length_prior(&self) -> &LengthPrior {
        &self.lengths
    }

    /// Number of principal components (the leading, orthonormal columns of
    /// [`components`](Self::components)); the rest are dictionary atoms.
    pub fn n_principal(&self) -> usize {
        self.n_principal
    }

    /// The mean pose `mu` (canonical frame, metres).
    pub fn mean(&self) -> Pose3 {
        vector_to_pose(&self.mean)
    }

    /// The mean pose as a [`POSE_DIM`]-vector (landmark-major, metres).
    pub fn mean_vector(&self) -> &DVector<f64> {
        &self.mean
    }

    /// The components `B` as a [`POSE_DIM`] x `n_components` matrix: the orthonormal
    /// principal components ordered by decreasing variance, then any dictionary atoms (unit
    /// norm).
    pub fn components(&self) -> &DMatrix<f64> {
        &self.components
    }

    /// Number of components (principal components and dictionary atoms).
    pub fn n_components(&self) -> usize {
        self.components.ncols()
    }

    /// Variance of the training poses along each component, m^2.
    pub fn explained_variance(&self) -> &[f64] {
        &self.variances
    }

    /// Share of the total training variance kept by the principal components (0..=1).
    pub fn explained_variance_ratio(&self) -> f64 {
        if self.total_variance > 0.0 {
            self.variances[..self.n_principal].iter().sum::<f64>() / self.total_variance
        } else {
            0.0
        }
    }

    /// Total variance of the normalised training poses, m^2.
    pub fn total_variance(&self) -> f64 {
        self.total_variance
    }

    /// The anthropometric target: the sum of squared limb lengths that every normalised
    /// training pose has (their average before normalisation), m^2.
    pub fn anthropometric_target(&self) -> f64 {
        self.anthropometric_target
    }

    /// Number of training poses.
    pub fn n_training(&self) -> usize {
        self.n_training
    }

    /// The pose `mu + B w` for coefficients `w` (one per component, metres).
    ///
    /// # Errors
    /// [`ReconstructError::DimensionMismatch`] when `w` has not `n_components` entries.
    pub fn pose(&self, w: &[f64]) -> Result<Pose3, ReconstructError> {
        if w.len() != self.n_components() {
            return Err(ReconstructError::DimensionMismatch {
                what: "basis coefficients",
                expected: self.n_components(),
                got: w.len(),
            });
        }
        Ok(vector_to_pose(
            &(&self.mean + &self.components * DVector::from_column_slice(w)),
        ))
    }
}

/// The serde layout of a [`PoseBasis`] as written (nalgebra's `(data, rows, columns)` for
/// the vector and the matrix), decoded without nalgebra so that a hostile shape is an error
/// instead of an overflow in nalgebra's own size check.
#[derive(Deserialize)]
struct StoredBasis {
    mean: (Vec<f64>, usize, ()),
    components: (Vec<f64>, usize, usize),
    variances: Vec<f64>,
    total_variance: f64,
    anthropometric_target: f64,
    n_training: usize,
    n_principal: usize,
    limits: JointLimits,
    lengths: LengthPrior,
}

impl TryFrom<StoredBasis> for PoseBasis {
    type Error = String;

    fn try_from(s: StoredBasis) -> Result<PoseBasis, String> {
        let (mean, mean_rows, ()) = s.mean;
        let (data, rows, cols) = s.components;
        if mean.len() != mean_rows {
            return Err(format!(
                "mean vector declares {mean_rows} rows but holds {} numbers",
                mean.len()
            ));
        }
        if rows.checked_mul(cols) != Some(data.len()) {
            return Err(format!(
                "component matrix declares {rows} x {cols} but holds {} numbers",
                data.len()
            ));
        }
        Ok(PoseBasis {
            mean: DVector::from_vec(mean),
            components: DMatrix::from_vec(rows, cols, data),
            variances: s.variances,
            total_variance: s.total_variance,
            anthropometric_target: s.anthropometric_target,
            n_training: s.n_training,
            n_principal: s.n_principal,
            limits: s.limits,
            lengths: s.lengths,
        })
    }
}

/// The invariants `fit` establishes, checked after every decode: a 45-entry mean, 1 to 45
/// orthonormal 45-entry principal components and at most [`MAX_ATOMS`] unit-norm atoms, one
/// variance each, finite numbers, a positive anthropometric target, valid joint limits and a
/// valid length prior.
impl Validate for PoseBasis {
    type Invalid = ReconstructError;

    fn validate(&self) -> Result<(), ReconstructError> {
        let invalid = |reason: String| ReconstructError::InvalidBasis { reason };
        let k = self.components.ncols();
        if self.mean.len() != POSE_DIM || self.components.nrows() != POSE_DIM {
            return Err(invalid(format!(
                "mean has {} entries and components {} rows, expected {POSE_DIM}",
                self.mean.len(),
                self.components.nrows()
            )));
        }
        let p = self.n_principal;
        if p == 0 || p > POSE_DIM || k < p || k - p > MAX_ATOMS || self.variances.len() != k {
            return Err(invalid(format!(
                "{p} principal components (1 to {POSE_DIM} allowed) of {k} columns (at most \
                 {MAX_ATOMS} atoms) with {} variances",
                self.variances.len()
            )));
        }
        let numbers = self.mean.iter().chain(self.components.iter());
        let scalars = self
            .variances
            .iter()
            .chain([&self.total_variance, &self.anthropometric_target]);
        if !numbers.chain(scalars).all(|v| v.is_finite()) {
            return Err(invalid("non-finite number".into()));
        }
        if !is_positive(self.anthropometric_target) {
            return Err(invalid(format!(
                "anthropometric target {} is not positive",
                self.anthropometric_target
            )));
        }
        let principal = self.components.columns(0, p);
        let gram = principal.transpose() * principal;
        let off = (gram - DMatrix::identity(p, p)).abs().max();
        if off > 1e-8 {
            return Err(invalid(format!(
                "principal components are not orthonormal (error {off:.3e})"
            )));
        }
        if let Some(j) = (p..k).find(|&j| (self.components.column(j).norm() - 1.0).abs() > 1e-8) {
            return Err(invalid(format!(
                "dictionary atom {} is not of unit norm",
                j - p
            )));
        }
        self.limits.check().map_err(invalid)?;
        self.lengths.check().map_err(invalid)?;
        Ok(())
    }
}

/// Basis files: [`camloc_store::POSE_BASIS_KIND`] (magic `CAMLOCPB`); load with
/// [`Persist::load`], write with [`Persist::save`] (no overwrite unless asked).
impl Persist for PoseBasis {
    const KIND: FileKind = camloc_store::POSE_BASIS_KIND;
}

/// Most dictionary atoms a basis file may hold.
pub const MAX_ATOMS: usize = 1024;

/// `atoms` k-means centres of the (normalised, pelvis-centred) pose vectors, as unit-norm
/// deviations from `mean`. Starts from the farthest-point sampling of the vectors (from the
/// one farthest from the mean), then [`KMEANS_ITERATIONS`] Lloyd iterations; an emptied
/// cluster keeps its centre. Centres equal to the mean are dropped.
fn cluster_atoms(vectors: &[DVector<f64>], mean: &DVector<f64>, atoms: usize) -> Vec<DVector<f64>> {
    let first = vectors
        .iter()
        .enumerate()
        .max_by(|a, b| distance2(a.1, mean).total_cmp(&distance2(b.1, mean)))
        .map_or(0, |(i, _)| i);
    let mut centres = vec![vectors[first].clone()];
    let mut nearest: Vec<f64> = vectors.iter().map(|v| distance2(v, &centres[0])).collect();
    while centres.len() < atoms {
        let far = nearest
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(i, _)| i);
        let new = vectors[far].clone();
        nearest
            .par_iter_mut()
            .zip(vectors.par_iter())
            .for_each(|(n, v)| *n = n.min(distance2(v, &new)));
        centres.push(new);
    }
    let mut assignment = vec![0usize; vectors.len()];
    for _ in 0..KMEANS_ITERATIONS {
        let packed = pack_centres(&centres);
        assignment
            .par_iter_mut()
            .zip(vectors.par_iter())
            .for_each(|(a, v)| *a = nearest_centre(v, &packed));
        let mut sums = vec![DVector::zeros(POSE_DIM); centres.len()];
        let mut counts = vec![0usize; centres.len()];
        for (&a, v) in assignment.iter().zip(vectors) {
            sums[a] += v;
            counts[a] += 1;
        }
        for ((c, s), &n) in centres.iter_mut().zip(sums).zip(&counts) {
            if n > 0 {
                *c = s / n as f64;
            }
        }
    }
    centres
        .into_iter()
        .filter_map(|c| {
            let d = c - mean;
            let norm = d.norm();
            (norm > 1e-9).then(|| d / norm)
        })
        .collect()
}

/// The squared distance between two pose vectors, summed coordinate by coordinate in order.
fn distance2(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
}

/// The centres in groups of [`CENTRES_AT_ONCE`], each group coordinate-major (the group's
/// first coordinates, then its second ones, ...), the last group padded with infinitely
/// distant centres: the layout [`nearest_centre`] reads.
fn pack_centres(centres: &[DVector<f64>]) -> Vec<f64> {
    let padding = DVector::from_element(POSE_DIM, f64::INFINITY);
    let mut packed =
        Vec::with_capacity(centres.len().div_ceil(CENTRES_AT_ONCE) * CENTRES_AT_ONCE * POSE_DIM);
    for group in centres.chunks(CENTRES_AT_ONCE) {
        for j in 0..POSE_DIM {
            packed.extend((0..CENTRES_AT_ONCE).map(|k| group.get(k).unwrap_or(&padding)[j]));
        }
    }
    packed
}

/// The index of the centre nearest to `v` (the first of equally near ones) among centres
/// packed by [`pack_centres`]: the squared distances of [`distance2`], each summed in its
/// order, for a group of centres side by side (independent sums in the lanes of a vector).
fn nearest_centre(v: &DVector<f64>, packed: &[f64]) -> usize {
    let (mut best, mut best_distance) = (0, f64::INFINITY);
    for (g, group) in packed.chunks_exact(CENTRES_AT_ONCE * POSE_DIM).enumerate() {
        let mut sums = [0.0; CENTRES_AT_ONCE];
        for (&x, centres) in v.iter().zip(group.chunks_exact(CENTRES_AT_ONCE)) {
            for (sum, &c) in sums.iter_mut().zip(centres) {
                let d = x - c;
                *sum += d * d;
            }
        }
        for (k, distance) in sums.into_iter().enumerate() {
            if distance.total_cmp(&best_distance).is_lt() {
                (best, best_distance) = (g * CENTRES_AT_ONCE + k, distance);
            }
        }
    }
    best
}

/// Centres whose distances [`nearest_centre`] sums side by side.
const CENTRES_AT_ONCE: usize = 8;

/// Sum of the 14 squared limb lengths of `pose`, m^2 (the anthropometric quantity that
/// reconstruction holds fixed).
pub fn sum_squared_limb_lengths(pose: &Pose3) -> f64 {
    limb_vectors(&pose_to_vector(pose)).norm_squared()
}

/// The pose as a landmark-major [`POSE_DIM`]-vector.
pub(crate) fn pose_to_vector(pose: &Pose3) -> DVector<f64> {
    DVector::from_iterator(POSE_DIM, pose.points.iter().flatten().copied())
}

/// The pose translated so that its pelvis is at the origin, as a vector.
fn pelvis_centred_vector(pose: &Pose3) -> DVector<f64> {
    let pelvis = pose.points[0];
    DVector::from_iterator(
        POSE_DIM,
        pose.points
            .iter()
            .flat_map(|p| [p[0] - pelvis[0], p[1] - pelvis[1], p[2] - pelvis[2]]),
    )
}

/// A landmark-major [`POSE_DIM`]-vector as a pose (the vector must have that length, which
/// every caller in this crate guarantees by construction).
pub(crate) fn vector_to_pose(v: &DVector<f64>) -> Pose3 {
    let mut points = [[0.0; 3]; NUM_LANDMARKS];
    for (p, chunk) in points.iter_mut().zip(v.as_slice().chunks_exact(3)) {
        p.copy_from_slice(chunk);
    }
    Pose3 { points }
}

/// Limb vectors (child minus parent, [`LIMBS`] order) of a landmark-major pose vector.
pub(crate) fn limb_vectors(v: &DVector<f64>) -> DVector<f64> {
    DVector::from_iterator(
        LIMB_DIM,
        LIMBS.iter().flat_map(|(parent, child)| {
            let (p, c) = (3 * parent.index(), 3 * child.index());
            [v[c] - v[p], v[c + 1] - v[p + 1], v[c + 2] - v[p + 2]]
        }),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The packed search finds the centre `min_by` over [`distance2`] finds (the first of
        /// equally near ones), for any number of centres (whole and partial groups) and with
        /// repeated centres.
        #[test]
        fn nearest_centre_is_the_first_nearest(
            values in proptest::collection::vec(-2.0f64..2.0, POSE_DIM * 12),
            count in 1usize..12,
            repeat in 0usize..12,
        ) {
            let vectors: Vec<DVector<f64>> = values
                .chunks_exact(POSE_DIM)
                .map(DVector::from_column_slice)
                .collect();
            let mut centres = vectors[1..=count].to_vec();
            centres.push(centres[repeat % count].clone());
            let v = &vectors[0];
            let expected = centres
                .iter()
                .enumerate()
                .min_by(|a, b| distance2(v, a.1).total_cmp(&distance2(v, b.1)))
                .map_or(0, |(i, _)| i);
            prop_assert_eq!(nearest_centre(v, &pack_centres(&centres)), expected);
            prop_assert_eq!(nearest_centre(&centres[count].clone(), &pack_centres(&centres)), repeat % count);
        }
    }
}
