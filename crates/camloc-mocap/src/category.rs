//! Motion categories of mocap clips, derived from the CMU index text
//! (`cmu/cmu-mocap-index-text.txt`).
//!
//! The index lists every trial as `<subject>_<trial><TAB><description>` under a header line
//! `Subject #<n> (<subject description>)`. A clip's category is found by matching the words of
//! its trial description against an ordered list of keyword rules ([`CATEGORY_RULES`]); when
//! no rule matches, the subject's description is tried the same way; when that fails too (or
//! the clip or subject is not in the index), the category is [`MotionCategory::Other`].

use std::collections::HashMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::MocapError;

/// What a clip's person is doing, coarsely: the unit of the per-category and
/// leave-one-category-out evaluations.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
pub enum MotionCategory {
    /// Walking of any kind (normal, backwards, stealthy, on uneven terrain, on steps).
    Walk,
    /// Running and jogging, with stops, turns and side steps.
    Run,
    /// Jumps (forward, high, over obstacles, up to grab).
    Jump,
    /// Dance (ballet, modern dance).
    Dance,
    /// Ball sports and golf (soccer, basketball, golf swings, ...).
    Sport,
    /// Fighting and martial arts (boxing, punches, kicks, swordplay, karate).
    Fight,
    /// Acrobatics and climbing (cartwheels, dives and rolls, playground climbing, ladders).
    Acrobatics,
    /// Gestures and pantomime (signals, directing traffic, nursery rhymes, animal imitations,
    /// bows).
    Gesture,
    /// Everyday actions and exercise (washing, mopping, drinking, bending, standing up,
    /// exercise squats among jumping jacks and stretches).
    Everyday,
    /// Sitting: on a chair, a stool or the ground, sitting down and getting up.
    Sit,
    /// Squatting and crouching.
    Squat,
    /// Kneeling.
    Kneel,
    /// Crawling and lying on the floor.
    Crawl,
    /// Anything the index does not describe or the rules do not recognise.
    #[default]
    Other,
}

impl MotionCategory {
    /// Every category, in a fixed order.
    pub const ALL: [MotionCategory; 14] = [
        MotionCategory::Walk,
        MotionCategory::Run,
        MotionCategory::Jump,
        MotionCategory::Dance,
        MotionCategory::Sport,
        MotionCategory::Fight,
        MotionCategory::Acrobatics,
        MotionCategory::Gesture,
        MotionCategory::Everyday,
        MotionCategory::Sit,
        MotionCategory::Squat,
        MotionCategory::Kneel,
        MotionCategory::Crawl,
        MotionCategory::Other,
    ];

    /// The postures: categories whose body is low or seated rather than upright (sit, squat,
    /// kneel, crawl).
    pub const POSTURES: [MotionCategory; 4] = [
        MotionCategory::Sit,
        MotionCategory::Squat,
        MotionCategory::Kneel,
        MotionCategory::Crawl,
    ];

    /// Whether this is one of the [`POSTURES`](Self::POSTURES).
    pub fn is_posture(self) -> bool {
        Self::POSTURES.contains(&self)
    }

    /// Lower-case name (`"walk"`, `"run"`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            MotionCategory::Walk => "walk",
            MotionCategory::Run => "run",
            MotionCategory::Jump => "jump",
            MotionCategory::Dance => "dance",
            MotionCategory::Sport => "sport",
            MotionCategory::Fight => "fight",
            MotionCategory::Acrobatics => "acrobatics",
            MotionCategory::Gesture => "gesture",
            MotionCategory::Everyday => "everyday",
            MotionCategory::Sit => "sit",
            MotionCategory::Squat => "squat",
            MotionCategory::Kneel => "kneel",
            MotionCategory::Crawl => "crawl",
            MotionCategory::Other => "other",
        }
    }

    /// The category whose keyword rules match `description` first ([`CATEGORY_RULES`]), if
    /// any. Matching is on whole lower-case words (letters only; digits and punctuation
    /// separate words), a rule of several words matching them consecutively.
    pub fn from_description(description: &str) -> Option<MotionCategory> {
        let lower = description.to_lowercase();
        let words: Vec<&str> = lower
            .split(|c: char| !c.is_alphabetic())
            .filter(|w| !w.is_empty())
            .collect();
        CATEGORY_RULES.iter().find_map(|(category, phrases)| {
            phrases
                .iter()
                .any(|phrase| {
                    let needle: Vec<&str> = phrase.split(' ').collect();
                    words.windows(needle.len()).any(|w| w == needle.as_slice())
                })
                .then_some(*category)
        })
    }
}

impl std::fmt::Display for MotionCategory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for MotionCategory {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MotionCategory::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = MotionCategory::ALL.iter().map(|c| c.name()).collect();
                format!(
                    "unknown motion category '{s}' (expected one of {})",
                    names.join(", ")
                )
            })
    }
}

/// The largest CMU index file [`MocapIndex::load`] reads (the real one is 68 KB).
pub const MAX_INDEX_BYTES: u64 = 64 << 20;

/// The keyword rules, tried in this order; the first rule with a matching word (or
/// consecutive words) decides. The order settles mixed descriptions: "run dive over roll" is
/// acrobatics, "basketball signals" a gesture, "run jump over" a jump, "walk to run" a run,
/// "jumping jacks, jog, squats" everyday exercise, "soccer - kick ball" a sport and not a
/// fight, "climb 3 steps" a walk but "climb ladder" acrobatics. The postures come before jumps,
/// runs and walks, so that a clip that walks to a chair and sits ("walking, sitting, stand up")
/// is a sit and "walk, crawl" a crawl, and sitting before kneeling and squatting.
pub const CATEGORY_RULES: &[(MotionCategory, &[&str])] = &[
    (
        MotionCategory::Dance,
        &[
            "dance",
            "dancing",
            "ballet",
            "pirouette",
            "salsa",
            "waltz",
            "jete",
            "arabesque",
        ],
    ),
    (
        MotionCategory::Acrobatics,
        &[
            "cartwheel",
            "cartwheels",
            "flip",
            "flips",
            "somersault",
            "handstand",
            "acrobatics",
            "dive",
            "roll",
            "rolls",
            "playground",
            "hang",
            "gymnastics",
            "tumble",
            "tumbling",
            "ladder",
        ],
    ),
    (
        MotionCategory::Gesture,
        &[
            "signal",
            "signals",
            "traffic",
            "wave",
            "point",
            "nursery",
            "bow",
            "curtsey",
            "human subject",
            "pantomime",
            "gesture",
            "gestures",
            "conduct",
        ],
    ),
    (
        MotionCategory::Sport,
        &[
            "soccer",
            "basketball",
            "golf",
            "baseball",
            "tennis",
            "football",
            "hockey",
            "volleyball",
            "frisbee",
            "bowling",
            "dribble",
            "tai chi",
        ],
    ),
    (
        MotionCategory::Fight,
        &[
            "box",
            "boxing",
            "punch",
            "punching",
            "strike",
            "karate",
            "martial",
            "swordplay",
            "sword",
            "fight",
            "fighting",
            "kick",
            "kicks",
            "taekwondo",
            "kung",
        ],
    ),
    (
        MotionCategory::Everyday,
        &["jumping jacks", "stretch", "stretches"],
    ),
    (
        MotionCategory::Sit,
        &[
            "sit", "sits", "sitting", "seated", "chair", "sofa", "couch", "bench",
        ],
    ),
    (
        MotionCategory::Kneel,
        &["kneel", "kneels", "kneeling", "knelt"],
    ),
    (
        MotionCategory::Squat,
        &[
            "squat",
            "squats",
            "squatting",
            "crouch",
            "crouches",
            "crouching",
            "crouched",
        ],
    ),
    (
        MotionCategory::Crawl,
        &[
            "crawl", "crawls", "crawling", "lie", "lies", "lying", "prone", "creep",
        ],
    ),
    (
        MotionCategory::Jump,
        &[
            "jump", "jumps", "jumping", "hop", "hopping", "leap", "leaps",
        ],
    ),
    (
        MotionCategory::Run,
        &["run", "runs", "running", "jog", "jogging", "sprint"],
    ),
    (
        MotionCategory::Walk,
        &[
            "walk", "walks", "walking", "navigate", "march", "marching", "stroll", "steps",
            "stairs", "terrain",
        ],
    ),
    (
        MotionCategory::Everyday,
        &[
            "wash",
            "mop",
            "drink",
            "stand",
            "bend",
            "scoop",
            "lift",
            "sweep",
            "laugh",
            "range of motion",
            "bottlecap",
            "reach",
            "pick",
            "clean",
            "cook",
            "exercise",
        ],
    ),
];

/// The CMU index: trial and subject descriptions, for looking up clip categories.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MocapIndex {
    /// Trial name (e.g. `"02_01"`) to its description.
    trials: HashMap<String, String>,
    /// Subject id without leading zeros (e.g. `"2"`) to the subject's description.
    subjects: HashMap<String, String>,
}

/// How a clip's category was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CategorySource {
    /// From the trial's own description.
    Trial,
    /// From the subject's description (the trial's matched no rule).
    Subject,
    /// Not found: the trial and subject are missing from the index, or neither description
    /// matched a rule.
    NotFound,
}

impl MocapIndex {
    /// Parses the text of `cmu-mocap-index-text.txt`. Lines that are neither a subject header
    /// nor a trial line are ignored.
    pub fn parse(text: &str) -> MocapIndex {
        let mut index = MocapIndex::default();
        for line in text.lines() {
            let line = line.trim_end();
            if let Some(rest) = line.strip_prefix("Subject #") {
                let (id, description) = rest.split_once(' ').unwrap_or((rest, ""));
                if let Ok(n) = id.trim().parse::<u64>() {
                    index
                        .subjects
                        .insert(n.to_string(), description.to_string());
                }
            } else if let Some((trial, description)) = line.split_once('\t') {
                let trial = trial.trim();
                let well_formed = trial.split_once('_').is_some_and(|(s, t)| {
                    !s.is_empty()
                        && !t.is_empty()
                        && s.chars().chain(t.chars()).all(|c| c.is_ascii_digit())
                });
                if well_formed {
                    index
                        .trials
                        .insert(trial.to_string(), description.trim().to_string());
                }
            }
        }
        index
    }

    /// Reads and parses the index file at `path` (at most [`MAX_INDEX_BYTES`]; CMU's is 68 KB;
    /// bytes that are not UTF-8 are read as U+FFFD).
    ///
    /// # Errors
    /// [`MocapError::Io`] naming the file when it cannot be read, [`MocapError::TooLarge`]
    /// beyond the bound.
    pub fn load(path: &Path) -> Result<MocapIndex, MocapError> {
        use std::io::Read;
        let io = |source| MocapError::Io {
            path: path.to_owned(),
            source,
        };
        let mut bytes = Vec::new();
        (std::fs::File::open(path).map_err(io)?)
            .take(MAX_INDEX_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() as u64 > MAX_INDEX_BYTES {
            return Err(MocapError::TooLarge {
                path: path.to_owned(),
                limit: MAX_INDEX_BYTES,
            });
        }
        Ok(MocapIndex::parse(&String::from_utf8_lossy(&bytes)))
    }

    /// Number of trials listed.
    pub fn trials(&self) -> usize {
        self.trials.len()
    }

    /// The description of trial `clip` (e.g. `"02_01"`), if listed.
    pub fn trial_description(&self, clip: &str) -> Option<&str> {
        self.trials.get(clip).map(String::as_str)
    }

    /// The description of `subject` (leading zeros ignored), if listed.
    pub fn subject_description(&self, subject: &str) -> Option<&str> {
        let key = subject
            .parse::<u64>()
            .map_or_else(|_| subject.to_string(), |n| n.to_string());
        self.subjects.get(&key).map(String::as_str)
    }

    /// The category of clip `clip` of `subject` and how it was found: the trial description's
    /// category, else the subject description's, else [`MotionCategory::Other`].
    pub fn category(&self, subject: &str, clip: &str) -> (MotionCategory, CategorySource) {
        if let Some(c) = self
            .trial_description(clip)
            .and_then(MotionCategory::from_description)
        {
            return (c, CategorySource::Trial);
        }
        match self
            .subject_description(subject)
            .and_then(MotionCategory::from_description)
        {
            Some(c) => (c, CategorySource::Subject),
            None => (MotionCategory::Other, CategorySource::NotFound),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INDEX: &str = "Carnegie-Mellon Graphics Lab\n\nSubject #2 (various expressions and human behaviors)\n\n\
02_01\twalk\n02_03\trun/jog\n02_05\tpunch/strike\n02_10\twash self\n\n\
Subject #64 (golf)\n\n64_01\tSwing\n\nSubject #127 (Action Adventure Obstacles, running, jumping, ducking, rolling)\n\n\
127_07\tRun Dive Over Roll Run\n127_10\tRun Jump Over\n127_20\tWalk to Run\n\
Subject #14 (various everyday behaviors, dance moves)\n14_01\tboxing\n14_02\tjumping jacks, jog, squats, side twists, stretches\n\
14_09\tsit on stepstool, stand up\n86_09\twalking, sitting, looking, stand up\n133_01\tWalk Crawl\n\
69_70\twalk up to object, squat, pick up object\n22_03\tA sits, holds face in hands; B kneels, comforts A\n\
114_04\tGetting up from chair\n22_14\talternating squats\n77_02\tkneeling, praying\n10_01\tsoccer - kick ball\n29_05\tdog (human subject)\n29_01\tbasketball signals\n14_20\tclimb 3 steps\n14_21\tclimb ladder\n";

    #[test]
    fn trial_rules_in_order_then_subject_then_other() {
        let index = MocapIndex::parse(INDEX);
        let cat = |s: &str, c: &str| index.category(s, c);
        assert_eq!(
            cat("02", "02_01"),
            (MotionCategory::Walk, CategorySource::Trial)
        );
        assert_eq!(cat("02", "02_03").0, MotionCategory::Run);
        assert_eq!(cat("02", "02_05").0, MotionCategory::Fight);
        assert_eq!(cat("02", "02_10").0, MotionCategory::Everyday);
        // "Swing" matches nothing: the subject's "golf" decides.
        assert_eq!(
            cat("64", "64_01"),
            (MotionCategory::Sport, CategorySource::Subject)
        );
        assert_eq!(cat("127", "127_07").0, MotionCategory::Acrobatics);
        assert_eq!(cat("127", "127_10").0, MotionCategory::Jump);
        assert_eq!(cat("127", "127_20").0, MotionCategory::Run);
        assert_eq!(cat("14", "14_01").0, MotionCategory::Fight);
        assert_eq!(cat("14", "14_02").0, MotionCategory::Everyday);
        assert_eq!(
            cat("14", "14_09").0,
            MotionCategory::Sit,
            "stepstool is no step"
        );
        // Postures before walks; sitting before kneeling; exercise squats stay everyday.
        assert_eq!(cat("86", "86_09").0, MotionCategory::Sit);
        assert_eq!(cat("133", "133_01").0, MotionCategory::Crawl);
        assert_eq!(cat("69", "69_70").0, MotionCategory::Squat);
        assert_eq!(cat("22", "22_03").0, MotionCategory::Sit);
        assert_eq!(cat("114", "114_04").0, MotionCategory::Sit);
        assert_eq!(cat("22", "22_14").0, MotionCategory::Squat);
        assert_eq!(cat("77", "77_02").0, MotionCategory::Kneel);
        assert!(MotionCategory::Kneel.is_posture() && !MotionCategory::Walk.is_posture());
        assert_eq!(cat("10", "10_01").0, MotionCategory::Sport);
        assert_eq!(cat("29", "29_05").0, MotionCategory::Gesture);
        assert_eq!(cat("29", "29_01").0, MotionCategory::Gesture);
        assert_eq!(cat("14", "14_20").0, MotionCategory::Walk);
        assert_eq!(cat("14", "14_21").0, MotionCategory::Acrobatics);
        // Neither trial nor subject listed.
        assert_eq!(
            cat("77", "77_01"),
            (MotionCategory::Other, CategorySource::NotFound)
        );
        // Subject listed without leading zero; trial missing.
        assert_eq!(cat("002", "002_99").0, MotionCategory::Other);
        assert_eq!(
            index.subject_description("002"),
            index.subject_description("2")
        );
    }

    #[test]
    fn names_round_trip() {
        for c in MotionCategory::ALL {
            assert_eq!(c.name().parse::<MotionCategory>(), Ok(c));
        }
        assert!("nope".parse::<MotionCategory>().is_err());
    }
}
