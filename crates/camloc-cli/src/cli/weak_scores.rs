//! The warning that a detector's weak joints are read as detected (`--min-score 0`, the
//! default): the input's first poses read again at 0 and at [`WeakScores::threshold`]
//! ([`WeakScores::of_input`]).

use camloc::keypoints::WeakScores;

use super::InputArgs;

/// Says on standard error how many landmarks of the input's first
/// [`WeakScores::SAMPLE_POSES`] poses score below [`WeakScores::threshold`] when `input` is read
/// at `--min-score 0` and they are at least [`WeakScores::SAY_FROM_SHARE`] of them. Standard
/// input and named pipes (which cannot be read twice) are not looked at, nor what cannot be
/// read: the command's own reading reports it.
pub fn warn_of_weak_scores(input: &InputArgs) {
    if input.min_score != 0.0 || input.is_standard_input() {
        return;
    }
    let counts = WeakScores::of_input(
        input.path(),
        input.format,
        &input.options(),
        input.recursive,
    );
    if let Some(counts) = counts.filter(WeakScores::worth_saying) {
        stderr_line!(
            "camloc: warning: {counts} (--min-score 0, the default): a detector writes \
             coordinates for joints it cannot see; try --min-score {}, which fills them in \
             instead (with --sequence from the frames around; a seated frame's hidden legs \
             can come out standing)",
            counts.threshold()
        );
    }
}
