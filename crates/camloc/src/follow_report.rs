//! What following a video's untracked poses found that a user should hear of
//! ([`FollowReport`]): persons that may be one, persons of a few frames, and videos too
//! crowded to follow.

use crate::Continuation;

/// The fewest poses, in 1/30 s, of a person followed whom [`FollowReport`] does not call
/// brief (a third of a second), in a video whose untracked poses span at least three times
/// as long: a simulated user's false detection on the background for 3 frames had come out as
/// a person with its own BVH and bone lengths, without a word.
pub const BRIEF_PERSON_STEPS: f64 = 10.0;

/// The persons [`FollowReport::warnings`] names in a warning before it counts the rest.
const NAMED: usize = 5;

/// What [`follow_untracked`](crate::follow_untracked) found, each item with its video's file
/// (`None` for a video that is the whole input).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FollowReport {
    /// Persons that may be one ([`continuations`](crate::continuations)).
    pub continuations: Vec<(Option<String>, Continuation)>,
    /// Persons of fewer poses than [`BRIEF_PERSON_STEPS`] (at the video's rate): the person
    /// and its poses.
    pub brief: Vec<(Option<String>, u64, usize)>,
    /// Videos with a frame of more than
    /// [`MAX_FOLLOWED_PER_FRAME`](crate::MAX_FOLLOWED_PER_FRAME) poses without ids, whose
    /// people were not followed (each pose's person is its position in its frame).
    pub crowded: Vec<Option<String>>,
}

impl FollowReport {
    /// The warnings of what was found (none when nothing was).
    pub fn warnings(&self) -> Vec<String> {
        let of =
            |file: &Option<String>| file.as_ref().map_or(String::new(), |f| format!(" of {f}"));
        let more = |n: usize| match n.saturating_sub(NAMED) {
            0 => String::new(),
            n => format!(" and {n} more"),
        };
        let mut warnings = Vec::new();
        if !self.continuations.is_empty() {
            let named: Vec<String> = (self.continuations.iter().take(NAMED))
                .map(|(file, c)| {
                    format!(
                        "person {} (from frame {}) after person {} (to frame {}){}",
                        c.later.0,
                        c.later.1,
                        c.earlier.0,
                        c.earlier.1,
                        of(file)
                    )
                })
                .collect();
            warnings.push(format!(
                "persons that may be one person, each starting where and soon after another \
                 ended (people without ids are followed by where they are, and one who turns \
                 on the spot, folds up or is missed for long comes out as two): {}{}; give \
                 ids to join them (`person` in camloc JSON, which `camloc convert` writes)",
                named.join(", "),
                more(self.continuations.len())
            ));
        }
        if !self.brief.is_empty() {
            let named: Vec<String> = (self.brief.iter().take(NAMED))
                .map(|(file, person, poses)| format!("person {person}{} ({poses} poses)", of(file)))
                .collect();
            warnings.push(format!(
                "persons seen for under a third of a second: {}{}: false detections, \
                 duplicates or people passing by? their outputs are written as any person's",
                named.join(", "),
                more(self.brief.len())
            ));
        }
        if !self.crowded.is_empty() {
            let named: Vec<String> = (self.crowded.iter().take(NAMED))
                .map(|file| file.clone().unwrap_or_else(|| "the input".into()))
                .collect();
            warnings.push(format!(
                "a frame holds more than {} poses without ids in {}{}: their people are not \
                 followed (each pose's person is its position in its frame, which changes \
                 as people come and go); give ids (`person` in camloc JSON)",
                crate::MAX_FOLLOWED_PER_FRAME,
                named.join(", "),
                more(self.crowded.len())
            ));
        }
        warnings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_was_found_is_named() {
        assert!(FollowReport::default().warnings().is_empty());
        let report = FollowReport {
            continuations: vec![(
                None,
                Continuation {
                    earlier: (0, 9),
                    later: (2, 11),
                },
            )],
            brief: vec![(Some("cam.npy".into()), 3, 2)],
            crowded: vec![None],
        };
        let warnings = report.warnings();
        assert!(warnings[0].contains("person 2 (from frame 11) after person 0 (to frame 9)"));
        assert!(warnings[1].contains("person 3 of cam.npy (2 poses)"));
        assert!(warnings[2].contains("more than 64 poses without ids in the input"));
    }
}
