//! Persons of untracked poses that may be one person ([`continuations`]): the following of
//! [`follow_people`](crate::follow_people) loses a person who turns on the spot, folds up or
//! is missed for long, and goes on with a new person.

use std::collections::HashMap;

use camloc_reconstruct::FrameRate;

use crate::identity::{IDENTITY_SIZE_RATIO, TorsoAnchor, reach_torsos, torso_step};
use crate::{FOLLOW_GAP_STEPS, LOST_REACH_FACTOR};

/// The most persons that ended before it a person is compared with by [`continuations`] (those
/// that ended last): a hostile input of people appearing and vanishing everywhere would make
/// the comparisons grow with the square of the persons.
const MAX_CANDIDATES: usize = 64;

/// One person's ends: its first and last poses with an anchor (frame number and anchor), and
/// its first and last frame numbers.
struct Ends {
    person: u64,
    first: (u64, TorsoAnchor),
    last: (u64, TorsoAnchor),
    span: [u64; 2],
}

/// A person followed that starts where and soon after another one ends.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Continuation {
    /// The person that ends, and its last frame number.
    pub earlier: (u64, u64),
    /// The person that starts after it, and its first frame number.
    pub later: (u64, u64),
}

/// The persons of one video (`people`, the person of each pose, with its frame number in
/// `frames` and its anchor in `anchors`, as [`follow_people`](crate::follow_people) gives
/// them) whose first pose comes within twice [`FOLLOW_GAP_STEPS`] of another person's last
/// one and within [`LOST_REACH_FACTOR`] times its reach of it, the sizes within
/// [`IDENTITY_SIZE_RATIO`]: each such later person with the nearest earlier one, in order of
/// the later person's first frame. (A simulated user's game of 7 people had a runner who
/// reversed at 5.5 m/s, and a diver who rolled, each come out as two or three persons
/// without a word.)
pub fn continuations(
    frames: &[u64],
    anchors: &[Option<TorsoAnchor>],
    people: &[u64],
    rate: FrameRate,
) -> Vec<Continuation> {
    let mut ends: Vec<Ends> = Vec::new();
    let mut slots: HashMap<u64, usize> = HashMap::new();
    for ((&frame, anchor), &person) in frames.iter().zip(anchors).zip(people) {
        let slot = match slots.get(&person) {
            Some(&s) => s,
            None => {
                let Some(a) = *anchor else { continue };
                ends.push(Ends {
                    person,
                    first: (frame, a),
                    last: (frame, a),
                    span: [frame; 2],
                });
                slots.insert(person, ends.len() - 1);
                ends.len() - 1
            }
        };
        let e = &mut ends[slot];
        e.span = [e.span[0].min(frame), e.span[1].max(frame)];
        if let Some(a) = *anchor {
            if frame < e.first.0 {
                e.first = (frame, a);
            }
            if frame > e.last.0 {
                e.last = (frame, a);
            }
        }
    }
    let step = rate.step() as f64;
    // The persons by their last frame, so that each later person looks only at those that
    // ended within the window before it (at most MAX_CANDIDATES, the latest).
    let mut by_end: Vec<&Ends> = ends.iter().collect();
    by_end.sort_by_key(|e| e.span[1]);
    let window = (2.0 * FOLLOW_GAP_STEPS * step) as u64;
    let mut found: Vec<Continuation> = ends
        .iter()
        .filter_map(|later| {
            let (first, start) = later.first;
            let before = by_end.partition_point(|e| e.span[1] < later.span[0]);
            let from = by_end.partition_point(|e| e.span[1] + window < later.span[0]);
            by_end[from.max(before.saturating_sub(MAX_CANDIDATES))..before]
                .iter()
                .filter_map(|earlier| {
                    let (last, end) = earlier.last;
                    let steps = (first - last) as f64 / step;
                    let (moved, ratio) = torso_step(&end, &start);
                    (steps <= 2.0 * FOLLOW_GAP_STEPS
                        && moved <= LOST_REACH_FACTOR * reach_torsos(steps)
                        && ratio <= IDENTITY_SIZE_RATIO)
                        .then_some((moved, earlier.person, last))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, earlier, last)| Continuation {
                    earlier: (earlier, last),
                    later: (later.person, first),
                })
        })
        .collect();
    found.sort_by_key(|c| (c.later.1, c.later.0));
    found
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
    fn a_person_starting_where_another_ended_is_named_and_others_are_not() {
        // Person 0 at frames 0-9 ends at x = 190; person 2 starts at frame 11 at x = 300 (a
        // torso and some away); person 1 walks far away throughout; person 3 starts at frame
        // 12 at x = 2000.
        let (mut frames, mut anchors, mut people) = (Vec::new(), Vec::new(), Vec::new());
        let mut add = |f: u64, x: f64, p: u64| {
            frames.push(f);
            anchors.push(at(x));
            people.push(p);
        };
        for f in 0..20u64 {
            if f < 10 {
                add(f, 100.0 + 10.0 * f as f64, 0);
            } else if f > 10 {
                add(f, 300.0 + 5.0 * f as f64, 2);
            }
            add(f, 1000.0, 1);
            if f >= 12 {
                add(f, 2000.0, 3);
            }
        }
        let found = continuations(&frames, &anchors, &people, FrameRate::default());
        assert_eq!(
            found,
            vec![Continuation {
                earlier: (0, 9),
                later: (2, 11)
            }]
        );
    }
}
