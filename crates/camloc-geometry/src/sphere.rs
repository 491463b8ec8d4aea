//! The virtual camera sphere: eq. 4 look-at rotations, Table 1, general sphere sets, folding.

use serde::{Deserialize, Serialize};

use crate::{CameraLabel, GeometryError, Matrix3, Vector3};

/// Point on a sphere of `radius` (metres) around the origin at `azimuth_deg` (angle in the xy
/// plane from +x, counter-clockwise seen from above) and `elevation_deg` (above the xy plane).
///
/// Azimuth 180 deg is in front of a canonical body (which faces -x), 270 deg on its left (-y),
/// 0 deg behind it (+x), 90 deg on its right (+y).
pub fn sphere_point(azimuth_deg: f64, elevation_deg: f64, radius: f64) -> Vector3 {
    let (sa, ca) = azimuth_deg.to_radians().sin_cos();
    let (se, ce) = elevation_deg.to_radians().sin_cos();
    Vector3::new(radius * ce * ca, radius * ce * sa, radius * se)
}

/// Rotation of a camera at `position` looking at the origin, eq. 4 of the paper:
/// `z = -p/|p|`, `x = normalise(z x [0,0,1])`, `y = z x x`, `R = [x; y; z]` (rows).
///
/// # Errors
/// [`GeometryError::Pole`] when `position` is on the z axis (the construction is undefined),
/// [`GeometryError::DegeneratePosition`] at the origin or for non-finite input.
pub fn look_at_origin(position: Vector3) -> Result<Matrix3, GeometryError> {
    let norm = position.norm();
    if !(norm > 0.0) || !norm.is_finite() {
        return Err(GeometryError::DegeneratePosition);
    }
    let z = -position / norm;
    let x = z.cross(&Vector3::z());
    let xn = x.norm();
    // |z x e_z| = sin(angle to the pole); below ~1e-9 the direction of x is noise.
    if xn < 1e-9 {
        return Err(GeometryError::Pole {
            x: position.x,
            y: position.y,
            z: position.z,
        });
    }
    let x = x / xn;
    let y = z.cross(&x);
    Ok(Matrix3::from_rows(&[
        x.transpose(),
        y.transpose(),
        z.transpose(),
    ]))
}

/// The angle between two azimuths, degrees in `[0, 180]`.
pub fn azimuth_gap_deg(a_deg: f64, b_deg: f64) -> f64 {
    let d = (a_deg - b_deg).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// Camera height class of Table 1. Serialised by its lower-case [`name`](Level::name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    /// Below the body, looking up (Table 1: elevation -45 deg).
    Lower,
    /// At body height (elevation 0).
    Middle,
    /// Above the body, looking down (elevation +45 deg).
    Upper,
}

impl Level {
    /// Lower-case word for the level (`"lower"`, `"middle"`, `"upper"`).
    pub const fn name(self) -> &'static str {
        match self {
            Level::Lower => "lower",
            Level::Middle => "middle",
            Level::Upper => "upper",
        }
    }

    /// 0, 1 and 2 for the lower, middle and upper level: the levels from the lowest.
    pub const fn index(self) -> usize {
        match self {
            Level::Lower => 0,
            Level::Middle => 1,
            Level::Upper => 2,
        }
    }

    /// The Table-1 level nearest to `elevation_deg` (-45, 0 or +45 deg).
    pub fn nearest(elevation_deg: f64) -> Level {
        if elevation_deg < -22.5 {
            Level::Lower
        } else if elevation_deg > 22.5 {
            Level::Upper
        } else {
            Level::Middle
        }
    }
}

/// Which side of the (canonical, -x facing) body a camera stands on. Serialised by its
/// lower-case [`name`](Side::name).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// In front of the body (azimuth 180 deg, camera on -x).
    Front,
    /// On the body's left (azimuth 270 deg, camera on -y).
    Left,
    /// Behind the body (azimuth 0 deg, camera on +x).
    Back,
    /// On the body's right (azimuth 90 deg, camera on +y).
    Right,
}

impl Side {
    /// Lower-case word for the side (`"front"`, `"left"`, `"back"`, `"right"`).
    pub const fn name(self) -> &'static str {
        match self {
            Side::Front => "front",
            Side::Left => "left",
            Side::Back => "back",
            Side::Right => "right",
        }
    }

    /// The side whose centre azimuth is nearest to `azimuth_deg`.
    pub fn nearest(azimuth_deg: f64) -> Side {
        let a = azimuth_deg.rem_euclid(360.0);
        if !(45.0..315.0).contains(&a) {
            Side::Back
        } else if a < 135.0 {
            Side::Right
        } else if a < 225.0 {
            Side::Front
        } else {
            Side::Left
        }
    }

    /// The side seen in a left-right mirror image (left <-> right).
    pub const fn mirrored(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
            other => other,
        }
    }
}

/// One camera of a [`CameraSet`]: a class label and where it stands.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Viewpoint {
    /// Class label, 1-based (Table 1 numbering for [`CameraSet::table1`]).
    pub label: u16,
    /// Azimuth of the camera position, degrees (see [`sphere_point`]).
    pub azimuth_deg: f64,
    /// Elevation of the camera position, degrees.
    pub elevation_deg: f64,
    /// Nearest Table-1 height class.
    pub level: Level,
    /// Nearest Table-1 side.
    pub side: Side,
    /// Camera rotation from eq. 4 (rows: camera x, y, z axes in world coordinates).
    pub rotation: Matrix3,
}

impl Viewpoint {
    /// Label formatted as in Table 1 (`"01"` ... `"12"`).
    pub fn label_text(&self) -> String {
        format!("{:02}", self.label)
    }

    /// Its angles in a few characters, degrees: `"az 225, el -20"` (what tells apart the
    /// cameras of a set whose level and side names repeat: [`CameraSet::names_repeat`]).
    pub fn angles_text(&self) -> String {
        format!("az {:.0}, el {:+.0}", self.azimuth_deg, self.elevation_deg)
    }

    /// Camera position on a sphere of `radius` metres.
    pub fn position(&self, radius: f64) -> Vector3 {
        sphere_point(self.azimuth_deg, self.elevation_deg, radius)
    }
}

/// A set of viewpoints on the virtual sphere, the classes of camera localization.
///
/// Labels run from 1 to `len()`: elevation rings in increasing order, and within a ring
/// azimuths from the front (180 deg) towards the left (270 deg), back and right. With 4
/// azimuths and elevations (-45, 0, +45) this is exactly Table 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraSet {
    azimuths: usize,
    elevations_deg: Vec<f64>,
    viewpoints: Vec<Viewpoint>,
}

impl CameraSet {
    /// The 12 cameras of Table 1 (labels 01-12).
    pub fn table1() -> CameraSet {
        // Four azimuths at three finite non-polar elevations cannot fail.
        match CameraSet::sphere(4, &[-45.0, 0.0, 45.0]) {
            Ok(set) => set,
            Err(e) => unreachable!("Table 1 is a valid sphere: {e}"),
        }
    }

    /// `azimuths` equally spaced azimuths (starting at the front, 180 deg) times the given
    /// elevations (degrees, strictly between -90 and 90, increasing).
    ///
    /// # Errors
    /// [`GeometryError::InvalidSphere`] for zero azimuths, no elevations, elevations that are not
    /// strictly increasing, or an elevation at or beyond a pole.
    pub fn sphere(azimuths: usize, elevations_deg: &[f64]) -> Result<CameraSet, GeometryError> {
        if azimuths == 0 || elevations_deg.is_empty() {
            return Err(GeometryError::InvalidSphere(
                "need at least one azimuth and one elevation".into(),
            ));
        }
        let count = azimuths.checked_mul(elevations_deg.len());
        if count.is_none_or(|n| n > u16::MAX as usize) {
            return Err(GeometryError::InvalidSphere(format!(
                "{azimuths} azimuths x {} elevations is too many viewpoints (at most {})",
                elevations_deg.len(),
                u16::MAX
            )));
        }
        if let Some(bad) = elevations_deg
            .iter()
            .find(|e| !e.is_finite() || e.abs() >= 90.0)
        {
            return Err(GeometryError::InvalidSphere(format!(
                "elevation {bad} deg is not strictly between -90 and 90 (eq. 4 is undefined at the poles)"
            )));
        }
        if elevations_deg.windows(2).any(|w| w[1] <= w[0]) {
            return Err(GeometryError::InvalidSphere(
                "elevations must be strictly increasing".into(),
            ));
        }
        let mut viewpoints = Vec::with_capacity(azimuths * elevations_deg.len());
        for &elevation_deg in elevations_deg {
            for j in 0..azimuths {
                let azimuth_deg = (180.0 + 360.0 * j as f64 / azimuths as f64).rem_euclid(360.0);
                let rotation = look_at_origin(sphere_point(azimuth_deg, elevation_deg, 1.0))?;
                viewpoints.push(Viewpoint {
                    label: (viewpoints.len() + 1) as u16,
                    azimuth_deg,
                    elevation_deg,
                    level: Level::nearest(elevation_deg),
                    side: Side::nearest(azimuth_deg),
                    rotation,
                });
            }
        }
        Ok(CameraSet {
            azimuths,
            elevations_deg: elevations_deg.to_vec(),
            viewpoints,
        })
    }

    /// Checks that the set is exactly what [`CameraSet::sphere`] builds from its azimuth
    /// count and elevations (labels, angles, levels, sides and rotations): the check for a set
    /// decoded from a file, since every other method relies on that layout.
    ///
    /// # Errors
    /// [`GeometryError::InvalidSphere`] for invalid parameters or viewpoints that differ from
    /// the ones the parameters give.
    pub fn validate(&self) -> Result<(), GeometryError> {
        let rebuilt = CameraSet::sphere(self.azimuths, &self.elevations_deg)?;
        if rebuilt.viewpoints != self.viewpoints {
            return Err(GeometryError::InvalidSphere(format!(
                "the {} stored viewpoints are not the {} viewpoints of {} azimuths x {} elevations",
                self.viewpoints.len(),
                rebuilt.viewpoints.len(),
                self.azimuths,
                self.elevations_deg.len()
            )));
        }
        Ok(())
    }

    /// Number of viewpoints (classes).
    pub fn len(&self) -> usize {
        self.viewpoints.len()
    }

    /// Always `false`: a camera set has at least one viewpoint.
    pub fn is_empty(&self) -> bool {
        self.viewpoints.is_empty()
    }

    /// Whether two of its cameras have the same level and side (a sphere of more than 4
    /// azimuths, or of several rings in a level): their names alone do not tell them apart.
    pub fn names_repeat(&self) -> bool {
        let views = &self.viewpoints;
        (views.iter().enumerate())
            .any(|(i, v)| (views[..i].iter()).any(|w| (w.level, w.side) == (v.level, v.side)))
    }

    /// Number of azimuths per elevation ring.
    pub fn azimuths(&self) -> usize {
        self.azimuths
    }

    /// Elevations of the rings, degrees.
    pub fn elevations_deg(&self) -> &[f64] {
        &self.elevations_deg
    }

    /// All viewpoints, in label order.
    pub fn viewpoints(&self) -> &[Viewpoint] {
        &self.viewpoints
    }

    /// `value` as a label of this set.
    ///
    /// # Errors
    /// [`GeometryError::InvalidLabel`] for 0 or a label above [`CameraSet::len`].
    pub fn label(&self, value: u16) -> Result<CameraLabel, GeometryError> {
        match CameraLabel::new(value) {
            Ok(label) if usize::from(value) <= self.len() => Ok(label),
            _ => Err(GeometryError::InvalidLabel {
                label: value,
                cameras: Some(self.len()),
            }),
        }
    }

    /// The viewpoint with `label` (1-based), or `None`.
    pub fn get(&self, label: u16) -> Option<&Viewpoint> {
        (label as usize)
            .checked_sub(1)
            .and_then(|i| self.viewpoints.get(i))
    }

    /// Label of the viewpoint in the ring of `label` whose azimuth is nearest to
    /// `azimuth_deg`, among those accepted by `keep`; `label` itself when none is accepted.
    fn nearest_in_ring(&self, label: u16, azimuth_deg: f64, keep: impl Fn(f64) -> bool) -> u16 {
        let Some(i) = (label as usize).checked_sub(1).filter(|&i| i < self.len()) else {
            return label;
        };
        self.nearest_azimuth(i / self.azimuths, azimuth_deg, keep)
            .map_or(label, |v| v.label)
    }

    /// The viewpoint of ring `ring` (index into [`elevations_deg`](Self::elevations_deg))
    /// whose azimuth is nearest to `azimuth_deg` (the first of equally near ones), among those
    /// accepted by `keep`.
    fn nearest_azimuth(
        &self,
        ring: usize,
        azimuth_deg: f64,
        keep: impl Fn(f64) -> bool,
    ) -> Option<&Viewpoint> {
        self.viewpoints[ring * self.azimuths..(ring + 1) * self.azimuths]
            .iter()
            .filter(|v| keep(v.azimuth_deg))
            .min_by(|a, b| {
                azimuth_gap_deg(a.azimuth_deg, azimuth_deg)
                    .total_cmp(&azimuth_gap_deg(b.azimuth_deg, azimuth_deg))
            })
    }

    /// The viewpoint whose cell holds the direction `(azimuth_deg, elevation_deg)`
    /// (degrees, [`sphere_point`]'s angles): the ring whose elevation is nearest, then in it
    /// the viewpoint whose azimuth is nearest (the first of equally near ones each time). For
    /// Table 1 the level is the elevation band (middle from -22.5 to 22.5 deg) and the side
    /// the azimuth quadrant (+-45 deg around the camera), whatever the other angle: a camera
    /// 20 deg above the body is a middle one from any side, as a lab's camera ring is, where
    /// the camera nearest by angle would be an upper one halfway between two sides.
    pub fn by_ring_and_side(&self, azimuth_deg: f64, elevation_deg: f64) -> &Viewpoint {
        let ring = self
            .elevations_deg
            .iter()
            .enumerate()
            .min_by(|a, b| {
                (a.1 - elevation_deg)
                    .abs()
                    .total_cmp(&(b.1 - elevation_deg).abs())
            })
            .map_or(0, |(r, _)| r);
        self.nearest_azimuth(ring, azimuth_deg, |_| true)
            .unwrap_or(&self.viewpoints[ring * self.azimuths])
    }

    /// Mirror folding (paper section 8.1): a camera behind the body maps to its mirror image in
    /// front of it at the same elevation (03 -> 01, 07 -> 05, 11 -> 09 in Table 1; for an odd
    /// number of azimuths, the nearest camera that is not behind); other labels are unchanged.
    /// Unknown labels are returned as they are.
    pub fn fold_back_to_front(&self, label: u16) -> u16 {
        let Some(v) = self.get(label) else {
            return label;
        };
        let behind = |az: f64| az.to_radians().cos() > 1e-9;
        if !behind(v.azimuth_deg) {
            return label;
        }
        // Reflection across the frontal (yz) plane: az -> 180 - az.
        self.nearest_in_ring(label, 180.0 - v.azimuth_deg, |az| !behind(az))
    }

    /// The label a left-right mirrored image of the same pose is seen from (reflection across
    /// the sagittal plane, az -> -az: left <-> right, front and back unchanged). Unknown labels
    /// are returned as they are.
    pub fn mirror_left_right(&self, label: u16) -> u16 {
        let Some(v) = self.get(label) else {
            return label;
        };
        self.nearest_in_ring(label, -v.azimuth_deg, |_| true)
    }

    /// The viewpoint whose rotation is nearest to `rotation` (smallest rotation angle between
    /// them), e.g. to give a jittered camera its class.
    pub fn nearest(&self, rotation: &Matrix3) -> &Viewpoint {
        let mut best = &self.viewpoints[0];
        let mut best_trace = f64::NEG_INFINITY;
        for v in &self.viewpoints {
            // trace(A B^T) = 1 + 2 cos(angle between A and B): largest trace is nearest.
            let t = (v.rotation.component_mul(rotation)).sum();
            if t > best_trace {
                best_trace = t;
                best = v;
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check_rotation;
    use proptest::prelude::*;

    const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

    /// Table 1 of the paper, transcribed row by row (labels 01-12).
    fn table1_transcribed() -> [[f64; 9]; 12] {
        [
            [0., -1., 0., H, 0., -H, H, 0., H],      // 01 lower front
            [1., 0., 0., 0., H, -H, 0., H, H],       // 02 lower left
            [0., 1., 0., -H, 0., -H, -H, 0., H],     // 03 lower back
            [-1., 0., 0., 0., -H, -H, 0., -H, H],    // 04 lower right
            [0., -1., 0., 0., 0., -1., 1., 0., 0.],  // 05 middle front
            [1., 0., 0., 0., 0., -1., 0., 1., 0.],   // 06 middle left
            [0., 1., 0., 0., 0., -1., -1., 0., 0.],  // 07 middle back
            [-1., 0., 0., 0., 0., -1., 0., -1., 0.], // 08 middle right
            [0., -1., 0., -H, 0., -H, H, 0., -H],    // 09 upper front
            [1., 0., 0., 0., -H, -H, 0., H, -H],     // 10 upper left
            [0., 1., 0., H, 0., -H, -H, 0., -H],     // 11 upper back
            [-1., 0., 0., 0., H, -H, 0., -H, -H],    // 12 upper right
        ]
    }

    /// Table 1's names are its cameras' own; 8 azimuths or several middle rings repeat them,
    /// and the angles tell those apart.
    #[test]
    fn names_repeat_on_finer_spheres() {
        assert!(!CameraSet::table1().names_repeat());
        assert!(CameraSet::sphere(8, &[0.0]).unwrap().names_repeat());
        assert!(
            CameraSet::sphere(4, &[-20.0, 0.0, 20.0])
                .unwrap()
                .names_repeat()
        );
        assert!(
            !CameraSet::sphere(4, &[-45.0, 0.0, 45.0])
                .unwrap()
                .names_repeat()
        );
        let fine = CameraSet::sphere(8, &[-20.0, 0.0]).unwrap();
        assert_eq!(fine.viewpoints()[1].angles_text(), "az 225, el -20");
        assert_eq!(fine.viewpoints()[8].angles_text(), "az 180, el +0");
    }

    #[test]
    fn table1_is_reproduced_by_eq4() {
        let set = CameraSet::table1();
        assert_eq!(set.len(), 12);
        for (i, expected) in table1_transcribed().iter().enumerate() {
            let v = set.get(i as u16 + 1).unwrap();
            let r = Matrix3::from_row_slice(expected);
            let err = (v.rotation - r).abs().max();
            assert!(err < 1e-4, "camera {:02}: error {err}", v.label);
        }
        let words: Vec<_> = set
            .viewpoints()
            .iter()
            .map(|v| format!("{} {}", v.level.name(), v.side.name()))
            .collect();
        assert_eq!(words[0], "lower front");
        assert_eq!(words[5], "middle left");
        assert_eq!(words[11], "upper right");
    }

    #[test]
    fn validate_accepts_built_sets_and_refuses_tampered_ones() {
        let set = CameraSet::table1();
        set.validate().unwrap();
        CameraSet::sphere(5, &[-10.0, 30.0])
            .unwrap()
            .validate()
            .unwrap();
        let mut no_azimuth = set.clone();
        no_azimuth.azimuths = 0;
        assert!(no_azimuth.validate().is_err());
        let mut huge = set.clone();
        huge.azimuths = usize::MAX;
        assert!(huge.validate().is_err());
        let mut short = set.clone();
        short.viewpoints.pop();
        assert!(short.validate().is_err());
        let mut relabelled = set.clone();
        relabelled.viewpoints[3].label = 40;
        assert!(relabelled.validate().is_err());
        let mut turned = set;
        turned.viewpoints[0].rotation[(0, 0)] = f64::NAN;
        assert!(turned.validate().is_err());
    }

    #[test]
    fn folding_and_mirroring_follow_table1() {
        let set = CameraSet::table1();
        let folded: Vec<u16> = (1..=12).map(|l| set.fold_back_to_front(l)).collect();
        assert_eq!(folded, [1, 2, 1, 4, 5, 6, 5, 8, 9, 10, 9, 12]);
        let mirrored: Vec<u16> = (1..=12).map(|l| set.mirror_left_right(l)).collect();
        assert_eq!(mirrored, [1, 4, 3, 2, 5, 8, 7, 6, 9, 12, 11, 10]);
        assert_eq!(set.fold_back_to_front(99), 99);
    }

    #[test]
    fn ring_and_side_follow_table1() {
        let cameras = CameraSet::table1();
        assert_eq!(cameras.by_ring_and_side(170.0, 40.0).label, 9);
        assert_eq!(cameras.by_ring_and_side(0.0, -10.0).label, 7);
        // 20 deg up, halfway between front and left: nearer the upper cameras by angle, but
        // in the middle ring's band.
        assert_eq!(cameras.by_ring_and_side(224.0, 20.0).label, 5);
        assert_eq!(cameras.by_ring_and_side(226.0, 20.0).label, 6);
        assert_eq!(cameras.by_ring_and_side(226.0, 23.0).label, 10);
        assert_eq!(cameras.by_ring_and_side(90.0, -50.0).label, 4);
        assert_eq!(azimuth_gap_deg(350.0, 10.0), 20.0);
        assert_eq!(azimuth_gap_deg(-90.0, 270.0), 0.0);
    }

    #[test]
    fn poles_are_errors_not_nan() {
        assert!(matches!(
            look_at_origin(Vector3::new(0.0, 0.0, 3.0)),
            Err(GeometryError::Pole { .. })
        ));
        assert!(matches!(
            look_at_origin(Vector3::zeros()),
            Err(GeometryError::DegeneratePosition)
        ));
        assert!(CameraSet::sphere(8, &[90.0]).is_err());
        assert!(CameraSet::sphere(0, &[0.0]).is_err());
        assert!(CameraSet::sphere(4, &[10.0, 0.0]).is_err());
    }

    #[test]
    fn nearest_finds_the_exact_camera() {
        let set = CameraSet::sphere(8, &[-30.0, 0.0, 30.0, 60.0]).unwrap();
        for v in set.viewpoints() {
            assert_eq!(set.nearest(&v.rotation).label, v.label);
        }
    }

    proptest! {
        #[test]
        fn look_at_is_a_rotation_facing_the_origin(az in 0.0f64..360.0, el in -89.0f64..89.0,
                                                   r in 0.1f64..100.0) {
            let p = sphere_point(az, el, r);
            let rot = look_at_origin(p).unwrap();
            prop_assert!(check_rotation(&rot, 1e-12).is_ok());
            // The optical axis points from the camera to the origin.
            let axis = rot.row(2).transpose();
            prop_assert!((axis + p / r).norm() < 1e-12);
            // The image x axis is horizontal (eq. 4 builds it in the xy plane).
            prop_assert!(rot[(0, 2)].abs() < 1e-12);
        }

        #[test]
        fn general_sphere_mirror_is_an_involution(n in 1usize..16, m in 1usize..5) {
            let elevations: Vec<f64> = (0..m).map(|i| -60.0 + 120.0 * i as f64 / m as f64).collect();
            let set = CameraSet::sphere(n, &elevations).unwrap();
            for v in set.viewpoints() {
                let mirrored = set.mirror_left_right(v.label);
                prop_assert_eq!(set.mirror_left_right(mirrored), v.label);
                let mv = set.get(mirrored).unwrap();
                prop_assert!(((mv.azimuth_deg + v.azimuth_deg).rem_euclid(360.0)).min(
                    360.0 - (mv.azimuth_deg + v.azimuth_deg).rem_euclid(360.0)) < 1e-9);
                let folded = set.get(set.fold_back_to_front(v.label)).unwrap();
                prop_assert!(folded.azimuth_deg.to_radians().cos() <= 1e-9);
            }
        }
    }
}
