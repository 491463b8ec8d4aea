//! Small dense kernels on column-major `n x n` matrices held in slices (entry `(i, j)` at
//! `i + j n`; nalgebra's storage order), for the small systems solved many times per pose
//! (the pursuit's coefficient steps, the refinement's frame blocks): no allocation, no
//! generic dispatch.

/// Factorises the symmetric `a` (its lower triangle is read) in place into its lower
/// Cholesky factor `L` (`a = L L^T`; the strict upper triangle is left as it was). `false`
/// when `a` is not numerically positive definite (a pivot not positive, or not finite).
///
/// Left-looking by columns: column `j` is updated by the columns before it in order, each
/// update a contiguous `axpy`, so that entry `(i, j)` is `a_ij - sum_k L_ik L_jk` summed in
/// increasing `k`.
pub(crate) fn cholesky_in_place(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let (done, rest) = a.split_at_mut(j * n);
        let column = &mut rest[j..n];
        for k in 0..j {
            let previous = &done[k * n + j..(k + 1) * n];
            let l_jk = previous[0];
            for (x, l_ik) in column.iter_mut().zip(previous) {
                *x -= l_ik * l_jk;
            }
        }
        let pivot = column[0];
        if !(pivot > 0.0 && pivot.is_finite()) {
            return false;
        }
        let d = pivot.sqrt();
        column[0] = d;
        for x in &mut column[1..] {
            *x /= d;
        }
    }
    true
}

/// Solves `L x = b` in place (`x` holds `b` on entry, `n` entries), `L` the lower triangle of
/// `l`.
pub(crate) fn forward_solve(l: &[f64], n: usize, x: &mut [f64]) {
    for j in 0..n {
        let column = &l[j * n + j..(j + 1) * n];
        let (head, tail) = x[j..n].split_at_mut(1);
        head[0] /= column[0];
        let x_j = head[0];
        for (x_i, l_ij) in tail.iter_mut().zip(&column[1..]) {
            *x_i -= l_ij * x_j;
        }
    }
}

/// Solves `L^T x = b` in place (`x` holds `b` on entry, `n` entries), `L` the lower triangle
/// of `l`.
pub(crate) fn transposed_back_solve(l: &[f64], n: usize, x: &mut [f64]) {
    for j in (0..n).rev() {
        let column = &l[j * n + j..(j + 1) * n];
        let below: f64 = x[j + 1..n]
            .iter()
            .zip(&column[1..])
            .map(|(x_i, l_ij)| l_ij * x_i)
            .sum();
        x[j] = (x[j] - below) / column[0];
    }
}

/// The sum of squares of `x`.
pub(crate) fn norm_squared(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    #[test]
    fn kernels_match_nalgebra() {
        let n = 5;
        let m = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3) % 11) as f64 * 0.1 - 0.4);
        let a = &m * m.transpose() + DMatrix::identity(n, n) * 0.3;
        let mut factor = a.as_slice().to_vec();
        assert!(cholesky_in_place(&mut factor, n));
        let l = a.clone().cholesky().unwrap().unpack();
        for j in 0..n {
            for i in j..n {
                assert!((factor[i + j * n] - l[(i, j)]).abs() < 1e-12);
            }
        }
        let b = DVector::from_fn(n, |i, _| i as f64 - 1.5);
        let mut x = b.as_slice().to_vec();
        forward_solve(&factor, n, &mut x);
        transposed_back_solve(&factor, n, &mut x);
        let expected = a.clone().cholesky().unwrap().solve(&b);
        assert!(
            x.iter()
                .zip(expected.iter())
                .all(|(p, q)| (p - q).abs() < 1e-12)
        );
        let mut not_pd = (-a).as_slice().to_vec();
        assert!(!cholesky_in_place(&mut not_pd, n));
    }
}
