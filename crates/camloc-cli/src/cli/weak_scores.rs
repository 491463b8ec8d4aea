//! The warning that a detector's weak joints are read as detected (`--min-score 0`, the
//! default): the input's first poses read twice, at 0 and at [`WeakScores::THRESHOLD`].

use std::path::Path;

use camloc::keypoints::{KeypointRecord, WeakScores};

use super::InputArgs;
use super::input::Inputs;

/// Says on standard error how many landmarks of the input's first
/// [`WeakScores::SAMPLE_POSES`] poses score below [`WeakScores::THRESHOLD`] when `input` is read
/// at `--min-score 0` and they are at least [`WeakScores::SAY_FROM_SHARE`] of them. Standard
/// input and named pipes (which cannot be read twice) and inputs that cannot be opened are not
/// looked at: the command's own reading reports those.
pub fn warn_of_weak_scores(input: &InputArgs) {
    // Only what can be read again: a named pipe, like standard input, is read once.
    let path = input.path();
    let readable_twice =
        path != Path::new("-") && std::fs::metadata(path).is_ok_and(|m| m.is_file() || m.is_dir());
    if input.min_score != 0.0 || !readable_twice {
        return;
    }
    let mut strong = input.options();
    strong.min_score = WeakScores::THRESHOLD;
    let (Ok(all), Ok(strong)) = (Inputs::open(input), Inputs::open_with(input, strong)) else {
        return;
    };
    // A file that fails at the threshold (scores on another scale) ends the comparison there.
    let first = |inputs: Inputs| -> Vec<KeypointRecord> {
        inputs
            .take(WeakScores::SAMPLE_POSES)
            .map_while(Result::ok)
            .collect()
    };
    let counts = WeakScores::compare(&first(all), &first(strong));
    if counts.worth_saying() {
        stderr_line!(
            "camloc: warning: {counts} (--min-score 0, the default): a detector writes \
             coordinates for joints it cannot see; --min-score {} treats them as missing and \
             fills them in (with --sequence from the frames around a short gap)",
            WeakScores::THRESHOLD
        );
    }
}
