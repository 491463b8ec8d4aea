//! The second-order part of [`Descriptor::JointsQuadratic`](crate::Descriptor::JointsQuadratic):
//! products of pairs of the joints descriptor's joint coordinates.
//!
//! A linear classifier on these products is a quadratic function of the 2D joint positions
//! (in the mid-hip / mid-shoulder frame): it can weigh, say, the foreshortening of a limb
//! against the width of the shoulders, which a linear function of the coordinates cannot.

/// Number of products of `n` values taken in pairs with repetition (`i <= j`).
pub const fn pair_count(n: usize) -> usize {
    n * (n + 1) / 2
}

/// Writes `values[i] * values[j]` for every `i <= j` (row by row: `(0,0), (0,1), ...,
/// (1,1), ...`) into `out` (length [`pair_count`]`(values.len())`). When `undefined` is given
/// (one flag per value, one per product), a product is flagged when either factor is.
pub fn pairwise_products(
    values: &[f64],
    out: &mut [f64],
    undefined: Option<(&[bool], &mut [bool])>,
) {
    let mut k = 0;
    for (i, &a) in values.iter().enumerate() {
        for &b in &values[i..] {
            if let Some(o) = out.get_mut(k) {
                *o = a * b;
            }
            k += 1;
        }
    }
    if let Some((given, flags)) = undefined {
        let mut k = 0;
        for i in 0..values.len() {
            for j in i..values.len() {
                if let Some(f) = flags.get_mut(k) {
                    *f = given.get(i).copied().unwrap_or(false)
                        || given.get(j).copied().unwrap_or(false);
                }
                k += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_in_order_with_flags() {
        let mut out = [0.0; 6];
        let mut flags = [false; 6];
        pairwise_products(
            &[1.0, 2.0, 3.0],
            &mut out,
            Some((&[false, true, false], &mut flags)),
        );
        assert_eq!(out, [1.0, 2.0, 3.0, 4.0, 6.0, 9.0]);
        assert_eq!(flags, [false, true, false, true, true, false]);
        assert_eq!(pair_count(24), 300);
    }
}
