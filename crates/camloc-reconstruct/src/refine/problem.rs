//! One frame of the skeleton refinement: its data, its state, and its robust cost with the
//! Gauss-Newton normal equations around a state.
//!
//! Parameters of a frame, in this order: the rotation increment `w` (3; `R <- R exp([w]x)`),
//! the camera (3: `log s` and the translation `t` of weak perspective, or the translation `T`
//! of full perspective), the tangent steps of the 14 bone directions (2 each); then, shared by
//! every frame, the 14 log bone lengths.
//!
//! Residuals: the 15 landmarks' reprojection (2 each, in units of the image noise, with a
//! Huber loss), each bone direction's distance from its anchor (the pursuit's direction, in
//! units of the direction deviation) and, in sequences, each bone's direction in the
//! camera's orientation against the mean of its neighbouring frames' (in units of the
//! smoothness deviation; directions, not positions, so that the smoothness does not prefer
//! short bones).

use camloc_skeleton::{NUM_LANDMARKS, NUM_LIMBS};
use nalgebra::{Matrix2x3, Matrix3, SMatrix, SVector, Vector2, Vector3};

use super::kinematics::{chains, forward, moved, tangent_basis};

/// Parameters of one frame.
pub(super) const FRAME: usize = 3 + 3 + 2 * NUM_LIMBS;
/// Parameters of one frame and the shared lengths.
pub(super) const ALL: usize = FRAME + NUM_LIMBS;
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
    /// `p = s [I2 0] R X + t`.
    Weak,
    /// `p = f (Y_x, Y_y) / Y_z + c`, `Y = R X + T`.
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
}

/// A frame's unknowns.
#[derive(Clone, Debug)]
pub(super) struct FrameState {
    /// Body frame to camera.
    pub(super) rotation: Matrix3<f64>,
    /// `(log s, t_u, t_v)` for weak perspective, `T` for perspective.
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
}

/// Depths in front of a perspective camera must exceed this (metres).
const MIN_DEPTH: f64 = 1e-3;

/// One sparse row of the Jacobian: parameter indices and values.
struct Row {
    index: [usize; 18],
    value: [f64; 18],
    n: usize,
}

impl Row {
    fn new() -> Row {
        Row {
            index: [0; 18],
            value: [0.0; 18],
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

    /// Where the camera sees the body-frame point `x`, and the derivative of that image point
    /// with respect to the camera-frame point `R x`; `None` behind a perspective camera.
    fn see(
        &self,
        projection: Projection,
        x: &Vector3<f64>,
    ) -> Option<(Vector2<f64>, Matrix2x3<f64>)> {
        let y = self.rotation * x;
        match projection {
            Projection::Weak => {
                let s = self.camera[0].exp();
                let p = Vector2::new(s * y.x + self.camera[1], s * y.y + self.camera[2]);
                Some((p, Matrix2x3::new(s, 0.0, 0.0, 0.0, s, 0.0)))
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

    /// The image points of the body-frame `points`; `None` behind a perspective camera.
    pub(super) fn project(
        &self,
        projection: Projection,
        points: &[Vector3<f64>; NUM_LANDMARKS],
    ) -> Option<[[f64; 2]; NUM_LANDMARKS]> {
        let mut out = [[0.0; 2]; NUM_LANDMARKS];
        for (o, x) in out.iter_mut().zip(points) {
            let (p, _) = self.see(projection, x)?;
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
        if matches!(projection, Projection::Weak) {
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

/// The cost of `state` (half the sum of squared weighted residuals, Huber on the image) for
/// the bone `lengths`, with the camera-oriented bone directions `target` of the smoothness;
/// with `normal`, adds
/// the Gauss-Newton normal equations there (lengths included when `free_lengths`). `None`
/// when a landmark is behind a perspective camera.
pub(super) fn evaluate(
    data: &FrameData,
    state: &FrameState,
    lengths: &[f64; NUM_LIMBS],
    target: Option<&[Vector3<f64>; NUM_LIMBS]>,
    weights: &Weights,
    mut normal: Option<(&mut Hessian, &mut Gradient)>,
    free_lengths: bool,
) -> Option<f64> {
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
        let (p, g) = state.see(data.projection, x)?;
        let u = data.observed[i];
        let e = (p - Vector2::new(u[0], u[1])) * weights.image;
        let (loss, w) = huber(e.norm(), weights.huber);
        cost += loss;
        let Some((h, grad)) = normal.as_mut() else {
            continue;
        };
        let q = g * state.rotation * (weights.image * w.sqrt());
        let (chain, n) = chains[i];
        for row in 0..2 {
            let mut r = Row::new();
            let qr = q.row(row).transpose();
            for a in 0..3 {
                r.push(a, qr.dot(&Vector3::ith(a, 1.0).cross(x)));
            }
            match data.projection {
                Projection::Weak => {
                    let s = state.camera[0].exp();
                    let y = state.rotation * x;
                    r.push(CAM, s * y[row] * weights.image * w.sqrt());
                    r.push(CAM + 1 + row, weights.image * w.sqrt());
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
                if free_lengths {
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
    if let (Some(target), true) = (target, weights.smooth > 0.0) {
        for (b, d) in state.directions.iter().enumerate() {
            let e = (state.rotation * d - target[b]) * weights.smooth;
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
                    r.push(a, turn[row] * weights.smooth);
                }
                for (k, bend) in bends.iter().enumerate() {
                    r.push(DIR + 2 * b + k, bend[row] * weights.smooth);
                }
                r.accumulate(h, grad, e[row]);
            }
        }
    }
    Some(cost)
}
