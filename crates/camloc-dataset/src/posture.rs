//! Postures: seated, squatting, kneeling and floor-sitting bodies made from any canonical pose
//! by turning its thighs, shins and torso within joint-angle limits learned from motion
//! capture (docs/conventions.md section 7), and the body angles those limits are learned on.

use camloc_skeleton::{Landmark, Pose3};
use rand::Rng;
use serde::{Deserialize, Serialize};

/// Height of the lowest landmark above the floor, metres: ankles, knees on the floor and
/// wrists on the floor are joint centres a few centimetres above it. Used to stand a pose on
/// the floor ([`pelvis_height_m`]).
pub const FLOOR_CLEARANCE_M: f64 = 0.07;

/// The pelvis height above the floor of a canonical pose (pelvis at the origin, z up) standing,
/// sitting or kneeling on a floor: its lowest landmark [`FLOOR_CLEARANCE_M`] above it. Metres.
pub fn pelvis_height_m(pose: &Pose3) -> f64 {
    let lowest = pose
        .points
        .iter()
        .map(|p| p[2])
        .fold(f64::INFINITY, f64::min);
    pose.get(Landmark::Pelvis)[2] - lowest + FLOOR_CLEARANCE_M
}

/// The angles of a body's legs and torso, degrees, in the canonical frame (facing -x, right
/// side towards +y, z up). Left leg first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyAngles {
    /// Hip flexion per leg: the angle of the thigh (hip to knee) from the torso's downward
    /// axis (neck to pelvis) in the torso's sagittal plane, positive towards the front.
    pub hip_flexion_deg: [f64; 2],
    /// Knee flexion per leg: the angle between thigh and shin (0 = straight leg).
    pub knee_flexion_deg: [f64; 2],
    /// Torso pitch: the angle of the pelvis-to-neck direction from the vertical in the
    /// sagittal plane, positive leaning forward.
    pub torso_pitch_deg: f64,
    /// Thigh angle from the vertical (downward) direction per leg, whatever its direction.
    pub thigh_from_vertical_deg: [f64; 2],
}

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The unit vector along `a`, or `None` for a (near) zero vector.
fn unit(a: V3) -> Option<V3> {
    let n = norm(a);
    (n > 1e-12).then(|| scale(a, 1.0 / n))
}

/// The angle between two vectors, degrees (0 when either vanishes).
fn angle_deg(a: V3, b: V3) -> f64 {
    norm(cross(a, b)).atan2(dot(a, b)).to_degrees()
}

/// The two legs as (hip, knee, ankle), left first.
const LEGS: [[Landmark; 3]; 2] = [
    [Landmark::LeftHip, Landmark::LeftKnee, Landmark::LeftAnkle],
    [
        Landmark::RightHip,
        Landmark::RightKnee,
        Landmark::RightAnkle,
    ],
];

/// The body angles of a canonical pose. A degenerate torso (neck on the pelvis) measures
/// hip flexion from the vertical instead.
pub fn body_angles(pose: &Pose3) -> BodyAngles {
    let up =
        unit(sub(pose.get(Landmark::Neck), pose.get(Landmark::Pelvis))).unwrap_or([0.0, 0.0, 1.0]);
    let across = sub(pose.get(Landmark::RightHip), pose.get(Landmark::LeftHip));
    let lateral = unit(sub(across, scale(up, dot(across, up)))).unwrap_or([0.0, 1.0, 0.0]);
    let forward = cross(up, lateral);
    let mut angles = BodyAngles {
        hip_flexion_deg: [0.0; 2],
        knee_flexion_deg: [0.0; 2],
        // The angle of `up` from +z towards the front (-x), in the xz plane.
        torso_pitch_deg: (-up[0]).atan2(up[2]).to_degrees(),
        thigh_from_vertical_deg: [0.0; 2],
    };
    for (k, [hip, knee, ankle]) in LEGS.into_iter().enumerate() {
        let thigh = sub(pose.get(knee), pose.get(hip));
        let shin = sub(pose.get(ankle), pose.get(knee));
        angles.hip_flexion_deg[k] = dot(thigh, forward).atan2(-dot(thigh, up)).to_degrees();
        angles.knee_flexion_deg[k] = angle_deg(thigh, shin);
        angles.thigh_from_vertical_deg[k] = angle_deg(thigh, [0.0, 0.0, -1.0]);
    }
    angles
}

/// Whether a canonical pose is seated or low: a thigh more than 60 deg from the vertical
/// (sitting, squatting, kneeling on one knee; the share the data README counts).
pub fn is_low_posture(pose: &Pose3) -> bool {
    body_angles(pose)
        .thigh_from_vertical_deg
        .iter()
        .any(|&a| a > 60.0)
}

/// A coarse posture: the sub-classes of a localizer that classifies (posture, camera) pairs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PostureGroup {
    /// Standing, walking, running: the pelvis at least [`LOW_PELVIS_SHARE`] of the leg length
    /// above the floor, the torso within 45 deg of the vertical.
    Upright,
    /// Seated, squatting, kneeling, sitting on the floor: the pelvis lower than that.
    Low,
    /// Bent over, crawling, lying, upside down: the torso more than 45 deg from the vertical.
    Bent,
}

/// The pelvis height above the floor, as a share of the mean leg length (hip to knee to
/// ankle), below which a body with an upright torso is [`PostureGroup::Low`]; standing it
/// is about 1.08 (the ankle joints stand [`FLOOR_CLEARANCE_M`] above the floor), seated on a
/// chair about 0.6.
pub const LOW_PELVIS_SHARE: f64 = 0.9;

impl PostureGroup {
    /// Every group, in the order of [`index`](Self::index).
    pub const ALL: [PostureGroup; 3] =
        [PostureGroup::Upright, PostureGroup::Low, PostureGroup::Bent];

    /// The group of a canonical pose.
    pub fn of(pose: &Pose3) -> PostureGroup {
        if body_angles(pose).torso_pitch_deg.abs() > 45.0 {
            return PostureGroup::Bent;
        }
        let legs: f64 = LEGS
            .iter()
            .map(|[hip, knee, ankle]| {
                norm(sub(pose.get(*knee), pose.get(*hip)))
                    + norm(sub(pose.get(*ankle), pose.get(*knee)))
            })
            .sum::<f64>()
            / 2.0;
        if pelvis_height_m(pose) < LOW_PELVIS_SHARE * legs {
            PostureGroup::Low
        } else {
            PostureGroup::Upright
        }
    }

    /// Position in [`ALL`](Self::ALL).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Lower-case name (`"upright"`, `"low"`, `"bent"`).
    pub fn name(self) -> &'static str {
        match self {
            PostureGroup::Upright => "upright",
            PostureGroup::Low => "low",
            PostureGroup::Bent => "bent",
        }
    }
}

/// The joint-angle limits postures are made within, degrees: learned from motion capture
/// ([`PostureLimits::learn`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PostureLimits {
    /// Largest hip flexion (thigh from the torso's downward axis, forward).
    pub hip_flexion_max_deg: f64,
    /// Largest knee flexion.
    pub knee_flexion_max_deg: f64,
    /// Torso pitch range `(backward, forward)`, forward positive.
    pub torso_pitch_deg: (f64, f64),
}

/// Share of the poses whose angles [`PostureLimits::learn`] keeps within the limits (the
/// rest are outliers: marker glitches, dives and rolls).
pub const LIMIT_COVERAGE: f64 = 0.999;

impl PostureLimits {
    /// The limits of the central [`LIMIT_COVERAGE`] of `poses` (both legs counted): the
    /// largest hip and knee flexions and the torso pitch range below which that share lies.
    /// No poses allow nothing: every limit 0.
    pub fn learn<'a>(poses: impl IntoIterator<Item = &'a Pose3>) -> PostureLimits {
        let (mut hips, mut knees, mut pitches) = (Vec::new(), Vec::new(), Vec::new());
        for pose in poses {
            let a = body_angles(pose);
            hips.extend(a.hip_flexion_deg);
            knees.extend(a.knee_flexion_deg);
            pitches.push(a.torso_pitch_deg);
        }
        if pitches.is_empty() {
            return PostureLimits {
                hip_flexion_max_deg: 0.0,
                knee_flexion_max_deg: 0.0,
                torso_pitch_deg: (0.0, 0.0),
            };
        }
        let tail = 1.0 - LIMIT_COVERAGE;
        PostureLimits {
            hip_flexion_max_deg: quantile(&mut hips, LIMIT_COVERAGE),
            knee_flexion_max_deg: quantile(&mut knees, LIMIT_COVERAGE),
            torso_pitch_deg: (
                quantile(&mut pitches, 0.5 * tail),
                quantile(&mut pitches, 1.0 - 0.5 * tail),
            ),
        }
    }
}

/// The `q` quantile (nearest rank) of `values` (not empty), which it sorts.
fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    let k = ((values.len() - 1) as f64 * q).round() as usize;
    values[k.min(values.len() - 1)]
}

/// A kind of posture [`make_posture`] makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PostureKind {
    /// Sitting on a chair or stool: thighs about horizontal, shins about vertical.
    Chair,
    /// Squatting: thighs about horizontal or higher, knees ahead of the ankles, torso
    /// leaning forward.
    Squat,
    /// Kneeling on both knees: thighs about vertical, shins on the floor behind.
    Kneel,
    /// Kneeling on one knee, the other foot on the floor in front.
    HalfKneel,
    /// Sitting on the floor with the legs forward, straight or bent.
    FloorSit,
    /// Sitting on the floor cross-legged.
    CrossLegged,
}

impl PostureKind {
    /// Every kind with its share of the postures made.
    pub const MIX: [(PostureKind, f64); 6] = [
        (PostureKind::Chair, 0.35),
        (PostureKind::Squat, 0.2),
        (PostureKind::Kneel, 0.1),
        (PostureKind::HalfKneel, 0.1),
        (PostureKind::FloorSit, 0.15),
        (PostureKind::CrossLegged, 0.1),
    ];

    /// A kind drawn with the shares of [`MIX`](Self::MIX).
    pub fn draw(rng: &mut impl Rng) -> PostureKind {
        let mut u: f64 = rng.random_range(0.0..1.0);
        for (kind, share) in Self::MIX {
            if u < share {
                return kind;
            }
            u -= share;
        }
        PostureKind::Chair
    }
}

/// One leg's target, degrees in the canonical frame: `thigh` from straight down towards the
/// front, `spread` of the knee sideways (outwards positive), `shin` from straight down
/// towards the front (negative: the ankle behind the knee), `shin_spread` of the ankle
/// sideways (outwards positive).
#[derive(Clone, Copy, Debug)]
struct LegTarget {
    thigh: f64,
    spread: f64,
    shin: f64,
    shin_spread: f64,
}

fn uniform(rng: &mut impl Rng, (lo, hi): (f64, f64)) -> f64 {
    if hi > lo {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
}

/// The torso pitch and the two legs' targets of `kind` (degrees), drawn from its ranges.
fn draw_targets(kind: PostureKind, rng: &mut impl Rng) -> (f64, [LegTarget; 2]) {
    // (torso pitch, thigh, spread, shin, shin spread) ranges; each leg varies by up to 8 deg
    // from the shared draw.
    let leg = |rng: &mut _, thigh: (f64, f64), spread, shin: (f64, f64), shin_spread| {
        let t = uniform(rng, thigh);
        let s = uniform(rng, shin);
        let spread = uniform(rng, spread);
        let shin_spread = uniform(rng, shin_spread);
        [0, 1].map(|_| LegTarget {
            thigh: t + uniform(rng, (-8.0, 8.0)),
            spread: spread + uniform(rng, (-5.0, 5.0)),
            shin: s + uniform(rng, (-8.0, 8.0)),
            shin_spread,
        })
    };
    match kind {
        PostureKind::Chair => (
            uniform(rng, (-20.0, 35.0)),
            leg(
                rng,
                (65.0, 100.0),
                (0.0, 20.0),
                (-30.0, 30.0),
                (-10.0, 10.0),
            ),
        ),
        PostureKind::Squat => (
            uniform(rng, (10.0, 55.0)),
            leg(
                rng,
                (70.0, 115.0),
                (5.0, 30.0),
                (-50.0, -10.0),
                (-10.0, 10.0),
            ),
        ),
        PostureKind::Kneel => (
            uniform(rng, (-10.0, 35.0)),
            leg(
                rng,
                (-5.0, 35.0),
                (0.0, 15.0),
                (-100.0, -85.0),
                (-10.0, 10.0),
            ),
        ),
        PostureKind::HalfKneel => {
            let pitch = uniform(rng, (-10.0, 35.0));
            let kneeling = leg(
                rng,
                (-5.0, 35.0),
                (0.0, 15.0),
                (-100.0, -85.0),
                (-10.0, 10.0),
            );
            let standing = leg(
                rng,
                (60.0, 100.0),
                (0.0, 15.0),
                (-20.0, 25.0),
                (-10.0, 10.0),
            );
            if rng.random_bool(0.5) {
                (pitch, [kneeling[0], standing[1]])
            } else {
                (pitch, [standing[0], kneeling[1]])
            }
        }
        PostureKind::FloorSit => {
            let pitch = uniform(rng, (-30.0, 25.0));
            let mut legs = leg(rng, (75.0, 100.0), (0.0, 25.0), (0.0, 0.0), (-5.0, 5.0));
            for l in &mut legs {
                // Knees straight or bent up to 50 deg: the shin points forward, lower.
                l.shin = l.thigh - uniform(rng, (0.0, 50.0));
            }
            (pitch, legs)
        }
        PostureKind::CrossLegged => (
            uniform(rng, (-15.0, 25.0)),
            leg(
                rng,
                (55.0, 85.0),
                (30.0, 55.0),
                (60.0, 100.0),
                (-80.0, -50.0),
            ),
        ),
    }
}

/// The unit direction of a leg segment in the canonical frame: `forward_deg` from straight
/// down towards the front (-x), then `spread_deg` towards the side `side` (-1 left, +1
/// right).
fn leg_direction(forward_deg: f64, spread_deg: f64, side: f64) -> V3 {
    let (sf, cf) = forward_deg.to_radians().sin_cos();
    let (ss, cs) = spread_deg.to_radians().sin_cos();
    [-sf * cs, side * ss, -cf * cs]
}

/// Turns the points of `pose` listed in `landmarks` about the lateral axis (+y) through
/// `pivot` by `angle_deg`, positive leaning forward (towards -x for points above the pivot).
fn pitch_about(
    pose: &mut Pose3,
    landmarks: impl Iterator<Item = Landmark>,
    pivot: V3,
    angle_deg: f64,
) {
    let (s, c) = (-angle_deg).to_radians().sin_cos();
    for l in landmarks {
        let p = sub(pose.get(l), pivot);
        let turned = [c * p[0] + s * p[2], p[1], -s * p[0] + c * p[2]];
        pose.points[l.index()] = add(pivot, turned);
    }
}

/// `pose` (canonical) in a posture of `kind`: the upper body (neck, head and arms) turned
/// rigidly about the pelvis to a new torso pitch, keeping the arms where they are relative
/// to the torso (at the face, on the knees, ...), and each leg's thigh and shin set to new
/// directions with their own lengths. The angles are drawn from `kind`'s ranges and kept
/// within `limits`: the torso pitch within its range, the hip flexion (thigh against torso)
/// and the knee flexion below their maxima. The result is not canonicalised again.
pub fn make_posture(
    pose: &Pose3,
    kind: PostureKind,
    limits: &PostureLimits,
    rng: &mut impl Rng,
) -> Pose3 {
    let (pitch, mut legs) = draw_targets(kind, rng);
    let (lo, hi) = limits.torso_pitch_deg;
    let mut pitch = pitch.clamp(lo.min(hi), hi.max(lo));
    // The hip flexion is about thigh + pitch: lean back first, then lower the thighs.
    let hip_max = limits.hip_flexion_max_deg;
    let steepest = legs
        .iter()
        .map(|l| l.thigh)
        .fold(f64::NEG_INFINITY, f64::max);
    if steepest + pitch > hip_max {
        pitch = (hip_max - steepest).max(lo.min(hi));
        for l in &mut legs {
            l.thigh = l.thigh.min(hip_max - pitch);
        }
    }
    let mut out = *pose;
    let pelvis = pose.get(Landmark::Pelvis);
    let current = body_angles(pose).torso_pitch_deg;
    pitch_about(&mut out, Landmark::Neck.subtree(), pelvis, pitch - current);
    // A leg's knee and ankle for a target, with its own bone lengths.
    let place = |k: usize, target: &LegTarget| {
        let [hip, knee, ankle] = LEGS[k];
        let side = if k == 0 { -1.0 } else { 1.0 };
        let thigh_len = norm(sub(pose.get(knee), pose.get(hip)));
        let shin_len = norm(sub(pose.get(ankle), pose.get(knee)));
        let thigh = leg_direction(target.thigh, target.spread, side);
        let mut shin = leg_direction(target.shin, target.shin_spread, side);
        // Knee flexion within the limit: turn the shin towards the thigh's direction.
        for _ in 0..32 {
            if angle_deg(thigh, shin) <= limits.knee_flexion_max_deg {
                break;
            }
            shin = unit(add(scale(shin, 0.9), scale(thigh, 0.1))).unwrap_or(thigh);
        }
        let k = add(pose.get(hip), scale(thigh, thigh_len));
        (k, add(k, scale(shin, shin_len)))
    };
    let mut placed = [place(0, &legs[0]), place(1, &legs[1])];
    if kind == PostureKind::HalfKneel {
        // The front foot stands on the floor the other knee kneels on: raise its thigh (within
        // the hip limit) until its ankle is no lower than that knee.
        let kneeling = usize::from(legs[1].shin < legs[0].shin);
        let front = 1 - kneeling;
        let floor = placed[kneeling].0[2];
        while placed[front].1[2] < floor - 0.03 && legs[front].thigh + pitch < hip_max {
            legs[front].thigh += 2.0;
            placed[front] = place(front, &legs[front]);
        }
    }
    for ([_, knee, ankle], (k, a)) in LEGS.into_iter().zip(placed) {
        out.points[knee.index()] = k;
        out.points[ankle.index()] = a;
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proptest::prelude::*;
    use rand::SeedableRng;

    use crate::test_poses::standing;

    /// Limits like those learned from the CMU data, for tests.
    pub(crate) const LIMITS: PostureLimits = PostureLimits {
        hip_flexion_max_deg: 120.0,
        knee_flexion_max_deg: 150.0,
        torso_pitch_deg: (-30.0, 60.0),
    };

    #[test]
    fn a_standing_pose_is_upright_and_straight() {
        let a = body_angles(&standing());
        assert!(a.torso_pitch_deg.abs() < 10.0, "{a:?}");
        for k in 0..2 {
            assert!(a.hip_flexion_deg[k].abs() < 15.0, "{a:?}");
            assert!(a.knee_flexion_deg[k] < 15.0, "{a:?}");
        }
        assert!(!is_low_posture(&standing()));
        assert_eq!(PostureGroup::of(&standing()), PostureGroup::Upright);
        // Pelvis 0.9 m above the ankles, ankles 7 cm above the floor.
        assert!((pelvis_height_m(&standing()) - 0.97).abs() < 1e-12);
    }

    proptest! {
        /// Every posture keeps the bone lengths, puts the torso pitch, hip and knee flexion
        /// within the limits, keeps the arms fixed relative to the torso, and (but for the
        /// kneeling ones) folds a thigh beyond 45 deg from the vertical.
        #[test]
        fn postures_keep_bones_and_limits(seed in 0u64..400) {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let p = standing();
            let kind = PostureKind::draw(&mut rng);
            let q = make_posture(&p, kind, &LIMITS, &mut rng);
            for l in 0..camloc_skeleton::NUM_LIMBS {
                prop_assert!((q.limb_length(l) - p.limb_length(l)).abs() < 1e-9, "limb {}", l);
            }
            let a = body_angles(&q);
            prop_assert!(a.torso_pitch_deg >= -30.0 - 1e-6 && a.torso_pitch_deg <= 60.0 + 1e-6, "{:?}", a);
            for k in 0..2 {
                prop_assert!(a.knee_flexion_deg[k] <= 150.0 + 1e-6, "{:?} {:?}", kind, a);
                prop_assert!(a.hip_flexion_deg[k] <= 120.0 + 3.0, "{:?} {:?}", kind, a);
            }
            // The wrist relative to the neck, in torso coordinates, is unchanged.
            let rel = |x: &Pose3| {
                let d = sub(x.get(Landmark::LeftWrist), x.get(Landmark::Neck));
                let up = unit(sub(x.get(Landmark::Neck), x.get(Landmark::Pelvis))).unwrap();
                (dot(d, up), d[1])
            };
            prop_assert!((rel(&q).0 - rel(&p).0).abs() < 1e-9 && (rel(&q).1 - rel(&p).1).abs() < 1e-9);
            // Every posture lowers the pelvis; a torso pitched beyond 45 deg counts as bent.
            let group = PostureGroup::of(&q);
            prop_assert!(group == PostureGroup::Low || (group == PostureGroup::Bent && a.torso_pitch_deg.abs() > 45.0), "{:?} {:?} {:?} {}", kind, group, a, pelvis_height_m(&q));
            if !matches!(kind, PostureKind::Kneel | PostureKind::HalfKneel) {
                prop_assert!(a.thigh_from_vertical_deg.iter().any(|&t| t > 45.0), "{:?} {:?}", kind, a);
            }
        }
    }

    #[test]
    fn limits_are_learned_from_the_poses() {
        assert_eq!(
            PostureLimits::learn(std::iter::empty()).knee_flexion_max_deg,
            0.0
        );
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let seated: Vec<Pose3> = (0..400)
            .map(|_| make_posture(&standing(), PostureKind::Chair, &LIMITS, &mut rng))
            .collect();
        let poses: Vec<Pose3> = std::iter::repeat_n(standing(), 400).chain(seated).collect();
        let learned = PostureLimits::learn(&poses);
        assert!(
            learned.hip_flexion_max_deg > 80.0 && learned.hip_flexion_max_deg <= 123.0,
            "{learned:?}"
        );
        let standing_only = PostureLimits::learn(std::iter::repeat_n(&standing(), 10));
        assert!(
            standing_only.hip_flexion_max_deg < 15.0,
            "{standing_only:?}"
        );
    }
}
