//! Quadratures on μ ∈ [0, 1] for the discrete-ordinates solver: Gauss–Legendre and
//! Gauss–Radau (one node fixed at an end point), and Prahl's split rule — Gauss on the
//! totally-internally-reflected range [0, μ_c] and Radau on the escape cone [μ_c, 1] with
//! its fixed node at μ = 1, so that the normally incident refracted beam is a node.

/// Legendre P_{n−1}(x) and P_n(x) by the three-term recurrence (n ≥ 1).
fn legendre_pair(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    (p0, p1)
}

/// Gauss–Legendre nodes and weights on [0, 1].
pub fn gauss_legendre01(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-15 {
                break;
            }
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

/// `n`-point Gauss–Legendre rule on [a, b]: (nodes ascending, weights).
pub(crate) fn gauss(n: usize, a: f64, b: f64) -> (Vec<f64>, Vec<f64>) {
    let (x, w) = gauss_legendre01(n);
    let mut pairs: Vec<(f64, f64)> = x
        .iter()
        .zip(&w)
        .map(|(&x, &w)| (a + (b - a) * x, (b - a) * w))
        .collect();
    pairs.sort_by(|p, q| p.0.total_cmp(&q.0));
    pairs.into_iter().unzip()
}

/// `n`-point Gauss–Radau rule on [a, b] with a node fixed at `b` (exact for polynomials of
/// degree ≤ 2n − 2): (nodes ascending — the last is `b` — , weights).
///
/// On [−1, 1] with the fixed node at −1 the free nodes are the zeros of
/// (P_{n−1} + P_n)/(1 + x), weights (1 − x_i)/(n² P_{n−1}(x_i)²) and 2/n² at −1; they are
/// bracketed on a fine grid in θ = arccos(−x) and refined by bisection, then reflected.
pub(crate) fn radau_right(n: usize, a: f64, b: f64) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 1, "radau: need at least one node");
    let nf = n as f64;
    let mut xs = vec![-1.0];
    let mut ws = vec![2.0 / (nf * nf)];
    if n > 1 {
        let f = |x: f64| {
            let (pm, p) = legendre_pair(n, x);
            pm + p
        };
        let m = 32 * n;
        let grid = |j: usize| -(std::f64::consts::PI * j as f64 / m as f64).cos();
        let mut x0 = grid(1);
        let mut f0 = f(x0);
        for j in 2..=m {
            let x1 = if j == m { 1.0 } else { grid(j) };
            let f1 = f(x1);
            if f0 == 0.0 || f0.signum() != f1.signum() {
                let (mut lo, mut hi, mut flo) = (x0, x1, f0);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    let fm = f(mid);
                    if fm == 0.0 {
                        lo = mid;
                        hi = mid;
                        break;
                    }
                    if fm.signum() == flo.signum() {
                        lo = mid;
                        flo = fm;
                    } else {
                        hi = mid;
                    }
                }
                let r = 0.5 * (lo + hi);
                if f0 != 0.0 || xs.last().is_none_or(|&l| (r - l).abs() > 1e-12) {
                    let (pm, _) = legendre_pair(n, r);
                    xs.push(r);
                    ws.push((1.0 - r) / (nf * nf * pm * pm));
                }
            }
            x0 = x1;
            f0 = f1;
        }
        assert_eq!(xs.len(), n, "radau: root bracketing failed");
    }
    // Reflect x → −x (fixed node to +1) and map [−1, 1] → [a, b]; ascending order.
    let h = 0.5 * (b - a);
    let mut pairs: Vec<(f64, f64)> = xs
        .iter()
        .zip(&ws)
        .map(|(&x, &w)| (a + h * (1.0 - x), h * w))
        .collect();
    pairs.sort_by(|p, q| p.0.total_cmp(&q.0));
    if let Some(last) = pairs.last_mut() {
        last.0 = b;
    }
    pairs.into_iter().unzip()
}

/// The hemisphere rule used inside the medium: for η > 1, `n_tir` Gauss nodes on [0, μ_c]
/// (μ_c = √(1 − 1/η²), the critical cosine) and `n_cone` Radau nodes on [μ_c, 1] ending at
/// μ = 1; otherwise (no total internal reflection) `n_tir + n_cone` Radau nodes on [0, 1].
/// Returns (nodes ascending, weights, highest degree d such that polynomials of degree ≤ d
/// are integrated exactly on [0, 1]).
pub(crate) fn hemisphere(n_cone: usize, n_tir: usize, eta: f64) -> (Vec<f64>, Vec<f64>, usize) {
    let mu_c = critical_cosine(eta);
    if mu_c > 0.0 && n_tir > 0 {
        let (mut x, mut w) = gauss(n_tir, 0.0, mu_c);
        let (x2, w2) = radau_right(n_cone, mu_c, 1.0);
        x.extend(x2);
        w.extend(w2);
        (x, w, (2 * n_tir - 1).min(2 * n_cone - 2))
    } else {
        let n = n_cone + n_tir;
        let (x, w) = radau_right(n, 0.0, 1.0);
        (x, w, 2 * n - 2)
    }
}

/// Critical cosine inside a medium of relative index η: √(1 − 1/η²) for η > 1, else 0.
pub(crate) fn critical_cosine(eta: f64) -> f64 {
    if eta > 1.0 {
        (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt()
    } else {
        0.0
    }
}
