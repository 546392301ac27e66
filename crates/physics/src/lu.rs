//! A dense square solve by LU with partial pivoting for Newton's small systems
//! ([`crate::polish`]), which are mostly zeros (the program's matrix and the cones' arrows):
//! nalgebra's `LU::new` and `LU::solve`, the same floating-point operations in the same order,
//! except those whose multiplier is exactly zero, which are skipped.
//!
//! Column `i` is eliminated with the first row `p ≥ i` of largest `|a_pi|` as pivot (a column
//! of zeros is skipped): rows `i` and `p` are swapped, the column below the diagonal is
//! multiplied by `1 / a_ii`, and each later column `k` with `a_ik ≠ 0` gets
//! `a_rk ← (−a_ik)·a_ri + a_rk`. The solve applies the swaps to `b` in order, then the unit
//! lower triangle forwards and the upper one backwards (`b_i ← b_i / a_ii`, then
//! `b_r ← (−b_i)·a_ri + b_r` above it, for `b_i ≠ 0`). A skipped update adds `±0` to each entry
//! it would have touched, which leaves every entry as it was but a zero's sign; so the solution
//! is nalgebra's up to the signs of zeros (the test holds it to that, on systems with ties,
//! zero columns and singular ones).

use nalgebra::{DMatrix, DVector};

/// `x` with `a x = b`, `a` square; `None` where the upper triangle has a zero on its diagonal
/// (as nalgebra's `a.lu().solve(&b)`).
pub(crate) fn lu_solve(mut a: DMatrix<f64>, mut b: DVector<f64>) -> Option<DVector<f64>> {
    let n = a.nrows();
    assert_eq!(n, a.ncols(), "LU solve: the matrix is not square");
    assert_eq!(n, b.len(), "LU solve: mismatched right-hand side");
    // Column-major: entry (r, c) at c·n + r.
    let m = a.as_mut_slice();
    let mut swaps: Vec<(usize, usize)> = Vec::with_capacity(n);
    for i in 0..n {
        let column = &m[i * n..(i + 1) * n];
        let (mut piv, mut largest) = (i, column[i].abs());
        for (r, v) in column.iter().enumerate().skip(i + 1) {
            if v.abs() > largest {
                (piv, largest) = (r, v.abs());
            }
        }
        let diag = column[piv];
        if diag == 0.0 {
            continue;
        }
        if piv != i {
            swaps.push((i, piv));
            for c in 0..n {
                m.swap(c * n + i, c * n + piv);
            }
        }
        let inv_diag = 1.0 / diag;
        for r in i + 1..n {
            m[i * n + r] *= inv_diag;
        }
        let (done, rest) = m.split_at_mut((i + 1) * n);
        let coeffs = &done[i * n + i + 1..];
        for column in rest.chunks_exact_mut(n) {
            let pivot = column[i];
            if pivot == 0.0 {
                continue;
            }
            for (y, x) in column[i + 1..].iter_mut().zip(coeffs) {
                *y += -pivot * x;
            }
        }
    }
    let b = b.as_mut_slice();
    for &(i, p) in &swaps {
        b.swap(i, p);
    }
    for i in 0..n.saturating_sub(1) {
        let coeff = b[i];
        if coeff == 0.0 {
            continue;
        }
        for (y, x) in b[i + 1..].iter_mut().zip(&m[i * n + i + 1..(i + 1) * n]) {
            *y += -coeff * x;
        }
    }
    for i in (0..n).rev() {
        let diag = m[i * n + i];
        if diag == 0.0 {
            return None;
        }
        let coeff = b[i] / diag;
        b[i] = coeff;
        if coeff == 0.0 {
            continue;
        }
        for (y, x) in b[..i].iter_mut().zip(&m[i * n..i * n + i]) {
            *y += -coeff * x;
        }
    }
    Some(DVector::from_column_slice(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// nalgebra's solution, up to the signs of zeros.
    fn same_as_nalgebra(n: usize, entries: &[f64], rhs: &[f64]) {
        let a = DMatrix::from_column_slice(n, n, &entries[..n * n]);
        let b = DVector::from_column_slice(&rhs[..n]);
        let theirs = a.clone().lu().solve(&b);
        let ours = lu_solve(a, b);
        match (theirs, ours) {
            (None, None) => {}
            (Some(t), Some(o)) => {
                for (x, y) in t.iter().zip(o.iter()) {
                    assert!(x == y || x.is_nan() && y.is_nan(), "{t} vs {o}");
                }
            }
            (t, o) => panic!("nalgebra {t:?}, ours {o:?}"),
        }
    }

    proptest! {
        /// Entries spread over magnitudes, a third of them zero (as in Newton's systems).
        #[test]
        fn sparse_spread_entries(
            n in 1usize..30,
            entries in proptest::collection::vec(
                prop_oneof![Just(0.0), -1e3f64..1e3, -1e-3f64..1e-3], 900),
            rhs in proptest::collection::vec(prop_oneof![Just(0.0), -1e3f64..1e3], 30),
        ) {
            same_as_nalgebra(n, &entries, &rhs);
        }

        /// Entries from a few values: ties between pivots, zero columns, singular systems.
        #[test]
        fn few_values(
            n in 1usize..12,
            picks in proptest::collection::vec(0usize..5, 144),
            rhs in proptest::collection::vec(-2.0f64..2.0, 12),
        ) {
            let values = [0.0, 1.0, -1.0, 2.0, 0.5];
            let entries: Vec<f64> = picks.iter().map(|&k| values[k]).collect();
            same_as_nalgebra(n, &entries, &rhs);
        }
    }
}
