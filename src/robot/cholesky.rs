//! The 6×6 Cholesky solve of the IK descent's normal equations, on plain arrays.
//!
//! It performs nalgebra 0.35's `matrix.cholesky().map(|c| c.solve(&g))` operation by operation
//! (the same products, sums, square roots and quotients, in the same order), so it returns the
//! same bits, and `None` in the same cases; nalgebra's generic version runs its inner loops over
//! dynamically sized views and cost a seventh of a planning run. The tests compare the two bit
//! for bit.

use nalgebra::{Matrix6, Vector6};

/// The solution of `a x = g` for a symmetric positive definite `a` (only its lower triangle is
/// read), or `None` when a pivot is zero or not positive (as nalgebra's `Cholesky::new`).
pub(super) fn solve6(a: &Matrix6<f64>, g: &Vector6<f64>) -> Option<Vector6<f64>> {
    // Column-major like nalgebra: l[col][row].
    let mut l = [[0.0f64; 6]; 6];
    for (j, col) in l.iter_mut().enumerate() {
        for (i, v) in col.iter_mut().enumerate() {
            *v = a[(i, j)];
        }
    }
    for j in 0..6 {
        let (done, rest) = l.split_at_mut(j);
        let col_j = &mut rest[0];
        for col_k in done.iter() {
            // nalgebra: col_j[j..].axpy(-l[j][k], &col_k[j..], 1), i.e. y = a·x·1 + 1·y (the
            // products by one are exact, and so is swapping the terms of a sum).
            let factor = -col_k[j];
            for (y, x) in col_j[j..].iter_mut().zip(&col_k[j..]) {
                *y += factor * x;
            }
        }
        let diag = col_j[j];
        // `is_zero`, then `try_sqrt` (which refuses negatives and NaN).
        if diag == 0.0 || diag.is_nan() || diag < 0.0 {
            return None;
        }
        let denom = diag.sqrt();
        col_j[j] = denom;
        for v in &mut col_j[j + 1..] {
            *v /= denom;
        }
    }
    let mut b = [g[0], g[1], g[2], g[3], g[4], g[5]];
    // L y = g: nalgebra's `solve_lower_triangular_unchecked_mut`.
    for i in 0..6 {
        let coeff = b[i] / l[i][i];
        b[i] = coeff;
        for (y, x) in b[i + 1..].iter_mut().zip(&l[i][i + 1..]) {
            *y += -coeff * x;
        }
    }
    // Lᵀ x = y: nalgebra's `ad_solve_lower_triangular_unchecked_mut`, whose dot product over
    // fewer than eight terms starts from zero and adds the terms in order.
    for i in (0..6).rev() {
        let mut dot = 0.0;
        for r in i + 1..6 {
            dot += l[i][r] * b[r];
        }
        b[i] = (b[i] - dot) / l[i][i];
    }
    Some(Vector6::from(b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn nalgebra(a: &Matrix6<f64>, g: &Vector6<f64>) -> Option<Vector6<f64>> {
        a.cholesky().map(|c| c.solve(g))
    }

    fn same_bits(x: Option<Vector6<f64>>, y: Option<Vector6<f64>>) -> bool {
        match (x, y) {
            (None, None) => true,
            (Some(x), Some(y)) => x.iter().zip(y.iter()).all(|(p, q)| p.to_bits() == q.to_bits()),
            _ => false,
        }
    }

    #[test]
    fn agrees_with_nalgebra_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        for case in 0..20_000 {
            // Damped normal equations as the descent builds them, with Jacobians of every
            // scale, rank-deficient ones, and (every tenth case) an indefinite matrix.
            let scale = 10f64.powi(rng.random_range(-6..3));
            let mut jac = Matrix6::from_fn(|_, _| scale * rng.random_range(-1.0..1.0));
            if case % 7 == 0 {
                let c = rng.random_range(0..6);
                jac.column_mut(c).fill(0.0);
            }
            let jtj = jac.transpose() * jac;
            let lambda = 10f64.powi(rng.random_range(-12..8));
            let mut a = jtj;
            for k in 0..6 {
                a[(k, k)] += lambda * (jtj[(k, k)] + 1e-9);
            }
            if case % 10 == 0 {
                a[(3, 3)] = -a[(3, 3)];
            }
            if case % 13 == 0 {
                a[(0, 0)] = 0.0;
            }
            let g = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let (x, y) = (solve6(&a, &g), nalgebra(&a, &g));
            assert!(same_bits(x, y), "case {case}: {x:?} vs {y:?}");
        }
    }
}
