//! One person's reconstructed frames seen by one fixed camera, placed in a world frame of
//! that camera: where the person stood and which way they faced in each frame
//! ([`world_poses`]), for animation with root motion.

use camloc_geometry::{Matrix3, Vector3};
use camloc_skeleton::{NUM_LANDMARKS, Pose3};

use crate::{FrameRate, Reconstruction};

mod centred;
mod contact;
mod floor;
mod foot_lock;
mod image_ankles;
mod planted;

/// [`world_poses`] places the pelvis at the mean of its places in the frames within this many
/// frames before and after (at 30 frames a second; within as long a time at faster rates,
/// [`FrameRate`]; the straight line through them where some are missing): the depth from one
/// frame's scale jitters (on tripod views of CMU walks, 30 frames a second, the
/// path walked came out 30% long without it).
pub const SMOOTHING_FRAMES: usize = 2;

/// The frames of one person filmed by one fixed camera, in time order (`None`: a frame
/// without a reconstruction), placed in one z-up world frame, metres: each frame's pose turned
/// by its camera rotation and moved to its pelvis's place in front of the camera.
///
/// - **The camera**: `intrinsics` (focal length and principal point, pixels) when known;
///   then each frame's perspective camera ([`Reconstruction::perspective`]) places the
///   pelvis. Else the focal length is the median of the frames' estimated ones (a sequence's
///   shared distance, [`Refinement::distance`](crate::Refinement::distance)) and the
///   principal point the centre of the box of the pelvis's image positions; each frame's
///   weak-perspective camera then gives the pelvis's depth (focal length over scale) and its
///   place across the image, and its rotation, fitted as if the optical axis went through
///   the pelvis, is turned from that ray to the optical axis. Without any focal length the
///   depth is the same in every frame and the rotations are taken as they are.
/// - **Estimated focal length**: without `intrinsics`, the estimated focal length is scaled
///   by the factor that puts the frames' lowest landmarks at one height (`world/contact.rs`,
///   `depth_factor`: every depth scales with it, and so does the floor's rise with the
///   depth), weighed in logarithms against the estimate by its own error and the
///   localizer's vertical's, when the person's depth changed enough to tell. A simulated
///   user's walks towards and away from cameras 1.5-6 m high: the extent in depth 0.51-10.5
///   times the truth's before, 0.74-1.87 times after.
/// - **Floor contact**: with a depth per frame (a focal length known or estimated), each
///   frame's pelvis is first moved along its ray from the camera, weighing the depth from its
///   scale against the depth that puts its lowest landmark on the plane fitted to all frames'
///   lowest landmarks (`world/contact.rs`; the slow part of a frame's distance from it is
///   kept when large, and frames far off it keep theirs: a jump): the steeper the camera
///   looks down, the more a depth error shows as a height error, and the more the floor
///   decides. A simulated user's child walking under a camera 3 m high, 5 m
///   away (true lengths and focal length): the lower ankle's height, 5th / 50th / 95th
///   percentile, -0.7 / 1.2 / 3.2 cm against -0.9 / 8.0 / 16.7 cm before (the truth's 2.6-4.8
///   cm), the path walked 12.27 m against 13.01 (the truth's 12.35). Another's CMU walks,
///   runs and stairs from five tripods at 0.5-6 m (35 clips and cameras, focal length
///   given): the pelvis 6.4 cm from the truth on average against 8.2 cm, the lower ankle's
///   median height 7.5 cm against 11.6; its jumps' height 8.7 cm off on average, as before,
///   but -3.1 cm on average against +6.6 (`SLOW_ERROR_M`; with every change of this list).
/// - **Smoothing**: the pelvis's place is averaged over [`SMOOTHING_FRAMES`] frames on each
///   side (fewer near the ends, as many on both sides; where some are `None`, the straight
///   line through those present, taken at the frame; the frames' own poses and rotations are
///   kept). `frames` should hold a `None` for each video frame the person is missing from,
///   so that time passes there.
/// - **Upright**: `verticals` gives, where known, each frame's world vertical in camera
///   coordinates as the localizer saw it (the third column of
///   `Localization::viewpoint_rotation`). The reconstruction's camera may tilt the body
///   towards or away from the camera (by 14 deg for a walk towards a tripod in a user's trial,
///   where the localizer was within 1 deg), which would make the floor slope; the bodies are
///   turned by one rotation so that their vertical is the localizer's on average. Without
///   any, the reconstructions' own.
/// - **Up** is the mean over the frames of the body frame's vertical seen by the camera (the
///   basis's poses are upright in that frame: its z is the world's vertical, for seated and
///   crawling poses too).
/// - **Axes**: x is the camera's right made horizontal, y points away from the camera, z up.
/// - **Planted feet**: the pelvis's path is then moved so that a foot on the floor stays
///   where it stands (the depth from one frame's scale jitters by centimetres, and the feet
///   slid with it): per axis, the path nearest the placed one whose steps are those of the
///   planted ankle seen from the pelvis and which bends little from frame to frame
///   (`world/planted.rs`). In each step the planted foot
///   is the one that moves less, unless it moves with the pelvis (a person gliding or
///   carried) or is above the floor; a foot that keeps its place on average, in the world
///   or in the image (each frame's reprojection), is planted too, both feet when both do
///   (a person standing or sitting still). Across `None` frames the path only bends.
/// - **Locked feet**: within each run of frames where an ankle is planted, the ankle is put
///   at the run's mean place by turning the thigh and shin about the hip (the knee in its
///   plane, the lengths kept, the knee straightened by at most 5 deg and not beyond 165
///   deg), the correction going
///   in even steps between two runs of a foot and fading over 2 frames at the ends
///   (`world/foot_lock.rs`), after the floor below: after the path's move the planted feet
///   still slid by 1.0-2.1 cm a frame on a simulated user's five tripod walks (the truth's
///   0.25-0.3 cm), locked by 0.16-1.4 cm, the poses' PA-MPJPE within 1.4 mm. These poses are
///   the animation's; the reconstructions themselves are not changed.
/// - **Floor**: a slope of the planted ankles' heights along the path gentler than 20 deg
///   (from the depth's error, which grows with the distance, and from the localizer's
///   elevation: the child above walked on a floor sloping 12 deg towards the camera) is taken
///   out by moving each frame up or down; steeper ones (stairs) are kept (`world/floor.rs`). The floor, z = 0,
///   has a tenth of the planted ankles below it; with fewer than 10 planted ankles, the
///   lowest landmark of all frames is on it.
/// - **Origin**: across the floor, the first frame's pelvis.
///
/// Sizes and distances are in the length prior's size when the bone lengths were estimated.
/// A panning or moving camera turns its own motion into the person's.
pub fn world_poses(
    frames: &[Option<&Reconstruction>],
    verticals: &[Option<[f64; 3]>],
    intrinsics: Option<(f64, [f64; 2])>,
    rate: FrameRate,
) -> Vec<Option<Pose3>> {
    let found: Vec<&Reconstruction> = frames.iter().flatten().copied().collect();
    if found.is_empty() {
        return vec![None; frames.len()];
    }
    let mut place = Placement::of(&found, intrinsics);
    let tilt = tilt_to(frames, verticals);
    // Each frame's body -> camera rotation and pelvis in the camera frame, the pelvis
    // averaged over the frames within SMOOTHING_FRAMES of it.
    let seen_by = |place: &Placement| -> Vec<Option<(Matrix3, Vector3)>> {
        frames
            .iter()
            .map(|f| {
                f.map(|r| {
                    let (rotation, pelvis) = place.frame(r);
                    (rotation * tilt, pelvis)
                })
            })
            .collect()
    };
    let mut seen = seen_by(&place);
    let up_sum: Vector3 = seen
        .iter()
        .flatten()
        .map(|(r, _)| r.column(2).into_owned())
        .sum();
    let up = if up_sum.norm() > 0.0 {
        up_sum.normalize()
    } else {
        -Vector3::y()
    };
    let [right, away] = horizontal_axes(&up);
    // An estimated focal length scales every depth: the floor under the frames says by how
    // much, when the person's depth changed enough for it to tell.
    if let (None, Placement::Weak { focal: Some(f), .. }) = (intrinsics, &mut place)
        && let Some(factor) = contact::depth_factor(frames, &seen, &up, rate)
    {
        *f *= factor;
        seen = seen_by(&place);
    }
    if place.has_depth() {
        contact::onto_floor(frames, &mut seen, &up, [right, away], rate);
    }
    // The pelvis's place averaged over SMOOTHING_FRAMES (at the rate) on each side: the
    // straight line through the frames present there, taken at the frame.
    let pelvis: Vec<Option<[f64; 3]>> = seen.iter().map(|s| s.map(|(_, p)| p.into())).collect();
    for (s, p) in seen.iter_mut().zip(centred::centred_lines(
        &pelvis,
        SMOOTHING_FRAMES * rate.step(),
    )) {
        if let (Some((_, place)), Some(p)) = (s, p) {
            *place = Vector3::from(p);
        }
    }
    // Rows: the world axes in camera coordinates (camera -> world).
    let to_world = Matrix3::from_rows(&[right.transpose(), away.transpose(), up.transpose()]);
    let mut placed: Vec<Option<Pose3>> = frames
        .iter()
        .zip(&seen)
        .map(|(f, seen)| {
            let (r, (rotation, pelvis)) = (f.as_ref()?, seen.as_ref()?);
            let points: [[f64; 3]; NUM_LANDMARKS] = std::array::from_fn(|j| {
                let x = Vector3::from(r.pose.points[j]);
                (to_world * (rotation * x + pelvis)).into()
            });
            Some(Pose3 { points })
        })
        .collect();
    // Each frame's landmarks as its camera saw them: a foot still there is planted whatever
    // depth the frame's scale gave it.
    let images: Vec<Option<[[f64; 2]; NUM_LANDMARKS]>> = frames
        .iter()
        .map(|f| f.map(Reconstruction::reprojection))
        .collect();
    let planted = planted::plant_feet(&mut placed, &images, rate);
    let floor = floor::level(&mut placed, &planted.stepping);
    foot_lock::lock_feet(&mut placed, &planted.all, rate);
    let first = placed
        .iter()
        .flatten()
        .next()
        .map_or([0.0; 3], |p| p.points[0]);
    let floor = floor.unwrap_or_else(|| {
        placed
            .iter()
            .flatten()
            .flat_map(|p| p.points.iter().map(|q| q[2]))
            .fold(f64::INFINITY, f64::min)
    });
    let origin = [first[0], first[1], floor];
    placed
        .into_iter()
        .map(|p| {
            p.map(|p| Pose3 {
                points: p.points.map(|q| std::array::from_fn(|k| q[k] - origin[k])),
            })
        })
        .collect()
}

/// The world's axes across the floor in camera coordinates, for the world vertical `up`
/// (unit): x the camera's right made horizontal, y away from the camera (up x right).
fn horizontal_axes(up: &Vector3) -> [Vector3; 2] {
    let right = Vector3::x() - up * up.x;
    let right = if right.norm() > 1e-9 {
        right.normalize()
    } else {
        Vector3::z().cross(up).normalize()
    };
    [right, up.cross(&right)]
}

/// The rotation `T` of the body frame that makes the frames' bodies upright as `verticals`
/// say (each frame's world vertical in camera coordinates, where known): each frame's camera
/// then sees the body's vertical `R T z` along its vertical on average (`T z` is the mean
/// of `R^T v` over the frames, `R` body -> camera); the identity without any.
fn tilt_to(frames: &[Option<&Reconstruction>], verticals: &[Option<[f64; 3]>]) -> Matrix3 {
    let mut vertical = Vector3::zeros();
    for (f, v) in frames.iter().zip(verticals) {
        if let (Some(r), Some(v)) = (f, v) {
            vertical += r.camera.rotation.transpose() * Vector3::from(*v);
        }
    }
    camloc_geometry::rotation_between(&Vector3::z(), &vertical).unwrap_or_else(Matrix3::identity)
}

/// How [`world_poses`] places a frame in the camera frame.
enum Placement {
    /// Known intrinsics: each frame's perspective camera (rotation and translation).
    Perspective,
    /// Weak perspective with a focal length (pixels; `None`: unknown) and a principal point.
    Weak {
        focal: Option<f64>,
        principal: [f64; 2],
    },
}

impl Placement {
    /// The placement of `found` (at least one frame) given `intrinsics`.
    fn of(found: &[&Reconstruction], intrinsics: Option<(f64, [f64; 2])>) -> Placement {
        if intrinsics.is_some() && found.iter().all(|r| r.perspective.is_some()) {
            return Placement::Perspective;
        }
        let mut focals: Vec<f64> = found
            .iter()
            .filter_map(|r| r.perspective.as_ref().map(|p| p.focal_px))
            .filter(|f| f.is_finite() && *f > 0.0)
            .collect();
        focals.sort_by(f64::total_cmp);
        let focal = intrinsics
            .map(|(f, _)| f)
            .or_else(|| focals.get(focals.len() / 2).copied());
        let principal = intrinsics.map_or_else(
            || {
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for r in found {
                    for k in 0..2 {
                        lo[k] = lo[k].min(r.camera.translation[k]);
                        hi[k] = hi[k].max(r.camera.translation[k]);
                    }
                }
                [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]
            },
            |(_, c)| c,
        );
        Placement::Weak { focal, principal }
    }

    /// `true` when each frame has a depth of its own (a focal length is known or estimated).
    fn has_depth(&self) -> bool {
        !matches!(self, Placement::Weak { focal: None, .. })
    }

    /// The body -> camera rotation of `r` and its pelvis in the camera frame, metres.
    fn frame(&self, r: &Reconstruction) -> (Matrix3, Vector3) {
        let (focal, principal) = match (self, &r.perspective) {
            (Placement::Perspective, Some(p)) => {
                return (p.rotation, Vector3::from(p.translation));
            }
            // (Not made: `of` gives `Perspective` only when every frame has one.)
            (Placement::Perspective, None) => (None, [0.0; 2]),
            (Placement::Weak { focal, principal }, _) => (*focal, *principal),
        };
        let s = r.camera.scale;
        let across = [
            (r.camera.translation[0] - principal[0]) / s,
            (r.camera.translation[1] - principal[1]) / s,
        ];
        match focal {
            Some(f) => {
                let pelvis = Vector3::new(across[0], across[1], f / s);
                // The rotation was fitted along the ray to the pelvis: turn that ray onto the
                // optical axis's place.
                let ray = camloc_geometry::rotation_between(&Vector3::z(), &pelvis)
                    .unwrap_or_else(Matrix3::identity);
                (ray * r.camera.rotation, pelvis)
            }
            None => (r.camera.rotation, Vector3::new(across[0], across[1], 0.0)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_geometry::WeakPerspective;
    use camloc_skeleton::Landmark;

    /// A standing pose (metres, canonical frame: facing -x, z up).
    fn standing() -> Pose3 {
        let mut points = [[0.0; 3]; NUM_LANDMARKS];
        let place = |points: &mut [[f64; 3]; NUM_LANDMARKS], l: Landmark, p: [f64; 3]| {
            points[l.index()] = p;
        };
        place(&mut points, Landmark::LeftHip, [0.0, -0.1, -0.05]);
        place(&mut points, Landmark::LeftKnee, [0.0, -0.1, -0.5]);
        place(&mut points, Landmark::LeftAnkle, [0.0, -0.1, -0.95]);
        place(&mut points, Landmark::RightHip, [0.0, 0.1, -0.05]);
        place(&mut points, Landmark::RightKnee, [0.0, 0.1, -0.5]);
        place(&mut points, Landmark::RightAnkle, [0.0, 0.1, -0.95]);
        place(&mut points, Landmark::Neck, [0.0, 0.0, 0.5]);
        place(&mut points, Landmark::Head, [0.0, 0.0, 0.75]);
        place(&mut points, Landmark::LeftShoulder, [0.0, -0.2, 0.45]);
        place(&mut points, Landmark::LeftElbow, [0.0, -0.25, 0.2]);
        place(&mut points, Landmark::LeftWrist, [0.0, -0.25, -0.05]);
        place(&mut points, Landmark::RightShoulder, [0.0, 0.2, 0.45]);
        place(&mut points, Landmark::RightElbow, [0.0, 0.25, 0.2]);
        place(&mut points, Landmark::RightWrist, [0.0, 0.25, -0.05]);
        Pose3 { points }
    }

    /// A camera level with the pelvis seeing the body from its front turned by `yaw` about
    /// the vertical, the pelvis at `t` in the image (scale 100 px per metre).
    fn seen(yaw: f64, t: [f64; 2]) -> Reconstruction {
        // Body -> camera: the camera looks along +x of the body (at its front, which faces
        // -x), image y down.
        let turn = Matrix3::new(
            yaw.cos(),
            -yaw.sin(),
            0.0,
            yaw.sin(),
            yaw.cos(),
            0.0,
            0.0,
            0.0,
            1.0,
        );
        let front = Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, -1.0, 1.0, 0.0, 0.0);
        Reconstruction::seen_by(
            standing(),
            WeakPerspective {
                scale: 100.0,
                rotation: front * turn,
                translation: t,
            },
        )
    }

    #[test]
    fn the_localizer_s_verticals_level_the_floor_of_a_tilted_reconstruction() {
        // A walk straight away from the camera (10 m, then 20 m: scale 100, then 50 px per
        // metre at 1000 px), reconstructed leaning 10 deg towards the camera; the localizer
        // saw the body upright.
        let pitch = 10f64.to_radians();
        let lean = Matrix3::new(
            pitch.cos(),
            0.0,
            pitch.sin(),
            0.0,
            1.0,
            0.0,
            -pitch.sin(),
            0.0,
            pitch.cos(),
        );
        let (mut near, mut far) = (seen(0.0, [0.0, 0.0]), seen(0.0, [0.0, 0.0]));
        let upright: [f64; 3] = near.camera.rotation.column(2).into_owned().into();
        far.camera.scale = 50.0;
        for r in [&mut near, &mut far] {
            r.camera.rotation *= lean;
        }
        let camera = Some((1000.0, [0.0, 0.0]));
        let rise = |placed: Vec<Option<Pose3>>| {
            let (a, b) = (placed[0].unwrap(), placed[1].unwrap());
            b.get(Landmark::Pelvis)[2] - a.get(Landmark::Pelvis)[2]
        };
        let own = rise(world_poses(
            &[Some(&near), Some(&far)],
            &[],
            camera,
            FrameRate::default(),
        ));
        let told = rise(world_poses(
            &[Some(&near), Some(&far)],
            &[Some(upright), Some(upright)],
            camera,
            FrameRate::default(),
        ));
        // Alone, the floor slopes by the lean over the 10 m walked; told, it is level.
        assert!((own.abs() - 10.0 * pitch.sin()).abs() < 1e-6, "{own}");
        assert!(told.abs() < 1e-9, "{told}");
    }

    #[test]
    fn a_person_walking_across_and_turning_moves_and_turns_in_the_world() {
        let a = seen(0.0, [0.0, 0.0]);
        let b = seen(std::f64::consts::FRAC_PI_2, [100.0, 0.0]);
        let placed = world_poses(&[Some(&a), None, Some(&b)], &[], None, FrameRate::default());
        assert!(placed[1].is_none());
        let (p, q) = (placed[0].unwrap(), placed[2].unwrap());
        // Feet on the floor, upright: the head above the pelvis by the pose's 0.75 m.
        let lowest = p.points.iter().map(|x| x[2]).fold(f64::INFINITY, f64::min);
        assert!(lowest.abs() < 1e-12, "{lowest}");
        let pelvis = Landmark::Pelvis.index();
        let head = Landmark::Head.index();
        assert!((p.points[head][2] - p.points[pelvis][2] - 0.75).abs() < 1e-9);
        // The first pelvis is the origin across the floor; the second is 1 m to the right.
        assert!(p.points[pelvis][0].abs() < 1e-12 && p.points[pelvis][1].abs() < 1e-12);
        assert!(
            (q.points[pelvis][0] - 1.0).abs() < 1e-9,
            "{:?}",
            q.points[pelvis]
        );
        // The shoulder line turned by a quarter turn about the vertical.
        let line = |pose: &Pose3| {
            let (l, r) = (
                pose.get(Landmark::LeftShoulder),
                pose.get(Landmark::RightShoulder),
            );
            Vector3::new(r[0] - l[0], r[1] - l[1], r[2] - l[2]).normalize()
        };
        assert!(line(&p).dot(&line(&q)).abs() < 1e-9);
        assert!(line(&p)[2].abs() < 1e-9 && line(&q)[2].abs() < 1e-9);
        // Lengths are kept.
        for limb in 0..camloc_skeleton::NUM_LIMBS {
            assert!((q.limb_length(limb) - b.pose.limb_length(limb)).abs() < 1e-9);
        }
    }
}
