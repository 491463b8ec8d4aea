//! One person's frames of `camloc reconstruct --sequence`, prepared (frames left out, limbs
//! swapped back in the others, each with its warning, in the persons' order) and solved (the
//! sequence's reconstruction and its placement in the world), the persons of a few frames
//! each solved side by side ([`solve_persons`]).

use camloc::reconstruct::BoneLengths;
use camloc::skeleton::Landmark;
use camloc::{PartialPose2, Pose3, PoseReconstruction, PoseReconstructor, TorsoAnchor};
use rayon::prelude::*;

use super::stream::{KEEP_MAX_POSES, counted};

/// Most frames of the persons solved side by side: persons of a few frames each (a crowd, a
/// flaky tracker's short tracks) are solved in parallel in groups of at most this many frames
/// (one person's solve of a few frames uses one core: 100,000 one-frame tracks had kept one
/// core of two busy); a person of more frames is solved alone, in parallel inside.
pub const PARALLEL_FRAMES: usize = 4096;

/// One person's frames ready for the solve.
pub struct Prepared {
    /// The frames' numbers (`None`: unknown), in time order.
    pub numbers: Vec<Option<u64>>,
    /// The poses, with the limbs a detector swapped left for right swapped back.
    pub poses: Vec<PartialPose2>,
    /// Per frame, the chains swapped back (bit per [`camloc::SideChain::ALL`] chain).
    pub swapped_sides: Vec<u8>,
    /// Per frame, whether it is left out of the sequence (another person's, a second pose of
    /// its frame): reconstructed on its own.
    pub left_out: Vec<bool>,
}

impl Prepared {
    /// The frames of `person` (their frame `numbers` and `poses`, in time order), with the
    /// frames left out of the sequence and the limbs swapped back in the others, each warned
    /// of on standard error.
    pub fn of(
        person: u64,
        numbers: Vec<Option<u64>>,
        mut poses: Vec<PartialPose2>,
        reconstructor: &PoseReconstructor,
    ) -> Prepared {
        let rate = reconstructor.frame_rate();
        let anchors: Vec<_> = poses.iter().map(TorsoAnchor::of).collect();
        // A second pose of a frame, and a frame whose pose is not where the frames around it
        // put the person, are reconstructed on their own, outside the sequence.
        let left_out = super::sequence::left_out_of_sequence(
            person,
            &numbers,
            &anchors,
            rate,
            "reconstructed on its own, left out of the sequence (its lengths, smoothness and \
             animation)",
        )
        .mask(numbers.len());
        let swapped_sides =
            super::sequence::sides_swapped_back(person, &numbers, &mut poses, &left_out, rate);
        Prepared {
            numbers,
            poses,
            swapped_sides,
            left_out,
        }
    }
}

/// One person's frames solved.
pub struct Solved {
    /// Each frame's reconstruction, or its error's message.
    pub frames: Vec<Result<PoseReconstruction, String>>,
    /// The person's bone lengths; `None` when the sequence failed.
    pub lengths: Option<BoneLengths>,
    /// How well the bone lengths given fit the frames (`None`: none given, or no fit).
    pub lengths_fit: Option<camloc::LengthsFit>,
    /// The frames the BVH animates (none without `--bvh` / `--html`): placed in the world
    /// (`root_motion`) or in place.
    pub animated: Vec<Option<Pose3>>,
    /// The frames reconstructed in the sequence (not left out).
    pub reconstructed: usize,
}

/// Warns on standard error when frames of the animation of `person` (its name; `numbers`:
/// its frames' numbers; `animated`: the frames the BVH animates, the floor at z = 0) go below
/// the floor ([`camloc::below_floor`]).
pub fn warn_of_sinking(person: &str, numbers: &[Option<u64>], animated: &[Option<Pose3>]) {
    let Some(below) = camloc::below_floor(animated) else {
        return;
    };
    stderr_line!(
        "camloc: warning: {person}: the animation's feet go {:.0} cm below the floor in {} \
         (first at {}): {}",
        100.0 * below.deepest_m,
        counted(below.frames as u64, "frame"),
        super::sequence::frame_name(numbers, below.first),
        camloc::BELOW_FLOOR_CAUSES
    );
}

/// Warns on standard error of the landmarks of `person` (its name) filled in, not seen, often
/// or over half a second among its reconstructed frames (`often`:
/// [`camloc::often_filled_frames`]) and, unless its lengths were given (`lengths_given`), of
/// the limbs no frame shows.
pub fn warn_of_filled(person: &str, often: Option<camloc::OftenFilled>, lengths_given: bool) {
    if let Some(often) = often {
        stderr_line!(
            "camloc: warning: {person}: landmarks filled in, not seen (their 3D is a guess, from \
             the pose basis or the frames around a short gap; `imputed` in JSON), of its {}: {}",
            counted(often.frames as u64, "reconstructed frame"),
            often.summary(lengths_given)
        );
    }
}

/// Solves each of `persons`, side by side ([`PARALLEL_FRAMES`]); with `animate`, also the
/// frames the BVH animates (placed in the world with `root_motion`).
pub fn solve_persons(
    reconstructor: &PoseReconstructor,
    persons: &[Prepared],
    animate: bool,
    root_motion: bool,
) -> Vec<Solved> {
    persons
        .par_iter()
        .with_max_len(1)
        .map(|p| solve(reconstructor, p, animate, root_motion))
        .collect()
}

/// Solves one person's frames (see [`solve_persons`]).
fn solve(
    reconstructor: &PoseReconstructor,
    person: &Prepared,
    animate: bool,
    root_motion: bool,
) -> Solved {
    let Prepared {
        numbers,
        poses,
        left_out,
        ..
    } = person;
    // A frame after more than `sequence_break_frames` frame numbers the person is missing
    // from starts a new run (the left-out frames count for none).
    let result = reconstructor.reconstruct_sequence_at_frames(numbers, poses, left_out);
    // The left-out frames are reconstructed on their own, also when the sequence failed.
    let lengths_fit = result.as_ref().ok().and_then(|r| r.lengths_fit);
    let (frames, lengths): (Vec<Result<PoseReconstruction, String>>, Option<BoneLengths>) =
        match result {
            Ok(r) => (
                r.frames
                    .into_iter()
                    .map(|f| f.map_err(|e| e.to_string()))
                    .collect(),
                Some(r.lengths),
            ),
            Err(e) => (
                (0..poses.len())
                    .map(|m| match left_out[m] {
                        true => reconstructor
                            .reconstruct(&poses[m])
                            .map_err(|e| e.to_string()),
                        false => Err(e.to_string()),
                    })
                    .collect(),
                None,
            ),
        };
    // Placed where the camera saw them, on the video's timeline (frames where the person was
    // not detected count as time passing, as do the frames left out of the sequence); only
    // for the files made at the end.
    let found: Vec<_> = frames
        .iter()
        .zip(left_out)
        .map(|(f, &left)| f.as_ref().ok().filter(|_| !left))
        .collect();
    let reconstructed = found.iter().flatten().count();
    let placed: Vec<Option<Pose3>> = if animate {
        reconstructor.place_on_timeline(numbers, &found, KEEP_MAX_POSES as usize)
    } else {
        vec![None; poses.len()]
    };
    // The poses the BVH gets: as placed, or in place (the body frame, facing one way, the
    // pelvis above the origin at the height the placement gives it: the feet on the floor,
    // the body bobbing as it did).
    let animated: Vec<Option<Pose3>> = if root_motion {
        placed
    } else {
        found
            .iter()
            .zip(&placed)
            .map(|(r, world)| {
                let (r, world) = (r.as_ref()?, world.as_ref()?);
                let height = world.get(Landmark::Pelvis)[2];
                Some(Pose3 {
                    points: r
                        .reconstruction
                        .pose
                        .points
                        .map(|q| [q[0], q[1], q[2] + height]),
                })
            })
            .collect()
    };
    Solved {
        frames,
        lengths,
        lengths_fit,
        animated,
        reconstructed,
    }
}
