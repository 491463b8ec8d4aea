//! People of detections without a tracker's ids: [`follow_people`] numbers the poses of a
//! video whose person numbers are only the detector's order of each frame's poses (OpenPose
//! without tracking, MMPose without `track_id`), following each person by where it is.

use camloc_reconstruct::FrameRate;

use crate::identity::{TorsoAnchor, other_poses_of_frames};
use crate::videos_of;

/// The most poses of one frame that [`follow_people`] follows: each person costs a pass over
/// the poses not yet taken, so a frame of more poses (a crowd, or a hostile file of one frame
/// with millions) leaves the detector's order as it is.
pub const MAX_FOLLOWED_PER_FRAME: usize = 64;

/// The person of each pose of one video whose poses carry no tracker's id (`frames`: each
/// pose's frame number; `anchors`: where each is, [`TorsoAnchor::of`]; in any order), or
/// `None` when a frame has more than [`MAX_FOLLOWED_PER_FRAME`] poses. Person 0 is, frame by
/// frame in frame order, the pose that [`left_out_of_sequence`](crate::left_out_of_sequence)
/// takes for a person among a frame's poses (of those within reach of where the person is
/// expected, the nearest; in its first frame, the first in the input; a frame of one pose is
/// the person's), person 1 is the same among the poses left, and so on, until every pose has
/// a person. So a single person keeps the number 0 throughout; the detector's order of people
/// (OpenPose's `people[i]`) changes whenever one is missed or another appears, which had made a
/// walker's frame with a bystander listed first the bystander's, and the walker's pose there
/// a two-frame person of its own (a simulated animator's OpenPose folder: a junk animation, and
/// the walker's frame interpolated). `rate`: frames a second, for the reach.
pub fn follow_people(
    frames: &[u64],
    anchors: &[Option<TorsoAnchor>],
    rate: FrameRate,
) -> Option<Vec<u64>> {
    let mut order: Vec<usize> = (0..frames.len()).collect();
    order.sort_by_key(|&i| (frames[i], i));
    let most_per_frame = order
        .chunk_by(|&a, &b| frames[a] == frames[b])
        .map(<[usize]>::len)
        .max()
        .unwrap_or(0);
    if most_per_frame > MAX_FOLLOWED_PER_FRAME {
        return None;
    }
    let mut people = vec![0; frames.len()];
    let mut pool = order;
    let mut person = 0;
    // Each pass takes at least the first pose of the pool's first frame (a person without a
    // pose yet takes the first), and at most one pose a frame: it ends within
    // `most_per_frame` passes.
    while !pool.is_empty() {
        let pool_frames: Vec<Option<u64>> = pool.iter().map(|&i| Some(frames[i])).collect();
        let pool_anchors: Vec<Option<TorsoAnchor>> = pool
            .iter()
            .map(|&i| anchors.get(i).copied().flatten())
            .collect();
        let mut left = vec![false; pool.len()];
        for m in other_poses_of_frames(&pool_frames, &pool_anchors, rate) {
            left[m] = true;
        }
        let mut rest = Vec::with_capacity(pool.len());
        for (&i, &left) in pool.iter().zip(&left) {
            if left {
                rest.push(i);
            } else {
                people[i] = person;
            }
        }
        pool = rest;
        person += 1;
    }
    Some(people)
}

/// Gives the poses whose person is only their position among their frame's poses
/// (`positional(i)` of the record at `i`: OpenPose without tracking, MMPose without
/// `track_id`) the persons [`follow_people`] follows from `anchor(i)` at `rate`, video by video
/// ([`videos_of`]): their `keys`' persons are replaced. A video with such a
/// pose without a frame number, or more than [`MAX_FOLLOWED_PER_FRAME`] of them in a
/// frame, keeps the detector's order; other poses keep their persons.
pub fn follow_untracked<S: AsRef<str>>(
    keys: &mut [(Option<u64>, Option<u64>)],
    sources: &[S],
    folder: bool,
    positional: impl Fn(usize) -> bool,
    anchor: impl Fn(usize) -> Option<TorsoAnchor>,
    rate: FrameRate,
) {
    let followed: Vec<(Vec<usize>, Vec<u64>)> = videos_of(keys, sources, folder)
        .into_iter()
        .filter_map(|(_, records)| {
            let untracked: Vec<usize> = records.into_iter().filter(|&i| positional(i)).collect();
            let frames: Option<Vec<u64>> = untracked.iter().map(|&i| keys[i].0).collect();
            let anchors: Vec<Option<TorsoAnchor>> = untracked.iter().map(|&i| anchor(i)).collect();
            let people = follow_people(&frames?, &anchors, rate)?;
            Some((untracked, people))
        })
        .collect();
    for (untracked, people) in followed {
        for (i, person) in untracked.into_iter().zip(people) {
            keys[i].1 = Some(person);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64) -> Option<TorsoAnchor> {
        Some(TorsoAnchor {
            pelvis: [x, 300.0],
            torso: 100.0,
        })
    }

    #[test]
    fn a_walker_stays_person_0_when_a_bystander_is_listed_first() {
        // Frames 0-5: a walker moving 10 px a frame; a bystander 600 px away in frames 3 and
        // 4, listed first in frame 4.
        let mut frames = Vec::new();
        let mut anchors = Vec::new();
        for f in 0..6u64 {
            let walker = at(100.0 + 10.0 * f as f64);
            let bystander = at(800.0);
            let poses = match f {
                3 => vec![walker, bystander],
                4 => vec![bystander, walker],
                _ => vec![walker],
            };
            for a in poses {
                frames.push(f);
                anchors.push(a);
            }
        }
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        let walker: Vec<u64> = people
            .iter()
            .zip(&anchors)
            .filter(|(_, a)| a.unwrap().pelvis[0] < 500.0)
            .map(|(&p, _)| p)
            .collect();
        let bystander: Vec<u64> = people
            .iter()
            .zip(&anchors)
            .filter(|(_, a)| a.unwrap().pelvis[0] > 500.0)
            .map(|(&p, _)| p)
            .collect();
        assert_eq!(walker, vec![0; 6]);
        assert_eq!(bystander, vec![1; 2]);
    }

    #[test]
    fn two_people_who_swap_places_in_the_list_keep_their_numbers() {
        // Two walkers 400 px apart, listed in an order that changes every other frame, given
        // out of frame order.
        let mut frames = Vec::new();
        let mut anchors = Vec::new();
        for f in (0..8u64).rev() {
            let (a, b) = (at(100.0 + 5.0 * f as f64), at(500.0 - 5.0 * f as f64));
            let poses = if f % 2 == 0 { [a, b] } else { [b, a] };
            for p in poses {
                frames.push(f);
                anchors.push(p);
            }
        }
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        for (p, a) in people.iter().zip(&anchors) {
            // Frame 0 lists the left walker first: person 0.
            assert_eq!(*p, u64::from(a.unwrap().pelvis[0] > 300.0), "{a:?}");
        }
    }

    #[test]
    fn one_pose_a_frame_is_one_person_and_a_crowd_is_left_in_its_order() {
        let frames: Vec<u64> = (0..5).collect();
        let anchors = vec![at(0.0), at(900.0), None, at(0.0), at(450.0)];
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        assert_eq!(people, vec![0; 5]);
        let crowd = vec![0u64; MAX_FOLLOWED_PER_FRAME + 1];
        let anchors = vec![at(0.0); crowd.len()];
        assert!(follow_people(&crowd, &anchors, FrameRate::default()).is_none());
        assert_eq!(
            follow_people(&[], &[], FrameRate::default()),
            Some(Vec::new())
        );
    }
}
