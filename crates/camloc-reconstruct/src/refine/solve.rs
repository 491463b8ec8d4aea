//! Levenberg-Marquardt over the frames of one person with shared bone lengths and camera
//! distance: each frame's parameters are eliminated (Schur complement), the shared ones (14
//! log lengths, the inverse distance) solved, the frames' steps recovered. A frame's normal equations are kept between the two passes for short
//! problems and made again for long ones, so that memory does not grow with the frames.

use camloc_skeleton::NUM_LIMBS;
use nalgebra::{SMatrix, SVector, Vector3};
use rayon::prelude::*;

use super::problem::{
    FRAME, FrameData, FrameState, Free, Gradient, Hessian, SHARED, Shared, Weights, evaluate,
};
use crate::dense::{cholesky_in_place, forward_solve, transposed_back_solve};
use crate::length_prior::LimbMatrix;

/// Frames whose normal equations are kept between the two passes of a step.
const KEPT_FRAMES: usize = 64;

/// Frames below which the frames are processed on one thread.
const PARALLEL_FRAMES: usize = 16;

/// Frames whose reduced systems are made at once (in parallel) before they are summed.
const SCHUR_CHUNK: usize = 1024;

/// Initial, smallest and largest Marquardt damping.
const DAMPING: (f64, f64, f64) = (1e-3, 1e-9, 1e8);

/// The prior on the shared log lengths when they are unknowns: `|W (l - mean)|^2 / 2`.
pub(super) struct LengthUnknowns<'a> {
    pub(super) whitening: &'a LimbMatrix,
    pub(super) mean_log: [f64; NUM_LIMBS],
}

/// The prior on the shared inverse distance (1/m) when it is an unknown:
/// `((kappa - mean) weight)^2 / 2`.
pub(super) struct KappaUnknown {
    /// The prior's mean, 1/m.
    pub(super) mean: f64,
    /// 1 / the deviation (m).
    pub(super) weight: f64,
}

/// The shared unknowns as the solver moves them.
#[derive(Clone, Copy, Debug)]
pub(super) struct SharedState {
    /// Log bone lengths (log metres).
    pub(super) log_lengths: [f64; NUM_LIMBS],
    /// The weak-perspective camera's inverse distance (1/m, >= 0).
    pub(super) kappa: f64,
}

impl SharedState {
    /// The lengths in metres and the inverse distance.
    pub(super) fn shared(&self) -> Shared {
        Shared {
            lengths: self.log_lengths.map(f64::exp),
            kappa: self.kappa,
        }
    }
}

/// What the solver works on.
pub(super) struct Problem<'a> {
    pub(super) frames: &'a [FrameData],
    pub(super) weights: Weights,
    /// `None`: the lengths are given and stay.
    pub(super) lengths: Option<LengthUnknowns<'a>>,
    /// `None`: the inverse distance stays.
    pub(super) kappa: Option<KappaUnknown>,
    /// Most Levenberg-Marquardt steps.
    pub(super) iterations: usize,
    /// Sequences: frames on each side whose mean bone directions a frame's smoothness holds
    /// it to (at least 1; [`FrameRate::step`](crate::FrameRate::step)).
    pub(super) smoothing_frames: usize,
}

/// One frame's damped normal equations `[A B; B^T D]`, `g`, with the frame's block
/// factorised, `A + damping = L L^T`, and the lengths' coupling reduced by it: `L^-1 B` and
/// `L^-1 g_frame`, so that the frame drops out as `D - (L^-1 B)^T (L^-1 B)` (the Schur
/// complement) and its step is `-L^-T (L^-1 g_frame + L^-1 B dl)`.
struct Eliminated {
    /// `L` in the lower triangle.
    factor: SMatrix<f64, FRAME, FRAME>,
    reduced_b: SMatrix<f64, FRAME, SHARED>,
    reduced_g: SVector<f64, FRAME>,
    d: SMatrix<f64, SHARED, SHARED>,
    g_shared: SVector<f64, SHARED>,
}

impl Problem<'_> {
    fn free(&self) -> Free {
        Free {
            lengths: self.lengths.is_some(),
            kappa: self.kappa.is_some(),
        }
    }

    /// Each frame's smoothness target: the mean camera-oriented bone directions of the
    /// [`smoothing_frames`](Self::smoothing_frames) frames before and after it.
    fn targets(&self, states: &[FrameState]) -> Option<Vec<[Vector3<f64>; NUM_LIMBS]>> {
        if !(self.weights.smooth > 0.0) || states.len() < 2 {
            return None;
        }
        let seen: Vec<_> = states.iter().map(FrameState::camera_directions).collect();
        let side = self.smoothing_frames;
        Some(
            (0..states.len())
                .map(|t| {
                    let neighbours: Vec<&[Vector3<f64>; NUM_LIMBS]> = (t.saturating_sub(side)
                        ..=t + side)
                        .filter(|&n| n != t)
                        .filter_map(|n| seen.get(n))
                        .collect();
                    let k = neighbours.len() as f64;
                    std::array::from_fn(|i| {
                        neighbours.iter().map(|p| p[i]).sum::<Vector3<f64>>() / k
                    })
                })
                .collect(),
        )
    }

    /// The cost of the frames (none behind a camera) plus the priors on the shared
    /// unknowns.
    fn cost(
        &self,
        states: &[FrameState],
        shared: &SharedState,
        targets: Option<&[[Vector3<f64>; NUM_LIMBS]]>,
    ) -> f64 {
        let metres = shared.shared();
        let one = |t: usize| {
            evaluate(
                &self.frames[t],
                &states[t],
                &metres,
                targets.map(|all| &all[t]),
                &self.weights,
                None,
                Free {
                    lengths: false,
                    kappa: false,
                },
            )
            .unwrap_or(f64::INFINITY)
        };
        // Frames evaluated in parallel but summed in order, so that the cost (and the
        // minimisation that compares costs) does not depend on the thread schedule.
        let frames: f64 = if states.len() < PARALLEL_FRAMES {
            (0..states.len()).map(one).sum()
        } else {
            let costs: Vec<f64> = (0..states.len()).into_par_iter().map(one).collect();
            costs.iter().sum()
        };
        frames + self.prior_cost(shared)
    }

    fn prior_cost(&self, shared: &SharedState) -> f64 {
        let lengths = self.lengths.as_ref().map_or(0.0, |u| {
            let r = u.whitening
                * SVector::<f64, NUM_LIMBS>::from_fn(|b, _| shared.log_lengths[b] - u.mean_log[b]);
            0.5 * r.norm_squared()
        });
        let kappa = self
            .kappa
            .as_ref()
            .map_or(0.0, |k| 0.5 * ((shared.kappa - k.mean) * k.weight).powi(2));
        lengths + kappa
    }

    /// Frame `t`'s normal equations, damped by `damping` and factorised; `None` when the
    /// frame cannot be linearised or factorised.
    fn eliminate(
        &self,
        t: usize,
        state: &FrameState,
        shared: &Shared,
        target: Option<&[Vector3<f64>; NUM_LIMBS]>,
        damping: f64,
    ) -> Option<Eliminated> {
        let mut h = Hessian::zeros();
        let mut g = Gradient::zeros();
        evaluate(
            &self.frames[t],
            state,
            shared,
            target,
            &self.weights,
            Some((&mut h, &mut g)),
            self.free(),
        )?;
        let mut a = h.fixed_view::<FRAME, FRAME>(0, 0).into_owned();
        for i in 0..FRAME {
            a[(i, i)] += damping * (a[(i, i)] + 1e-9);
        }
        if !cholesky_in_place(a.as_mut_slice(), FRAME) {
            return None;
        }
        let mut reduced_b = SMatrix::<f64, FRAME, SHARED>::zeros();
        let free = self.free();
        if free.lengths || free.kappa {
            reduced_b.copy_from(&h.fixed_view::<FRAME, SHARED>(0, FRAME));
            for column in reduced_b.as_mut_slice().chunks_exact_mut(FRAME) {
                forward_solve(a.as_slice(), FRAME, column);
            }
        }
        let mut reduced_g = g.fixed_rows::<FRAME>(0).into_owned();
        forward_solve(a.as_slice(), FRAME, reduced_g.as_mut_slice());
        Some(Eliminated {
            factor: a,
            reduced_b,
            reduced_g,
            d: h.fixed_view::<SHARED, SHARED>(FRAME, FRAME).into_owned(),
            g_shared: g.fixed_rows::<SHARED>(FRAME).into_owned(),
        })
    }

    /// One damped Gauss-Newton step from `states`, `shared`: the trial states and shared
    /// unknowns, `None` when a system cannot be solved.
    fn step(
        &self,
        states: &[FrameState],
        shared: &SharedState,
        targets: Option<&[[Vector3<f64>; NUM_LIMBS]]>,
        damping: f64,
    ) -> Option<(Vec<FrameState>, SharedState)> {
        let metres = shared.shared();
        let eliminate =
            |t: usize| self.eliminate(t, &states[t], &metres, targets.map(|all| &all[t]), damping);
        let kept: Option<Vec<Eliminated>> = if states.len() <= KEPT_FRAMES {
            (0..states.len())
                .map(eliminate)
                .collect::<Option<Vec<_>>>()
                .map(Some)?
        } else {
            None
        };
        let free = self.free();
        let mut ds = SVector::<f64, SHARED>::zeros();
        if free.lengths || free.kappa {
            type System = (SMatrix<f64, SHARED, SHARED>, SVector<f64, SHARED>);
            let schur = |e: &Eliminated| -> System {
                (
                    e.d - e.reduced_b.tr_mul(&e.reduced_b),
                    e.g_shared - e.reduced_b.tr_mul(&e.reduced_g),
                )
            };
            let zero: System = (SMatrix::zeros(), SVector::zeros());
            let add = |a: System, b: System| -> System { (a.0 + b.0, a.1 + b.1) };
            let (mut s, mut r) = match &kept {
                Some(all) => all.iter().map(schur).fold(zero, add),
                // In chunks, summed in frame order: memory bounded by a chunk, the same sum
                // whatever the threads.
                None => {
                    let mut total = zero;
                    for first in (0..states.len()).step_by(SCHUR_CHUNK) {
                        let chunk = first..(first + SCHUR_CHUNK).min(states.len());
                        total = chunk
                            .into_par_iter()
                            .map(|t| eliminate(t).map(|e| schur(&e)))
                            .collect::<Option<Vec<_>>>()?
                            .into_iter()
                            .fold(total, add);
                    }
                    total
                }
            };
            if let Some(unknowns) = &self.lengths {
                let w = unknowns.whitening;
                let residual = w * SVector::<f64, NUM_LIMBS>::from_fn(|b, _| {
                    shared.log_lengths[b] - unknowns.mean_log[b]
                });
                let mut block = s.fixed_view_mut::<NUM_LIMBS, NUM_LIMBS>(0, 0);
                block += w.transpose() * w;
                let mut rows = r.fixed_rows_mut::<NUM_LIMBS>(0);
                rows += w.transpose() * residual;
            }
            if let Some(k) = &self.kappa {
                s[(NUM_LIMBS, NUM_LIMBS)] += k.weight * k.weight;
                r[NUM_LIMBS] += k.weight * k.weight * (shared.kappa - k.mean);
            }
            for i in 0..SHARED {
                let fixed = if i < NUM_LIMBS {
                    !free.lengths
                } else {
                    !free.kappa
                };
                if fixed {
                    // A fixed unknown: its step is 0.
                    s.row_mut(i).fill(0.0);
                    s.column_mut(i).fill(0.0);
                    s[(i, i)] = 1.0;
                    r[i] = 0.0;
                } else {
                    s[(i, i)] += damping * (s[(i, i)] + 1e-9);
                }
            }
            ds = -s.cholesky()?.solve(&r);
        }
        let move_frame = |t: usize, e: &Eliminated| -> FrameState {
            let mut step = e.reduced_g + e.reduced_b * ds;
            transposed_back_solve(e.factor.as_slice(), FRAME, step.as_mut_slice());
            states[t].stepped(self.frames[t].projection, &-step)
        };
        let trial: Vec<FrameState> = match &kept {
            Some(all) => all
                .iter()
                .enumerate()
                .map(|(t, e)| move_frame(t, e))
                .collect(),
            None => (0..states.len())
                .into_par_iter()
                .map(|t| eliminate(t).map(|e| move_frame(t, &e)))
                .collect::<Option<Vec<_>>>()?,
        };
        let trial_shared = SharedState {
            log_lengths: std::array::from_fn(|b| shared.log_lengths[b] + ds[b]),
            // A camera cannot be beyond infinity.
            kappa: (shared.kappa + ds[NUM_LIMBS]).max(0.0),
        };
        Some((trial, trial_shared))
    }

    /// Minimises the cost from `states` and `shared` (both updated in place); returns the
    /// number of steps taken.
    pub(super) fn solve(&self, states: &mut Vec<FrameState>, shared: &mut SharedState) -> usize {
        let mut damping = DAMPING.0;
        let mut steps = 0;
        for _ in 0..self.iterations {
            let targets = self.targets(states);
            let current = self.cost(states, shared, targets.as_deref());
            let mut accepted = None;
            while damping <= DAMPING.2 {
                if let Some((trial, trial_shared)) =
                    self.step(states, shared, targets.as_deref(), damping)
                {
                    let cost = self.cost(&trial, &trial_shared, targets.as_deref());
                    if cost < current {
                        accepted = Some((trial, trial_shared, cost));
                        damping = (damping / 3.0).max(DAMPING.1);
                        break;
                    }
                }
                damping *= 5.0;
            }
            let Some((trial, trial_shared, cost)) = accepted else {
                break;
            };
            *states = trial;
            *shared = trial_shared;
            steps += 1;
            if current - cost <= 1e-6 * current {
                break;
            }
        }
        steps
    }
}
