//! The greedy loop of projected matching pursuit: choose the component that best explains the
//! residual, then alternate exact constrained coefficient solves with camera updates.

use camloc_geometry::WeakPerspective;
use camloc_skeleton::NUM_LANDMARKS;
use nalgebra::{DMatrix, DVector};

use super::camera_update::{CameraUpdate, with_optimal_translation};
use super::coefficients::CoefficientStep;
use super::observation::Observation;
use super::reconstructor::Reconstructor;
use crate::basis::POSE_DIM;
use crate::lsq::QuadraticConstraint;
use crate::{ReconstructError, is_positive};

/// One hypothesis of the pursuit: selected components, coefficients, pose, camera, error.
#[derive(Clone, Debug)]
pub(super) struct Fit {
    pub(super) selected: Vec<usize>,
    pub(super) coefficients: Vec<f64>,
    pub(super) points: [[f64; 3]; NUM_LANDMARKS],
    pub(super) camera: WeakPerspective,
    /// Squared reprojection error in normalised image units.
    pub(super) error: f64,
    pub(super) iterations: usize,
    /// The constraint's multiplier in the last coefficient step: where the next one's
    /// Newton iteration starts (the root does not depend on the start; a near one saves
    /// steps).
    pub(super) multiplier: Option<f64>,
}

impl Reconstructor {
    /// The greedy loop: add components while they help.
    pub(super) fn pursue(
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
        // The best so far as (j, |a_j . r|^2 / s^2, |a_j|^2 / s^2) (the common factor s drops
        // out); scores compared without roots or divisions.
        let mut best: Option<(usize, f64, f64)> = None;
        let [x, y, z] = axis;
        for (j, (&(trace, c), dot)) in self.scatter.iter().zip(dots.iter()).enumerate() {
            let along = c[0] * x * x
                + c[3] * y * y
                + c[5] * z * z
                + 2.0 * (c[1] * x * y + c[2] * x * z + c[4] * y * z);
            let norm2 = trace - along;
            if !is_positive(norm2) || fit.selected.contains(&j) {
                continue;
            }
            let dot2 = dot * dot;
            if best.is_none_or(|(_, d, n)| dot2 * n > d * norm2) {
                best = Some((j, dot2, norm2));
            }
        }
        best.map(|(j, _, _)| j)
    }

    /// Alternates coefficient solves and camera updates on the selected set until the error
    /// stops falling. Every step keeps the lower-error camera, so the error never rises.
    pub(super) fn alternate(
        &self,
        obs: &Observation,
        fit: &mut Fit,
        update: CameraUpdate,
    ) -> Result<(), ReconstructError> {
        let constraint = self.constraint(&fit.selected)?;
        let mut step = CoefficientStep::starting_from(fit.multiplier);
        let mut previous = f64::INFINITY;
        for _ in 0..self.config.max_alternations {
            self.solve_coefficients(obs, &fit.camera, &fit.selected, &constraint, &mut step)?;
            let points = self.points(&fit.selected, step.coefficients());
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
            fit.coefficients.clear();
            fit.coefficients.extend_from_slice(step.coefficients());
            fit.points = points;
            fit.camera = camera;
            fit.error = error;
            fit.iterations += 1;
            fit.multiplier = step.multiplier();
            let improved = error < previous * (1.0 - self.config.alternation_tolerance);
            if !improved {
                break;
            }
            previous = error;
        }
        Ok(())
    }

    /// The anthropometric constraint on the coefficients of `selected`, factorised.
    pub(super) fn constraint(
        &self,
        selected: &[usize],
    ) -> Result<QuadraticConstraint, ReconstructError> {
        let m = selected.len();
        let q = DMatrix::from_fn(m, m, |r, c| self.gram[(selected[r], selected[c])]);
        let c = DVector::from_fn(m, |r, _| self.cross[selected[r]]);
        QuadraticConstraint::new(&q, &c, self.offset)
    }

    /// The pose `mu + sum_j w_j b_j` over `selected`, as points.
    pub(super) fn points(
        &self,
        selected: &[usize],
        coefficients: &[f64],
    ) -> [[f64; 3]; NUM_LANDMARKS] {
        let mut flat = [0.0; POSE_DIM];
        flat.copy_from_slice(self.basis.mean_vector().as_slice());
        for (&j, &w) in selected.iter().zip(coefficients) {
            for (x, b) in flat.iter_mut().zip(self.component(j)) {
                *x += w * b;
            }
        }
        let mut points = [[0.0; 3]; NUM_LANDMARKS];
        for (point, xyz) in points.iter_mut().zip(flat.chunks_exact(3)) {
            point.copy_from_slice(xyz);
        }
        points
    }
}
