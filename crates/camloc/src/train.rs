//! Training a [`CameraLocalizer`]: descriptors of the (mirrored, landmark-dropped) samples,
//! the multinomial classifier and the continuous-viewpoint heads.

use camloc_dataset::{Dataset, PostureGroup, camera_direction_deg, direction_vector};
use camloc_learning::{
    DesignRows, DirectionHeads, Features, FitReport, IterationLog, NewtonProblem,
    QuadraticExpansion,
};
use camloc_skeleton::PartialPose2;
use camloc_store::Validate;

use crate::dropout::DropoutPlan;
use crate::localizer::most_probable;
use crate::rows::{column_means, extract_rows_into, impute_rows, sample_pose};
use crate::train_options::check_viewpoint_lambda;
use crate::{CameraHeight, CameraLocalizer, CamlocError, Capacity, TrainOptions, TrainingInfo};

impl CameraLocalizer {
    /// Trains on every sample of `dataset`. `progress` receives the Newton iteration log.
    /// With [`TrainOptions::viewpoint_lambda`], the viewpoint heads are then fitted on the
    /// same samples ([`fit_viewpoint`](Self::fit_viewpoint)).
    ///
    /// # Errors
    /// Invalid options ([`TrainOptions::validate`]); [`CamlocError::Dataset`] for a sample
    /// whose label is not a camera of the dataset or whose clip index is out of range;
    /// [`CamlocError::Inconsistent`] for an empty dataset, or with viewpoint heads one with a
    /// camera of no samples; [`CamlocError::Feature`] naming the
    /// first sample whose descriptor fails; [`CamlocError::Learning`] from the solver.
    pub fn train(
        dataset: &Dataset,
        options: &TrainOptions,
        progress: impl FnMut(&IterationLog),
    ) -> Result<(CameraLocalizer, FitReport), CamlocError> {
        options.validate()?;
        dataset.validate()?;
        let descriptor = options.descriptor;
        if dataset.samples.is_empty() {
            return Err(CamlocError::Inconsistent {
                what: "dataset",
                detail: "no samples to train on".into(),
            });
        }
        // Before the fit: the heads fitted after it need views of every camera.
        if options.viewpoint_lambda.is_some() {
            check_every_camera_seen(dataset, "dataset")?;
        }
        let d = descriptor.len();
        let cameras = &dataset.header.cameras;
        // The posture group of every sample, numbered over the groups present (a group no
        // sample has would leave classes without samples, whose biases have no optimum).
        let mut groups: Vec<usize> = dataset
            .samples
            .iter()
            .map(|s| {
                if options.posture_classes {
                    PostureGroup::of(&s.pose3).index()
                } else {
                    0
                }
            })
            .collect();
        let present: Vec<usize> = (0..PostureGroup::ALL.len())
            .filter(|g| groups.contains(g))
            .collect();
        for g in &mut groups {
            *g = present.iter().position(|p| p == g).unwrap_or(0);
        }
        let posture_groups = present.len().max(1);
        // The samples' poses and labels, then (mirror) their mirror images.
        let (n, images) = (dataset.samples.len(), if options.mirror { 2 } else { 1 });
        let poses = poses_with_mirror_images(dataset, options.mirror);
        let mut labels: Vec<u16> = dataset.samples.iter().map(|s| s.label).collect();
        if options.mirror {
            labels.extend_from_within(..);
            labels[n..]
                .iter_mut()
                .for_each(|l| *l = cameras.mirror_left_right(*l));
            // A mirrored body keeps its posture.
            groups.extend_from_within(..);
        }
        let dropout = match &options.dropout {
            Some(dropout) => Some(DropoutPlan::draw(dropout, poses.len() / images)?),
            None => None,
        };
        // Room for the dropout copies' rows, so that adding them moves nothing.
        let copies = dropout.as_ref().map_or(0, |plan| images * plan.len());
        let mut x = Vec::with_capacity((poses.len() + copies) * d);
        let undefined = extract_rows_into(&descriptor, &poses, 0, &mut x)?;
        let imputation = column_means(&x, &undefined, d);
        impute_rows(&mut x, &undefined, &imputation);
        drop(undefined);
        // Labels are 1..=cameras (checked by `dataset.validate()`), mirroring keeps them so.
        let mut y: Vec<usize> = labels
            .iter()
            .zip(&groups)
            .map(|(&l, g)| g * cameras.len() + usize::from(l) - 1)
            .collect();
        if let Some(plan) = &dropout {
            let labels = plan.add_rows(&descriptor, &poses, &y, &imputation, images, &mut x)?;
            y.extend_from_slice(&labels);
        }
        // The rows hold what training reads of the poses from here on.
        let n_poses = poses.len();
        drop(poses);
        // The expansion is fitted on the samples (and mirror images) before dropout.
        let expansion = match options.capacity {
            Capacity::Linear => None,
            Capacity::Quadratic { components } => Some(QuadraticExpansion::fit(
                &Features::new(&x[..n_poses * d], d)?,
                components,
            )?),
        };
        if options.mirror {
            // Rows [samples, mirror images, dropout copies, their mirror images] become
            // [samples, dropout copies, mirror images, theirs]: the second half is the first
            // half's mirror images, row for row (the image pairs of the fit).
            let (images, copies) = (n_poses / 2, (y.len() - n_poses) / 2);
            x[images * d..(2 * images + copies) * d].rotate_left(images * d);
            y[images..2 * images + copies].rotate_left(images);
        }
        // Expanded rows are made as the solver reads them, never held beside its copy.
        let features = Features::new(&x, d)?;
        let mut rows = DesignRows::with_expansion(features, expansion.as_ref())?;
        if options.mirror {
            rows = rows.in_image_pairs()?;
        }
        let n_classes = dataset.header.cameras.len() * posture_groups;
        let problem = NewtonProblem::from_rows(&rows, &y, n_classes, &options.regression)?;
        // The problem holds its own copy of the rows: before its iterations, free every row
        // but the samples' own, which only linear viewpoint heads read.
        // (Mirror images are made again by the heads' own fit, their rows being spread out.)
        let linear_heads = options.viewpoint_lambda.is_some()
            && options.viewpoint_capacity == Capacity::Linear
            && !options.mirror;
        x.truncate(if linear_heads {
            dataset.samples.len() * d
        } else {
            0
        });
        x.shrink_to_fit();
        let (mut model, report) = options.regression.solve_with_progress(problem, progress)?;
        let rows_per_camera = camera_row_counts(&y, cameras.len());
        if options.camera_balance > 0.0 {
            let shift = balancing_shift(&rows_per_camera, posture_groups, options.camera_balance);
            model = model.with_bias_shift(&shift)?;
        }
        let info = TrainingInfo {
            camloc_version: env!("CARGO_PKG_VERSION").to_string(),
            protocol: dataset.header.protocol,
            samples: dataset.samples.len(),
            subjects: dataset.subjects().into_iter().map(|(s, _)| s).collect(),
            lambda: options.regression.lambda,
            capacity: options.capacity,
            dropout: options.dropout,
            mirror: options.mirror,
            posture_classes: options.posture_classes,
            camera_balance: options.camera_balance,
            camera_priors: learnt_priors(&rows_per_camera, options.camera_balance),
        };
        let mut localizer = CameraLocalizer {
            descriptor,
            cameras: dataset.header.cameras.clone(),
            expansion,
            model,
            posture_groups,
            imputation,
            info,
            viewpoint: None,
            viewpoint_expansion: None,
            camera_height: CameraHeight::Any,
            intrinsics: None,
        };
        if let Some(lambda) = options.viewpoint_lambda {
            if linear_heads {
                // The heads see the classifier's rows of the samples themselves (the first
                // rows, before dropout copies: kept above).
                localizer.fit_viewpoint_rows(&x, dataset, lambda, false)?;
            } else {
                let capacity = options.viewpoint_capacity;
                localizer.fit_viewpoint_with_capacity(dataset, lambda, capacity)?;
            }
        }
        Ok((localizer, report))
    }

    /// Fits (or refits) the continuous-viewpoint heads on `dataset`: per camera class, a
    /// ridge regression (weight `lambda`) from the descriptor to the unit direction of the
    /// sample's camera (from its rotation), fitted on the samples labelled with that class
    /// and, when the classifier was trained on mirror images ([`TrainOptions::mirror`]), on
    /// the mirror images labelled with it (so that a mirrored pose gets the mirrored
    /// direction); then the uncertainty is calibrated on the same samples, by the class this
    /// localizer chooses and its probability. A dataset whose directions cover the sphere
    /// band (protocol `sphere`) gives heads that resolve directions between the cameras.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for a bad `lambda`; [`CamlocError::Inconsistent`] when
    /// the dataset's cameras are not this model's or one of them has no samples; dataset,
    /// descriptor and solver errors as in [`train`](Self::train).
    pub fn fit_viewpoint(&mut self, dataset: &Dataset, lambda: f64) -> Result<(), CamlocError> {
        self.fit_viewpoint_with_capacity(dataset, lambda, Capacity::Linear)
    }

    /// [`fit_viewpoint`](Self::fit_viewpoint) with heads of their own `capacity`:
    /// [`Capacity::Linear`], the classifier's features; [`Capacity::Quadratic`], the
    /// descriptor and the products of its leading whitened principal components, an
    /// expansion fitted on the dataset's descriptors (a quadratic regression of the
    /// direction, whatever the classifier's capacity), or the classifier's own expansion when
    /// it has that many components (the heads then read the classifier's rows: one expansion
    /// per pose instead of two).
    ///
    /// # Errors
    /// As [`fit_viewpoint`](Self::fit_viewpoint); expansion errors for a bad number of
    /// components.
    pub fn fit_viewpoint_with_capacity(
        &mut self,
        dataset: &Dataset,
        lambda: f64,
        capacity: Capacity,
    ) -> Result<(), CamlocError> {
        dataset.validate()?;
        check_viewpoint_lambda(lambda)?;
        if dataset.header.cameras != self.cameras {
            return Err(CamlocError::Inconsistent {
                what: "viewpoint dataset",
                detail: "its cameras are not the model's".into(),
            });
        }
        // Mirror images as the classifier saw them, so that mirror-image poses get
        // mirror-image directions.
        let mirror = self.info.mirror;
        let poses = poses_with_mirror_images(dataset, mirror);
        let descriptors = self.descriptor_rows(&poses, 0)?;
        drop(poses);
        let d = self.descriptor.len();
        self.viewpoint_expansion = match (capacity, &self.expansion) {
            (Capacity::Linear, _) => None,
            // The classifier's expansion already has that capacity: the heads read its rows.
            (Capacity::Quadratic { components }, Some(e)) if e.n_components() == components => None,
            (Capacity::Quadratic { components }, _) => Some(QuadraticExpansion::fit(
                &Features::new(&descriptors, d)?,
                components,
            )?),
        };
        self.fit_viewpoint_rows(&descriptors, dataset, lambda, mirror)
    }

    /// The viewpoint heads fitted on the imputed descriptor rows `descriptors` (row-major,
    /// expanded as the heads read them) of the samples of `dataset`, then (`mirror`) of their
    /// mirror images, and calibrated by the classes the classifier chooses for them.
    fn fit_viewpoint_rows(
        &mut self,
        descriptors: &[f64],
        dataset: &Dataset,
        lambda: f64,
        mirror: bool,
    ) -> Result<(), CamlocError> {
        check_viewpoint_lambda(lambda)?;
        let x = Features::new(descriptors, self.descriptor.len())?;
        let classifier = DesignRows::with_expansion(x, self.expansion.as_ref())?;
        let features = match &self.viewpoint_expansion {
            Some(e) => DesignRows::expanded(x, e)?,
            None => classifier,
        };
        check_every_camera_seen(dataset, "viewpoint dataset")?;
        let (directions, classes) = self.viewpoint_targets(dataset, mirror);
        let mut heads =
            DirectionHeads::fit(&features, &directions, &classes, self.cameras.len(), lambda)?;
        let mut classes = vec![0.0; self.model.n_classes()];
        let mut probabilities = vec![0.0; self.cameras.len()];
        let mut chosen = Vec::with_capacity(classifier.n_samples());
        classifier.try_for_each_row(|_, row| {
            self.model_camera_probabilities_into(row, &mut classes, &mut probabilities)?;
            chosen.push(most_probable(&probabilities));
            Ok::<(), CamlocError>(())
        })?;
        heads.calibrate(&features, &chosen, &directions)?;
        self.viewpoint = Some(heads);
        Ok(())
    }

    /// The heads' targets of the samples of `dataset`, then (`mirror`) of their mirror
    /// images: each one's camera direction (a unit vector in the canonical frame) and its
    /// class (0-based). The mirror image of a view is the body reflected through its sagittal
    /// plane seen from the reflected camera (y -> -y, azimuth -> -azimuth; the label
    /// [`CameraSet::mirror_left_right`](camloc_geometry::CameraSet::mirror_left_right)).
    fn viewpoint_targets(&self, dataset: &Dataset, mirror: bool) -> (Vec<[f64; 3]>, Vec<usize>) {
        let rows = dataset.samples.len() * if mirror { 2 } else { 1 };
        let mut directions = Vec::with_capacity(rows);
        let mut classes = Vec::with_capacity(rows);
        for s in &dataset.samples {
            let (azimuth, elevation) = camera_direction_deg(&s.rotation);
            directions.push(direction_vector(azimuth, elevation));
            classes.push(usize::from(s.label) - 1);
        }
        if mirror {
            directions.extend_from_within(..);
            classes.extend_from_within(..);
            let n = dataset.samples.len();
            directions[n..].iter_mut().for_each(|d| d[1] = -d[1]);
            for (class, s) in classes[n..].iter_mut().zip(&dataset.samples) {
                *class = usize::from(self.cameras.mirror_left_right(s.label)) - 1;
            }
        }
        (directions, classes)
    }
}

/// The poses of the samples of `dataset` (their dropped landmarks missing), then, with
/// `mirror`, their mirror images ([`PartialPose2::mirrored`]), in room made once.
fn poses_with_mirror_images(dataset: &Dataset, mirror: bool) -> Vec<PartialPose2> {
    let n = dataset.samples.len();
    let mut poses = Vec::with_capacity(if mirror { 2 * n } else { n });
    poses.extend(dataset.samples.iter().map(sample_pose));
    if mirror {
        poses.extend_from_within(..);
        poses[n..].iter_mut().for_each(|p| *p = p.mirrored());
    }
    poses
}

/// [`CamlocError::Inconsistent`] (about `what`) naming the first camera of the dataset's set
/// that none of its samples has: viewpoint heads need views of every camera.
fn check_every_camera_seen(dataset: &Dataset, what: &'static str) -> Result<(), CamlocError> {
    match dataset.samples_per_camera().iter().find(|c| c.samples == 0) {
        Some(unseen) => Err(CamlocError::Inconsistent {
            what,
            detail: format!(
                "camera {} has no samples; the viewpoint heads need samples of every camera \
                 (or train without heads: TrainOptions::viewpoint_lambda None, \
                 camloc train --no-viewpoint)",
                unseen.label
            ),
        }),
        None => Ok(()),
    }
}

/// Rows per camera among the training rows `y` (class `g * cameras + c` is camera `c`).
fn camera_row_counts(y: &[usize], cameras: usize) -> Vec<usize> {
    let mut counts = vec![0usize; cameras];
    for &class in y {
        counts[class % cameras] += 1;
    }
    counts
}

/// The bias shift that moves the camera priors `strength` of the way to even ones: for class
/// `g * cameras + c`, minus `strength` times the log of camera `c`'s share of the training
/// rows (`counts`, per camera) relative to an even share (0 for a camera without rows, whose
/// classes the fit already drove down).
fn balancing_shift(counts: &[usize], groups: usize, strength: f64) -> Vec<f64> {
    let even = counts.iter().sum::<usize>() as f64 / counts.len() as f64;
    let per_camera: Vec<f64> = counts
        .iter()
        .map(|&n| {
            if n > 0 {
                -strength * (n as f64 / even).ln()
            } else {
                0.0
            }
        })
        .collect();
    (0..groups)
        .flat_map(|_| per_camera.iter().copied())
        .collect()
}

/// The priors over the cameras the classifier keeps after [`balancing_shift`] of `strength`:
/// each camera's share of the rows (`counts`) raised to `1 - strength`, normalised.
fn learnt_priors(counts: &[usize], strength: f64) -> Vec<f64> {
    let raised: Vec<f64> = counts
        .iter()
        .map(|&n| (n as f64).powf(1.0 - strength))
        .collect();
    let total: f64 = raised.iter().sum();
    raised.iter().map(|r| r / total).collect()
}
