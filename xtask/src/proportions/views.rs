//! One camera filming a window of frames: `jittered` (a camera near a random Table-1
//! viewpoint, 3-8 m, f = 1000 px, 3% noise) or `rig` (a tripod camera of the studio,
//! distortion, detector noise), fixed over the window, the noise drawn per frame.

use camloc::Pose2;
use camloc::Pose3;
use camloc::dataset::{Jitter, Rig};
use camloc_geometry::{Perspective, look_at_origin, roll_about_optical_axis, sphere_point};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// The studio of a test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Studio {
    /// A camera near a Table-1 viewpoint (docs/conventions.md section 7, `jittered`).
    Jittered,
    /// A tripod camera of [`Rig::default`] (section 7, `rig`).
    Rig,
}

impl Studio {
    /// The protocol's name.
    pub fn name(self) -> &'static str {
        match self {
            Studio::Jittered => "jittered",
            Studio::Rig => "rig",
        }
    }
}

/// One frame as the camera saw it.
pub struct View {
    /// The 2D landmarks, pixels from the principal point.
    pub pose2: Pose2,
    /// The camera's focal length, pixels.
    pub focal: f64,
}

/// 2D noise of `jittered`, as a fraction of the 2D torso.
const JITTERED_NOISE: f64 = 0.03;

/// The views of `poses` (consecutive frames, canonical) by one camera of `studio` drawn
/// from `seed`.
pub fn film(poses: &[Pose3], studio: Studio, seed: u64) -> Result<Vec<View>, String> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut noise_rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5DEE_CE66_D1CE_4E5B);
    match studio {
        Studio::Jittered => {
            let j = Jitter::default();
            let azimuth = 90.0 * f64::from(rng.random_range(0u8..4))
                + rng.random_range(-j.azimuth_deg..=j.azimuth_deg);
            let elevation = 45.0 * f64::from(rng.random_range(-1i8..=1))
                + rng.random_range(-j.elevation_deg..=j.elevation_deg);
            let roll = rng.random_range(-j.roll_deg..=j.roll_deg).to_radians();
            let distance = rng.random_range(j.distance_m.0..=j.distance_m.1);
            let centre = sphere_point(azimuth, elevation, distance);
            let rotation =
                roll_about_optical_axis(&look_at_origin(centre).map_err(|e| e.to_string())?, roll);
            let camera = Perspective {
                rotation,
                centre,
                focal: j.focal,
            };
            poses
                .iter()
                .map(|pose| {
                    let mut pose2 =
                        Pose2::new(camera.project(&pose.points).map_err(|e| e.to_string())?);
                    let sigma = JITTERED_NOISE * pose2.torso_length();
                    if let Ok(normal) = Normal::new(0.0, sigma) {
                        for c in pose2.points.iter_mut().flatten() {
                            *c += normal.sample(&mut noise_rng);
                        }
                    }
                    Ok(View {
                        pose2,
                        focal: j.focal,
                    })
                })
                .collect()
        }
        Studio::Rig => {
            let rig = Rig::default();
            let azimuth = rng.random_range(0.0..360.0);
            let camera_seed: u64 = rng.random();
            poses
                .iter()
                .map(|pose| {
                    // The same draws for every frame: the same camera and place in the room.
                    let mut camera_rng = ChaCha8Rng::seed_from_u64(camera_seed);
                    let seen = rig
                        .view(pose, azimuth, &mut camera_rng)
                        .map_err(|e| e.to_string())?;
                    let mut pose2 = Pose2::new(seen.points);
                    let torso = pose2.torso_length();
                    rig.noise.apply(&mut pose2.points, torso, &mut noise_rng);
                    Ok(View {
                        pose2,
                        focal: seen.focal,
                    })
                })
                .collect()
        }
    }
}
