//! `--camera-height from-input` (the default): the shares of the camera heights in the
//! input, estimated from its poses before any is localized
//! ([`CameraLocalizer::estimate_height_shares`]).

use std::io::IsTerminal;
use std::path::Path;

use camloc::dataset::Dataset;
use camloc::skeleton::PartialPose2;
use camloc::{CameraHeight, CameraLocalizer, HeightShares};

use super::input::Inputs;
use super::{CameraHeightArg, CameraHeightArgs, CliError, InputArgs, load_model};

/// At most about this many poses, spread over the input, are read for the estimate (of three
/// shares: a few thousand settle them).
pub const ESTIMATE_POSES: usize = 20_000;

/// The model at `model` (or the embedded one) under the prior `height` asks for, and the
/// input to localize with it: [`load_model`], then [`for_input`].
pub fn load_for_input(
    model: Option<&Path>,
    height: &CameraHeightArgs,
    input: &InputArgs,
    quiet: bool,
) -> Result<(CameraLocalizer, Inputs), CliError> {
    for_input(load_model(model, height)?, height, input, quiet)
}

/// The localizer `height` asks for and the input to localize with it. Under
/// `--camera-height from-input` the input is read once for the estimate, then opened again
/// for the run (standard input is kept in memory to be read twice); the estimate is said on
/// standard error unless `quiet` or standard error is not a terminal.
pub fn for_input(
    localizer: CameraLocalizer,
    height: &CameraHeightArgs,
    input: &InputArgs,
    quiet: bool,
) -> Result<(CameraLocalizer, Inputs), CliError> {
    let inputs = Inputs::open(input)?;
    if height.camera_height != CameraHeightArg::FromInput {
        return Ok((localizer, inputs));
    }
    let ((shares, used, read), inputs) = if inputs.is_stdin() {
        let records: Vec<_> = inputs.collect();
        let poses = records
            .iter()
            .filter_map(|r| r.as_ref().ok())
            .map(|r| r.pose);
        (
            estimate(&localizer, poses, None),
            Inputs::from_records(records),
        )
    } else {
        let hint = inputs.len_hint();
        let poses = Inputs::open(input)?.filter_map(Result::ok).map(|r| r.pose);
        (estimate(&localizer, poses, hint), inputs)
    };
    say(&shares, used, read, quiet);
    Ok((
        localizer.with_camera_height(CameraHeight::Shares(shares)),
        inputs,
    ))
}

/// The localizer `height` asks for, for the samples of `dataset` (with their missing
/// landmarks); the estimate is said as by [`for_input`].
pub fn for_dataset(
    localizer: CameraLocalizer,
    height: &CameraHeightArgs,
    dataset: &Dataset,
    quiet: bool,
) -> CameraLocalizer {
    if height.camera_height != CameraHeightArg::FromInput {
        return localizer;
    }
    let shares = localizer.estimate_height_shares_of(dataset);
    say(&shares, dataset.samples.len(), dataset.samples.len(), quiet);
    localizer.with_camera_height(CameraHeight::Shares(shares))
}

/// The shares estimated from at most about [`ESTIMATE_POSES`] of `poses`, evenly spread
/// (every k-th: k from `hint`, the number of poses when known, else doubled as they come),
/// how many of them it used and how many poses were read.
fn estimate(
    localizer: &CameraLocalizer,
    poses: impl Iterator<Item = PartialPose2>,
    hint: Option<u64>,
) -> (HeightShares, usize, usize) {
    let mut every = hint.map_or(1, |n| {
        usize::try_from(n)
            .unwrap_or(usize::MAX)
            .div_ceil(ESTIMATE_POSES)
            .max(1)
    });
    let mut kept = Vec::new();
    let mut read = 0;
    for (i, pose) in poses.enumerate() {
        read = i + 1;
        if i % every != 0 {
            continue;
        }
        kept.push(pose);
        if kept.len() == 2 * ESTIMATE_POSES {
            // Keep every other one: poses 0, 2k, 4k, ... of the input, then go on by 2k.
            let mut index = 0;
            kept.retain(|_| {
                index += 1;
                index % 2 == 1
            });
            every *= 2;
        }
    }
    (localizer.estimate_height_shares(&kept), kept.len(), read)
}

/// Says the estimate, made from `used` of the `read` poses, on standard error (unless
/// `quiet` or not a terminal).
fn say(shares: &HeightShares, used: usize, read: usize, quiet: bool) {
    if !quiet && std::io::stderr().is_terminal() {
        let poses = if used == read {
            format!("its {read} poses")
        } else {
            format!("{used} of its {read} poses")
        };
        eprintln!(
            "camloc: camera heights of the input, from {poses}: {shares} \
             (--camera-height any: each pose on its own)"
        );
    }
}
