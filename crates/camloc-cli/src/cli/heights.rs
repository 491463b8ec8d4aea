//! `--camera-height from-input` (the default): the shares of the camera heights in the
//! input, estimated from its first poses before any is localized
//! ([`CameraLocalizer::estimate_height_shares`]).

use std::path::Path;

use camloc::dataset::Dataset;
use camloc::reconstruct::Intrinsics;
use camloc::skeleton::PartialPose2;
use camloc::{
    CameraLocalizer, HEIGHT_SHARE_MAX_POSES, HEIGHT_SHARE_PSEUDO_VIEWS, HeightEstimate,
    HeightShares, Level,
};

use super::input::Inputs;
use super::{CameraHeightArg, CameraHeightArgs, CliError, InputArgs, load_model};

/// The model at `model` (or the embedded one) under the prior `height` asks for, aiming the
/// poses with the camera's `intrinsics` when given
/// ([`CameraLocalizer::with_intrinsics`]), the input to localize with it and the estimate of
/// its camera heights: [`load_model`], then [`for_input`] (whose estimate sees the poses
/// aimed).
pub fn load_for_input(
    model: Option<&Path>,
    height: &CameraHeightArgs,
    input: &InputArgs,
    intrinsics: Option<Intrinsics>,
    quiet: bool,
) -> Result<(CameraLocalizer, Inputs, Option<HeightEstimate>), CliError> {
    let localizer = load_model(model, height)?.with_intrinsics(intrinsics)?;
    for_input(localizer, height, input, quiet)
}

/// The localizer `height` asks for, the input to localize with it and, under `--camera-height
/// from-input`, the estimate of its camera heights the localizer is under. Under
/// `--camera-height from-input` the first [`HEIGHT_SHARE_MAX_POSES`] records of the input are
/// read and kept for the estimate, then given back in front of the rest (the input is read
/// once, standard input and pipes alike; the first results come once they are read). The
/// estimate is said on standard error unless `quiet` or standard error is not a terminal.
pub fn for_input(
    localizer: CameraLocalizer,
    height: &CameraHeightArgs,
    input: &InputArgs,
    quiet: bool,
) -> Result<(CameraLocalizer, Inputs, Option<HeightEstimate>), CliError> {
    let mut inputs = Inputs::open(input)?;
    if height.camera_height != CameraHeightArg::FromInput {
        return Ok((localizer, inputs, None));
    }
    let mut first: Vec<_> = inputs.by_ref().take(HEIGHT_SHARE_MAX_POSES).collect();
    let poses: Vec<PartialPose2> = first
        .iter()
        .filter_map(|r| r.as_ref().ok())
        .map(|r| r.pose)
        .collect();
    let estimate = localizer.estimate_height_shares(&poses);
    // One more record tells whether the estimate read the whole input.
    let next = inputs.next();
    let whole = next.is_none();
    first.extend(next);
    inputs.put_back(first);
    say(&estimate, whole, quiet);
    Ok((
        localizer.with_camera_height(estimate.camera_height()),
        inputs,
        Some(estimate),
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
    let estimate = localizer.estimate_height_shares_of(dataset);
    say(
        &estimate,
        dataset.samples.len() <= HEIGHT_SHARE_MAX_POSES,
        quiet,
    );
    localizer.with_camera_height(estimate.camera_height())
}

/// Says `estimate` (of the `whole` input, or of its first poses) on standard error, unless
/// `quiet` or not a terminal.
fn say(estimate: &HeightEstimate, whole: bool, quiet: bool) {
    if !super::progress::shown(quiet) {
        return;
    }
    let read = estimate.read;
    let poses = match (whole, read) {
        (true, 1) => "its 1 pose".to_string(),
        (true, _) => format!("its {read} poses"),
        (false, _) => format!("its first {read} poses"),
    };
    // Poses whose torso must be filled in are localized but not counted.
    let localized = if estimate.localized == read {
        String::new()
    } else {
        format!(", {} of them with a torso", estimate.localized)
    };
    match estimate.shares {
        Some(shares) => stderr_line!(
            "camloc: camera heights of the input, from {poses}{localized}, worth {:.0} \
             independent view(s) against {HEIGHT_SHARE_PSEUDO_VIEWS} at eye level: {shares}{} \
             (--camera-height any: each pose on its own)",
            estimate.views,
            elevations(&shares)
        ),
        None => stderr_line!(
            "camloc: no pose with a torso to estimate the camera heights of the input from \
             ({poses}): each pose is localized on its own"
        ),
    }
}

/// The mean elevation of `shares`' middle cameras when the middle height holds half of the
/// cameras or more, e.g. `; its middle cameras about 14.2 deg above the pelvis`; empty
/// otherwise (of an input mostly seen from above it would describe few poses).
fn elevations(shares: &HeightShares) -> String {
    match shares.elevations_deg()[Level::Middle.index()] {
        Some(e) if shares.middle >= 0.5 => {
            format!("; its middle cameras about {e:.1} deg above the pelvis")
        }
        _ => String::new(),
    }
}
