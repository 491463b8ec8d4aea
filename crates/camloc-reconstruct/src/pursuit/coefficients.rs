//! The coefficient step of the pursuit: exact constrained least squares for the selected
//! components' coefficients with the camera fixed, from the normal equations, in buffers
//! reused across the alternations.

use camloc_geometry::WeakPerspective;
use camloc_skeleton::NUM_LANDMARKS;

use super::observation::{IMAGE_DIM, Observation};
use super::reconstructor::Reconstructor;
use crate::ReconstructError;
use crate::basis::POSE_DIM;
use crate::lsq::{NormalSolve, QuadraticConstraint};

/// The buffers of [`Reconstructor::solve_coefficients`]: kept over the alternations of one
/// selected set, so that a step allocates nothing.
#[derive(Debug, Default)]
pub(super) struct CoefficientStep {
    /// The selected components' centred projections, column-major `IMAGE_DIM x m`.
    projected: Vec<f64>,
    /// `A^T A` (column-major `m x m`) and `A^T b` of the step.
    normal: Vec<f64>,
    rhs: Vec<f64>,
    /// The solve, with its solution.
    solve: NormalSolve,
}

impl CoefficientStep {
    /// Buffers whose first solve starts its Newton iteration at `multiplier`.
    pub(super) fn starting_from(multiplier: Option<f64>) -> CoefficientStep {
        CoefficientStep {
            solve: NormalSolve::starting_from(multiplier),
            ..CoefficientStep::default()
        }
    }

    /// The constraint's multiplier in the last step.
    pub(super) fn multiplier(&self) -> Option<f64> {
        self.solve.multiplier()
    }

    /// The coefficients of the last step.
    pub(super) fn coefficients(&self) -> &[f64] {
        &self.solve.w
    }
}

impl Reconstructor {
    /// Exact constrained least squares for the coefficients of `selected` (whose constraint
    /// is `constraint`) with the camera's scale and rotation fixed and the translation
    /// eliminated by centring: `min |A w - b|^2 + prior` with `A` the centred projections of
    /// the components and `b` the observation minus the centred projection of the mean; the
    /// coefficient prior adds `prior / var_j` to the diagonal of `A^T A`. The coefficients
    /// are left in `step` ([`CoefficientStep::coefficients`]).
    pub(super) fn solve_coefficients(
        &self,
        obs: &Observation,
        camera: &WeakPerspective,
        selected: &[usize],
        constraint: &QuadraticConstraint,
        step: &mut CoefficientStep,
    ) -> Result<(), ReconstructError> {
        let m = selected.len();
        step.projected.resize(IMAGE_DIM * m, 0.0);
        for (column, &j) in step.projected.chunks_exact_mut(IMAGE_DIM).zip(selected) {
            project_centred(camera, self.component(j), column);
        }
        let mut residual = [0.0; IMAGE_DIM];
        project_centred(camera, self.basis.mean_vector().as_slice(), &mut residual);
        for (r, target) in residual.iter_mut().zip(obs.points.iter().flatten()) {
            *r = target - *r;
        }
        step.normal.resize(m * m, 0.0);
        step.rhs.resize(m, 0.0);
        for a in 0..m {
            let column_a = &step.projected[IMAGE_DIM * a..IMAGE_DIM * (a + 1)];
            for b in a..m {
                let column_b = &step.projected[IMAGE_DIM * b..IMAGE_DIM * (b + 1)];
                let dot: f64 = column_a.iter().zip(column_b).map(|(x, y)| x * y).sum();
                step.normal[a + b * m] = dot;
                step.normal[b + a * m] = dot;
            }
            step.rhs[a] = column_a.iter().zip(&residual).map(|(x, y)| x * y).sum();
        }
        if self.config.coefficient_prior > 0.0 {
            // The prior's rows sqrt(prior / var_j) w_j = 0 under the image rows.
            for (a, &j) in selected.iter().enumerate() {
                let variance = self.basis.explained_variance()[j].max(f64::MIN_POSITIVE);
                let weight = (self.config.coefficient_prior / variance).sqrt();
                step.normal[a + a * m] += weight * weight;
            }
        }
        constraint.solve_normal(&step.normal, &step.rhs, &mut step.solve)?;
        Ok(())
    }

    /// Component `j` as a landmark-major slice (`j` must be a valid component index).
    pub(super) fn component(&self, j: usize) -> &[f64] {
        let data = self.basis.components().as_slice();
        &data[POSE_DIM * j..POSE_DIM * (j + 1)]
    }
}

/// `s [I2 0] R` applied to every landmark of the pose-space vector `v`, centred over the
/// landmarks, into the image-space `out` (`u0, v0, u1, ...`).
fn project_centred(camera: &WeakPerspective, v: &[f64], out: &mut [f64]) {
    let r = &camera.rotation;
    let mut mean = [0.0; 2];
    for (x, o) in v.chunks_exact(3).zip(out.chunks_exact_mut(2)) {
        for row in 0..2 {
            let p = camera.scale * (r[(row, 0)] * x[0] + r[(row, 1)] * x[1] + r[(row, 2)] * x[2]);
            o[row] = p;
            mean[row] += p / NUM_LANDMARKS as f64;
        }
    }
    for (i, o) in out.iter_mut().enumerate() {
        *o -= mean[i % 2];
    }
}
