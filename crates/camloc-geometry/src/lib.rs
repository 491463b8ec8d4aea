//! Geometry of camloc: where cameras stand and how they see.
//!
//! Conventions (docs/conventions.md sections 1-2): the world is right-handed, z up, in metres. A
//! camera is a rotation `R` whose rows are the camera's x, y and z axes in world coordinates (row 3
//! is the optical axis) plus a position. Image coordinates are `u = row1 . X`, `v = row2 . X`, with
//! `v` growing downwards.
//!
//! * [`look_at_origin`]: the rotation of a camera at a sphere point looking at the origin (eq. 4).
//! * [`CameraSet`] / [`Viewpoint`]: the 12 cameras of Table 1 ([`CameraSet::table1`]) or any
//!   `n azimuths x m elevations` sphere ([`CameraSet::sphere`]); mirror folding.
//! * [`WeakPerspective`] (eq. 2) and [`Perspective`] projection.
//! * [`procrustes_camera`]: the orthogonal Procrustes weak-perspective camera (eq. 3).

mod camera;
mod error;
mod label;
mod procrustes;
mod rotation;
mod sphere;

pub use camera::{Perspective, WeakPerspective};
pub use error::GeometryError;
pub use label::CameraLabel;
pub use procrustes::procrustes_camera;
pub use rotation::{
    check_rotation, roll_about_optical_axis, rotation_about_axis, rotation_about_z,
    rotation_between,
};
pub use sphere::{
    CameraSet, Level, Side, Viewpoint, azimuth_gap_deg, look_at_origin, sphere_point,
};

/// A 3x3 rotation matrix (f64).
pub type Matrix3 = nalgebra::Matrix3<f64>;
/// A 3-vector (f64).
pub type Vector3 = nalgebra::Vector3<f64>;
