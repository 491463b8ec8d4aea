//! One frame of the skeleton refinement: its data, its state, and its robust cost with the
//! Gauss-Newton normal equations around a state.
//!
//! Parameters of a frame, in this order: the rotation increment `w` (3; `R <- R exp([w]x)`),
//! the camera (3: `log s` and the translation `t` of the on-axis camera, or the translation
//! `T` of full perspective), the tangent steps of the 14 bone directions (2 each); then, shared by
//! every frame, the 14 log bone lengths and the weak-perspective camera's inverse distance.
//!
//! Residuals: the 15 landmarks' reprojection (2 each, in units of the image noise, with a
//! Huber loss), each bone direction's distance from its anchor (the pursuit's direction, in
//! units of the direction deviation), the head's angle to the torso beyond its limit (in
//! units of its deviation) and, in sequences, each bone's direction in the
//! camera's orientation against the mean of its neighbouring frames' (in units of the
//! smoothness deviation; directions, not positions, so that the smoothness does not prefer
//! short bones).

use camloc_skeleton::{LIMBS, NECK_HEAD_LIMB, NUM_LANDMARKS, NUM_LIMBS, TORSO_LIMB};
use nalgebra::{Matrix2x3, Matrix3, SMatrix, SVector, Vector2, Vector3};

use super::kinematics::{MAX_CHAIN, chains, forward, moved, tangent_basis};

/// Parameters of one frame.
pub(super) const FRAME: usize = 3 + 3 + 2 * NUM_LIMBS;
/// Parameters shared by the frames: the log lengths and the inverse distance.
pub(super) const SHARED: usize = NUM_LIMBS + 1;
/// Parameters of one frame and the shared ones.
pub(super) const ALL: usize = FRAME + SHARED;
/// The inverse distance among all parameters.
const KAPPA: usize = FRAME + NUM_LIMBS;
/// First camera parameter.
const CAM: usize = 3;
/// First direction parameter.
const DIR: usize = 6;

/// Normal equations over [`ALL`] parameters.
pub(super) type Hessian = SMatrix<f64, ALL, ALL>;
/// A gradient over [`ALL`] parameters.
pub(super) type Gradient = SVector<f64, ALL>;

/// How a frame's camera projects, in the frame's normalised image units.
#[derive(Clone, Copy, Debug)]
pub(super) enum Projection {
    /// No intrinsics: `p = s (Y_x, Y_y) / (1 + kappa Y_z) + t`, `Y = R X`, with the shared
    /// inverse distance `kappa` (1/m, >= 0): weak perspective at 0, else a perspective camera
    /// `1 / kappa` metres from the pelvis with the pelvis on its optical axis.
    OnAxis,
    /// Known intrinsics: `p = f (Y_x, Y_y) / Y_z + c`, `Y = R X + T`.
    Perspective {
        /// Focal length.
        focal: f64,
        /// Principal point.
        principal: [f64; 2],
    },
}

/// What a frame's fit is held to.
#[derive(Clone, Debug)]
pub(super) struct FrameData {
    /// The 2D landmarks (normalised image units).
    pub(super) observed: [[f64; 2]; NUM_LANDMARKS],
    /// The bone directions the pursuit found (unit, body frame).
    pub(super) anchors: [Vector3<f64>; NUM_LIMBS],
    pub(super) projection: Projection,
    /// Bit `i` set when landmark `i` was filled in rather than observed: it has no
    /// reprojection term (the direction prior holds its bones).
    pub(super) imputed: u16,
}

/// A frame's unknowns.
#[derive(Clone, Debug)]
pub(super) struct FrameState {
    /// Body frame to camera.
    pub(super) rotation: Matrix3<f64>,
    /// `(log s, t_u, t_v)` for the on-axis camera, `T` for perspective.
    pub(super) camera: [f64; 3],
    /// Unit bone directions, body frame.
    pub(super) directions: [Vector3<f64>; NUM_LIMBS],
}

/// Inverse deviations and the robust threshold of the residuals.
#[derive(Clone, Copy, Debug)]
pub(super) struct Weights {
    /// 1 / the image noise deviation (normalised image units).
    pub(super) image: f64,
    /// The Huber threshold, in deviations.
    pub(super) huber: f64,
    /// 1 / the direction deviation.
    pub(super) direction: f64,
    /// 1 / the smoothness deviation (of unit directions); 0 without smoothness.
    pub(super) smooth: f64,
    /// The factor of [`smooth`](Self::smooth) for a bone whose end landmark was filled in.
    pub(super) hidden_smooth: f64,
    /// The head's limit: the angle between the neck-to-head and pelvis-to-neck bones beyond
    /// which [`head`](Self::head) holds it back (radians; infinite for none).
    pub(super) head_limit: f64,
    /// 1 / the deviation of the head's angle beyond the limit (radians).
    pub(super) head: f64,
}

/// Depths in front of a perspective camera must exceed this (metres).
const MIN_DEPTH: f64 = 1e-3;
/// For the on-axis camera at a finite distance, a landmark's depth must exceed this
/// fraction of the pelvis's.
const MIN_DEPTH_RATIO: f64 = 0.2;
/// Most parameters in one reprojection row: rotation, camera, inverse distance, and a
/// direction (2) and a length per limb of the longest chain.
const ROW: usize = 3 + 3 + 1 + 3 * MAX_CHAIN;

/// Which shared parameters are unknowns.
#[derive(Clone, Copy, Debug)]
pub(super) struct Free {
    /// The log lengths.
    pub(super) lengths: bool,
    /// The inverse distance.
    pub(super) kappa: bool,
}

/// One sparse row of the Jacobian: parameter indices and values.
struct Row {
    index: [usize; ROW],
    value: [f64; ROW],
    n: usize,
}

impl Row {
    fn new() -> Row {
        Row {
            index: [0; ROW],
            value: [0.0; ROW],
            n: 0,
        }
    }

    fn push(&mut self, index: usize, value: f64) {
        if self.n < self.index.len() {
            self.index[self.n] = index;
            self.value[self.n] = value;
            self.n += 1;
        }
    }

    /// Adds `J^T J` and `J^T r` of this row with residual `r`.
    fn accumulate(&self, h: &mut Hessian, g: &mut Gradient, r: f64) {
        for a in 0..self.n {
            let (i, v) = (self.index[a], self.value[a]);
            g[i] += v * r;
            for b in 0..self.n {
                h[(i, self.index[b])] += v * self.value[b];
            }
        }
    }
}

impl FrameState {
    /// The landmarks in the body frame for the bone `lengths`.
    pub(super) fn points(&self, lengths: &[f64; NUM_LIMBS]) -> [Vector3<f64>; NUM_LANDMARKS] {
        forward(lengths, &self.directions)
    }

    /// The bone directions in the camera's orientation.
    pub(super) fn camera_directions(&self) -> [Vector3<f64>; NUM_LIMBS] {
        self.directions.map(|d| self.rotation * d)
    }

    /// Where the camera (with the inverse distance `kappa` when on-axis) sees the
    /// body-frame point `x`, and the derivative of that image point with respect to the
    /// camera-frame point `R x`; `None` behind the camera.
    fn see(
        &self,
        projection: Projection,
        kappa: f64,
        x: &Vector3<f64>,
    ) -> Option<(Vector2<f64>, Matrix2x3<f64>)> {
        let y = self.rotation * x;
        match projection {
            Projection::OnAxis => {
                let den = 1.0 + kappa * y.z;
                if !(den > MIN_DEPTH_RATIO) {
                    return None;
                }
                let f = self.camera[0].exp() / den;
                let k = kappa / den;
                let p = Vector2::new(f * y.x + self.camera[1], f * y.y + self.camera[2]);
                Some((
                    p,
                    Matrix2x3::new(f, 0.0, -f * y.x * k, 0.0, f, -f * y.y * k),
                ))
            }
            Projection::Perspective { focal, principal } => {
                let z = y + Vector3::from(self.camera);
                if !(z.z > MIN_DEPTH) {
                    return None;
                }
                let inv = 1.0 / z.z;
                let p = Vector2::new(
                    focal * z.x * inv + principal[0],
                    focal * z.y * inv + principal[1],
                );
                let f = focal * inv;
                Some((
                    p,
                    Matrix2x3::new(f, 0.0, -f * z.x * inv, 0.0, f, -f * z.y * inv),
                ))
            }
        }
    }

    /// The image points of the body-frame `points` (inverse distance `kappa` under weak
    /// perspective); `None` behind the camera.
    pub(super) fn project(
        &self,
        projection: Projection,
        kappa: f64,
        points: &[Vector3<f64>; NUM_LANDMARKS],
    ) -> Option<[[f64; 2]; NUM_LANDMARKS]> {
        let mut out = [[0.0; 2]; NUM_LANDMARKS];
        for (o, x) in out.iter_mut().zip(points) {
            let (p, _) = self.see(projection, kappa, x)?;
            *o = [p.x, p.y];
        }
        Some(out)
    }

    /// This state moved by `step` (the frame's [`FRAME`] parameters).
    pub(super) fn stepped(&self, projection: Projection, step: &SVector<f64, FRAME>) -> FrameState {
        let turn = nalgebra::Rotation3::new(Vector3::new(step[0], step[1], step[2]));
        let mut camera = self.camera;
        for (k, c) in camera.iter_mut().enumerate() {
            *c += step[CAM + k];
        }
        if matches!(projection, Projection::OnAxis) {
            // Keep the scale's logarithm in a range where exp neither overflows nor vanishes.
            camera[0] = camera[0].clamp(-300.0, 300.0);
        }
        FrameState {
            rotation: self.rotation * turn.matrix(),
            camera,
            directions: std::array::from_fn(|b| {
                moved(
                    &self.directions[b],
                    [step[DIR + 2 * b], step[DIR + 2 * b + 1]],
                )
            }),
        }
    }
}

/// Huber's loss of a residual of norm `rho` (in deviations) with threshold `k`, and the
/// weight that makes least squares match it there.
fn huber(rho: f64, k: f64) -> (f64, f64) {
    if rho <= k {
        (0.5 * rho * rho, 1.0)
    } else {
        (k * rho - 0.5 * k * k, k / rho)
    }
}

/// The cost of the head's angle beyond [`Weights::head_limit`] (half its square in
/// deviations), with its Gauss-Newton terms added to `normal`.
fn head_tilt(
    state: &FrameState,
    weights: &Weights,
    tangents: &[[Vector3<f64>; 2]; NUM_LIMBS],
    normal: Option<&mut (&mut Hessian, &mut Gradient)>,
) -> f64 {
    let (torso, head) = (TORSO_LIMB, NECK_HEAD_LIMB);
    let (t, h) = (state.directions[torso], state.directions[head]);
    let cos = t.dot(&h).clamp(-1.0, 1.0);
    let angle = cos.acos();
    let excess = angle - weights.head_limit;
    if !(excess > 0.0) {
        return 0.0;
    }
    let r = excess * weights.head;
    if let Some((hessian, gradient)) = normal {
        // d angle = -d cos / sin angle; a tangent step e of one bone changes cos by e . other.
        let sin = angle.sin().max(1e-9);
        let mut row = Row::new();
        for (k, e_k) in tangents[head].iter().enumerate() {
            row.push(DIR + 2 * head + k, -e_k.dot(&t) / sin * weights.head);
        }
        for (k, e_k) in tangents[torso].iter().enumerate() {
            row.push(DIR + 2 * torso + k, -e_k.dot(&h) / sin * weights.head);
        }
        row.accumulate(hessian, gradient, r);
    }
    0.5 * r * r
}

/// A frame's shared parameters: the bone lengths (metres) and the inverse distance of a
/// weak-perspective camera (1/m).
#[derive(Clone, Copy, Debug)]
pub(super) struct Shared {
    /// Bone lengths, metres.
    pub(super) lengths: [f64; NUM_LIMBS],
    /// Inverse distance, 1/m (0 under full perspective, where it has no part).
    pub(super) kappa: f64,
}

/// The cost of `state` (half the sum of squared weighted residuals, Huber on the image) for
/// the `shared` parameters, with the camera-oriented bone directions `target` of the
/// smoothness; with `normal`, adds the Gauss-Newton normal equations there (the shared
/// parameters included where `free`). `None` when a landmark is behind the camera.
pub(super) fn evaluate(
    data: &FrameData,
    state: &FrameState,
    shared: &Shared,
    target: Option<&[Vector3<f64>; NUM_LIMBS]>,
    weights: &Weights,
    mut normal: Option<(&mut Hessian, &mut Gradient)>,
    free: Free,
) -> Option<f64> {
    let lengths = &shared.lengths;
    let points = state.points(lengths);
    let chains = chains();
    let tangents: [[Vector3<f64>; 2]; NUM_LIMBS] = std::array::from_fn(|b| {
        if normal.is_some() {
            tangent_basis(&state.directions[b])
        } else {
            [Vector3::zeros(); 2]
        }
    });
    let mut cost = 0.0;
    for (i, x) in points.iter().enumerate() {
        if data.imputed & (1 << i) != 0 {
            continue;
        }
        let (p, g) = state.see(data.projection, shared.kappa, x)?;
        let u = data.observed[i];
        let e = (p - Vector2::new(u[0], u[1])) * weights.image;
        let (loss, w) = huber(e.norm(), weights.huber);
        cost += loss;
        let Some((h, grad)) = normal.as_mut() else {
            continue;
        };
        let q = g * state.rotation * (weights.image * w.sqrt());
        let (chain, n) = chains[i];
        // The on-axis camera's camera-frame point, depth factor and scale, once per landmark.
        let y = state.rotation * x;
        let den = 1.0 + shared.kappa * y.z;
        let scale = state.camera[0].exp();
        for row in 0..2 {
            let mut r = Row::new();
            let qr = q.row(row).transpose();
            for a in 0..3 {
                r.push(a, qr.dot(&Vector3::ith(a, 1.0).cross(x)));
            }
            match data.projection {
                Projection::OnAxis => {
                    let seen = scale * y[row] / den;
                    r.push(CAM, seen * weights.image * w.sqrt());
                    r.push(CAM + 1 + row, weights.image * w.sqrt());
                    if free.kappa {
                        r.push(KAPPA, -seen * y.z / den * weights.image * w.sqrt());
                    }
                }
                Projection::Perspective { .. } => {
                    for k in 0..3 {
                        r.push(CAM + k, g[(row, k)] * weights.image * w.sqrt());
                    }
                }
            }
            for &b in &chain[..n] {
                for (k, e_k) in tangents[b].iter().enumerate() {
                    r.push(DIR + 2 * b + k, lengths[b] * qr.dot(e_k));
                }
                if free.lengths {
                    r.push(FRAME + b, lengths[b] * qr.dot(&state.directions[b]));
                }
            }
            r.accumulate(h, grad, e[row] * w.sqrt());
        }
    }
    for (b, (d, anchor)) in state.directions.iter().zip(&data.anchors).enumerate() {
        let diff = (d - anchor) * weights.direction;
        cost += 0.5 * diff.norm_squared();
        if let Some((h, grad)) = normal.as_mut() {
            for (k, e_k) in tangents[b].iter().enumerate() {
                let i = DIR + 2 * b + k;
                h[(i, i)] += weights.direction * weights.direction;
                grad[i] += weights.direction * e_k.dot(&diff);
            }
        }
    }
    cost += head_tilt(state, weights, &tangents, normal.as_mut());
    if let (Some(target), true) = (target, weights.smooth > 0.0) {
        for (b, d) in state.directions.iter().enumerate() {
            // A bone whose end was filled in, not seen, follows its neighbours more.
            let smooth = if data.imputed & (1 << LIMBS[b].1.index()) != 0 {
                weights.smooth * weights.hidden_smooth
            } else {
                weights.smooth
            };
            let e = (state.rotation * d - target[b]) * smooth;
            cost += 0.5 * e.norm_squared();
            let Some((h, grad)) = normal.as_mut() else {
                continue;
            };
            let turns: [Vector3<f64>; 3] =
                std::array::from_fn(|a| state.rotation * Vector3::ith(a, 1.0).cross(d));
            let bends = tangents[b].map(|e_k| state.rotation * e_k);
            for row in 0..3 {
                let mut r = Row::new();
                for (a, turn) in turns.iter().enumerate() {
                    r.push(a, turn[row] * smooth);
                }
                for (k, bend) in bends.iter().enumerate() {
                    r.push(DIR + 2 * b + k, bend[row] * smooth);
                }
                r.accumulate(h, grad, e[row]);
            }
        }
    }
    Some(cost)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gradient of the normal equations is the cost's, parameter by parameter (finite
    /// differences), for both projections, with every shared parameter free.
    #[test]
    fn the_gradient_matches_finite_differences() {
        let lengths = [
            0.1, 0.45, 0.42, 0.1, 0.45, 0.42, 0.5, 0.25, 0.18, 0.3, 0.25, 0.18, 0.3, 0.25,
        ];
        let directions: [Vector3<f64>; NUM_LIMBS] = std::array::from_fn(|b| {
            Vector3::new(
                (b as f64).sin(),
                (b as f64 * 1.7).cos(),
                0.3 + 0.1 * b as f64,
            )
            .normalize()
        });
        let anchors = directions.map(|d| (d + Vector3::new(0.05, -0.03, 0.02)).normalize());
        let rotation = *nalgebra::Rotation3::new(Vector3::new(0.3, -0.5, 0.2)).matrix();
        let target = directions.map(|d| rotation * (d + Vector3::new(0.0, 0.04, 0.0)).normalize());
        let weights = Weights {
            image: 10.0,
            huber: 1e9,
            direction: 5.0,
            smooth: 3.0,
            hidden_smooth: 2.0,
            head_limit: 0.2,
            head: 4.0,
        };
        for (projection, camera) in [
            (Projection::OnAxis, [0.2, 0.1, -0.05]),
            (
                Projection::Perspective {
                    focal: 8.0,
                    principal: [0.1, 0.2],
                },
                [0.1, -0.2, 4.0],
            ),
        ] {
            let state = FrameState {
                rotation,
                camera,
                directions,
            };
            let shared = Shared {
                lengths,
                kappa: 0.3,
            };
            let mut observed = state
                .project(projection, shared.kappa, &state.points(&lengths))
                .unwrap();
            for (j, o) in observed.iter_mut().enumerate() {
                o[0] += 0.02 * (j as f64).cos();
                o[1] -= 0.03 * (j as f64 * 0.7).sin();
            }
            let data = FrameData {
                observed,
                anchors,
                projection,
                // The left wrist filled in: its bone's smoothness is the hidden one.
                imputed: 1 << camloc_skeleton::Landmark::LeftWrist.index(),
            };
            let free = Free {
                lengths: true,
                kappa: true,
            };
            let mut h = Hessian::zeros();
            let mut g = Gradient::zeros();
            let cost = |s: &FrameState, sh: &Shared| {
                evaluate(&data, s, sh, Some(&target), &weights, None, free).unwrap()
            };
            evaluate(
                &data,
                &state,
                &shared,
                Some(&target),
                &weights,
                Some((&mut h, &mut g)),
                free,
            )
            .unwrap();
            let eps = 1e-6;
            for i in 0..ALL {
                let (plus, minus) = if i < FRAME {
                    let mut step = SVector::<f64, FRAME>::zeros();
                    step[i] = eps;
                    let plus = cost(&state.stepped(projection, &step), &shared);
                    step[i] = -eps;
                    (plus, cost(&state.stepped(projection, &step), &shared))
                } else if i < KAPPA {
                    let mut up = shared;
                    up.lengths[i - FRAME] *= eps.exp();
                    let mut down = shared;
                    down.lengths[i - FRAME] *= (-eps).exp();
                    (cost(&state, &up), cost(&state, &down))
                } else {
                    let mut up = shared;
                    up.kappa += eps;
                    let mut down = shared;
                    down.kappa -= eps;
                    (cost(&state, &up), cost(&state, &down))
                };
                let numeric = (plus - minus) / (2.0 * eps);
                // The inverse distance moves nothing under full perspective.
                let expected = if i == KAPPA && matches!(projection, Projection::Perspective { .. })
                {
                    0.0
                } else {
                    numeric
                };
                assert!(
                    (g[i] - expected).abs() < 1e-4 * (1.0 + expected.abs()),
                    "{projection:?} parameter {i}: {} against {expected}",
                    g[i]
                );
            }
        }
    }
}
