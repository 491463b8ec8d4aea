//! Assembly of the packed Hessian blocks `W^T U` (see the [`newton`](crate::newton) module
//! docs for the derivation) as cache-sized GEMMs on all cores.
//!
//! The rows (samples) are split into a fixed number of tasks, each owning a `Q x T`
//! accumulator; rayon schedules the tasks dynamically (a core slowed down by another
//! process does not hold the others back), and the accumulators are summed in task order,
//! so the result does not depend on the schedule: fits are bit-for-bit reproducible for a
//! given number of rayon threads (which fixes the number of tasks). The
//! chunk buffers (`U` and `W` for one chunk of rows) are per running task, taken from a
//! pool allocated once per fit.

use std::sync::{Mutex, MutexGuard, PoisonError};

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use rayon::prelude::*;

use crate::Mode;
use crate::softmax::sigmoid_curvature;

/// Rows per chunk: `U` is this many rows by `D(D+1)/2` (about 5.8 MB at the paper's size,
/// L3-resident) and every chunk is one GEMM with this inner dimension. Measured best among
/// 128..1024 on a 2-core AVX2 machine.
const CHUNK_ROWS: usize = 256;
/// Tasks per rayon thread: enough for dynamic load balancing, few enough that the
/// per-task accumulators stay small.
const TASKS_PER_THREAD: usize = 4;
/// Sample weights below this are treated as 0. It keeps subnormal numbers, which are about
/// a hundred times slower, out of the GEMM; the dropped contributions are at most
/// `1e-250 x_a x_b`, far below the rounding of any Hessian entry of a problem with
/// `lambda > 0` or a class that has samples.
const WEIGHT_FLOOR: f64 = 1e-250;

/// Chunk buffers of one running task.
#[derive(Debug)]
struct Scratch {
    /// `chunk x T` column-major products `x_ia x_ib`, `a <= b`.
    products: Vec<f64>,
    /// `chunk x Q` column-major sample weights.
    weights: Vec<f64>,
}

/// A contiguous range of rows and its partial sum of the packed blocks.
#[derive(Debug)]
struct Task {
    first_row: usize,
    end_row: usize,
    /// `Q x T` column-major.
    accumulator: Vec<f64>,
}

/// What the packed blocks are made of.
#[derive(Debug)]
pub(crate) struct PackedHessian {
    /// Class pairs `(j, l)` of the weight columns: `j < l` with weight `p_j p_l`
    /// (multinomial), or `(j, j)` with weight `sigma(z_j)(1 - sigma(z_j))` (one-vs-rest).
    pub(crate) class_pairs: Vec<(usize, usize)>,
    /// Feature pairs `(a, b)`, `a <= b`, of the product columns.
    pub(crate) feature_pairs: Vec<(usize, usize)>,
    tasks: Vec<Task>,
    scratch: Vec<Mutex<Scratch>>,
    /// `Q x T` column-major sum of the tasks' accumulators: entry `(q, t)` is
    /// `sum_i w_iq x_ia x_ib` for class pair `q` and feature pair `t = (a, b)`.
    pub(crate) packed: Vec<f64>,
}

/// Locks a free scratch buffer set (or waits for one if more tasks run at once than there
/// are sets, e.g. inside a larger thread pool). The buffers carry no state between chunks,
/// so a poisoned lock is simply taken over.
fn take_scratch(pool: &[Mutex<Scratch>]) -> Option<MutexGuard<'_, Scratch>> {
    pool.iter().find_map(|m| m.try_lock().ok()).or_else(|| {
        pool.first()
            .map(|m| m.lock().unwrap_or_else(PoisonError::into_inner))
    })
}

/// `sum_i a_i b_i` with four interleaved partial sums (so that it vectorises), in a fixed
/// order (so that results are reproducible).
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut lanes = [0.0; 4];
    let (a4, a_rest) = a.split_at(a.len() - a.len() % 4);
    let (b4, b_rest) = b.split_at(a4.len().min(b.len()));
    for (ca, cb) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        for ((l, &va), &vb) in lanes.iter_mut().zip(ca).zip(cb) {
            *l += va * vb;
        }
    }
    let tail: f64 = a_rest.iter().zip(b_rest).map(|(va, vb)| va * vb).sum();
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

/// Weight of class pair `(j, l)` for one sample whose `K` probabilities (multinomial) or
/// logits (one-vs-rest) are `s`; below [`WEIGHT_FLOOR`] it is 0.
#[inline]
fn sample_weight(mode: Mode, s: &[f64], j: usize, l: usize) -> f64 {
    let v = match mode {
        Mode::Multinomial => s[j] * s[l],
        Mode::OneVsRest => sigmoid_curvature(s[j]),
    };
    if v < WEIGHT_FLOOR { 0.0 } else { v }
}

impl PackedHessian {
    /// Buffers for `n` samples, `dim = d + 1` design columns and `k` classes.
    pub(crate) fn new(n: usize, dim: usize, k: usize, mode: Mode) -> Self {
        let class_pairs: Vec<(usize, usize)> = match mode {
            Mode::Multinomial => (0..k)
                .flat_map(|j| (j + 1..k).map(move |l| (j, l)))
                .collect(),
            Mode::OneVsRest => (0..k).map(|j| (j, j)).collect(),
        };
        let feature_pairs: Vec<(usize, usize)> = (0..dim)
            .flat_map(|a| (a..dim).map(move |b| (a, b)))
            .collect();
        let q = class_pairs.len();
        let t = feature_pairs.len();
        let threads = rayon::current_num_threads().max(1);
        let n_tasks = (threads * TASKS_PER_THREAD).clamp(1, n.div_ceil(CHUNK_ROWS).max(1));
        let rows_per_task = n.div_ceil(n_tasks);
        let chunk = CHUNK_ROWS.min(rows_per_task);
        let tasks = (0..n_tasks)
            .map(|i| Task {
                first_row: (i * rows_per_task).min(n),
                end_row: ((i + 1) * rows_per_task).min(n),
                accumulator: vec![0.0; q * t],
            })
            .collect();
        let scratch = (0..threads.min(n_tasks))
            .map(|_| {
                Mutex::new(Scratch {
                    products: vec![0.0; chunk * t],
                    weights: vec![0.0; chunk * q],
                })
            })
            .collect();
        Self {
            class_pairs,
            feature_pairs,
            tasks,
            scratch,
            packed: vec![0.0; q * t],
        }
    }

    /// Floating-point operations of one [`accumulate`](Self::accumulate): `2 n T Q`.
    pub(crate) fn flops(&self, n: usize) -> f64 {
        2.0 * n as f64 * self.feature_pairs.len() as f64 * self.class_pairs.len() as f64
    }

    /// Recomputes [`packed`](Self::packed) when every sample has the same weights
    /// (all feature weights zero, so that the logits do not depend on the sample):
    /// `G_q = w_q X^T X`, one packed Gram matrix (`n T` multiply-adds) instead of `Q`
    /// weighted ones. `shared` holds the `K` probabilities (multinomial) or logits
    /// (one-vs-rest) common to all samples.
    pub(crate) fn accumulate_uniform(&mut self, x: &[f64], n: usize, mode: Mode, shared: &[f64]) {
        let feature_pairs = &self.feature_pairs;
        let dim = feature_pairs.last().map_or(0, |&(_, b)| b + 1);
        // Per task: its rows' Gram matrix (one GEMM), packed into the first T entries of its
        // accumulator.
        self.tasks.par_iter_mut().for_each(|task| {
            let rows = task.end_row - task.first_row;
            let mut gram = faer::Mat::<f64>::zeros(dim, dim);
            if rows > 0 {
                let block =
                    MatRef::from_column_major_slice_with_stride(&x[task.first_row..], rows, dim, n);
                matmul(
                    gram.as_mut(),
                    Accum::Replace,
                    block.transpose(),
                    block,
                    1.0,
                    Par::Seq,
                );
            }
            for (g, &(a, b)) in task.accumulator.iter_mut().zip(feature_pairs) {
                *g = gram[(a, b)];
            }
        });
        let q = self.class_pairs.len();
        for (ti, column) in self.packed.chunks_exact_mut(q.max(1)).enumerate() {
            let gram: f64 = self
                .tasks
                .iter()
                .filter_map(|task| task.accumulator.get(ti))
                .sum();
            for (v, &(j, l)) in column.iter_mut().zip(&self.class_pairs) {
                *v = sample_weight(mode, shared, j, l) * gram;
            }
        }
    }

    /// Recomputes [`packed`](Self::packed) from the `n x D` column-major design matrix `x`
    /// and the `K x n` probabilities (multinomial) or logits (one-vs-rest).
    pub(crate) fn accumulate(
        &mut self,
        x: &[f64],
        n: usize,
        k: usize,
        mode: Mode,
        per_sample: &[f64],
    ) {
        let class_pairs = &self.class_pairs;
        let feature_pairs = &self.feature_pairs;
        let q = class_pairs.len();
        let t = feature_pairs.len();
        let pool = &self.scratch;
        self.tasks.par_iter_mut().for_each(|task| {
            task.accumulator.fill(0.0);
            // The pool is never empty (`new` creates at least one set).
            let Some(mut scratch) = take_scratch(pool) else {
                return;
            };
            let Scratch { products, weights } = &mut *scratch;
            let chunk = weights.len() / q.max(1);
            let mut start = task.first_row;
            while start < task.end_row && chunk > 0 {
                let rows = chunk.min(task.end_row - start);
                let weights = &mut weights[..rows * q];
                let samples = &per_sample[start * k..(start + rows) * k];
                for (column, &(j, l)) in weights.chunks_exact_mut(rows).zip(class_pairs) {
                    for (w, s) in column.iter_mut().zip(samples.chunks_exact(k)) {
                        *w = sample_weight(mode, s, j, l);
                    }
                }
                let products = &mut products[..rows * t];
                for (column, &(a, b)) in products.chunks_exact_mut(rows).zip(feature_pairs) {
                    let xa = &x[a * n + start..a * n + start + rows];
                    let xb = &x[b * n + start..b * n + start + rows];
                    for ((u, &va), &vb) in column.iter_mut().zip(xa).zip(xb) {
                        *u = va * vb;
                    }
                }
                matmul(
                    MatMut::from_column_major_slice_mut(&mut task.accumulator, q, t),
                    Accum::Add,
                    MatRef::from_column_major_slice(weights, rows, q).transpose(),
                    MatRef::from_column_major_slice(products, rows, t),
                    1.0,
                    Par::Seq,
                );
                start += rows;
            }
        });
        self.packed.fill(0.0);
        for task in &self.tasks {
            for (s, &v) in self.packed.iter_mut().zip(&task.accumulator) {
                *s += v;
            }
        }
    }
}
