//! [`BoneLengths`]: the 14 limb lengths of one person, validated, with a JSON form
//! (`lengths/json.rs`) and its errors ([`BoneLengthError`]).

use camloc_skeleton::{LIMB_NAMES, NUM_LIMBS, Pose3};

mod json;

pub use json::{BONE_LENGTHS_FORMAT, BONE_LENGTHS_VERSION, MAX_BONE_LENGTHS_FILE_BYTES};

/// The shortest limb length [`BoneLengths`] accepts, metres.
pub const MIN_BONE_LENGTH_M: f64 = 0.01;

/// The longest limb length [`BoneLengths`] accepts, metres (a value above it is most likely
/// in centimetres or millimetres).
pub const MAX_BONE_LENGTH_M: f64 = 1.5;

/// The share of a person's standing height (soles to the top of the head) that the legs take,
/// hip joint to ankle (thigh plus shin): 0.491, the segment lengths of Winter's
/// anthropometric proportions (thigh 0.245, leg 0.246 of the height; D. A. Winter,
/// "Biomechanics and Motor Control of Human Movement", 4th ed., 2009, fig. 4.1).
/// [`BoneLengths::standing_height_m`] divides by it.
pub const LEGS_SHARE_OF_HEIGHT: f64 = 0.491;

/// The shortest standing height a reconstruction can be scaled to, metres
/// (`camloc reconstruct --height`).
pub const MIN_HEIGHT_M: f64 = 0.5;

/// The tallest standing height a reconstruction can be scaled to, metres.
pub const MAX_HEIGHT_M: f64 = 2.6;

/// A foot, metres.
const FOOT_M: f64 = 0.3048;

/// The JSON key of each limb, parallel to [`camloc_skeleton::LIMBS`] (docs/conventions.md
/// section 3): `left_pelvis_hip`, `left_thigh`, `left_shin`, the same on the right, `torso`,
/// `neck_head`, `left_collar`, `left_upper_arm`, `left_forearm`, the same on the right.
pub const BONE_KEYS: [&str; NUM_LIMBS] = [
    "left_pelvis_hip",
    "left_thigh",
    "left_shin",
    "right_pelvis_hip",
    "right_thigh",
    "right_shin",
    "torso",
    "neck_head",
    "left_collar",
    "left_upper_arm",
    "left_forearm",
    "right_collar",
    "right_upper_arm",
    "right_forearm",
];

/// The lengths of the 14 limbs of one person (docs/conventions.md section 3), metres, in the
/// order of [`camloc_skeleton::LIMBS`] (pelvis-left hip, left thigh, left shin, the same on the
/// right, torso, neck-head, left collar, upper arm, forearm, the same on the right).
///
/// Every value is finite and within [`MIN_BONE_LENGTH_M`]..=[`MAX_BONE_LENGTH_M`]: a value is
/// only ever made through [`BoneLengths::from_array`] (or the readers, which call it).
///
/// Its JSON form (`camloc reconstruct --bone-lengths FILE`, docs/cli.md) is
///
/// ```json
/// {"format": "camloc-bone-lengths", "version": 1, "unit": "m",
///  "lengths": {"left_pelvis_hip": 0.09, "left_thigh": 0.42, ...}}
/// ```
///
/// with all 14 keys of [`BONE_KEYS`] under `"lengths"`; `format`, `version` and `unit` may be
/// left out and are checked when present; a `person` string (whose lengths, as
/// `--bone-lengths-out` writes it) is read and left aside. [`BoneLengths`] serialises (serde)
/// as the `"lengths"` object alone.
///
/// ```
/// use camloc_reconstruct::BoneLengths;
/// let mut a = [0.3; 14];
/// a[6] = 0.5; // torso
/// let lengths = BoneLengths::from_array(a)?;
/// assert_eq!(lengths.as_array()[6], 0.5);
/// let text = lengths.to_json_string();
/// assert_eq!(BoneLengths::from_json_str(&text)?, lengths);
/// assert!(BoneLengths::from_array([45.0; 14]).is_err()); // centimetres, not metres
/// # Ok::<(), camloc_reconstruct::BoneLengthError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoneLengths([f64; NUM_LIMBS]);

/// Why a set of bone lengths was refused.
#[derive(Debug, thiserror::Error)]
pub enum BoneLengthError {
    /// A length is NaN or infinite.
    #[error("bone lengths: {limb} is not a finite number ({value:?})")]
    NotFinite {
        /// The limb's name ([`camloc_skeleton::LIMB_NAMES`]).
        limb: &'static str,
        /// The value given.
        value: f64,
    },
    /// A length is outside the plausible range.
    #[error(
        "bone lengths: {limb} = {value:?} m is not a plausible bone length ({MIN_BONE_LENGTH_M} \
         to {MAX_BONE_LENGTH_M} m; lengths are in metres{unit_hint})"
    )]
    Implausible {
        /// The limb's name ([`camloc_skeleton::LIMB_NAMES`]).
        limb: &'static str,
        /// The value given, metres.
        value: f64,
        /// `""`, or what the lengths look like when every one of them would be plausible in
        /// centimetres, millimetres or feet (`"; all 14 look like centimetres: divide by
        /// 100"`).
        unit_hint: &'static str,
    },
    /// Given lengths whose legs make a person taller than [`MAX_HEIGHT_M`]
    /// ([`BoneLengths::given`]).
    #[error(
        "bone lengths: the legs make a person {height_m:.2} m tall, taller than a person \
         ({MAX_HEIGHT_M} m at most; lengths are in metres{unit_hint})"
    )]
    Height {
        /// The standing height of [`BoneLengths::standing_height_m`], metres.
        height_m: f64,
        /// `""`, or `"; they look like feet: divide by 3.28"` when the height would be one in
        /// feet.
        unit_hint: &'static str,
    },
    /// The JSON text is malformed or does not have the documented keys.
    #[error("bone lengths JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The JSON names another format, version or unit, or is not an object.
    #[error("bone lengths JSON: {0}")]
    Header(String),
    /// A bone lengths file cannot be read (or is too large to be one).
    #[error("bone lengths file {path}: {detail}")]
    File {
        /// The file, quoted.
        path: String,
        /// What went wrong.
        detail: String,
    },
    /// [`BoneLengths::mean_of`] was given no poses.
    #[error("bone lengths: no poses to measure")]
    NoPoses,
}

/// `true` for a length in [`MIN_BONE_LENGTH_M`]..=[`MAX_BONE_LENGTH_M`] metres.
fn plausible(length_m: f64) -> bool {
    (MIN_BONE_LENGTH_M..=MAX_BONE_LENGTH_M).contains(&length_m)
}

impl BoneLengths {
    /// The lengths `lengths` (metres, [`camloc_skeleton::LIMBS`] order), validated.
    ///
    /// # Errors
    /// [`BoneLengthError::NotFinite`] or [`BoneLengthError::Implausible`] naming the first
    /// limb that is not a finite length in [`MIN_BONE_LENGTH_M`]..=[`MAX_BONE_LENGTH_M`].
    pub fn from_array(lengths: [f64; NUM_LIMBS]) -> Result<BoneLengths, BoneLengthError> {
        for (value, limb) in lengths.iter().zip(LIMB_NAMES) {
            if !value.is_finite() {
                return Err(BoneLengthError::NotFinite {
                    limb,
                    value: *value,
                });
            }
            if !plausible(*value) {
                // Every length plausible in that unit, and the longest a body's (at least
                // 0.2 m: fourteen lengths of 2 are not 2 cm bones).
                let all_in = |per_m: f64| {
                    lengths.iter().all(|v| plausible(v / per_m))
                        && lengths.iter().any(|v| v / per_m >= 0.2)
                };
                let unit_hint = if all_in(100.0) {
                    "; all 14 look like centimetres: divide by 100"
                } else if all_in(1000.0) {
                    "; all 14 look like millimetres: divide by 1000"
                } else if all_in(1.0 / FOOT_M) {
                    "; all 14 look like feet: divide by 3.28"
                } else {
                    ""
                };
                return Err(BoneLengthError::Implausible {
                    limb,
                    value: *value,
                    unit_hint,
                });
            }
        }
        Ok(BoneLengths(lengths))
    }

    /// The lengths a user gives of a person (a file, an argument): [`from_array`]'s checks,
    /// and a [`standing_height_m`] of at most [`MAX_HEIGHT_M`] (to rounding: lengths that
    /// camloc scaled to a person of exactly that height are taken). Lengths in feet pass every
    /// limb's range (a thigh of 1.5 ft) but make a person of 5.6 m, whose animation a
    /// simulated animator found walking 12 m for 3.8. No shortest height is asked: the legs'
    /// share of a small child's height is below the adult rule's, and no unit makes a person
    /// smaller that the limbs' range lets through.
    ///
    /// # Errors
    /// As [`from_array`]; [`BoneLengthError::Height`] for a person too tall.
    ///
    /// [`from_array`]: Self::from_array
    /// [`standing_height_m`]: Self::standing_height_m
    pub fn given(lengths: [f64; NUM_LIMBS]) -> Result<BoneLengths, BoneLengthError> {
        let person = BoneLengths::from_array(lengths)?;
        let height_m = person.standing_height_m();
        // (A relative slack of 1e-9: 2.6 m of `--person-height` read back as 2.6000000000000005.)
        if height_m <= MAX_HEIGHT_M * (1.0 + 1e-9) {
            return Ok(person);
        }
        let in_feet = (MIN_HEIGHT_M..=MAX_HEIGHT_M).contains(&(height_m * FOOT_M));
        Err(BoneLengthError::Height {
            height_m,
            unit_hint: if in_feet {
                "; they look like feet: divide by 3.28"
            } else {
                ""
            },
        })
    }

    /// The 14 lengths, metres, in [`camloc_skeleton::LIMBS`] order.
    pub fn as_array(&self) -> [f64; NUM_LIMBS] {
        self.0
    }

    /// The length of limb `limb` (its index in [`camloc_skeleton::LIMBS`]), metres; `None`
    /// for an index of 14 or more.
    pub fn get(&self, limb: usize) -> Option<f64> {
        self.0.get(limb).copied()
    }

    /// The limb lengths of `pose` (metres).
    ///
    /// # Errors
    /// As [`BoneLengths::from_array`] (a pose with coinciding landmarks, a non-finite pose).
    pub fn of_pose(pose: &Pose3) -> Result<BoneLengths, BoneLengthError> {
        BoneLengths::from_array(std::array::from_fn(|limb| pose.limb_length(limb)))
    }

    /// The mean length of each limb over `poses` (metres): one person's lengths from the
    /// frames of a reconstruction or a capture.
    ///
    /// # Errors
    /// [`BoneLengthError::NoPoses`] for no poses; as [`BoneLengths::from_array`] for the mean
    /// (a non-finite pose makes it non-finite).
    pub fn mean_of(poses: &[Pose3]) -> Result<BoneLengths, BoneLengthError> {
        if poses.is_empty() {
            return Err(BoneLengthError::NoPoses);
        }
        let n = poses.len() as f64;
        BoneLengths::from_array(std::array::from_fn(|limb| {
            poses.iter().map(|p| p.limb_length(limb)).sum::<f64>() / n
        }))
    }

    /// Every length times `factor` (validated again).
    ///
    /// # Errors
    /// As [`BoneLengths::from_array`] when a scaled length leaves the plausible range.
    pub fn scaled(&self, factor: f64) -> Result<BoneLengths, BoneLengthError> {
        BoneLengths::from_array(self.0.map(|l| l * factor))
    }

    /// The standing height of a person with these lengths, metres (soles to the top of the
    /// head): the legs (thigh plus shin, the mean of the two sides) over
    /// [`LEGS_SHARE_OF_HEIGHT`]. The legs are the limbs whose landmarks skeletons, annotations
    /// and detectors place most alike (docs/keypoints.md); the legs of the 29 CMU subjects of
    /// the project's data give 1.52-1.84 m, median 1.72 m.
    pub fn standing_height_m(&self) -> f64 {
        let l = &self.0;
        ((l[1] + l[4]) / 2.0 + (l[2] + l[5]) / 2.0) / LEGS_SHARE_OF_HEIGHT
    }

    /// Sum of the squared lengths, m^2 (the anthropometric quantity of the pursuit).
    pub fn sum_of_squares(&self) -> f64 {
        self.0.iter().map(|l| l * l).sum()
    }

    /// Each limb's relative error `estimate / truth - 1` after one common scale factor
    /// applied to `self` (the estimate): the factor that makes the mean log ratio zero.
    /// Sizes cannot be told from one camera (a larger person farther away looks the same), so
    /// estimated lengths are compared by proportions.
    pub fn relative_errors(&self, truth: &BoneLengths) -> [f64; NUM_LIMBS] {
        let logs: [f64; NUM_LIMBS] = std::array::from_fn(|b| (self.0[b] / truth.0[b]).ln());
        let mean = logs.iter().sum::<f64>() / NUM_LIMBS as f64;
        logs.map(|l| (l - mean).exp() - 1.0)
    }
}
