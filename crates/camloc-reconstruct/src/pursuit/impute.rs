//! Missing 2D landmarks filled in from the pose basis seen by a known camera rotation, so
//! that a pose with landmarks missing (occluded, outside the image, under a detector's score
//! threshold) can be reconstructed (docs/conventions.md section 6, "Missing landmarks").

use camloc_geometry::Matrix3;
use camloc_skeleton::{Landmark, PartialPose2, Pose2};
use nalgebra::{DMatrix, DVector, Vector3};

use crate::{ReconstructError, Reconstructor};
use camloc_skeleton::{centroid, rms_radius};

impl Reconstructor {
    /// `pose` with its missing landmarks filled in (the present ones are returned as given):
    /// the present landmarks are fitted by a pose of the basis, `mu + B w` over its principal
    /// components, seen by a weak-perspective camera with the given `rotation` (body frame to
    /// camera frame, e.g. a localized viewpoint's) and unknown scale and translation; the
    /// coefficients `w` are held by a Gaussian prior (each component's training variance,
    /// the landmarks' deviation [`Refinement::image_sigma`](crate::Refinement::image_sigma)
    /// of the present landmarks' RMS radius). The missing landmarks are that pose's
    /// projections. A complete pose comes back unchanged.
    ///
    /// `rotation` is used as given: a matrix that is not a rotation gives meaningless fills.
    ///
    /// # Errors
    /// [`ReconstructError::NonFiniteInput`] for a present landmark that is not finite;
    /// [`ReconstructError::DegenerateInput`] when fewer than two landmarks are present or they
    /// coincide; [`ReconstructError::Numerical`] when the fit has no solution.
    pub fn impute(
        &self,
        pose: &PartialPose2,
        rotation: &Matrix3,
    ) -> Result<Pose2, ReconstructError> {
        if let Some(complete) = pose.complete().filter(Pose2::is_finite) {
            return Ok(complete);
        }
        self.impute_with_misfit(pose, rotation)
            .map(|(pose, _)| pose)
    }

    /// `pose` filled in as [`Reconstructor::impute`] fills it, and the fit's misfit: the share
    /// of the present landmarks' spread (their squared distances from their centroid) that
    /// the fitted basis pose's projections leave unexplained, 0 for a perfect fit, at most 1
    /// (the fit explains no less than the centroid alone). A rotation from which no pose of the basis looks like the present landmarks has
    /// a large misfit. A complete pose is fitted too (and comes back unchanged).
    ///
    /// # Errors
    /// As [`Reconstructor::impute`].
    pub fn impute_with_misfit(
        &self,
        pose: &PartialPose2,
        rotation: &Matrix3,
    ) -> Result<(Pose2, f64), ReconstructError> {
        let present: Vec<(usize, [f64; 2])> = pose
            .points
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (i, p)))
            .collect();
        if let Some(&(landmark, _)) = present
            .iter()
            .find(|(_, p)| !p.iter().all(|c| c.is_finite()))
        {
            return Err(ReconstructError::NonFiniteInput {
                landmark,
                name: Landmark::ALL[landmark].name(),
            });
        }
        if present.len() < 2 {
            return Err(ReconstructError::DegenerateInput(
                "fewer than two landmarks to fill the missing ones from",
            ));
        }
        // Centred on the present landmarks' centroid and divided by their largest deviation,
        // so that no square below overflows or underflows whatever the input's units.
        let points: Vec<[f64; 2]> = present.iter().map(|(_, p)| *p).collect();
        let centre = centroid(&points);
        let spread = points
            .iter()
            .flat_map(|p| [(p[0] - centre[0]).abs(), (p[1] - centre[1]).abs()])
            .fold(0.0, f64::max);
        if !(spread > 0.0 && spread.is_finite()) {
            return Err(ReconstructError::DegenerateInput(
                "the landmarks present coincide",
            ));
        }
        let observed: Vec<[f64; 2]> = points
            .iter()
            .map(|p| [(p[0] - centre[0]) / spread, (p[1] - centre[1]) / spread])
            .collect();
        let fit = self.basis_fit(&present, &observed, rotation)?;
        let unexplained: f64 = present
            .iter()
            .zip(&observed)
            .map(|((i, _), u)| {
                let d = fit.project(*i);
                (d[0] - u[0]).powi(2) + (d[1] - u[1]).powi(2)
            })
            .sum();
        let spread_squared: f64 = observed.iter().map(|u| u[0] * u[0] + u[1] * u[1]).sum();
        let mut points = pose.points.map(|p| p.unwrap_or_default());
        for (i, point) in points.iter_mut().enumerate() {
            if pose.points[i].is_none() {
                let d = fit.project(i);
                *point = [centre[0] + spread * d[0], centre[1] + spread * d[1]];
            }
        }
        Ok((Pose2::new(points), unexplained / spread_squared))
    }

    /// The basis pose and weak-perspective camera (rotation `rotation`) that fit the
    /// `observed` points (normalised) of the landmarks in `present`, by ridge least squares
    /// in `(s, t, v = s w)`.
    fn basis_fit(
        &self,
        present: &[(usize, [f64; 2])],
        observed: &[[f64; 2]],
        rotation: &Matrix3,
    ) -> Result<BasisFit, ReconstructError> {
        let basis = self.basis();
        let components: Vec<usize> = (0..basis.n_principal())
            .filter(|&k| basis.explained_variance()[k] > 0.0)
            .collect();
        let seen = |column: &[f64]| -> Vec<[f64; 2]> {
            column
                .chunks_exact(3)
                .map(|c| {
                    let q = rotation * Vector3::new(c[0], c[1], c[2]);
                    [q.x, q.y]
                })
                .collect()
        };
        let mean = seen(basis.mean_vector().as_slice());
        let seen_components: Vec<Vec<[f64; 2]>> = components
            .iter()
            .map(|&k| seen(basis.components().column(k).as_slice()))
            .collect();
        // The scale of the mean pose fitted alone sets the prior's units: v = s w.
        let mean_present: Vec<[f64; 2]> = present.iter().map(|(i, _)| mean[*i]).collect();
        let (observed_radius, mean_radius) = (rms_radius(observed), rms_radius(&mean_present));
        if !(mean_radius > 0.0 && observed_radius > 0.0) {
            return Err(ReconstructError::DegenerateInput(
                "the landmarks present coincide",
            ));
        }
        let scale = observed_radius / mean_radius;
        let sigma = self.config().refinement.image_sigma * observed_radius;
        // Unknowns: s, t_x, t_y, then v_k.
        let dim = 3 + components.len();
        let mut normal = DMatrix::<f64>::zeros(dim, dim);
        let mut rhs = DVector::<f64>::zeros(dim);
        let mut row = vec![0.0; dim];
        for ((i, _), u) in present.iter().zip(observed) {
            for axis in 0..2 {
                row.fill(0.0);
                row[0] = mean[*i][axis];
                row[1 + axis] = 1.0;
                for (r, c) in row[3..].iter_mut().zip(&seen_components) {
                    *r = c[*i][axis];
                }
                for a in 0..dim {
                    rhs[a] += row[a] * u[axis];
                    for b in 0..dim {
                        normal[(a, b)] += row[a] * row[b];
                    }
                }
            }
        }
        for (j, &k) in components.iter().enumerate() {
            normal[(3 + j, 3 + j)] += (sigma / scale).powi(2) / basis.explained_variance()[k];
        }
        let solution = normal
            .cholesky()
            .map(|c| c.solve(&rhs))
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or(ReconstructError::Numerical(
                "the fit of the present landmarks has no solution",
            ))?;
        Ok(BasisFit {
            mean,
            components: seen_components,
            solution,
        })
    }
}

/// A basis pose fitted to present landmarks: what each landmark projects to.
struct BasisFit {
    /// The mean pose's landmarks under the rotation (image axes, metres).
    mean: Vec<[f64; 2]>,
    /// The principal components' landmarks under the rotation.
    components: Vec<Vec<[f64; 2]>>,
    /// `(s, t_x, t_y, v_1, ...)`.
    solution: DVector<f64>,
}

impl BasisFit {
    /// Landmark `i` of the fitted pose, projected (normalised image units).
    fn project(&self, i: usize) -> [f64; 2] {
        std::array::from_fn(|axis| {
            self.solution[0] * self.mean[i][axis]
                + self.solution[1 + axis]
                + self
                    .components
                    .iter()
                    .zip(self.solution.iter().skip(3))
                    .map(|(c, v)| v * c[i][axis])
                    .sum::<f64>()
        })
    }
}
