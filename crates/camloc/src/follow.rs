//! People of detections without a tracker's ids: [`follow_people`] numbers the poses of a
//! video whose person numbers are only the detector's order of each frame's poses (OpenPose
//! without tracking, MMPose without `track_id`), following each person by where it is.

use camloc_keypoints::KeypointRecord;
use camloc_reconstruct::FrameRate;

use crate::identity::{
    TRACK_POSES, TorsoAnchor, expected_step, reach_torsos, step_cost, torso_step, within_reach,
};
use crate::{BRIEF_PERSON_STEPS, FollowReport, continuations, videos_of};

/// The most poses of one frame that [`follow_people`] follows: a frame of more (a crowd, or a
/// hostile file of one frame with millions) leaves the detector's order as it is.
pub const MAX_FOLLOWED_PER_FRAME: usize = 64;

/// How long a person may go unseen, in 1/30 s, and still be followed by [`follow_people`]
/// when seen again within reach (half a second: unseen for 2 s, a bystander seen 50 frames
/// before had taken a walker whose image a tilting camera moved).
pub const FOLLOW_GAP_STEPS: f64 = 15.0;

/// How near another pose of its frame that was taken for a person a pose must lie, in torso
/// lengths, to be taken for that person's second detection (a detector's duplicate) by
/// [`follow_people`] rather than for another person: two people side by side stand a
/// shoulder width (most of a torso length) apart. (A quarter of a torso had made persons of
/// their own of a simulated user's duplicates 10 px off people whose torsos were 30 px.)
pub const DUPLICATE_TORSOS: f64 = 0.5;

/// The most two torsos' sizes may differ (larger over smaller) for [`follow_people`] to take
/// one for the other's duplicate ([`DUPLICATE_TORSOS`]): one person behind another is smaller.
pub const DUPLICATE_SIZE_RATIO: f64 = 1.25;

/// How many times its reach a pose left over may lie from where the one person seen lately is
/// expected, when that person has no pose in the frame, for [`follow_people`] to take it for
/// that person's (a misplaced detection) rather than for a new person: a simulated user's
/// walker with a pelvis misplaced by two torsos beside a false detection elsewhere had become
/// a person of its own. Among several people seen lately the pose is left to be a new person:
/// taken for a person without a pose in the frame, it mixed a simulated crowd's people (6
/// people, changes of person 9 -> 15 and 16 -> 23 with the factor 2 or 3).
pub const LOST_REACH_FACTOR: f64 = 3.0;

/// The most persons seen lately that [`follow_people`] compares a frame's poses with (the
/// latest seen): each costs a comparison with every pose of every frame, which a hostile input
/// of people appearing everywhere at once would make grow without bound.
const MAX_ACTIVE: usize = 4 * MAX_FOLLOWED_PER_FRAME;

/// One person followed: its last poses with a torso (positions in frame order and anchors,
/// newest last) and where it was last seen.
struct Followed {
    recent: Vec<(usize, TorsoAnchor)>,
    last: usize,
}

/// The person of each pose of one video whose poses carry no tracker's id (`frames`: each
/// pose's frame number; `anchors`: where each is, [`TorsoAnchor::of`]; in any order), or
/// `None` when a frame has more than [`MAX_FOLLOWED_PER_FRAME`] poses. Frame by frame, in
/// frame order, each person seen within [`FOLLOW_GAP_STEPS`] takes the nearest pose within
/// its reach, as [`left_out_of_sequence`](crate::left_out_of_sequence) tells a person's pose
/// from the others of its frame (where the person is expected from its last poses and
/// velocity; a torso length, and 0.4 of one for every further 1/30 s), nearest pairs first;
/// a pose left over lying within [`DUPLICATE_TORSOS`] of a pose taken is that person's second
/// detection; while only one person has been seen lately, a pose left over within
/// [`LOST_REACH_FACTOR`] times its reach is that person's (a misplaced detection, which its
/// sequence then leaves out); a pose alone in its frame goes to the nearest of the persons
/// seen last (likewise); any other pose left over is a new person, numbered in order of
/// appearance (the first pose of the first frame is person 0). A pose without a torso goes to
/// the person seen last that has no pose in the frame yet, else is a new person. So a single
/// person keeps the number 0 throughout; the detector's order of people (OpenPose's
/// `people[i]`) changes whenever one is missed or another appears, which had made a walker's
/// frame with a bystander listed first the bystander's, and the walker's pose there a
/// two-frame person of its own (a simulated animator's OpenPose folder: a junk animation, and
/// the walker's frame interpolated); a simulated user's untracked videos of 2-6 people came out as 2-8
/// persons, each 79-100% one person's, where following one person after another (person 0
/// through the video, then person 1 among the poses left) had given 3-10, 56-97%
/// (docs/measured.md).
/// People who cross, or one who leaves as another enters nearby, may still be taken for
/// each other: no appearance is known. `rate`: frames a second, for the reach.
pub fn follow_people(
    frames: &[u64],
    anchors: &[Option<TorsoAnchor>],
    rate: FrameRate,
) -> Option<Vec<u64>> {
    let mut order: Vec<usize> = (0..frames.len()).collect();
    order.sort_by_key(|&i| (frames[i], i));
    if order
        .chunk_by(|&a, &b| frames[a] == frames[b])
        .any(|group| group.len() > MAX_FOLLOWED_PER_FRAME)
    {
        return None;
    }
    // Positions in frame order: their frame numbers and anchors.
    let numbers: Vec<Option<u64>> = order.iter().map(|&i| Some(frames[i])).collect();
    let anchor = |m: usize| anchors.get(order[m]).copied().flatten();
    let gap = FOLLOW_GAP_STEPS * rate.step() as f64;
    let mut people: Vec<Option<usize>> = vec![None; order.len()];
    let mut tracks: Vec<Followed> = Vec::new();
    // The persons seen lately (at most MAX_ACTIVE, the latest), and those of the last frame
    // with poses.
    let (mut active, mut last_frame): (Vec<usize>, Vec<usize>) = (Vec::new(), Vec::new());
    let mut start = 0;
    while start < order.len() {
        let end = (start + 1..order.len())
            .find(|&m| numbers[m] != numbers[start])
            .unwrap_or(order.len());
        let now = numbers[start].unwrap_or(0);
        let seen_lately = |t: &Followed| now - numbers[t.last].unwrap_or(0) <= gap as u64;
        active.retain(|&k| seen_lately(&tracks[k]));
        // Pairs within reach, nearest first.
        let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
        for &k in &active {
            let track = &tracks[k];
            for m in start..end {
                let distance =
                    anchor(m).and_then(|a| within_reach(&track.recent, &numbers, m, a, rate));
                if let Some(d) = distance {
                    pairs.push((d, k, m));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut taken = vec![false; tracks.len()];
        let mut within = Vec::new();
        for (_, k, m) in pairs {
            if !taken[k] && people[m].is_none() {
                taken[k] = true;
                people[m] = Some(k);
                within.push(m);
            }
        }
        // A pose left over near a pose taken is its person's second detection.
        for m in start..end {
            if people[m].is_none()
                && let Some(k) = anchor(m).and_then(|a| duplicate_of(&people, &within, &anchor, a))
            {
                people[m] = Some(k);
            }
        }
        // Then the one person seen lately, without a pose here, takes the nearest pose left
        // within LOST_REACH_FACTOR times its reach (its track does not move).
        if let [k] = active[..]
            && !taken[k]
        {
            let lost = (start..end)
                .filter(|&m| people[m].is_none())
                .filter_map(|m| {
                    let (moved, ratio, steps) =
                        expected_step(&tracks[k].recent, &numbers, m, anchor(m)?, rate)?;
                    (moved <= LOST_REACH_FACTOR * reach_torsos(steps))
                        .then_some((step_cost(moved, ratio), m))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((_, m)) = lost {
                taken[k] = true;
                people[m] = Some(k);
            }
        }
        for (m, slot) in people.iter_mut().enumerate().take(end).skip(start) {
            if slot.is_some() {
                continue;
            }
            let person = match anchor(m) {
                Some(a) => (end - start == 1)
                    .then(|| nearest(&tracks, &last_frame, &numbers, m, a, rate))
                    .flatten(),
                None => (active.iter().copied())
                    .filter(|&k| !taken[k])
                    .max_by_key(|&k| (tracks[k].last, std::cmp::Reverse(k))),
            };
            let person = person.unwrap_or_else(|| {
                tracks.push(Followed {
                    recent: Vec::new(),
                    last: m,
                });
                taken.push(false);
                within.push(m);
                tracks.len() - 1
            });
            taken[person] = true;
            *slot = Some(person);
        }
        // The persons' tracks go on from the poses within reach (and a new person's first).
        for (m, person) in people.iter().enumerate().take(end).skip(start) {
            let Some(k) = *person else { continue };
            tracks[k].last = m;
            if let (true, Some(a)) = (within.contains(&m), anchor(m)) {
                let recent = &mut tracks[k].recent;
                recent.push((m, a));
                if recent.len() > TRACK_POSES {
                    recent.remove(0);
                }
            }
        }
        last_frame.clear();
        last_frame.extend(people[start..end].iter().flatten().copied());
        last_frame.sort_unstable();
        last_frame.dedup();
        for &k in &last_frame {
            if !active.contains(&k) {
                active.push(k);
            }
        }
        if active.len() > MAX_ACTIVE {
            active.sort_by_key(|&k| std::cmp::Reverse(tracks[k].last));
            active.truncate(MAX_ACTIVE);
        }
        start = end;
    }
    let mut out = vec![0; frames.len()];
    for (m, &i) in order.iter().enumerate() {
        out[i] = people[m].unwrap_or(0) as u64;
    }
    Some(out)
}

/// The person of the pose taken in this frame (`within`, persons in `people`) that `a` lies
/// within [`DUPLICATE_TORSOS`] of, by size too: a detector's second detection of it.
fn duplicate_of(
    people: &[Option<usize>],
    within: &[usize],
    anchor: &impl Fn(usize) -> Option<TorsoAnchor>,
    a: TorsoAnchor,
) -> Option<usize> {
    within
        .iter()
        .filter_map(|&q| {
            let (moved, ratio) = torso_step(&anchor(q)?, &a);
            (moved <= DUPLICATE_TORSOS && ratio <= DUPLICATE_SIZE_RATIO)
                .then_some((moved, people[q]?))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, k)| k)
}

/// The person a pose alone in its frame, out of every person's reach, is taken for (its
/// sequence then leaves it out as misplaced): of the persons of the last frame with poses
/// (`last_frame`), the one whose expected place is nearest the pose at `m` (anchor `a`). The
/// most recently seen come first: a walker whose image a tilting camera moved out of reach had
/// been taken, as the nearest, for a bystander seen 50 frames before.
fn nearest(
    tracks: &[Followed],
    last_frame: &[usize],
    numbers: &[Option<u64>],
    m: usize,
    a: TorsoAnchor,
    rate: FrameRate,
) -> Option<usize> {
    (last_frame.iter())
        .map(|&k| {
            let cost = expected_step(&tracks[k].recent, numbers, m, a, rate)
                .map_or(f64::INFINITY, |(moved, ratio, _)| step_cost(moved, ratio));
            (cost, k)
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, k)| k)
}

/// Gives the poses whose person is only their position among their frame's poses
/// (`positional(i)` of the record at `i`: OpenPose without tracking, MMPose without
/// `track_id`) the persons [`follow_people`] follows from `anchor(i)` at `rate`, video by video
/// ([`videos_of`]): their `keys`' persons are replaced. A video with such a
/// pose without a frame number, or more than [`MAX_FOLLOWED_PER_FRAME`] of them in a
/// frame, keeps the detector's order; other poses keep their persons. Returns what a user
/// should hear of ([`FollowReport`]: persons that may be one, persons of a few frames, videos
/// too crowded to follow).
pub fn follow_untracked<S: AsRef<str>>(
    keys: &mut [(Option<u64>, Option<u64>)],
    sources: &[S],
    folder: bool,
    positional: impl Fn(usize) -> bool,
    anchor: impl Fn(usize) -> Option<TorsoAnchor>,
    rate: FrameRate,
) -> FollowReport {
    let mut report = FollowReport::default();
    let brief = BRIEF_PERSON_STEPS * rate.step() as f64;
    let followed: Vec<(Vec<usize>, Vec<u64>)> = videos_of(keys, sources, folder)
        .into_iter()
        .filter_map(|(file, records)| {
            let untracked: Vec<usize> = records.into_iter().filter(|&i| positional(i)).collect();
            let frames: Vec<u64> = untracked
                .iter()
                .map(|&i| keys[i].0)
                .collect::<Option<_>>()?;
            let anchors: Vec<Option<TorsoAnchor>> = untracked.iter().map(|&i| anchor(i)).collect();
            let file = file.map(str::to_owned);
            let Some(people) = follow_people(&frames, &anchors, rate) else {
                report.crowded.push(file);
                return None;
            };
            for c in continuations(&frames, &anchors, &people, rate) {
                report.continuations.push((file.clone(), c));
            }
            let span = frames
                .iter()
                .max()
                .zip(frames.iter().min())
                .map_or(0, |(a, b)| a - b);
            if span as f64 >= 3.0 * brief {
                let mut poses = std::collections::BTreeMap::<u64, usize>::new();
                for &p in &people {
                    *poses.entry(p).or_default() += 1;
                }
                for (person, n) in poses.into_iter().filter(|&(_, n)| (n as f64) < brief) {
                    report.brief.push((file.clone(), person, n));
                }
            }
            Some((untracked, people))
        })
        .collect();
    for (untracked, people) in followed {
        for (i, person) in untracked.into_iter().zip(people) {
            keys[i].1 = Some(person);
        }
    }
    report
}

/// [`follow_untracked`] on keypoint records read from one input (`folder`: read from a folder,
/// whose files of several frames each are a video each), with each record's frame, person,
/// source and torso: a record whose person was only its position in the frame
/// ([`KeypointRecord::person_is_position`]) gets the person followed at `rate`. Returns what a
/// user should hear of ([`FollowReport`]).
pub fn follow_records(
    records: &mut [KeypointRecord],
    folder: bool,
    rate: FrameRate,
) -> FollowReport {
    let mut keys: Vec<_> = records.iter().map(|r| (r.frame, r.person)).collect();
    let sources: Vec<&str> = records.iter().map(|r| r.source.as_str()).collect();
    let report = follow_untracked(
        &mut keys,
        &sources,
        folder,
        |i| records[i].person_is_position,
        |i| TorsoAnchor::of(&records[i].pose),
        rate,
    );
    for (record, (_, person)) in records.iter_mut().zip(keys) {
        record.person = person;
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frame numbers and anchors of a video's poses, `poses(f)` those of frame `f`.
    fn video(
        frames: impl Iterator<Item = u64>,
        poses: impl Fn(u64) -> Vec<Option<TorsoAnchor>>,
    ) -> (Vec<u64>, Vec<Option<TorsoAnchor>>) {
        frames
            .flat_map(|f| poses(f).into_iter().map(move |a| (f, a)))
            .unzip()
    }

    fn at(x: f64) -> Option<TorsoAnchor> {
        Some(TorsoAnchor {
            pelvis: [x, 300.0],
            torso: 100.0,
        })
    }

    /// Whether each pose's person is 1 exactly when it stands right of `x`.
    fn split_at(people: &[u64], anchors: &[Option<TorsoAnchor>], x: f64) {
        for (p, a) in people.iter().zip(anchors) {
            assert_eq!(*p, u64::from(a.unwrap().pelvis[0] > x), "{a:?}");
        }
    }

    #[test]
    fn a_walker_stays_person_0_when_a_bystander_is_listed_first() {
        // Frames 0-5: a walker moving 10 px a frame; a bystander 600 px away in frames 3 and
        // 4, listed first in frame 4.
        let (frames, anchors) = video(0..6, |f| {
            let (walker, bystander) = (at(100.0 + 10.0 * f as f64), at(800.0));
            match f {
                3 => vec![walker, bystander],
                4 => vec![bystander, walker],
                _ => vec![walker],
            }
        });
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        split_at(&people, &anchors, 500.0);
    }

    #[test]
    fn two_people_who_swap_places_in_the_list_keep_their_numbers() {
        // Two walkers 400 px apart, listed in an order that changes every other frame, given
        // out of frame order; frame 0 lists the left one first: person 0.
        let (frames, anchors) = video((0..8).rev(), |f| {
            let (a, b) = (at(100.0 + 5.0 * f as f64), at(500.0 - 5.0 * f as f64));
            if f % 2 == 0 { vec![a, b] } else { vec![b, a] }
        });
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        split_at(&people, &anchors, 300.0);
    }

    #[test]
    fn a_pose_alone_goes_to_the_person_near_it_and_a_duplicate_to_its_person() {
        // Two walkers 400 px apart; in frames 4-6 only the right one is detected, listed
        // first; frame 8 has a duplicate of the left one 5 px off.
        let (frames, anchors) = video(0..10, |f| {
            let (left, right) = (at(100.0 + 3.0 * f as f64), at(500.0 - 3.0 * f as f64));
            match f {
                4..=6 => vec![right],
                8 => vec![left, at(105.0 + 3.0 * f as f64), right],
                _ => vec![left, right],
            }
        });
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        split_at(&people, &anchors, 300.0);
    }

    #[test]
    fn one_person_s_misplaced_pose_beside_a_false_detection_stays_the_person_s() {
        // A walker; at frame 5 its pose is 2.5 torsos off (a misplaced pelvis) and a false
        // detection lies far away; the walker is person 0 throughout.
        let (frames, anchors) = video(0..10, |f| {
            let walker = at(100.0 + 3.0 * f as f64 + if f == 5 { 250.0 } else { 0.0 });
            if f == 5 {
                vec![at(1500.0), walker]
            } else {
                vec![walker]
            }
        });
        let people = follow_people(&frames, &anchors, FrameRate::default()).unwrap();
        split_at(&people, &anchors, 1000.0);
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
        // The crowd's video is named in the report (it had been left in its order without a
        // word), its poses keep their positions as persons.
        let mut keys: Vec<(Option<u64>, Option<u64>)> = (0..crowd.len() as u64)
            .map(|p| (Some(0), Some(p)))
            .collect();
        let sources = vec!["crowd.json"; keys.len()];
        let report = follow_untracked(
            &mut keys,
            &sources,
            true,
            |_| true,
            |_| at(0.0),
            FrameRate::default(),
        );
        // (One frame's file of a folder: the folder's files are one video, named by none.)
        assert_eq!(report.crowded, vec![None]);
        assert!(keys.iter().enumerate().all(|(p, k)| k.1 == Some(p as u64)));
    }
}
