//! Projected matching pursuit (Ramakrishna, Kanade & Sheikh, ECCV 2012; the paper's eqs. 5-6)
//! with the camera modes of docs/conventions.md section 6.

use camloc_geometry::{GeometryError, Matrix3, Vector3, WeakPerspective, check_rotation};
use camloc_skeleton::{NUM_LANDMARKS, Pose2, Pose3};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::basis::{LIMB_DIM, POSE_DIM, limb_vectors, vector_to_pose};
use crate::lsq::QuadraticConstraint;
use crate::prior::symmetrise;
use crate::{
    ModeKind, PoseBasis, ReconstructError, check_finite_landmarks, is_positive, is_positive_finite,
};

/// Number of image coordinates of a pose (15 landmarks x 2).
const IMAGE_DIM: usize = 2 * NUM_LANDMARKS;

/// Tolerance of the rotation check applied to rotations given in a [`CameraMode`].
const ROTATION_TOLERANCE: f64 = 1e-6;

/// Which sum of squared limb lengths the reconstructed pose must have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LengthTarget {
    /// The basis's anthropometric target, [`PoseBasis::anthropometric_target`]: the value every
    /// normalised training pose has.
    TrainingAverage,
    /// The value of the mean pose `mu` (as the pursuit's constraint is usually written; smaller
    /// than the training average, because averaging poses shortens limbs).
    Mean,
}

/// Options of [`Reconstructor`].
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
    /// about as well): see [`Reconstructor::reconstruct_hypotheses`] for how one is chosen.
    pub try_depth_reflection: bool,
    /// Prior on the coefficients: the pursuit minimises the squared reprojection error (in
    /// the normalised image units, the 2D input centred and scaled to unit RMS radius) plus
    /// `coefficient_prior * sum_j w_j^2 / var_j`, `var_j` the training poses' variance along
    /// basis pose `j` (a Gaussian prior on the coefficients, MAP instead of least squares);
    /// `>= 0`, 0 is the plain pursuit.
    pub coefficient_prior: f64,
    /// Prior: bring left and right limb lengths to their mean after the pursuit
    /// ([`symmetrise`]), then refit the camera.
    pub symmetry: bool,
    /// Prior: turn limb bones outside the basis's learned joint-angle limits onto their border
    /// after the pursuit ([`JointLimits::project`](crate::JointLimits::project)), then refit
    /// the camera; and prefer, between hypotheses that fit the 2D about equally, the one the
    /// limits like better.
    pub joint_limits: bool,
}

/// Default [`ReconstructConfig::coefficient_prior`], chosen by cross-validation grouped by
/// subject on the CMU data (`cargo xtask reconstruction`, docs/RESULTS.md).
pub const DEFAULT_COEFFICIENT_PRIOR: f64 = 0.01;

/// Two hypotheses fit the 2D "about equally" when their RMS reprojection errors are within
/// this fraction of each other; the joint-angle prior then chooses between them.
pub const EQUAL_FIT_TOLERANCE: f64 = 0.1;

impl Default for ReconstructConfig {
    /// `max_basis` 12 with the training-average length target, depth reflection on and both
    /// priors on (measured by `cargo xtask reconstruction`, docs/RESULTS.md).
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
        }
    }
}

/// How the camera is obtained during reconstruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraMode {
    /// `opt`: the orthogonal Procrustes camera (eq. 3), first from the mean pose, then
    /// re-estimated after every coefficient update. The baseline of the paper.
    Opt,
    /// `classified`: rotation fixed to the classified viewpoint's rotation (e.g. a Table-1
    /// camera); only scale and translation are estimated (the paper's section 8.2).
    Classified(Matrix3),
    /// `oracle`: rotation fixed to the true camera rotation (evaluation only); otherwise as
    /// [`CameraMode::Classified`].
    Oracle(Matrix3),
    /// `hybrid`: the given rotation (typically the classified one) as a start, refined by
    /// Procrustes. Two hypotheses are solved and the one with the lower reprojection error is
    /// kept: (1) the pursuit as [`CameraMode::Classified`], then the camera refined by
    /// Procrustes (eq. 3), alternating with the coefficients of the selected components while
    /// the error falls; (2) the pursuit as [`CameraMode::Opt`] but started from the given
    /// rotation instead of the mean pose's Procrustes camera. Either alone measured worse (see
    /// "Choosing a camera mode" in the crate documentation).
    Hybrid(Matrix3),
}

impl CameraMode {
    /// The mode without its rotation.
    pub fn kind(&self) -> ModeKind {
        match self {
            CameraMode::Opt => ModeKind::Opt,
            CameraMode::Classified(_) => ModeKind::Classified,
            CameraMode::Oracle(_) => ModeKind::Oracle,
            CameraMode::Hybrid(_) => ModeKind::Hybrid,
        }
    }

    /// Short lower-case name (`opt`, `classified`, `oracle`, `hybrid`).
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }
}

/// A reconstructed 3D pose and the camera that projects it onto the input.
#[derive(Clone, Debug, PartialEq)]
pub struct Reconstruction {
    /// The pose `mu + B w`, metres, in the basis's canonical body frame (pelvis at the origin;
    /// the frame in which the training poses face -x). The camera rotation maps this frame to
    /// the camera; with a fixed class rotation the pose is therefore oriented as a canonical
    /// pose seen from that class, with Procrustes modes its facing is whatever the estimated
    /// camera implies. Its size is the training average (the anthropometric target), not the
    /// subject's.
    pub pose: Pose3,
    /// Weak-perspective camera in the input's image units: `L = s [I2 0] R X + t`.
    pub camera: WeakPerspective,
    /// Eq. 6 at the solution: the Euclidean norm of the 30-vector of reprojection residuals,
    /// in the input's image units.
    pub projection_error: f64,
    /// Indices of the selected basis components, in order of selection (at most
    /// [`ReconstructConfig::max_basis`]).
    pub selected: Vec<usize>,
    /// Coefficients of the selected components, parallel to `selected` (metres).
    pub coefficients: Vec<f64>,
    /// Coefficient/camera alternations performed, over every hypothesis tried (both depth
    /// hypotheses; for [`CameraMode::Hybrid`], both solves).
    pub iterations: usize,
    /// `true` when this is the depth-reflected hypothesis.
    pub reflected: bool,
    /// How far the pursuit's pose lay outside the learned joint-angle limits, before the
    /// prior's projection: the sum over the 8 limb bones of the angle beyond the limits,
    /// radians (0: within them).
    pub limit_violation_rad: f64,
}

/// Reconstructs 3D poses from 2D landmarks with a [`PoseBasis`].
#[derive(Clone, Debug)]
pub struct Reconstructor {
    basis: PoseBasis,
    config: ReconstructConfig,
    /// `K x K` Gram matrix of the components' limb vectors: the constraint's `Q`.
    gram: DMatrix<f64>,
    /// Components' limb vectors dotted with the mean's: the constraint's `c`.
    cross: DVector<f64>,
    /// Mean's sum of squared limb lengths minus the target: the constraint's `e`.
    offset: f64,
    /// Per component, the trace of the 3 x 3 scatter `C_j = sum_i (b_ji - mean_i b_ji)(...)^T`
    /// of its 15 landmark vectors, and `C_j` itself (`xx, xy, xz, yy, yz, zz`): the squared
    /// norm of its centred projection by `s [I2 0] R` is `s^2 (tr C_j - r3^T C_j r3)`.
    scatter: Vec<(f64, [f64; 6])>,
}

/// How the camera is re-estimated.
#[derive(Clone, Copy, Debug)]
enum CameraUpdate {
    /// Procrustes (eq. 3), rotation free.
    Procrustes,
    /// Rotation fixed; least-squares scale and translation.
    Fixed(Matrix3),
}

impl CameraUpdate {
    /// The camera the pursuit starts from for the mean pose `points3`: this update's fit or,
    /// when a fixed rotation admits no positive least-squares scale (the input seen turned
    /// against the mean pose), that rotation with the scale that matches the two poses' RMS
    /// radii and the least-squares translation. Fails with the fit's error when no such
    /// scale exists either.
    fn start(
        self,
        points3: &[[f64; 3]; NUM_LANDMARKS],
        points2: &[[f64; 2]; NUM_LANDMARKS],
    ) -> Result<WeakPerspective, GeometryError> {
        let fitted = self.fit(points3, points2);
        let (Err(GeometryError::Degenerate(_)), CameraUpdate::Fixed(rotation)) = (&fitted, self)
        else {
            return fitted;
        };
        let flat = WeakPerspective::orthographic(rotation);
        let scale = rms_radius(points2) / rms_radius(&flat.project(points3));
        if !is_positive_finite(scale) {
            return fitted;
        }
        let camera = WeakPerspective { scale, ..flat };
        Ok(with_optimal_translation(&camera, points3, points2))
    }

    /// This update's fit or, where it fails (a degenerate pose, no positive scale), `current`
    /// with the least-squares translation: as in `alternate`, a failed update keeps the camera.
    fn fit_or_keep(
        self,
        current: &WeakPerspective,
        points3: &[[f64; 3]; NUM_LANDMARKS],
        points2: &[[f64; 2]; NUM_LANDMARKS],
    ) -> WeakPerspective {
        self.fit(points3, points2)
            .unwrap_or_else(|_| with_optimal_translation(current, points3, points2))
    }

    fn fit(
        self,
        points3: &[[f64; 3]; NUM_LANDMARKS],
        points2: &[[f64; 2]; NUM_LANDMARKS],
    ) -> Result<WeakPerspective, GeometryError> {
        match self {
            CameraUpdate::Procrustes => camloc_geometry::procrustes_camera(points3, points2),
            CameraUpdate::Fixed(r) => WeakPerspective::fit_with_rotation(r, points3, points2),
        }
    }
}

/// The 2D input, centred on its centroid and divided by its RMS radius, so that every
/// tolerance is unit-free.
struct Observation {
    points: [[f64; 2]; NUM_LANDMARKS],
    centroid: [f64; 2],
    scale: f64,
}

impl Observation {
    fn new(pose: &Pose2) -> Result<Observation, ReconstructError> {
        check_finite_landmarks(pose)?;
        // Extreme magnitudes (1e154, 1e-200, ...) are first brought into range by an exact
        // power of two `factor` (1 for ordinary poses), so that the squares below neither
        // overflow nor underflow; centroid and scale are mapped back at the end.
        let (pose, factor) = pose.within_safe_range();
        let centroid = centroid(&pose.points);
        let centred = pose
            .points
            .map(|p| [p[0] - centroid[0], p[1] - centroid[1]]);
        let scale = rms_radius(&pose.points);
        if !is_positive_finite(scale) {
            return Err(ReconstructError::DegenerateInput("all landmarks coincide"));
        }
        let has_torso = pose.torso_length() > 1e-9 * scale;
        if !has_torso {
            return Err(ReconstructError::DegenerateInput(
                "the torso (pelvis to neck) has zero length",
            ));
        }
        Ok(Observation {
            points: centred.map(|p| [p[0] / scale, p[1] / scale]),
            centroid: [centroid[0] / factor, centroid[1] / factor],
            scale: scale / factor,
        })
    }

    /// The normalised points as a 30-vector.
    fn vector(&self) -> DVector<f64> {
        DVector::from_iterator(IMAGE_DIM, self.points.iter().flatten().copied())
    }

    /// A camera fitted to the normalised points, expressed in the input's image units.
    fn denormalise(&self, camera: &WeakPerspective) -> WeakPerspective {
        WeakPerspective {
            scale: camera.scale * self.scale,
            rotation: camera.rotation,
            translation: [
                camera.translation[0] * self.scale + self.centroid[0],
                camera.translation[1] * self.scale + self.centroid[1],
            ],
        }
    }
}

/// One hypothesis of the pursuit: selected components, coefficients, pose, camera, error.
#[derive(Clone, Debug)]
struct Fit {
    selected: Vec<usize>,
    coefficients: Vec<f64>,
    points: [[f64; 3]; NUM_LANDMARKS],
    camera: WeakPerspective,
    /// Squared reprojection error in normalised image units.
    error: f64,
    iterations: usize,
}

/// One hypothesis of [`Reconstructor::solve`], after the priors.
struct Candidate {
    fit: Fit,
    reflected: bool,
    /// [`Reconstruction::limit_violation_rad`].
    violation: f64,
}

impl Reconstructor {
    /// Prepares a reconstructor (precomputes the constraint's quadratic form in basis
    /// coordinates).
    ///
    /// # Errors
    /// [`ReconstructError::InvalidConfig`] for `max_basis = 0`, `max_alternations = 0` or a
    /// tolerance outside `[0, 1)`.
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

    /// The sum of squared limb lengths every reconstruction has, m^2.
    pub fn length_target(&self) -> f64 {
        limb_vectors(self.basis.mean_vector()).norm_squared() - self.offset
    }

    /// Reconstructs the 3D pose seen in `pose` (any image units, `v` down) under `mode`: the
    /// first of [`reconstruct_hypotheses`](Self::reconstruct_hypotheses).
    ///
    /// # Errors
    /// As [`reconstruct_hypotheses`](Self::reconstruct_hypotheses).
    pub fn reconstruct(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
    ) -> Result<Reconstruction, ReconstructError> {
        let mut all = self.reconstruct_hypotheses(pose, mode, 1)?;
        all.pop()
            .ok_or(ReconstructError::Numerical("no hypothesis was solved"))
    }

    /// Reconstructs the 3D pose seen in `pose` (any image units, `v` down) under `mode`, and
    /// returns up to `max` hypotheses, the preferred one first.
    ///
    /// Algorithm (projected matching pursuit): start from `mu` and the mode's initial camera;
    /// repeatedly add the component whose projection has the largest normalised correlation
    /// with the current residual, then alternate an exact constrained least-squares solve of
    /// the selected coefficients (translation eliminated) with a camera update (Procrustes, or
    /// scale and translation for a fixed rotation), keeping whichever camera gives the lower
    /// error; stop when a new component lowers the error by less than
    /// [`ReconstructConfig::min_relative_decrease`] (it is then discarded) or `max_basis` is
    /// reached.
    ///
    /// Depth reflection (when [`ReconstructConfig::try_depth_reflection`]): the solution `X`
    /// is reflected in the plane through the pelvis orthogonal to the camera's optical axis
    /// `r3`, `X' = (I - 2 r3 r3^T) X`. The same camera sees `X'` exactly as it sees `X` (the
    /// reflection only negates depth), and the camera stays a proper rotation; only the pose
    /// changes handedness, so `X'` is generally not in the basis span. `X'` is therefore
    /// projected onto the basis (the same number of components, those whose unit columns
    /// correlate most with `X'` minus the mean — for a PCA basis the largest coefficients of
    /// the orthogonal projection; dictionary atoms are not orthogonal, so for them it is only
    /// a correlation — then the constrained 3D least-squares fit on those components)
    /// and the pursuit continues from there with the same camera update (for fixed-rotation
    /// modes: the reflected pose seen by the same rotation).
    ///
    /// Priors ([`ReconstructConfig::symmetry`], [`ReconstructConfig::joint_limits`]) then
    /// adjust each hypothesis and its camera is refitted. The hypotheses are ranked by
    /// reprojection error, except that of two whose RMS errors are within
    /// [`EQUAL_FIT_TOLERANCE`] of each other the one with the smaller joint-limit violation
    /// comes first (with the joint-limit prior on).
    ///
    /// [`CameraMode::Hybrid`] runs two such solves (see there), and their hypotheses are
    /// ranked together.
    ///
    /// # Errors
    /// [`ReconstructError::NonFiniteInput`], [`ReconstructError::DegenerateInput`] (zero torso,
    /// coincident landmarks), [`ReconstructError::InvalidRotation`] for a mode rotation that
    /// is not proper, [`ReconstructError::Geometry`] when a camera cannot be estimated (e.g.
    /// collinear 2D landmarks under Procrustes).
    pub fn reconstruct_hypotheses(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
        max: usize,
    ) -> Result<Vec<Reconstruction>, ReconstructError> {
        let obs = Observation::new(pose)?;
        let checked = |r: &Matrix3| {
            check_rotation(r, ROTATION_TOLERANCE)
                .map(|()| CameraUpdate::Fixed(*r))
                .map_err(|source| ReconstructError::InvalidRotation {
                    mode: mode.name(),
                    source,
                })
        };
        let mut candidates = match mode {
            CameraMode::Opt => self.solve(
                &obs,
                CameraUpdate::Procrustes,
                CameraUpdate::Procrustes,
                false,
            )?,
            CameraMode::Classified(r) | CameraMode::Oracle(r) => {
                let fixed = checked(r)?;
                self.solve(&obs, fixed, fixed, false)?
            }
            CameraMode::Hybrid(r) => {
                let fixed = checked(r)?;
                let mut all = self.solve(&obs, fixed, fixed, true)?;
                all.extend(self.solve(&obs, fixed, CameraUpdate::Procrustes, false)?);
                all
            }
        };
        let iterations = candidates.iter().map(|c| c.fit.iterations).sum();
        candidates.sort_by(|a, b| self.preference(a, b));
        Ok(candidates
            .into_iter()
            .take(max.max(1))
            .map(|c| Reconstruction {
                pose: Pose3 {
                    points: c.fit.points,
                },
                camera: obs.denormalise(&c.fit.camera),
                projection_error: c.fit.error.sqrt() * obs.scale,
                selected: c.fit.selected,
                coefficients: c.fit.coefficients,
                iterations,
                reflected: c.reflected,
                limit_violation_rad: c.violation,
            })
            .collect())
    }

    /// The order of two hypotheses: by error, unless they fit about equally and the
    /// joint-limit prior is on, then by violation.
    fn preference(&self, a: &Candidate, b: &Candidate) -> std::cmp::Ordering {
        let (ea, eb) = (a.fit.error.sqrt(), b.fit.error.sqrt());
        let close = (ea - eb).abs() <= EQUAL_FIT_TOLERANCE * ea.max(eb);
        if self.config.joint_limits && close && a.violation != b.violation {
            a.violation.total_cmp(&b.violation)
        } else {
            a.fit.error.total_cmp(&b.fit.error)
        }
    }

    /// Applies the configured priors to `fit`'s pose, refits its camera with `update` and
    /// returns the pose's joint-limit violation before the priors.
    fn apply_priors(
        &self,
        obs: &Observation,
        fit: &mut Fit,
        update: CameraUpdate,
    ) -> Result<f64, ReconstructError> {
        let limits = self.basis.joint_limits();
        let mut pose = Pose3 { points: fit.points };
        let violation = limits.violation(&pose);
        if !(self.config.symmetry || self.config.joint_limits) {
            return Ok(violation);
        }
        if self.config.symmetry {
            pose = symmetrise(&pose);
        }
        if self.config.joint_limits {
            pose = limits.project(&pose);
        }
        let camera = update.fit_or_keep(&fit.camera, &pose.points, &obs.points);
        fit.error = camera.squared_error(&pose.points, &obs.points)?;
        fit.camera = camera;
        fit.points = pose.points;
        Ok(violation)
    }

    /// One full solve: the camera `start` fitted to the mean pose, the pursuit with camera
    /// `update`, the depth-reflected hypothesis if configured, and, if `refine`, a Procrustes
    /// refinement of each hypothesis; then the priors. Returns the hypotheses (the direct one
    /// first).
    fn solve(
        &self,
        obs: &Observation,
        start: CameraUpdate,
        update: CameraUpdate,
        refine: bool,
    ) -> Result<Vec<Candidate>, ReconstructError> {
        let mean = self.points(&[], &[]);
        let camera = start.start(&mean, &obs.points)?;
        let initial = Fit {
            selected: Vec::new(),
            coefficients: Vec::new(),
            points: mean,
            error: camera.squared_error(&mean, &obs.points)?,
            camera,
            iterations: 0,
        };
        let primary = self.pursue(obs, initial, update)?;
        let other = if self.config.try_depth_reflection {
            let mut other = self.reflected_start(obs, &primary, update)?;
            self.alternate(obs, &mut other, update)?;
            Some(self.pursue(obs, other, update)?)
        } else {
            None
        };
        // The refinement never raises the error.
        let last = if refine {
            CameraUpdate::Procrustes
        } else {
            update
        };
        let finish = |mut fit: Fit, reflected: bool| -> Result<Candidate, ReconstructError> {
            if refine {
                self.alternate(obs, &mut fit, CameraUpdate::Procrustes)?;
            }
            let violation = self.apply_priors(obs, &mut fit, last)?;
            Ok(Candidate {
                fit,
                reflected,
                violation,
            })
        };
        let mut out = vec![finish(primary, false)?];
        if let Some(other) = other {
            out.push(finish(other, true)?);
        }
        Ok(out)
    }

    /// The greedy loop: add components while they help.
    fn pursue(
        &self,
        obs: &Observation,
        mut fit: Fit,
        update: CameraUpdate,
    ) -> Result<Fit, ReconstructError> {
        while fit.selected.len() < self.config.max_basis {
            let Some(next) = self.best_component(obs, &fit) else {
                break;
            };
            let mut trial = fit.clone();
            trial.selected.push(next);
            trial.coefficients.push(0.0);
            self.alternate(obs, &mut trial, update)?;
            let accept = fit.selected.is_empty()
                || trial.error < fit.error * (1.0 - self.config.min_relative_decrease);
            // Work spent on a rejected trial still counts.
            fit.iterations = trial.iterations;
            if !accept {
                break;
            }
            fit = trial;
        }
        Ok(fit)
    }

    /// The unselected component whose centred projection has the largest normalised
    /// correlation `|a_j . r| / |a_j|` with the residual `r`; `None` when every component is
    /// selected (or projects to nothing).
    ///
    /// With the centred residual `r` (the camera's translation is optimal), `a_j . r =
    /// s b_j . w` where `w_i = r1 r_ui + r2 r_vi` (rows `r1`, `r2` of the rotation): one
    /// product `B^T w` for all components, and `|a_j|^2 = s^2 (tr C_j - r3^T C_j r3)` from the
    /// precomputed scatter.
    fn best_component(&self, obs: &Observation, fit: &Fit) -> Option<usize> {
        let projected = fit.camera.project(&fit.points);
        let n = NUM_LANDMARKS as f64;
        let mut residual = [[0.0; 2]; NUM_LANDMARKS];
        let mut mean = [0.0; 2];
        for ((r, l), p) in residual.iter_mut().zip(&obs.points).zip(&projected) {
            *r = [l[0] - p[0], l[1] - p[1]];
            mean[0] += r[0] / n;
            mean[1] += r[1] / n;
        }
        let rot = &fit.camera.rotation;
        let w = DVector::from_iterator(
            POSE_DIM,
            residual.iter().flat_map(|r| {
                let (u, v) = (r[0] - mean[0], r[1] - mean[1]);
                (0..3).map(move |c| rot[(0, c)] * u + rot[(1, c)] * v)
            }),
        );
        let dots = self.basis.components().tr_mul(&w);
        let axis = [rot[(2, 0)], rot[(2, 1)], rot[(2, 2)]];
        let mut best: Option<(usize, f64)> = None;
        for (j, (&(trace, c), dot)) in self.scatter.iter().zip(dots.iter()).enumerate() {
            if fit.selected.contains(&j) {
                continue;
            }
            let [x, y, z] = axis;
            let along = c[0] * x * x
                + c[3] * y * y
                + c[5] * z * z
                + 2.0 * (c[1] * x * y + c[2] * x * z + c[4] * y * z);
            let norm2 = trace - along;
            if !is_positive(norm2) {
                continue;
            }
            // The common factor s drops out of the comparison.
            let score = dot.abs() / norm2.sqrt();
            if best.is_none_or(|(_, s)| score > s) {
                best = Some((j, score));
            }
        }
        best.map(|(j, _)| j)
    }

    /// Alternates coefficient solves and camera updates on the selected set until the error
    /// stops falling. Every step keeps the lower-error camera, so the error never rises.
    fn alternate(
        &self,
        obs: &Observation,
        fit: &mut Fit,
        update: CameraUpdate,
    ) -> Result<(), ReconstructError> {
        let target = obs.vector();
        let constraint = self.constraint(&fit.selected)?;
        let mut previous = f64::INFINITY;
        for _ in 0..self.config.max_alternations {
            let coefficients =
                self.solve_coefficients(&target, &fit.camera, &fit.selected, &constraint)?;
            let points = self.points(&fit.selected, &coefficients);
            let kept = with_optimal_translation(&fit.camera, &points, &obs.points);
            let kept_error = kept.squared_error(&points, &obs.points)?;
            // A camera update that fails (a degenerate intermediate pose) keeps the old camera.
            let refit = update
                .fit(&points, &obs.points)
                .and_then(|c| Ok((c, c.squared_error(&points, &obs.points)?)));
            let (camera, error) = match refit {
                Ok((refit, refit_error)) if refit_error <= kept_error => (refit, refit_error),
                _ => (kept, kept_error),
            };
            fit.coefficients = coefficients;
            fit.points = points;
            fit.camera = camera;
            fit.error = error;
            fit.iterations += 1;
            let improved = error < previous * (1.0 - self.config.alternation_tolerance);
            if !improved {
                break;
            }
            previous = error;
        }
        Ok(())
    }

    /// The anthropometric constraint on the coefficients of `selected`, factorised.
    fn constraint(&self, selected: &[usize]) -> Result<QuadraticConstraint, ReconstructError> {
        let m = selected.len();
        let q = DMatrix::from_fn(m, m, |r, c| self.gram[(selected[r], selected[c])]);
        let c = DVector::from_fn(m, |r, _| self.cross[selected[r]]);
        QuadraticConstraint::new(&q, &c, self.offset)
    }

    /// Exact constrained least squares for the coefficients of `selected` (whose constraint
    /// is `constraint`) with the camera's scale and rotation fixed and the translation
    /// eliminated by centring.
    fn solve_coefficients(
        &self,
        target: &DVector<f64>,
        camera: &WeakPerspective,
        selected: &[usize],
        constraint: &QuadraticConstraint,
    ) -> Result<Vec<f64>, ReconstructError> {
        let m = selected.len();
        // The prior's rows under the image rows: sqrt(prior / var_j) w_j = 0.
        let prior_rows = if self.config.coefficient_prior > 0.0 {
            m
        } else {
            0
        };
        let mut a = DMatrix::zeros(IMAGE_DIM + prior_rows, m);
        for (col, &j) in selected.iter().enumerate() {
            a.view_mut((0, col), (IMAGE_DIM, 1))
                .copy_from(&self.project_centred(camera, self.component(j)));
            if prior_rows > 0 {
                let variance = self.basis.explained_variance()[j].max(f64::MIN_POSITIVE);
                a[(IMAGE_DIM + col, col)] = (self.config.coefficient_prior / variance).sqrt();
            }
        }
        let mut b = DVector::zeros(IMAGE_DIM + prior_rows);
        b.rows_mut(0, IMAGE_DIM).copy_from(
            &(target - self.project_centred(camera, self.basis.mean_vector().as_slice())),
        );
        let solution = constraint.solve(&a, &b)?;
        Ok(solution.w.iter().copied().collect())
    }

    /// Component `j` as a landmark-major slice (`j` must be a valid component index).
    fn component(&self, j: usize) -> &[f64] {
        let data = self.basis.components().as_slice();
        &data[POSE_DIM * j..POSE_DIM * (j + 1)]
    }

    /// `s [I2 0] R` applied to every landmark of a pose-space vector, centred over the
    /// landmarks, as a 30-vector.
    fn project_centred(&self, camera: &WeakPerspective, v: &[f64]) -> DVector<f64> {
        let r = &camera.rotation;
        let mut out = DVector::zeros(IMAGE_DIM);
        let mut mean = [0.0; 2];
        for (i, x) in v.chunks_exact(3).enumerate() {
            for row in 0..2 {
                let p =
                    camera.scale * (r[(row, 0)] * x[0] + r[(row, 1)] * x[1] + r[(row, 2)] * x[2]);
                out[2 * i + row] = p;
                mean[row] += p / NUM_LANDMARKS as f64;
            }
        }
        for (i, o) in out.iter_mut().enumerate() {
            *o -= mean[i % 2];
        }
        out
    }

    /// The pose `mu + sum_j w_j b_j` over `selected`, as points.
    fn points(&self, selected: &[usize], coefficients: &[f64]) -> [[f64; 3]; NUM_LANDMARKS] {
        let mut v = self.basis.mean_vector().clone();
        for (&j, &w) in selected.iter().zip(coefficients) {
            for (x, b) in v.iter_mut().zip(self.component(j)) {
                *x += w * b;
            }
        }
        vector_to_pose(&v).points
    }

    /// Start of the depth-reflected hypothesis (see [`Reconstructor::reconstruct`]).
    fn reflected_start(
        &self,
        obs: &Observation,
        fit: &Fit,
        update: CameraUpdate,
    ) -> Result<Fit, ReconstructError> {
        let reflected = depth_reflection(&fit.points, &fit.camera.rotation);
        let residual = DVector::from_iterator(POSE_DIM, reflected.iter().flatten().copied())
            - self.basis.mean_vector();
        let full = self.basis.components().transpose() * &residual;
        let mut order: Vec<usize> = (0..full.len()).collect();
        order.sort_by(|&i, &j| full[j].abs().total_cmp(&full[i].abs()));
        let selected: Vec<usize> = order.into_iter().take(fit.selected.len().max(1)).collect();
        let a = DMatrix::from_fn(POSE_DIM, selected.len(), |r, c| {
            self.basis.components()[(r, selected[c])]
        });
        let solution = self.constraint(&selected)?.solve(&a, &residual)?;
        let coefficients: Vec<f64> = solution.w.iter().copied().collect();
        let points = self.points(&selected, &coefficients);
        let camera = update.fit_or_keep(&fit.camera, &points, &obs.points);
        Ok(Fit {
            error: camera.squared_error(&points, &obs.points)?,
            selected,
            coefficients,
            points,
            camera,
            iterations: 0,
        })
    }
}

/// The mean of `points` (their units).
fn centroid(points: &[[f64; 2]; NUM_LANDMARKS]) -> [f64; 2] {
    let n = NUM_LANDMARKS as f64;
    points
        .iter()
        .fold([0.0; 2], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n])
}

/// Root-mean-square distance of `points` from their centroid (their units).
fn rms_radius(points: &[[f64; 2]; NUM_LANDMARKS]) -> f64 {
    let n = NUM_LANDMARKS as f64;
    let centre = centroid(points);
    let sum: f64 = points
        .iter()
        .map(|p| (p[0] - centre[0]).powi(2) + (p[1] - centre[1]).powi(2))
        .sum();
    (sum / n).sqrt()
}

/// The camera with the same scale and rotation and the least-squares translation for
/// `points3` -> `points2` (maps the projected 3D centroid onto the 2D centroid).
fn with_optimal_translation(
    camera: &WeakPerspective,
    points3: &[[f64; 3]; NUM_LANDMARKS],
    points2: &[[f64; 2]; NUM_LANDMARKS],
) -> WeakPerspective {
    let centred = WeakPerspective {
        translation: [0.0, 0.0],
        ..*camera
    };
    let n = NUM_LANDMARKS as f64;
    let mut t = [0.0; 2];
    for (p, l) in centred.project(points3).iter().zip(points2) {
        t[0] += (l[0] - p[0]) / n;
        t[1] += (l[1] - p[1]) / n;
    }
    WeakPerspective {
        translation: t,
        ..*camera
    }
}

/// Reflects `points` in the plane through the origin orthogonal to the optical axis (row 3 of
/// `rotation`): `x -> x - 2 (r3 . x) r3`. A weak-perspective camera with this rotation sees the
/// reflected points exactly where it sees the originals, since the reflection only negates
/// their depth `r3 . x`.
pub(crate) fn depth_reflection(
    points: &[[f64; 3]; NUM_LANDMARKS],
    rotation: &Matrix3,
) -> [[f64; 3]; NUM_LANDMARKS] {
    let axis: Vector3 = rotation.row(2).transpose();
    points.map(|p| {
        let x = Vector3::from(p);
        (x - axis * (2.0 * axis.dot(&x))).into()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_geometry::rotation_about_axis;
    use proptest::prelude::*;

    fn cloud(seed: f64) -> [[f64; 3]; NUM_LANDMARKS] {
        let mut p = [[0.0; 3]; NUM_LANDMARKS];
        for (i, x) in p.iter_mut().enumerate() {
            let t = i as f64 + seed;
            *x = [(t * 0.7).sin() * 0.3, (t * 1.3).cos() * 0.2, t * 0.1 - 0.6];
        }
        p
    }

    proptest! {
        /// The depth reflection keeps every projection, is an involution, reverses
        /// handedness (negative triple product) and keeps limb lengths, for any proper camera.
        #[test]
        fn depth_reflection_keeps_projection(ax in -1.0f64..1.0, ay in -1.0f64..1.0,
                                             az in -1.0f64..1.0, angle in -3.1f64..3.1,
                                             s in 0.1f64..10.0, seed in 0.0f64..10.0) {
            prop_assume!(ax.abs() + ay.abs() + az.abs() > 0.1);
            let r = rotation_about_axis(Vector3::new(ax, ay, az), angle);
            let cam = WeakPerspective { scale: s, rotation: r, translation: [1.0, -2.0] };
            let x = cloud(seed);
            let y = depth_reflection(&x, &r);
            for (p, q) in cam.project(&x).iter().zip(cam.project(&y)) {
                prop_assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
            }
            let back = depth_reflection(&y, &r);
            for (p, q) in x.iter().zip(&back) {
                prop_assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-12));
            }
            let triple = |p: &[[f64; 3]; NUM_LANDMARKS]| {
                let v = |i: usize| Vector3::from(p[i]) - Vector3::from(p[0]);
                v(1).cross(&v(2)).dot(&v(3))
            };
            prop_assert!((triple(&x) + triple(&y)).abs() < 1e-12);
            let px = Pose3::new(x);
            let py = Pose3::new(y);
            for limb in 0..camloc_skeleton::NUM_LIMBS {
                prop_assert!((px.limb_length(limb) - py.limb_length(limb)).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn optimal_translation_centres_the_residual() {
        let r = rotation_about_axis(Vector3::new(0.2, 0.5, -0.4), 1.1);
        let cam = WeakPerspective {
            scale: 2.0,
            rotation: r,
            translation: [5.0, 7.0],
        };
        let x = cloud(0.3);
        let shifted = cam.project(&x).map(|p| [p[0] - 3.0, p[1] + 1.5]);
        let fixed = with_optimal_translation(&cam, &x, &shifted);
        assert!((fixed.translation[0] - 2.0).abs() < 1e-12);
        assert!((fixed.translation[1] - 8.5).abs() < 1e-12);
        assert!(fixed.squared_error(&x, &shifted).unwrap() < 1e-20);
    }
}
