//! Small dense linear algebra for the discrete-ordinates solver (row-major `n × n` slices):
//! Cholesky, cyclic Jacobi eigen-decomposition of a symmetric matrix and Gaussian
//! elimination with partial pivoting. Sizes here are ≤ ~100, so plain O(n³) loops suffice.

/// Lower-triangular Cholesky factor `l` of the symmetric positive-definite `a` (`a = l lᵀ`),
/// or `None` if `a` is not numerically positive definite.
pub(crate) fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= l[j * n + k] * l[j * n + k];
        }
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let djj = d.sqrt();
        l[j * n + j] = djj;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            l[i * n + j] = s / djj;
        }
    }
    Some(l)
}

/// Eigen-decomposition of the symmetric `a` by cyclic Jacobi rotations. Returns the
/// eigenvalues and the row-major matrix whose *columns* are the orthonormal eigenvectors.
/// `a` is overwritten (it ends up ≈ diagonal).
pub(crate) fn jacobi_eigen(a: &mut [f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut v = vec![0.0; n * n];
    for i in 0..n {
        v[i * n + i] = 1.0;
    }
    let scale: f64 = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    if scale > 0.0 {
        for _sweep in 0..100 {
            let mut off = 0.0;
            for p in 0..n {
                for q in p + 1..n {
                    off += a[p * n + q] * a[p * n + q];
                }
            }
            if off.sqrt() <= 1e-17 * scale {
                break;
            }
            for p in 0..n {
                for q in p + 1..n {
                    let apq = a[p * n + q];
                    if apq == 0.0 {
                        continue;
                    }
                    let (app, aqq) = (a[p * n + p], a[q * n + q]);
                    let theta = (aqq - app) / (2.0 * apq);
                    let t = if theta.is_finite() {
                        theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
                    } else {
                        0.0
                    };
                    if t == 0.0 {
                        // |a_pq| negligible next to the diagonal difference.
                        a[p * n + q] = 0.0;
                        a[q * n + p] = 0.0;
                        continue;
                    }
                    let c = 1.0 / (t * t + 1.0).sqrt();
                    let s = t * c;
                    // A ← Jᵀ A J with J_pp = J_qq = c, J_pq = s, J_qp = −s.
                    for k in 0..n {
                        let (akp, akq) = (a[k * n + p], a[k * n + q]);
                        a[k * n + p] = c * akp - s * akq;
                        a[k * n + q] = s * akp + c * akq;
                    }
                    for k in 0..n {
                        let (apk, aqk) = (a[p * n + k], a[q * n + k]);
                        a[p * n + k] = c * apk - s * aqk;
                        a[q * n + k] = s * apk + c * aqk;
                    }
                    a[p * n + q] = 0.0;
                    a[q * n + p] = 0.0;
                    for k in 0..n {
                        let (vkp, vkq) = (v[k * n + p], v[k * n + q]);
                        v[k * n + p] = c * vkp - s * vkq;
                        v[k * n + q] = s * vkp + c * vkq;
                    }
                }
            }
        }
    }
    let evals = (0..n).map(|i| a[i * n + i]).collect();
    (evals, v)
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting (`a` and `b` are
/// overwritten; the solution is returned). A singular pivot is replaced by a tiny number so
/// the result stays finite.
pub(crate) fn solve(a: &mut [f64], n: usize, b: &mut [f64]) -> Vec<f64> {
    for col in 0..n {
        let mut piv = col;
        for r in col + 1..n {
            if a[r * n + col].abs() > a[piv * n + col].abs() {
                piv = r;
            }
        }
        if piv != col {
            for k in 0..n {
                a.swap(col * n + k, piv * n + k);
            }
            b.swap(col, piv);
        }
        let mut d = a[col * n + col];
        if d == 0.0 {
            d = f64::MIN_POSITIVE;
            a[col * n + col] = d;
        }
        for r in col + 1..n {
            let f = a[r * n + col] / d;
            if f != 0.0 {
                for k in col..n {
                    a[r * n + k] -= f * a[col * n + k];
                }
                b[r] -= f * b[col];
            }
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let mut s = b[r];
        for k in r + 1..n {
            s -= a[r * n + k] * x[k];
        }
        x[r] = s / a[r * n + r];
    }
    x
}
