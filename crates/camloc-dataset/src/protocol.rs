//! How 3D poses are turned into labelled 2D samples: the [`Protocol`] and its camera
//! [`Jitter`].

use serde::{Deserialize, Serialize};

/// The elevation band of the `sphere` protocol, degrees: camera directions are drawn
/// uniformly (by area) over `|elevation| <= SPHERE_BAND_DEG`, the band the 12 Table-1 cameras
/// cover (their +-45 deg rings plus half the 45 deg spacing).
pub const SPHERE_BAND_DEG: f64 = 67.5;

/// How 3D poses are turned into labelled 2D samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Protocol {
    /// The paper's protocol: every pose seen exactly from every camera of the set,
    /// orthographically (landmarks in metres).
    Canonical,
    /// Realistic protocol: per sample the camera is jittered around its class centre
    /// (azimuth, elevation, roll), placed 3-8 m away with full perspective, and Gaussian noise
    /// is added to the 2D landmarks.
    Jittered,
    /// Cameras anywhere: per sample a direction drawn uniformly over the sphere band
    /// `|elevation| <= SPHERE_BAND_DEG` (uniform by area), roll, distance and noise as
    /// `jittered`, perspective; the label is the camera of the direction's elevation ring and
    /// azimuth quadrant ([`CameraSet::by_ring_and_side`]), and
    /// [`Sample::in_class_box`] records whether the direction lies in that camera's jittered
    /// class box.
    ///
    /// [`Sample::in_class_box`]: crate::Sample::in_class_box
    /// [`CameraSet::by_ring_and_side`]: camloc_geometry::CameraSet::by_ring_and_side
    Sphere,
    /// A studio or a room filmed from tripods ([`Rig`]): cameras fixed in the world 1.0-2.2 m
    /// above the floor and 2.5-7 m from the centre of a capture area, aimed at that centre; the
    /// person on the floor within 2 m of it, seen from an azimuth within half a camera spacing
    /// of the class's (the elevation follows from the heights); perspective with focal
    /// lengths of 500-2000 px and radial distortion; detector-like noise. The truth is the
    /// direction from the pelvis to the camera centre, the label the camera of its ring and
    /// side as under `sphere`, `in_class_box` too.
    ///
    /// [`Rig`]: crate::Rig
    Rig,
}

impl Protocol {
    /// Lower-case name (`"canonical"`, `"jittered"`, `"sphere"`, `"rig"`).
    pub const fn name(self) -> &'static str {
        match self {
            Protocol::Canonical => "canonical",
            Protocol::Jittered => "jittered",
            Protocol::Sphere => "sphere",
            Protocol::Rig => "rig",
        }
    }

    /// Default 2D Gaussian noise, as a fraction of the 2D torso length: 0 for canonical, 3%
    /// for jittered and sphere, 0 for rig (whose noise is its detector model,
    /// [`Rig::noise`](crate::Rig::noise)).
    pub const fn default_noise_fraction(self) -> f64 {
        match self {
            Protocol::Canonical | Protocol::Rig => 0.0,
            Protocol::Jittered | Protocol::Sphere => 0.03,
        }
    }
}

impl std::str::FromStr for Protocol {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "canonical" => Ok(Protocol::Canonical),
            "jittered" => Ok(Protocol::Jittered),
            "sphere" => Ok(Protocol::Sphere),
            "rig" => Ok(Protocol::Rig),
            other => Err(format!(
                "unknown protocol '{other}' (expected canonical, jittered, sphere or rig)"
            )),
        }
    }
}

impl std::fmt::Display for Protocol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Camera jitter of the `jittered` protocol (uniform ranges around the class centre).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Jitter {
    /// Azimuth offset bound, degrees (offset ~ U(-b, b)).
    pub azimuth_deg: f64,
    /// Elevation offset bound, degrees.
    pub elevation_deg: f64,
    /// Roll about the optical axis bound, degrees.
    pub roll_deg: f64,
    /// Camera distance range from the pelvis, metres.
    pub distance_m: (f64, f64),
    /// Focal length of the perspective camera, image units (pixels).
    pub focal: f64,
}

impl Default for Jitter {
    /// docs/conventions.md section 7: +-30 deg azimuth, +-15 deg elevation, +-5 deg roll, 3-8 m, f
    /// = 1000 px.
    fn default() -> Self {
        Jitter {
            azimuth_deg: 30.0,
            elevation_deg: 15.0,
            roll_deg: 5.0,
            distance_m: (3.0, 8.0),
            focal: 1000.0,
        }
    }
}
