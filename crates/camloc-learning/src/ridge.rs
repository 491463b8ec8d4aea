//! Multi-output ridge regression on standardised features, and [`DirectionHeads`]: one
//! ridge regression of a unit 3D direction per class, the continuous refinement of a
//! classifier whose classes are directions (camera viewpoints).

use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, Par, Side};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::elevation_fit::ElevationFit;
use crate::standardise::RawLinear;
use crate::{DesignRows, Features, LearningError, Standardiser};

/// Standardised rows [`RidgeModel`]'s fit multiplies together at a time (a few megabytes
/// of buffer whatever the number of rows).
const GRAM_ROWS: usize = 256;

/// A fitted multi-output ridge regression `y = W ((x - mean) / scale) + b`.
#[derive(Clone, Debug, PartialEq)]
pub struct RidgeModel {
    parameters: RidgeParameters,
    /// The map on raw features (standardisation folded in), derived from `parameters`.
    raw: RawLinear,
}

/// What a [`RidgeModel`] stores; the rest is derived from it on decoding.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct RidgeParameters {
    standardiser: Standardiser,
    /// `n_outputs x d`, row-major.
    weights: Vec<f64>,
    biases: Vec<f64>,
}

impl Serialize for RidgeModel {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.parameters.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for RidgeModel {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        RidgeParameters::deserialize(deserializer).map(RidgeModel::from_parameters)
    }
}

impl RidgeModel {
    /// Fits `min_W,b sum_i ||y_i - W z_i - b||^2 + lambda ||W||_F^2` on standardised
    /// features `z_i` (the standardiser is fitted on `x` and kept), with `y` row-major
    /// `n x n_outputs`. The bias is not penalised (it is the mean of `y`).
    ///
    /// # Errors
    /// [`LearningError::NoSamples`], [`LearningError::SizeMismatch`] for a `y` of the wrong
    /// length, [`LearningError::InvalidParameter`] for a negative or non-finite `lambda` or
    /// a non-finite target, [`LearningError::Singular`] when the regularised Gram matrix
    /// cannot be factorised (`lambda = 0` with dependent features).
    pub fn fit(
        x: &Features<'_>,
        y: &[f64],
        n_outputs: usize,
        lambda: f64,
    ) -> Result<RidgeModel, LearningError> {
        let n = x.n_samples();
        if n == 0 {
            return Err(LearningError::NoSamples);
        }
        check_fit_inputs(n, y, n_outputs, lambda)?;
        let rows = DesignRows::plain(*x);
        Self::fit_selected(&rows, &(0..n).collect::<Vec<_>>(), n_outputs, lambda, |i| {
            &y[i * n_outputs..(i + 1) * n_outputs]
        })
    }

    /// One ridge regression per class `0..n_classes`, each fitted ([`fit`](Self::fit)) on
    /// the rows of `x` of that class (`classes`, one per row) with targets `y` (row-major
    /// `n x n_outputs`), the classes in parallel. Expanded rows are made as each fit reads
    /// them (nothing the size of the rows is held).
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] for inconsistent lengths, [`LearningError::NoSamples`]
    /// when a class has no rows, [`LearningError::InvalidParameter`] for a non-finite target
    /// or a bad `lambda`, and [`LearningError::Singular`] as [`fit`](Self::fit).
    pub fn fit_per_class(
        x: &DesignRows<'_>,
        y: &[f64],
        n_outputs: usize,
        classes: &[usize],
        n_classes: usize,
        lambda: f64,
    ) -> Result<Vec<RidgeModel>, LearningError> {
        let n = x.n_samples();
        if classes.len() != n {
            return Err(LearningError::SizeMismatch {
                what: "classes",
                expected: n,
                found: classes.len(),
            });
        }
        check_fit_inputs(n, y, n_outputs, lambda)?;
        (0..n_classes)
            .into_par_iter()
            .map(|k| {
                let rows: Vec<usize> = (0..n).filter(|&i| classes[i] == k).collect();
                RidgeModel::fit_selected(x, &rows, n_outputs, lambda, |i| {
                    &y[i * n_outputs..(i + 1) * n_outputs]
                })
            })
            .collect()
    }

    /// [`fit`](Self::fit) on the rows of `x` that `selected` names (at least one), row `i`'s
    /// targets being `target(i)` (`n_outputs` finite values, checked by the caller). The
    /// standardised rows are multiplied together [`GRAM_ROWS`] at a time into the lower half
    /// of the Gram matrix, so that memory does not grow with the rows (they are read twice
    /// for the standardiser and once for the products; expanded rows are made as they are
    /// read).
    fn fit_selected<'y>(
        x: &DesignRows<'_>,
        selected: &[usize],
        n_outputs: usize,
        lambda: f64,
        target: impl Fn(usize) -> &'y [f64],
    ) -> Result<RidgeModel, LearningError> {
        if selected.is_empty() {
            return Err(LearningError::NoSamples);
        }
        let d = x.n_features();
        let standardiser = Standardiser::fit_selected(x, selected.iter().copied());
        let (means, scales) = (standardiser.means(), standardiser.scales());
        let n = selected.len() as f64;
        let mut y_mean = vec![0.0; n_outputs];
        for &i in selected {
            for (m, v) in y_mean.iter_mut().zip(target(i)) {
                *m += v / n;
            }
        }
        let mut gram = Mat::<f64>::zeros(d, d);
        let mut rhs = Mat::<f64>::zeros(d, n_outputs);
        // Columns: the standardised rows of a batch; rows: their centred targets.
        let mut z = Mat::<f64>::zeros(d, GRAM_ROWS);
        let mut yc = Mat::<f64>::zeros(GRAM_ROWS, n_outputs);
        let mut filled = 0;
        let mut add = |z: &Mat<f64>, yc: &Mat<f64>, filled: usize| {
            let (z, yc) = (z.subcols(0, filled), yc.subrows(0, filled));
            triangular::matmul(
                gram.as_mut(),
                BlockStructure::TriangularLower,
                Accum::Add,
                z,
                BlockStructure::Rectangular,
                z.transpose(),
                BlockStructure::Rectangular,
                1.0,
                Par::Seq,
            );
            faer::linalg::matmul::matmul(rhs.as_mut(), Accum::Add, z, yc, 1.0, Par::Seq);
        };
        let Ok(()) = x.for_each_selected(selected.iter().copied(), |i, row| {
            let column = z.col_mut(filled).iter_mut();
            for (((zj, &v), m), s) in column.zip(row).zip(means).zip(scales) {
                *zj = (v - m) / s;
            }
            for (k, (v, m)) in target(i).iter().zip(&y_mean).enumerate() {
                yc[(filled, k)] = v - m;
            }
            filled += 1;
            if filled == GRAM_ROWS {
                add(&z, &yc, filled);
                filled = 0;
            }
            Ok::<(), std::convert::Infallible>(())
        });
        if filled > 0 {
            add(&z, &yc, filled);
        }
        for j in 0..d {
            gram[(j, j)] += lambda;
        }
        let llt = gram
            .as_ref()
            .llt(Side::Lower)
            .map_err(|_| LearningError::Singular {
                iteration: 0,
                damping: lambda,
            })?;
        let w = llt.solve(&rhs);
        let weights = (0..n_outputs)
            .flat_map(|k| (0..d).map(move |j| (k, j)))
            .map(|(k, j)| w[(j, k)])
            .collect();
        Ok(RidgeModel::from_parameters(RidgeParameters {
            standardiser,
            weights,
            biases: y_mean,
        }))
    }

    /// The model of `parameters`, with the map on raw features derived from them (sizes are
    /// checked by [`validate`](Self::validate)).
    fn from_parameters(parameters: RidgeParameters) -> Self {
        let p = &parameters;
        let d = p.standardiser.n_features();
        let raw = RawLinear::fold(
            &p.standardiser,
            |j, k| p.weights.get(k * d + j).copied().unwrap_or(0.0),
            p.weights.len(),
            &p.biases,
        );
        RidgeModel { parameters, raw }
    }

    /// Checks the invariants of a decoded model: a valid standardiser, at least one output,
    /// `n_outputs x n_features` weights, all weights and biases finite.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] for inconsistent shapes,
    /// [`LearningError::InvalidParameter`] for a non-finite coefficient or a bad standardiser.
    pub fn validate(&self) -> Result<(), LearningError> {
        self.parameters.standardiser.validate()?;
        let expected = self.n_features().checked_mul(self.n_outputs());
        if self.n_outputs() == 0 || expected != Some(self.parameters.weights.len()) {
            return Err(LearningError::SizeMismatch {
                what: "ridge weights (n_outputs >= 1 times n_features)",
                expected: expected.unwrap_or(usize::MAX),
                found: self.parameters.weights.len(),
            });
        }
        crate::model::all_finite(
            "ridge coefficient",
            &self.parameters.weights,
            &self.parameters.biases,
        )
    }

    /// Number of input features.
    pub fn n_features(&self) -> usize {
        self.parameters.standardiser.n_features()
    }

    /// Number of outputs.
    pub fn n_outputs(&self) -> usize {
        self.parameters.biases.len()
    }

    /// Predicts the outputs of one raw feature row `x` into `out` (length
    /// [`n_outputs`](Self::n_outputs)), without allocating.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] for wrong lengths.
    pub fn predict_into(&self, x: &[f64], out: &mut [f64]) -> Result<(), LearningError> {
        let d = self.n_features();
        if x.len() != d {
            return Err(LearningError::SizeMismatch {
                what: "feature row",
                expected: d,
                found: x.len(),
            });
        }
        if out.len() != self.n_outputs() {
            return Err(LearningError::SizeMismatch {
                what: "output buffer",
                expected: self.n_outputs(),
                found: out.len(),
            });
        }
        self.raw.apply_into(x, out);
        Ok(())
    }
}

/// Bounds of the probability bins of [`DirectionHeads`]' uncertainty calibration: the
/// uncertainty of a prediction is looked up by the probability of its class.
pub const CONFIDENCE_BINS: [f64; 4] = [0.5, 0.8, 0.95, 0.99];

/// One ridge regression of a unit direction per class: given the class a classifier chose
/// (or a sample's true class in training), predicts the direction from the same features,
/// normalised to unit length. Each head is fitted only on samples of its class, so it
/// resolves the direction within the class's region, where the mapping is close to linear.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DirectionHeads {
    heads: Vec<RidgeModel>,
    /// Angular error (degrees) holding 68% of the calibration samples, per bin of
    /// [`CONFIDENCE_BINS`] (below the first bound, between bounds, above the last).
    uncertainty_deg: Vec<f64>,
    /// Per class, how its head's elevations follow the true ones on the calibration samples
    /// chosen as that class.
    elevation_fits: Vec<ElevationFit>,
}

impl DirectionHeads {
    /// Fits one head per class `0..n_classes` on the samples of that class (`x` rows,
    /// `directions` unit vectors `[x, y, z]` per sample, `classes` their class), with ridge
    /// weight `lambda`, the classes in parallel. Expanded rows are made as each head reads
    /// them (nothing the size of the rows is held). The uncertainty table is calibrated on
    /// `calibration`: per sample, the class chosen, its probability, the features and the
    /// true direction.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] for inconsistent lengths, [`LearningError::NoSamples`]
    /// naming no class in particular when a class has no samples,
    /// [`LearningError::InvalidParameter`] for a non-finite direction or a bad `lambda`, and
    /// [`LearningError::Singular`] as [`RidgeModel::fit`].
    pub fn fit(
        x: &DesignRows<'_>,
        directions: &[[f64; 3]],
        classes: &[usize],
        n_classes: usize,
        lambda: f64,
    ) -> Result<DirectionHeads, LearningError> {
        if directions.len() != x.n_samples() {
            return Err(LearningError::SizeMismatch {
                what: "directions",
                expected: x.n_samples(),
                found: directions.len(),
            });
        }
        let heads =
            RidgeModel::fit_per_class(x, directions.as_flattened(), 3, classes, n_classes, lambda)?;
        Ok(DirectionHeads {
            elevation_fits: vec![ElevationFit::IDENTITY; heads.len()],
            heads,
            uncertainty_deg: vec![f64::NAN; CONFIDENCE_BINS.len() + 1],
        })
    }

    /// Calibrates the uncertainty table: for each sample (row of `x`, the class
    /// `chosen` for it with probability `probability`, its true unit direction), the
    /// angular error of [`predict`](Self::predict); per probability bin, the error below
    /// which 68% of its samples lie (bins without samples take the next lower bin's value,
    /// or 180 deg). Then each class's [`ElevationFit`] of the predicted on the true
    /// elevations of the samples chosen as that class.
    ///
    /// # Errors
    /// As [`predict`](Self::predict), and [`LearningError::SizeMismatch`].
    pub fn calibrate(
        &mut self,
        x: &DesignRows<'_>,
        chosen: &[(usize, f64)],
        directions: &[[f64; 3]],
    ) -> Result<(), LearningError> {
        let n = x.n_samples();
        if chosen.len() != n || directions.len() != n {
            return Err(LearningError::SizeMismatch {
                what: "calibration classes and directions",
                expected: n,
                found: chosen.len().min(directions.len()),
            });
        }
        let mut errors: Vec<Vec<f64>> = vec![Vec::new(); CONFIDENCE_BINS.len() + 1];
        let mut elevations: Vec<Vec<(f64, f64)>> = vec![Vec::new(); self.heads.len()];
        x.try_for_each_row(|i, row| {
            let (class, p) = chosen[i];
            let predicted = self.predict(class, row)?;
            errors[bin_of(p)].push(angle_deg(&predicted, &directions[i]));
            elevations[class].push((elevation_deg(&directions[i]), elevation_deg(&predicted)));
            Ok(())
        })?;
        self.elevation_fits = elevations.into_iter().map(ElevationFit::of).collect();
        let mut last = 180.0;
        for (slot, mut e) in self.uncertainty_deg.iter_mut().zip(errors) {
            if !e.is_empty() {
                e.sort_by(f64::total_cmp);
                last = e[((e.len() as f64 * 0.68).ceil() as usize).clamp(1, e.len()) - 1];
            }
            *slot = last;
        }
        Ok(())
    }

    /// Checks the invariants of decoded heads against the classifier they refine: one head
    /// per class (`n_classes`), each a valid [`RidgeModel`] of `n_features` inputs and 3
    /// outputs, and one finite uncertainty in `[0, 180]` degrees per probability bin.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] naming the shape that differs,
    /// [`LearningError::InvalidParameter`] for a bad coefficient or uncertainty.
    pub fn validate(&self, n_classes: usize, n_features: usize) -> Result<(), LearningError> {
        if self.heads.len() != n_classes {
            return Err(LearningError::SizeMismatch {
                what: "direction heads (one per class)",
                expected: n_classes,
                found: self.heads.len(),
            });
        }
        for head in &self.heads {
            head.validate()?;
            if head.n_features() != n_features {
                return Err(LearningError::SizeMismatch {
                    what: "direction head features",
                    expected: n_features,
                    found: head.n_features(),
                });
            }
            if head.n_outputs() != 3 {
                return Err(LearningError::SizeMismatch {
                    what: "direction head outputs (x, y, z)",
                    expected: 3,
                    found: head.n_outputs(),
                });
            }
        }
        if self.uncertainty_deg.len() != CONFIDENCE_BINS.len() + 1 {
            return Err(LearningError::SizeMismatch {
                what: "uncertainty table (one per probability bin)",
                expected: CONFIDENCE_BINS.len() + 1,
                found: self.uncertainty_deg.len(),
            });
        }
        if self.elevation_fits.len() != n_classes {
            return Err(LearningError::SizeMismatch {
                what: "elevation fits (one per class)",
                expected: n_classes,
                found: self.elevation_fits.len(),
            });
        }
        self.elevation_fits
            .iter()
            .try_for_each(ElevationFit::validate)?;
        if let Some(v) = self
            .uncertainty_deg
            .iter()
            .find(|v| !(v.is_finite() && (0.0..=180.0).contains(*v)))
        {
            return Err(LearningError::InvalidParameter {
                name: "viewpoint uncertainty",
                value: format!("{v:?}"),
                reason: "must be calibrated: finite, in [0, 180] degrees",
            });
        }
        Ok(())
    }

    /// The unit direction predicted by the head of `class` for the raw feature row `x`.
    ///
    /// # Errors
    /// [`LearningError::LabelOutOfRange`] for an unknown class, [`RidgeModel::predict_into`]'s
    /// errors.
    pub fn predict(&self, class: usize, x: &[f64]) -> Result<[f64; 3], LearningError> {
        let head = self
            .heads
            .get(class)
            .ok_or(LearningError::LabelOutOfRange {
                row: 0,
                label: class,
                n_classes: self.heads.len(),
            })?;
        let mut u = [0.0; 3];
        head.predict_into(x, &mut u)?;
        let norm = u.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm > 0.0 {
            u.iter_mut().for_each(|v| *v /= norm);
        }
        Ok(u)
    }

    /// How the elevations of the head of `class` follow the true ones
    /// ([`ElevationFit::IDENTITY`] for an unknown class or before
    /// [`calibrate`](Self::calibrate)).
    pub fn elevation_fit(&self, class: usize) -> ElevationFit {
        self.elevation_fits
            .get(class)
            .copied()
            .unwrap_or(ElevationFit::IDENTITY)
    }

    /// The number of features each head reads (0 without heads).
    pub fn n_features(&self) -> usize {
        self.heads.first().map_or(0, RidgeModel::n_features)
    }

    /// The calibrated uncertainty (degrees, the angular radius holding about 68% of the
    /// calibration errors) of a prediction whose class has probability `probability`; NaN
    /// before [`calibrate`](Self::calibrate).
    pub fn uncertainty_deg(&self, probability: f64) -> f64 {
        self.uncertainty_deg
            .get(bin_of(probability))
            .copied()
            .unwrap_or(f64::NAN)
    }
}

/// Checks a ridge weight: finite and `>= 0`.
fn check_lambda(lambda: f64) -> Result<(), LearningError> {
    if !(lambda.is_finite() && lambda >= 0.0) {
        return Err(LearningError::InvalidParameter {
            name: "lambda",
            value: format!("{lambda:?}"),
            reason: "must be finite and >= 0",
        });
    }
    Ok(())
}

/// Checks what a ridge fit of `n` rows is given: `y` of `n x n_outputs` values
/// (`n_outputs >= 1`), all finite, and `lambda`.
fn check_fit_inputs(
    n: usize,
    y: &[f64],
    n_outputs: usize,
    lambda: f64,
) -> Result<(), LearningError> {
    if y.len() != n * n_outputs || n_outputs == 0 {
        return Err(LearningError::SizeMismatch {
            what: "targets (n_samples x n_outputs, n_outputs >= 1)",
            expected: n * n_outputs.max(1),
            found: y.len(),
        });
    }
    check_lambda(lambda)?;
    check_targets(y)
}

/// Checks regression targets: all finite.
fn check_targets(y: &[f64]) -> Result<(), LearningError> {
    match y.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(LearningError::InvalidParameter {
            name: "target",
            value: format!("{v:?}"),
            reason: "targets must be finite",
        }),
        None => Ok(()),
    }
}

fn bin_of(p: f64) -> usize {
    CONFIDENCE_BINS.iter().take_while(|&&b| p >= b).count()
}

/// Elevation in degrees of a unit direction `[x, y, z]` (z up).
fn elevation_deg(u: &[f64; 3]) -> f64 {
    u[2].clamp(-1.0, 1.0).asin().to_degrees()
}

/// Angle in degrees between two unit vectors (atan2 of the cross and dot products, accurate
/// at small angles where acos is not).
pub fn angle_deg(u: &[f64; 3], v: &[f64; 3]) -> f64 {
    let dot: f64 = (0..3).map(|k| u[k] * v[k]).sum();
    let c = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    c.iter()
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
        .atan2(dot)
        .to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ridge_recovers_a_linear_map_and_heads_a_direction() {
        // y = [2 x0 - x1 + 3, x1]; tiny lambda.
        let x: Vec<f64> = (0..40)
            .flat_map(|i| [i as f64 * 0.1, (i * i % 7) as f64])
            .collect();
        let y: Vec<f64> = x
            .chunks(2)
            .flat_map(|r| [2.0 * r[0] - r[1] + 3.0, r[1]])
            .collect();
        let f = Features::new(&x, 2).unwrap();
        let m = RidgeModel::fit(&f, &y, 2, 1e-9).unwrap();
        let mut out = [0.0; 2];
        m.predict_into(&[1.5, 2.0], &mut out).unwrap();
        assert!(
            (out[0] - 4.0).abs() < 1e-6 && (out[1] - 2.0).abs() < 1e-6,
            "{out:?}"
        );
        assert!(m.predict_into(&[1.0], &mut out).is_err());
        assert!(RidgeModel::fit(&f, &y[..3], 2, 1.0).is_err());
        assert!(RidgeModel::fit(&f, &y, 2, -1.0).is_err());

        // Directions in the xy plane at angle a = x0, one class: the head predicts them.
        let angles: Vec<f64> = (0..50).map(|i| -0.3 + 0.012 * i as f64).collect();
        let xs: Vec<f64> = angles.iter().flat_map(|a| [a.cos(), a.sin()]).collect();
        let dirs: Vec<[f64; 3]> = angles.iter().map(|a| [a.cos(), a.sin(), 0.0]).collect();
        let fx = DesignRows::plain(Features::new(&xs, 2).unwrap());
        let mut heads = DirectionHeads::fit(&fx, &dirs, &vec![0; 50], 1, 1e-9).unwrap();
        assert!(heads.uncertainty_deg(0.9).is_nan());
        let chosen = vec![(0, 0.9); 50];
        heads.calibrate(&fx, &chosen, &dirs).unwrap();
        assert!(heads.uncertainty_deg(0.9) < 1e-3);
        assert_eq!(heads.uncertainty_deg(0.2), 180.0);
        let u = heads.predict(0, &[0.1f64.cos(), 0.1f64.sin()]).unwrap();
        assert!(angle_deg(&u, &[0.1f64.cos(), 0.1f64.sin(), 0.0]) < 1e-3);
        assert!(heads.predict(1, &[1.0, 0.0]).is_err());
        heads.validate(1, 2).unwrap();
        assert!(heads.validate(2, 2).is_err());
        assert!(heads.validate(1, 3).is_err());
        let mut broken = heads.clone();
        broken.heads[0].parameters.weights[0] = f64::NAN;
        assert!(broken.validate(1, 2).is_err());
        let mut uncalibrated = heads.clone();
        uncalibrated.uncertainty_deg[0] = f64::NAN;
        assert!(uncalibrated.validate(1, 2).is_err());
    }

    /// Heads fitted on rows expanded as they are read give the heads fitted on the stored
    /// expansion (several batches of [`GRAM_ROWS`] per class, a partial last one).
    #[test]
    fn heads_on_rows_expanded_as_read_equal_heads_on_stored_rows() {
        let n = 3 * GRAM_ROWS + 17;
        let x: Vec<f64> = (0..n * 4)
            .map(|i| (i as f64 * 0.37).sin() + (i % 5) as f64 * 0.1)
            .collect();
        let f = Features::new(&x, 4).unwrap();
        let expansion = crate::QuadraticExpansion::fit(&f, 2).unwrap();
        let stored = expansion.expand_rows(&f).unwrap();
        let stored = Features::new(&stored, expansion.n_outputs()).unwrap();
        let classes: Vec<usize> = (0..n).map(|i| i % 2).collect();
        let directions: Vec<[f64; 3]> = x
            .chunks_exact(4)
            .map(|r| {
                let v = [1.0 + r[0] * r[1], r[2], 0.5 + r[3]];
                let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
                v.map(|a| a / norm)
            })
            .collect();
        let read = DesignRows::expanded(f, &expansion).unwrap();
        let a = DirectionHeads::fit(&read, &directions, &classes, 2, 0.1).unwrap();
        let b =
            DirectionHeads::fit(&DesignRows::plain(stored), &directions, &classes, 2, 0.1).unwrap();
        let mut largest = 0.0_f64;
        for (i, row) in stored.rows().enumerate().step_by(37) {
            let (u, v) = (
                a.predict(i % 2, row).unwrap(),
                b.predict(i % 2, row).unwrap(),
            );
            largest = largest.max(angle_deg(&u, &v));
        }
        assert!(largest < 1e-9, "heads differ by {largest} deg");

        // The ridge fit over several batches meets its optimality conditions: on the
        // standardised rows z, sum_i (y_i - f(x_i)) z_i = lambda w and sum_i (y_i - f(x_i)) = 0.
        let y: Vec<f64> = directions.as_flattened().to_vec();
        let lambda = 0.1;
        let m = RidgeModel::fit(&stored, &y, 3, lambda).unwrap();
        let (p, d) = (&m.parameters, stored.n_features());
        let mut gradient = vec![0.0; 3 * (d + 1)];
        let mut out = [0.0; 3];
        for (row, target) in stored.rows().zip(y.chunks_exact(3)) {
            m.predict_into(row, &mut out).unwrap();
            for k in 0..3 {
                let r = target[k] - out[k];
                gradient[k * (d + 1) + d] += r;
                for j in 0..d {
                    let z = (row[j] - p.standardiser.means()[j]) / p.standardiser.scales()[j];
                    gradient[k * (d + 1) + j] += r * z;
                }
            }
        }
        for k in 0..3 {
            for j in 0..=d {
                let penalty = if j < d {
                    lambda * p.weights[k * d + j]
                } else {
                    0.0
                };
                let g = gradient[k * (d + 1) + j] - penalty;
                assert!(g.abs() < 1e-8, "output {k}, feature {j}: {g}");
            }
        }
    }
}
