//! The continuous viewpoint of one person's frames, smoothed over time
//! ([`smooth_viewpoints`]): each frame's direction averaged with its neighbours', as the
//! camera and the person move little from one frame to the next.

use camloc_reconstruct::FrameRate;

use crate::sequence::{number_or_position, window_around};

/// Frames on each side of a frame that [`smooth_viewpoints`] averages with it at 30 frames a
/// second (a window of 7 frames, about a quarter of a second; at faster rates as long in
/// time, [`FrameRate::step`] times as many frames).
pub const VIEWPOINT_HALF_WINDOW: u64 = 3;

/// [`VIEWPOINT_HALF_WINDOW`] at `rate`: frame numbers on each side of a frame that
/// [`smooth_viewpoints`] averages with it.
pub fn viewpoint_half_window(rate: FrameRate) -> u64 {
    VIEWPOINT_HALF_WINDOW * rate.step() as u64
}

/// Angle (degrees) beyond which a neighbour's viewpoint is taken as another camera's (a cut in
/// the video) and left out of a frame's mean, when at least half of the window lies within
/// it of the frame's own (45: a smoothed viewpoint had averaged the two sides of a simulated
/// user's 180 deg cuts into one 29-35 deg off either, for 3 frames on each side).
pub const VIEWPOINT_CUT_DEG: f64 = 45.0;

/// A viewpoint: azimuth and elevation, degrees, in the person's canonical frame
/// (docs/conventions.md section 2: azimuth 180 = front, 270 = the person's left; elevation
/// positive above).
pub type Viewpoint = (f64, f64);

/// The viewpoints of one person's frames, in time order, smoothed: frame `k`'s is the
/// direction of the mean of the unit directions of the frames whose frame numbers lie within
/// [`VIEWPOINT_HALF_WINDOW`] (at `rate`) of its own (`frames[k]`; `None`: its position),
/// itself included, and whose viewpoints lie within [`VIEWPOINT_CUT_DEG`] of its own when at
/// least half of them do (a cut: the other camera's frames are left out; a frame far from
/// most of its neighbours, an outlier, is averaged with all of them). `None` where the frame
/// has no viewpoint (`viewpoints[k]` is `None`: not localized) or the directions cancel.
pub fn smooth_viewpoints(
    frames: &[Option<u64>],
    viewpoints: &[Option<Viewpoint>],
    rate: FrameRate,
) -> Vec<Option<Viewpoint>> {
    let half = viewpoint_half_window(rate);
    let number = |k: usize| number_or_position(frames, k);
    let unit = |(azimuth, elevation): Viewpoint| {
        let (a, e) = (azimuth.to_radians(), elevation.to_radians());
        [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()]
    };
    (0..viewpoints.len())
        .map(|k| {
            viewpoints[k]?;
            let centre = number(k);
            let window: Vec<[f64; 3]> =
                window_around(viewpoints.len(), k, |j| number(j).abs_diff(centre) <= half)
                    .filter_map(|j| viewpoints[j].map(unit))
                    .collect();
            let own = viewpoints[k].map(unit)?;
            let same_camera = |u: &&[f64; 3]| {
                u[0] * own[0] + u[1] * own[1] + u[2] * own[2]
                    >= VIEWPOINT_CUT_DEG.to_radians().cos()
            };
            let kept = window.iter().filter(same_camera).count();
            let sum = window
                .iter()
                .filter(|u| 2 * kept < window.len() || same_camera(u))
                .fold([0.0; 3], |s, u| [s[0] + u[0], s[1] + u[1], s[2] + u[2]]);
            let norm = (sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]).sqrt();
            (norm > 1e-9 * (window.len() as f64)).then(|| {
                // In [0, 360): rem_euclid of a tiny negative angle rounds to 360.
                let azimuth = sum[1].atan2(sum[0]).to_degrees().rem_euclid(360.0) % 360.0;
                let elevation = (sum[2] / norm).clamp(-1.0, 1.0).asin().to_degrees();
                (azimuth, elevation)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Viewpoint, b: Viewpoint) -> bool {
        let da = (a.0 - b.0 + 540.0).rem_euclid(360.0) - 180.0;
        da.abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9
    }

    #[test]
    fn a_steady_turn_is_kept_and_jitter_averaged_across_north() {
        // A person turning 2 deg a frame through azimuth 0/360, elevation 10 deg.
        let turn: Vec<Option<Viewpoint>> = (0..20)
            .map(|t| Some(((350.0 + 2.0 * f64::from(t)).rem_euclid(360.0), 10.0)))
            .collect();
        let frames: Vec<Option<u64>> = vec![None; 20];
        let smoothed = smooth_viewpoints(&frames, &turn, FrameRate::default());
        // Away from the ends a centred window of a steady turn keeps the azimuth.
        for t in 3..17 {
            let (a, e) = smoothed[t].unwrap();
            let da = (a - turn[t].unwrap().0 + 540.0).rem_euclid(360.0) - 180.0;
            assert!(da.abs() < 1e-6, "{t}: {a}");
            assert!((e - 10.0).abs() < 0.1, "{e}");
        }
        // Alternating +-4 deg of jitter about 90 deg is averaged out in the middle.
        let jitter: Vec<Option<Viewpoint>> = (0..7)
            .map(|t| Some((if t % 2 == 0 { 94.0 } else { 86.0 }, 0.0)))
            .collect();
        let middle = smooth_viewpoints(&frames[..7], &jitter, FrameRate::default())[3].unwrap();
        assert!((middle.0 - 90.0 - 4.0 / 7.0).abs() < 0.01, "{middle:?}");
    }

    #[test]
    fn a_cut_is_not_averaged_across_and_an_outlier_is() {
        // Ten frames from the back (0 deg), then ten from the front (180 deg): every frame
        // keeps its own camera's viewpoint, also next to the cut.
        let cut: Vec<Option<Viewpoint>> = (0..20)
            .map(|t| Some((if t < 10 { 0.0 } else { 180.0 }, 5.0)))
            .collect();
        let frames: Vec<Option<u64>> = vec![None; 20];
        let smoothed = smooth_viewpoints(&frames, &cut, FrameRate::default());
        for (t, (got, given)) in smoothed.iter().zip(&cut).enumerate() {
            assert!(close(got.unwrap(), given.unwrap()), "{t}: {got:?}");
        }
        // One frame 100 deg off among steady neighbours is pulled towards them.
        let mut outlier = vec![Some((90.0, 0.0)); 7];
        outlier[3] = Some((190.0, 0.0));
        let middle = smooth_viewpoints(&frames[..7], &outlier, FrameRate::default())[3].unwrap();
        assert!((middle.0 - 90.0).abs() < 20.0, "{middle:?}");
    }

    #[test]
    fn frames_far_apart_in_time_and_frames_without_a_viewpoint_are_not_mixed() {
        let viewpoints = [Some((10.0, 0.0)), None, Some((200.0, 0.0))];
        let frames = [Some(0), Some(1), Some(50)];
        let smoothed = smooth_viewpoints(&frames, &viewpoints, FrameRate::default());
        assert!(close(smoothed[0].unwrap(), (10.0, 0.0)));
        assert_eq!(smoothed[1], None);
        assert!(close(smoothed[2].unwrap(), (200.0, 0.0)));
    }
}
