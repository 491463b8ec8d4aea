//! [`DepthLifter`]: the depth of every landmark along the camera's optical axis, learned from
//! the 2D pose per camera class (docs/conventions.md section 6).
//!
//! The 2D pose fixes two of each landmark's three coordinates in the camera's frame; the
//! third, the depth, is what a single view leaves open and what the pose basis of the
//! pursuit guesses. The lifter predicts it by one ridge regression per camera class on the
//! quadratic expansion of the pose descriptor (the features of the quadratic classifier).
//! Its depths are in the units of the 2D pose centred on the centroid of its landmarks and
//! divided by their RMS radius about it (the pursuit's normalisation), about the centroid of
//! the 3D landmarks, positive away from the camera.

use camloc_dataset::{Dataset, Sample};
use camloc_features::Descriptor;
use camloc_geometry::{CameraLabel, CameraSet};
use camloc_learning::{DesignRows, Features, QuadraticExpansion, RidgeModel};
use camloc_reconstruct::depths_along_axis;
use camloc_skeleton::{NUM_LANDMARKS, Pose2, mirror_landmark_index};
use camloc_store::{FileKind, Persist, Validate};
use serde::{Deserialize, Serialize};

use crate::CamlocError;
use crate::torso_placement::own_placement_weight;

/// Ridge weight of the default depth lifter ([`DepthLifter::fit`]): on held-out CMU subjects
/// lambda 1, 10 and 100 were within 0.1 mm of each other (docs/RESULTS.md).
pub const DEFAULT_LIFTER_LAMBDA: f64 = 10.0;

/// Per camera class, a ridge regression of the landmarks' depths along the optical axis from
/// the quadratic expansion of the pose descriptor (module documentation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthLifter {
    descriptor: Descriptor,
    expansion: QuadraticExpansion,
    /// One per camera class, [`NUM_LANDMARKS`] outputs each.
    heads: Vec<RidgeModel>,
    /// The lifter of poses whose pelvis and neck sit at the hip and shoulder midpoints
    /// (detectors' and annotations' placement), when this one was fitted on skeletons' own
    /// placement ([`with_midpoint_lifter`](Self::with_midpoint_lifter)); none: this one
    /// lifts every pose. Decoded one level deep at most ([`shallow_midpoints`]).
    #[serde(deserialize_with = "shallow_midpoints")]
    midpoints: Option<Box<DepthLifter>>,
}

thread_local! {
    /// Whether this thread is decoding a midpoint lifter ([`shallow_midpoints`]).
    static DECODING_MIDPOINTS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// What a midpoint lifter's own midpoint lifter decodes to: an error whenever there is one.
struct NestedMidpoints;

impl<'de> Deserialize<'de> for NestedMidpoints {
    fn deserialize<D: serde::Deserializer<'de>>(_: D) -> Result<Self, D::Error> {
        Err(serde::de::Error::custom(
            "a midpoint lifter holds a midpoint lifter of its own",
        ))
    }
}

/// Decodes a lifter's midpoint lifter, refusing one inside it before decoding it: lifters
/// nest one level at most, and a forged file of thousands of nested ones would otherwise
/// overflow the stack while it is decoded, before [`Validate`] could refuse it.
fn shallow_midpoints<'de, D: serde::Deserializer<'de>>(
    decoder: D,
) -> Result<Option<Box<DepthLifter>>, D::Error> {
    if DECODING_MIDPOINTS.get() {
        return Option::<NestedMidpoints>::deserialize(decoder).map(|_| None);
    }
    DECODING_MIDPOINTS.set(true);
    let midpoints = Option::<Box<DepthLifter>>::deserialize(decoder);
    DECODING_MIDPOINTS.set(false);
    midpoints
}

impl DepthLifter {
    /// Fits the lifter on the complete samples of `dataset` (2D landmarks, true 3D pose and
    /// camera rotation, class = label): the `descriptor`, its quadratic expansion of
    /// `components` principal components, and per class a ridge regression with weight
    /// `lambda` of the depths ([`depth_targets`]).
    ///
    /// # Errors
    /// [`CamlocError::Inconsistent`] when no sample is complete or a camera has none;
    /// descriptor errors naming the sample; expansion and ridge errors.
    pub fn fit(
        dataset: &Dataset,
        descriptor: Descriptor,
        components: usize,
        lambda: f64,
    ) -> Result<DepthLifter, CamlocError> {
        let d = descriptor.len();
        let complete: Vec<&Sample> = dataset
            .samples
            .iter()
            .filter(|s| s.missing_mask == 0)
            .collect();
        let mut x = vec![0.0; complete.len() * d];
        for (i, (s, row)) in complete.iter().zip(x.chunks_exact_mut(d)).enumerate() {
            descriptor
                .extract_into(&s.landmarks, row)
                .map_err(|source| CamlocError::Feature {
                    context: format!("complete sample {i}"),
                    source,
                })?;
        }
        let n_classes = dataset.header.cameras.len();
        let classes: Vec<usize> = complete.iter().map(|s| usize::from(s.label) - 1).collect();
        if let Some(k) = (0..n_classes).find(|k| !classes.contains(k)) {
            return Err(CamlocError::Inconsistent {
                what: "depth lifter dataset",
                detail: format!("camera {} has no complete samples", k + 1),
            });
        }
        let features = Features::new(&x, d)?;
        let expansion = QuadraticExpansion::fit(&features, components)?;
        let depths: Vec<f64> = complete.iter().flat_map(|s| depth_targets(s)).collect();
        let heads = RidgeModel::fit_per_class(
            &DesignRows::expanded(features, &expansion)?,
            &depths,
            NUM_LANDMARKS,
            &classes,
            n_classes,
            lambda,
        )?;
        Ok(DepthLifter {
            descriptor,
            expansion,
            heads,
            midpoints: None,
        })
    }

    /// This lifter (fitted on poses in their skeleton's own placement of the pelvis and the
    /// neck) with `midpoints`, a lifter fitted on the same views with the pelvis at the mid-hip
    /// point and the neck at the mid-shoulder point, for the poses whose image shows that
    /// placement ([`depths`](Self::depths)), replacing any it had. The two placements differ
    /// by about a third of the torso, which a view from above or below cannot tell by its
    /// depth: one lifter fitted on both gave CMU torsos 30% too deep at 45 deg of elevation
    /// (docs/RESULTS.md).
    ///
    /// # Errors
    /// [`CamlocError::Inconsistent`] when `midpoints` has a midpoint lifter of its own or
    /// another number of camera classes.
    pub fn with_midpoint_lifter(mut self, midpoints: DepthLifter) -> Result<Self, CamlocError> {
        self.midpoints = Some(Box::new(midpoints));
        match self.midpoint_mismatch() {
            Some(detail) => Err(CamlocError::Inconsistent {
                what: "midpoint depth lifter",
                detail,
            }),
            None => Ok(self),
        }
    }

    /// What is wrong with this lifter's midpoint lifter as one: a midpoint lifter of its own,
    /// or another number of camera classes; none without one.
    fn midpoint_mismatch(&self) -> Option<String> {
        let midpoints = self.midpoints.as_ref()?;
        if midpoints.midpoints.is_some() {
            return Some("it has a midpoint lifter of its own".into());
        }
        (midpoints.n_classes() != self.n_classes()).then(|| {
            format!(
                "{} camera classes, the lifter {}",
                midpoints.n_classes(),
                self.n_classes()
            )
        })
    }

    /// This lifter without its midpoint lifter, and that lifter (each can be saved on its
    /// own, as the embedded ones are).
    pub fn split_midpoint_lifter(mut self) -> (DepthLifter, Option<DepthLifter>) {
        let midpoints = self.midpoints.take().map(|m| *m);
        (self, midpoints)
    }

    /// The lifter of poses in the midpoint placement, if this one has one.
    pub fn midpoint_lifter(&self) -> Option<&DepthLifter> {
        self.midpoints.as_deref()
    }

    /// The depths of the landmarks of `pose` (image coordinates, any units) seen by a camera
    /// of class `class` (0-based), in the units of the module documentation. With a
    /// [midpoint lifter](Self::with_midpoint_lifter), the two lifters' depths weighed by
    /// where the image puts the pelvis and the neck (`own_placement_weight`: the midpoint
    /// lifter's alone when both lie within 0.08 torso of the hip and shoulder midpoints, this
    /// one's alone beyond 0.16, docs/conventions.md section 6).
    ///
    /// # Errors
    /// [`CamlocError::Feature`] for non-finite landmarks or a degenerate torso;
    /// [`CamlocError::InvalidOption`] for a class the lifter does not have.
    pub fn depths(&self, pose: &Pose2, class: usize) -> Result<[f64; NUM_LANDMARKS], CamlocError> {
        self.placed_depths(pose, class, None)
    }

    /// [`depths`](Self::depths) with the weight `placement` of the own placement given (0:
    /// the midpoint lifter's depths, 1: this lifter's own; clamped to that range), as a
    /// sequence's poses are lifted with their person's (`sequence_own_placement_weight`);
    /// none: read from `pose` (`own_placement_weight`). Without a midpoint lifter, this
    /// lifter's own whatever the weight.
    ///
    /// # Errors
    /// As [`depths`](Self::depths).
    pub fn placed_depths(
        &self,
        pose: &Pose2,
        class: usize,
        placement: Option<f64>,
    ) -> Result<[f64; NUM_LANDMARKS], CamlocError> {
        let Some(midpoints) = &self.midpoints else {
            return self.own_depths(pose, class);
        };
        let own_weight = placement.unwrap_or_else(|| own_placement_weight(pose));
        if !(own_weight < 1.0) {
            return self.own_depths(pose, class);
        }
        let at_midpoints = midpoints.own_depths(pose, class)?;
        if own_weight <= 0.0 {
            return Ok(at_midpoints);
        }
        let own = self.own_depths(pose, class)?;
        Ok(std::array::from_fn(|j| {
            own_weight * own[j] + (1.0 - own_weight) * at_midpoints[j]
        }))
    }

    /// [`depths`](Self::depths) by this lifter's own heads.
    fn own_depths(&self, pose: &Pose2, class: usize) -> Result<[f64; NUM_LANDMARKS], CamlocError> {
        let head = self
            .heads
            .get(class)
            .ok_or_else(|| CamlocError::InvalidOption {
                name: "depth lifter class",
                detail: format!("{class} is not below {}", self.heads.len()),
            })?;
        let mut row = vec![0.0; self.descriptor.len()];
        self.descriptor
            .extract_into(pose, &mut row)
            .map_err(|source| CamlocError::Feature {
                context: "input pose".into(),
                source,
            })?;
        let mut expanded = vec![0.0; self.expansion.n_outputs()];
        self.expansion.expand_into(&row, &mut expanded)?;
        let mut depths = [0.0; NUM_LANDMARKS];
        head.predict_into(&expanded, &mut depths)?;
        Ok(depths)
    }

    /// The mean of the [`depths`](Self::depths) of `pose` seen by the camera `label` of
    /// `cameras` and of those of its mirror image (`pose.mirrored()`) seen by the mirrored
    /// camera ([`CameraSet::mirror_left_right`]), with left and right swapped back: a pose and
    /// its mirror image get mirror-image depths, which the lifter, fitted on people as
    /// recorded, does not give them (held-out subjects with 3% noise, `hybrid`: single poses
    /// 0.1-0.9 mm better, sequences 0.4 mm better to 0.1 mm worse; clean tripod views 0.4 mm
    /// worse; docs/RESULTS.md).
    ///
    /// # Errors
    /// As [`depths`](Self::depths), for either camera.
    pub fn mirror_symmetric_depths(
        &self,
        pose: &Pose2,
        cameras: &CameraSet,
        label: CameraLabel,
    ) -> Result<[f64; NUM_LANDMARKS], CamlocError> {
        self.mirror_symmetric_placed_depths(pose, cameras, label, None)
    }

    /// [`mirror_symmetric_depths`](Self::mirror_symmetric_depths) with the weight `placement`
    /// of the own placement as [`placed_depths`](Self::placed_depths) takes it (none: read
    /// from `pose`; its mirror image keeps its placement).
    ///
    /// # Errors
    /// As [`depths`](Self::depths), for either camera.
    pub fn mirror_symmetric_placed_depths(
        &self,
        pose: &Pose2,
        cameras: &CameraSet,
        label: CameraLabel,
        placement: Option<f64>,
    ) -> Result<[f64; NUM_LANDMARKS], CamlocError> {
        // Read once for the pose and its mirror image.
        let placement =
            placement.or_else(|| self.midpoints.is_some().then(|| own_placement_weight(pose)));
        // Labels are 1-based; the mirrored camera's is in the same set.
        let mirrored_class = usize::from(cameras.mirror_left_right(label.get())).saturating_sub(1);
        let direct = self.placed_depths(pose, label.index(), placement)?;
        let mirrored = self.placed_depths(&pose.mirrored(), mirrored_class, placement)?;
        Ok(std::array::from_fn(|i| {
            0.5 * (direct[i] + mirrored[mirror_landmark_index(i)])
        }))
    }

    /// The number of camera classes (one head each).
    pub fn n_classes(&self) -> usize {
        self.heads.len()
    }

    /// The lifter embedded in this build, with its midpoint lifter (both trained by `cargo
    /// xtask train-default` with the default model, on its viewpoint heads' views drawn again
    /// with wider people: docs/conventions.md section 6).
    ///
    /// # Errors
    /// [`CamlocError::NoDefault`] when the build embedded none; decoding errors otherwise.
    pub fn default_lifter() -> Result<DepthLifter, CamlocError> {
        let bytes = include_bytes!(concat!(env!("OUT_DIR"), "/default-lifter.bin"));
        let midpoints = include_bytes!(concat!(env!("OUT_DIR"), "/default-lifter-midpoints.bin"));
        if bytes.is_empty() || midpoints.is_empty() {
            return Err(CamlocError::NoDefault("depth lifter"));
        }
        let midpoints = Self::from_bytes_named(midpoints, "embedded default midpoint lifter")?;
        Self::from_bytes_named(bytes, "embedded default depth lifter")?
            .with_midpoint_lifter(midpoints)
    }

    /// Whether the embedded lifter ([`default_lifter`](Self::default_lifter)) serves a
    /// localizer of `cameras`: its depths are predicted per Table-1 camera, so it serves any
    /// model of Table 1's cameras (the embedded one, or one trained with `camloc train`), and
    /// no other.
    pub fn serves(cameras: &CameraSet) -> bool {
        *cameras == CameraSet::table1()
    }
}

/// The depths [`DepthLifter`] learns for `sample`: each landmark's coordinate along the
/// camera's optical axis (row 3 of its rotation) about the centroid of the 3D landmarks,
/// divided by the RMS radius of their coordinates across it (rows 1 and 2), so that they are
/// in the units of the normalised 2D pose that an orthographic view of the sample gives.
pub fn depth_targets(sample: &Sample) -> [f64; NUM_LANDMARKS] {
    depths_along_axis(&sample.pose3, &sample.rotation)
}

/// The lifter's invariants, run after every decode of a lifter file: a valid descriptor,
/// expansion and heads, the expansion reading the descriptor and every head reading the
/// expansion and giving [`NUM_LANDMARKS`] depths.
impl Validate for DepthLifter {
    type Invalid = CamlocError;

    fn validate(&self) -> Result<(), CamlocError> {
        let inconsistent = |detail: String| CamlocError::Inconsistent {
            what: "depth lifter",
            detail,
        };
        self.descriptor
            .validate()
            .map_err(|e| inconsistent(e.to_string()))?;
        self.expansion
            .validate()
            .map_err(|e| inconsistent(format!("feature expansion: {e}")))?;
        if self.expansion.n_inputs() != self.descriptor.len() {
            return Err(inconsistent(format!(
                "the expansion reads {} values, the descriptor has {}",
                self.expansion.n_inputs(),
                self.descriptor.len()
            )));
        }
        if self.heads.is_empty() {
            return Err(inconsistent("no class heads".into()));
        }
        if let Some(midpoints) = &self.midpoints {
            midpoints
                .validate()
                .map_err(|e| inconsistent(format!("midpoint lifter: {e}")))?;
        }
        if let Some(detail) = self.midpoint_mismatch() {
            return Err(inconsistent(format!("midpoint lifter: {detail}")));
        }
        for (k, head) in self.heads.iter().enumerate() {
            head.validate()
                .map_err(|e| inconsistent(format!("head {k}: {e}")))?;
            if head.n_features() != self.expansion.n_outputs() || head.n_outputs() != NUM_LANDMARKS
            {
                return Err(inconsistent(format!(
                    "head {k} maps {} features to {} values, expected {} to {NUM_LANDMARKS}",
                    head.n_features(),
                    head.n_outputs(),
                    self.expansion.n_outputs()
                )));
            }
        }
        Ok(())
    }
}

/// Lifter files: [`camloc_store::LIFTER_KIND`] (magic `CAMLOCDL`); load with
/// [`Persist::load`], write with [`Persist::save`] (no overwrite unless asked).
impl Persist for DepthLifter {
    const KIND: FileKind = camloc_store::LIFTER_KIND;
}
