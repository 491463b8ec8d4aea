//! The kernel of every prediction: a linear map of one feature row, `out_k = c_k + sum_j
//! V[j][k] x_j` (the logits of [`LogisticModel`](crate::LogisticModel), the outputs of
//! [`RidgeModel`](crate::RidgeModel), the whitened components of
//! [`QuadraticExpansion`](crate::QuadraticExpansion)).
//!
//! The outputs are taken in groups of up to [`MAX_GROUP`], and the features in blocks of
//! [`BLOCK`] (the last one padded with zeros). Per group the weights are packed block by
//! block, each block holding every output's [`BLOCK`] weights in turn, so that the kernel
//! reads them as one stream: per block of the row, one vector of features times one vector
//! of weights per output, added to that output's vector of partial sums. The partial sums
//! are added across their lanes at the end. A group of few outputs deals the blocks
//! round-robin to several sets of partial sums, so that the additions do not wait on each
//! other; the sets are added in a fixed order. Compared with a broadcast of each feature
//! against the outputs' weights, this needs a fifth fewer loads for 12 outputs and half as
//! many for 3 (the viewpoint heads: 170 -> 105 ns per head on the default model's 519
//! features); loads, not multiply-adds, bound this kernel.
//!
//! One implementation of the arithmetic on `pulp`'s SIMD vectors (safe code, as the Newton
//! solver's blocked products), instantiated for the instruction set found at run time: on
//! x86_64 CPUs with AVX2 and FMA (with or without AVX-512), fused multiply-adds on 256-bit
//! vectors; elsewhere one value at a time with a separate multiply and add. The two agree up to rounding; on one
//! machine every caller (one row or a batch, training or prediction) runs the same one, so
//! that results are reproducible there.

use pulp::{Simd, WithSimd};

/// Features per block: the `f64` lanes of a 256-bit vector.
const BLOCK: usize = 4;

/// Most outputs per group: 12 vectors of partial sums, a vector of features and a spare
/// fit the 16 vector registers of AVX2.
const MAX_GROUP: usize = 12;

/// A linear map `out_k = c_k + sum_j V[j][k] x_j` of `n_features` inputs, its weights packed
/// for the kernel (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct PackedLinear {
    /// Per group of outputs ([`group_sizes`]), per block of features, per output of the
    /// group, the [`BLOCK`] weights of the block's features (0 past the last feature).
    weights: Vec<f64>,
    /// `c_k`, one per output.
    biases: Vec<f64>,
}

impl PackedLinear {
    /// Packs the map with weight `weight(j, k)` of input `j` for output `k` (`j <
    /// n_features`, `k < biases.len()`) and biases `biases`.
    pub(crate) fn pack(
        n_features: usize,
        weight: impl Fn(usize, usize) -> f64,
        biases: Vec<f64>,
    ) -> Self {
        let blocks = n_features.div_ceil(BLOCK);
        let mut weights = Vec::with_capacity(blocks * BLOCK * biases.len());
        let mut first = 0;
        for size in group_sizes(biases.len()) {
            for block in 0..blocks {
                for k in first..first + size {
                    weights.extend(
                        (block * BLOCK..(block + 1) * BLOCK)
                            .map(|j| if j < n_features { weight(j, k) } else { 0.0 }),
                    );
                }
            }
            first += size;
        }
        Self { weights, biases }
    }

    /// Writes the outputs for the row `x` into `out` (one per output). The caller checks
    /// that `x` has the map's input count; a shorter `out` receives the leading outputs.
    #[inline]
    pub(crate) fn apply_into(&self, x: &[f64], out: &mut [f64]) {
        dispatch(Apply { map: self, x, out });
    }

    /// The map, with the instruction set of `simd`.
    #[inline(always)]
    fn apply<S: Simd>(&self, simd: S, x: &[f64], out: &mut [f64]) {
        // Weights per output of a group: every block, the last one padded.
        let per_output = x.len().div_ceil(BLOCK) * BLOCK;
        let full = x.len() - x.len() % BLOCK;
        let (x, rest) = x.split_at(full);
        let mut last = [0.0; BLOCK];
        last[..rest.len()].copy_from_slice(rest);
        let row = Row {
            full: x,
            last: (!rest.is_empty()).then_some(&last),
        };
        let m = self.biases.len().min(out.len());
        let mut weights = self.weights.as_slice();
        let mut first = 0;
        for size in group_sizes(self.biases.len()) {
            if first >= m {
                break;
            }
            let (panel, tail) = weights.split_at(per_output * size);
            weights = tail;
            let end = (first + size).min(m);
            let (out, biases) = (&mut out[first..end], &self.biases[first..end]);
            match size {
                MAX_GROUP => group_into::<S, MAX_GROUP, 1>(simd, row, panel, biases, out),
                8 => group_into::<S, 8, 1>(simd, row, panel, biases, out),
                4 => group_into::<S, 4, 2>(simd, row, panel, biases, out),
                3 => group_into::<S, 3, 4>(simd, row, panel, biases, out),
                2 => group_into::<S, 2, 4>(simd, row, panel, biases, out),
                _ => group_into::<S, 1, 8>(simd, row, panel, biases, out),
            }
            first += size;
        }
    }
}

/// Runs `op` on 256-bit vectors with fused multiply-adds where the CPU has AVX2 and FMA
/// (also when it has AVX-512: [`BLOCK`] and [`MAX_GROUP`] are sized for AVX2, and loads, not
/// the vector width, bound the kernel), else one value at a time.
#[cfg(target_arch = "x86_64")]
fn dispatch<Op: WithSimd>(op: Op) -> Op::Output {
    match pulp::x86::V3::try_new() {
        Some(simd) => Simd::vectorize(simd, op),
        None => Simd::vectorize(pulp::Scalar::new(), op),
    }
}

/// Runs `op` with the instruction set `pulp` finds at run time (vectors of at most
/// [`BLOCK`] lanes on these architectures).
#[cfg(not(target_arch = "x86_64"))]
fn dispatch<Op: WithSimd>(op: Op) -> Op::Output {
    pulp::Arch::new().dispatch(op)
}

/// One [`PackedLinear::apply_into`], run with the instruction set [`dispatch`] chose.
struct Apply<'a> {
    map: &'a PackedLinear,
    x: &'a [f64],
    out: &'a mut [f64],
}

impl WithSimd for Apply<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        self.map.apply(simd, self.x, self.out);
    }
}

/// A feature row in blocks: the whole blocks, and the last, partial one padded with zeros.
#[derive(Clone, Copy)]
struct Row<'a> {
    full: &'a [f64],
    last: Option<&'a [f64; BLOCK]>,
}

/// The sizes of the groups of `m` outputs, in order: [`MAX_GROUP`] while that many remain,
/// then 8, 4, 3, 2 or 1 (the largest that fits) until none remain.
fn group_sizes(m: usize) -> impl Iterator<Item = usize> {
    let mut left = m;
    std::iter::from_fn(move || {
        let size = [MAX_GROUP, 8, 4, 3, 2, 1]
            .into_iter()
            .find(|&size| size <= left)?;
        left -= size;
        Some(size)
    })
}

/// One group of `G` outputs: `out_o = biases_o + sum_j V[j][o] x_j`, the blocks of the row
/// dealt to `SETS` sets of partial sums (block `b` to set `b mod SETS`), the sets added in
/// order, then the lanes. `out` and `biases` may be shorter than `G`.
#[inline(always)]
fn group_into<S: Simd, const G: usize, const SETS: usize>(
    simd: S,
    row: Row<'_>,
    panel: &[f64],
    biases: &[f64],
    out: &mut [f64],
) {
    let zero = simd.splat_f64s(0.0);
    let mut sums = [[zero; G]; SETS];
    let blocks = row.full.chunks_exact(SETS * BLOCK);
    let (whole, rest) = panel.split_at(blocks.len() * SETS * G * BLOCK);
    for (xs, ws) in blocks.clone().zip(whole.chunks_exact(SETS * G * BLOCK)) {
        for ((sum, x), w) in sums
            .iter_mut()
            .zip(xs.chunks_exact(BLOCK))
            .zip(ws.chunks_exact(G * BLOCK))
        {
            add_block(simd, sum, x, w);
        }
    }
    let last = row.last.map(|last| &last[..]);
    for ((sum, x), w) in sums
        .iter_mut()
        .zip(blocks.remainder().chunks_exact(BLOCK).chain(last))
        .zip(rest.chunks_exact(G * BLOCK))
    {
        add_block(simd, sum, x, w);
    }
    for (o, (out, &c)) in out.iter_mut().zip(biases).enumerate() {
        let total = sums[1..]
            .iter()
            .fold(sums[0][o], |t, sum| simd.add_f64s(t, sum[o]));
        *out = c + simd.reduce_sum_f64s(total);
    }
}

/// `sums_o += x w_o` lane by lane, for the features `x` of one block and each output's
/// weights `w_o` for them (`w` holds them in turn): fused where the instruction set has it,
/// else a multiply and an add.
#[inline(always)]
fn add_block<S: Simd, const G: usize>(simd: S, sums: &mut [S::f64s; G], x: &[f64], w: &[f64]) {
    let x = S::as_simd_f64s(x).0;
    for (sum, w) in sums.iter_mut().zip(w.chunks_exact(BLOCK)) {
        for (&w, &x) in S::as_simd_f64s(w).0.iter().zip(x) {
            *sum = simd.mul_add_e_f64s(w, x, *sum);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every group shape (sizes 12, 8, 4, 3, 2 and 1, several sets of partial sums), whole
    /// and partial blocks of features and a shorter output give the direct sums, with the
    /// instruction set found at run time and one value at a time.
    #[test]
    fn packed_map_equals_the_direct_sums() {
        for d in [1usize, 2, 3, 4, 5, 7, 8, 9, 17, 33, 54] {
            for m in [1usize, 2, 3, 4, 5, 7, 8, 11, 12, 13, 20, 30, 36] {
                let weight = |j: usize, k: usize| ((j * 7 + k * 3) % 11) as f64 - 5.0;
                let biases: Vec<f64> = (0..m).map(|k| k as f64 * 0.5).collect();
                let x: Vec<f64> = (0..d).map(|j| (j % 5) as f64 * 0.25 - 0.5).collect();
                let map = PackedLinear::pack(d, weight, biases.clone());
                let direct: Vec<f64> = (0..m)
                    .map(|k| biases[k] + (0..d).map(|j| weight(j, k) * x[j]).sum::<f64>())
                    .collect();
                // Small integers times quarters: every order of the sums is exact.
                let mut out = vec![f64::NAN; m];
                map.apply_into(&x, &mut out);
                assert_eq!(out, direct, "d {d}, m {m}");
                let mut scalar = vec![f64::NAN; m];
                map.apply(pulp::Scalar::new(), &x, &mut scalar);
                assert_eq!(scalar, direct, "d {d}, m {m} (one value at a time)");
                let mut leading = vec![f64::NAN; m.div_ceil(2)];
                map.apply_into(&x, &mut leading);
                assert_eq!(leading, direct[..leading.len()], "d {d}, m {m} (leading)");
            }
        }
    }
}
