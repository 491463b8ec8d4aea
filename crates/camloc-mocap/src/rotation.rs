//! The little rigid-body algebra forward kinematics needs: coordinate axes, 3x3 rotation
//! matrices acting on column vectors, and the y-up to z-up change of frame.

/// A coordinate axis of the file's (y-up) frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// Index of the axis in a 3-vector.
    pub(crate) const fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// The axis named by a letter `x`/`y`/`z` (either case).
    pub(crate) fn from_letter(c: char) -> Option<Axis> {
        match c.to_ascii_lowercase() {
            'x' => Some(Axis::X),
            'y' => Some(Axis::Y),
            'z' => Some(Axis::Z),
            _ => None,
        }
    }
}

/// A 3x3 rotation matrix, row-major, acting on column vectors (`v' = R v`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rot3(pub(crate) [[f64; 3]; 3]);

impl Rot3 {
    /// The identity rotation.
    pub(crate) const IDENTITY: Rot3 = Rot3([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);

    /// Right-handed rotation by `angle_rad` radians about `axis`.
    pub(crate) fn about(axis: Axis, angle_rad: f64) -> Rot3 {
        let (s, c) = angle_rad.sin_cos();
        match axis {
            Axis::X => Rot3([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]),
            Axis::Y => Rot3([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]),
            Axis::Z => Rot3([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]),
        }
    }

    /// The matrix product `self * rhs` (apply `rhs` first).
    pub(crate) fn mul(&self, rhs: &Rot3) -> Rot3 {
        let (a, b) = (&self.0, &rhs.0);
        let mut out = [[0.0; 3]; 3];
        for (i, row) in out.iter_mut().enumerate() {
            for (j, o) in row.iter_mut().enumerate() {
                *o = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
            }
        }
        Rot3(out)
    }

    /// `R v`.
    pub(crate) fn apply(&self, v: [f64; 3]) -> [f64; 3] {
        let m = &self.0;
        [
            m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
            m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
        ]
    }

    /// The inverse rotation (the transpose).
    pub(crate) fn transpose(&self) -> Rot3 {
        let m = &self.0;
        Rot3([
            [m[0][0], m[1][0], m[2][0]],
            [m[0][1], m[1][1], m[2][1]],
            [m[0][2], m[1][2], m[2][2]],
        ])
    }
}

impl Rot3 {
    /// The rotation whose columns are `x`, `y` and `z` (it maps the unit axes onto them).
    pub(crate) fn from_columns(x: [f64; 3], y: [f64; 3], z: [f64; 3]) -> Rot3 {
        Rot3([[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]])
    }

    /// Right-handed rotation by `angle_rad` about the unit vector `axis` (Rodrigues).
    pub(crate) fn about_unit(axis: [f64; 3], angle_rad: f64) -> Rot3 {
        let (s, c) = angle_rad.sin_cos();
        let [x, y, z] = axis;
        let t = 1.0 - c;
        Rot3([
            [c + t * x * x, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, c + t * y * y, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, c + t * z * z],
        ])
    }

    /// The smallest rotation that turns the unit vector `from` onto the unit vector `to`
    /// (about their common normal); a half turn about an axis normal to `from` when they are
    /// opposite.
    pub(crate) fn swing(from: [f64; 3], to: [f64; 3]) -> Rot3 {
        let axis = cross(from, to);
        let (sin, cos) = (norm(axis), dot(from, to));
        if sin < 1e-12 && cos < 0.0 {
            // Opposite: any normal works; take the one from the axis `from` is least along.
            let k = (0..3)
                .min_by(|&a, &b| from[a].abs().total_cmp(&from[b].abs()))
                .unwrap_or(0);
            let mut e = [0.0; 3];
            e[k] = 1.0;
            return Rot3::about_unit(unit(cross(from, e)).unwrap_or(e), std::f64::consts::PI);
        }
        match unit(axis) {
            Some(axis) => Rot3::about_unit(axis, sin.atan2(cos)),
            None => Rot3::IDENTITY,
        }
    }

    /// `trace(self)`.
    pub(crate) fn trace(&self) -> f64 {
        self.0[0][0] + self.0[1][1] + self.0[2][2]
    }
}

/// `a + b`.
pub(crate) fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a - b`.
pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a . b`.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a x b`.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean norm.
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`, `None` when `a` has no direction (zero or not finite).
pub(crate) fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 0.0 && n.is_finite()).then(|| a.map(|c| c / n))
}

/// Maps a point of a y-up mocap file, in file units, to the z-up world in metres
/// (docs/conventions.md section 1): `(x, y, z) * scale -> (x, -z, y) * scale`.
pub(crate) fn y_up_to_z_up(v: [f64; 3], metres_per_unit: f64) -> [f64; 3] {
    [
        v[0] * metres_per_unit,
        -v[2] * metres_per_unit,
        v[1] * metres_per_unit,
    ]
}

/// Maps a z-up world point in metres to a y-up mocap file point in file units: the inverse
/// of [`y_up_to_z_up`], `(x, y, z) / scale -> (x, z, -y) / scale`.
pub(crate) fn z_up_to_y_up(v: [f64; 3], metres_per_unit: f64) -> [f64; 3] {
    [
        v[0] / metres_per_unit,
        v[2] / metres_per_unit,
        -v[1] / metres_per_unit,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn quarter_turns_are_right_handed() {
        let q = std::f64::consts::FRAC_PI_2;
        assert!(close(
            Rot3::about(Axis::X, q).apply([0.0, 1.0, 0.0]),
            [0.0, 0.0, 1.0]
        ));
        assert!(close(
            Rot3::about(Axis::Y, q).apply([0.0, 0.0, 1.0]),
            [1.0, 0.0, 0.0]
        ));
        assert!(close(
            Rot3::about(Axis::Z, q).apply([1.0, 0.0, 0.0]),
            [0.0, 1.0, 0.0]
        ));
    }

    #[test]
    fn product_applies_the_right_factor_first_and_transpose_inverts() {
        let q = std::f64::consts::FRAC_PI_2;
        let zx = Rot3::about(Axis::Z, q).mul(&Rot3::about(Axis::X, q));
        // x-rotation first: y -> z, then the z-rotation keeps z.
        assert!(close(zx.apply([0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]));
        let back = zx.transpose().mul(&zx);
        for (i, row) in back.0.iter().enumerate() {
            assert!(close(*row, Rot3::IDENTITY.0[i]));
        }
    }

    #[test]
    fn swing_turns_one_unit_vector_onto_another_by_the_smallest_angle() {
        let dirs = [
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            unit([0.3, -0.8, 0.5]).unwrap(),
            unit([-0.3, 0.8, -0.5]).unwrap(),
            [-1.0, 0.0, 0.0],
        ];
        for a in dirs {
            for b in dirs {
                let r = Rot3::swing(a, b);
                assert!(close(r.apply(a), b), "{a:?} -> {b:?}");
                let angle = ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos();
                assert!((angle - dot(a, b).clamp(-1.0, 1.0).acos()).abs() < 1e-6);
                let rtr = r.transpose().mul(&r);
                for (i, row) in rtr.0.iter().enumerate() {
                    assert!(close(*row, Rot3::IDENTITY.0[i]));
                }
            }
        }
        // About an axis, as `about` for the coordinate axes.
        let q = 0.7;
        assert!(close(
            Rot3::about_unit([0.0, 0.0, 1.0], q).apply([1.0, 2.0, 3.0]),
            Rot3::about(Axis::Z, q).apply([1.0, 2.0, 3.0])
        ));
    }

    #[test]
    fn y_up_maps_to_z_up_as_a_proper_rotation() {
        // x stays, file up (y) becomes z, file forward (z) becomes -y.
        assert_eq!(y_up_to_z_up([1.0, 2.0, 3.0], 2.0), [2.0, -6.0, 4.0]);
        // Right-handedness is preserved: x cross y = z in both frames.
        let (x, y) = (
            y_up_to_z_up([1.0, 0.0, 0.0], 1.0),
            y_up_to_z_up([0.0, 1.0, 0.0], 1.0),
        );
        let cross = [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ];
        assert_eq!(cross, y_up_to_z_up([0.0, 0.0, 1.0], 1.0));
        assert_eq!(z_up_to_y_up([2.0, -6.0, 4.0], 2.0), [1.0, 2.0, 3.0]);
    }
}
