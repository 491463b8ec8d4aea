//! Euler angles of a rotation in a BVH channel order, chosen to stay close to the previous
//! frame's angles so that the channels of a smooth motion are smooth curves.

use super::rotation::{Axis, Rot3};

/// Three distinct axes: the rotation is `R = R_a(first) R_b(second) R_c(third)` (the BVH
/// convention: the channels compose in the order they are listed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct EulerOrder(pub(crate) [Axis; 3]);

/// `cos` of the middle angle below which the first and third axes are taken as aligned
/// (gimbal lock): the first angle is then kept from the previous frame.
const GIMBAL_COS: f64 = 1e-7;

impl EulerOrder {
    /// The rotation of the angles `[first, second, third]` (radians).
    #[cfg(test)]
    pub(crate) fn compose(self, angles: [f64; 3]) -> Rot3 {
        let [a, b, c] = self.0;
        Rot3::about(a, angles[0])
            .mul(&Rot3::about(b, angles[1]))
            .mul(&Rot3::about(c, angles[2]))
    }

    /// The angles (radians) of `r` in this order. A rotation has two sets of angles (and any
    /// multiple of a full turn added to each); the set nearest to `previous` is returned, each
    /// angle moved by whole turns to within half a turn of its previous value, so that the
    /// angles of a continuous motion are continuous (they may leave `[-180, 180]` degrees).
    /// Without `previous` the set with the middle angle in `[-90, 90]` degrees is returned.
    pub(crate) fn decompose(self, r: &Rot3, previous: Option<[f64; 3]>) -> [f64; 3] {
        let [i, j, k] = self.0.map(Axis::index);
        let m = &r.0;
        // +1 for the cyclic orders (xyz, yzx, zxy), -1 for the others.
        let e = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
        let second = (e * m[i][k]).clamp(-1.0, 1.0).asin();
        let candidates = if second.cos() < GIMBAL_COS {
            // Gimbal lock: only first +- third is defined; keep the previous first angle.
            let first = previous.map_or(0.0, |p| p[0]);
            let rest = Rot3::about(self.0[1], second)
                .transpose()
                .mul(&Rot3::about(self.0[0], first).transpose())
                .mul(r);
            let (u, v) = ((k + 1) % 3, (k + 2) % 3);
            vec![[first, second, rest.0[v][u].atan2(rest.0[u][u])]]
        } else {
            let first = (-e * m[j][k]).atan2(m[k][k]);
            let third = (-e * m[i][j]).atan2(m[i][i]);
            let pi = std::f64::consts::PI;
            vec![
                [first, second, third],
                [first + pi, pi - second, third + pi],
            ]
        };
        let Some(previous) = previous else {
            return candidates[0];
        };
        let near = |angles: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|n| nearest_turn(angles[n], previous[n]))
        };
        let distance = |angles: &[f64; 3]| -> f64 {
            angles
                .iter()
                .zip(&previous)
                .map(|(a, p)| (a - p).powi(2))
                .sum()
        };
        candidates
            .into_iter()
            .map(near)
            .min_by(|a, b| distance(a).total_cmp(&distance(b)))
            .unwrap_or([0.0; 3])
    }
}

/// `angle` plus the whole number of turns that brings it nearest to `reference` (radians).
fn nearest_turn(angle: f64, reference: f64) -> f64 {
    let turn = std::f64::consts::TAU;
    angle + ((reference - angle) / turn).round() * turn
}

#[cfg(test)]
mod tests {
    use super::*;

    const ORDERS: [[Axis; 3]; 6] = [
        [Axis::X, Axis::Y, Axis::Z],
        [Axis::X, Axis::Z, Axis::Y],
        [Axis::Y, Axis::X, Axis::Z],
        [Axis::Y, Axis::Z, Axis::X],
        [Axis::Z, Axis::X, Axis::Y],
        [Axis::Z, Axis::Y, Axis::X],
    ];

    fn max_difference(a: &Rot3, b: &Rot3) -> f64 {
        a.0.iter()
            .flatten()
            .zip(b.0.iter().flatten())
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn decompose_inverts_compose_in_every_order_including_gimbal_lock() {
        let half = std::f64::consts::FRAC_PI_2;
        for axes in ORDERS {
            let order = EulerOrder(axes);
            for angles in [
                [0.3, -0.4, 1.2],
                [-2.9, 1.1, 0.05],
                [1.0, half, 0.4],
                [0.2, -half, -1.3],
                [0.0, 0.0, 0.0],
            ] {
                let r = order.compose(angles);
                for previous in [None, Some([0.0; 3]), Some([10.0, -3.0, 4.0])] {
                    let back = order.compose(order.decompose(&r, previous));
                    assert!(
                        max_difference(&back, &r) < 1e-9,
                        "{axes:?} {angles:?} {previous:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_steady_turn_gives_continuous_angles_past_half_a_turn() {
        // A turn about the first axis by 3 degrees a frame for 400 frames (more than three
        // full turns), with a constant tilt: no channel may jump.
        for axes in ORDERS {
            let order = EulerOrder(axes);
            let mut previous: Option<[f64; 3]> = None;
            for t in 0..400 {
                let angle = (3.0 * t as f64).to_radians();
                let r = order.compose([angle, 0.3, -0.2]);
                let got = order.decompose(&r, previous);
                if let Some(p) = previous {
                    for n in 0..3 {
                        assert!((got[n] - p[n]).abs() < 0.06, "{axes:?} frame {t}: {got:?}");
                    }
                }
                previous = Some(got);
            }
            let last = previous.unwrap_or_default();
            assert!((last[0] - (3.0 * 399.0_f64).to_radians()).abs() < 1e-9);
        }
    }
}
