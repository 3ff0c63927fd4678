//! The interpolation the measured tables share (`albedo`, `grid`, `sphere_grid`): cubic
//! Lagrange weights over four nodes, linear weights over two, and the monotone cubic
//! (Fritsch–Carlson) through equally spaced values.

/// Cubic Lagrange weights at `x` (in node units) over the four nearest of `n` nodes (linear
/// when there are fewer than four): the first node and the weights.
pub fn lagrange4(x: f64, n: usize) -> (usize, [f64; 4]) {
    let x = if x.is_finite() { x } else { 0.0 };
    if n < 4 {
        let (i, f) = linear2(x, n);
        return (i, [1.0 - f, f, 0.0, 0.0]);
    }
    let x = x.clamp(0.0, (n - 1) as f64);
    let first = (x.floor() as usize).saturating_sub(1).min(n - 4);
    let w = std::array::from_fn(|i| {
        (0..4)
            .filter(|&j| j != i)
            .map(|j| (x - (first + j) as f64) / (i as f64 - j as f64))
            .product()
    });
    (first, w)
}

/// Cubic Lagrange weights at `x` over the four nearest of the rising `nodes` (at least
/// four; `x` clamped to their span): the first node and the weights. At a node the weights
/// are exactly that node's 1 and the others' 0.
pub fn lagrange4_at(x: f64, nodes: &[f64]) -> (usize, [f64; 4]) {
    let n = nodes.len();
    let x = if x.is_finite() { x } else { nodes[0] };
    let x = x.clamp(nodes[0], nodes[n - 1]);
    let i = nodes.partition_point(|&t| t <= x).clamp(1, n - 1) - 1;
    let first = i.saturating_sub(1).min(n - 4);
    let t = &nodes[first..first + 4];
    let w = std::array::from_fn(|i| {
        (0..4)
            .filter(|&j| j != i)
            .map(|j| (x - t[j]) / (t[i] - t[j]))
            .product()
    });
    (first, w)
}

/// Linear weights at `x` (node units) between two of `n` ≥ 2 nodes: the first and its
/// neighbour's weight.
pub fn linear2(x: f64, n: usize) -> (usize, f64) {
    let x = if x.is_finite() { x } else { 0.0 };
    let x = x.clamp(0.0, (n - 1) as f64);
    let i = (x.floor() as usize).min(n - 2);
    (i, x - i as f64)
}

/// The monotone cubic (Fritsch–Carlson slopes, secant slopes at the ends) through `y` at
/// equally spaced nodes, at `x` in node units (clamped to the ends): it rises (falls) wherever
/// the data do, so a monotone table stays monotone between its nodes.
pub fn monotone(y: &[f64], x: f64) -> f64 {
    let n = y.len();
    let x = if x.is_finite() { x } else { 0.0 };
    let x = x.clamp(0.0, (n - 1) as f64);
    let k = (x.floor() as usize).min(n - 2);
    let d = |i: usize| y[i + 1] - y[i];
    let slope = |i: usize| {
        if i == 0 || i == n - 1 {
            d(i.min(n - 2))
        } else {
            let (a, b) = (d(i - 1), d(i));
            if a * b <= 0.0 {
                0.0
            } else {
                2.0 / (1.0 / a + 1.0 / b)
            }
        }
    };
    let t = x - k as f64;
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * y[k]
        + (t3 - 2.0 * t2 + t) * slope(k)
        + (-2.0 * t3 + 3.0 * t2) * y[k + 1]
        + (t3 - t2) * slope(k + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_reproduce_cubics_and_lines() {
        let f = |x: f64| 0.5 - x + 0.25 * x * x - 0.01 * x * x * x;
        for x in [0.0, 0.3, 2.5, 6.9, 7.0] {
            let (i, w) = lagrange4(x, 8);
            let v: f64 = (0..4).map(|k| w[k] * f((i + k) as f64)).sum();
            assert!((v - f(x)).abs() < 1e-12, "{x}");
            let nodes: Vec<f64> = (0..8).map(|k| k as f64).collect();
            let (i2, w2) = lagrange4_at(x, &nodes);
            assert_eq!(i2, i);
            assert!(w.iter().zip(&w2).all(|(a, b)| (a - b).abs() < 1e-12));
            let (j, g) = linear2(x, 8);
            assert!(((j as f64 + g) - x).abs() < 1e-12);
        }
    }

    #[test]
    fn the_monotone_cubic_keeps_monotone_data_monotone() {
        let y = [0.0, 0.01, 0.5, 0.51, 0.9, 1.0];
        let mut last = -1.0;
        for i in 0..=500 {
            let v = monotone(&y, i as f64 / 100.0);
            assert!(v >= last);
            last = v;
        }
        assert_eq!(monotone(&y, 2.0), 0.5);
        assert_eq!(monotone(&y, -3.0), 0.0);
        assert_eq!(monotone(&y, f64::NAN), 0.0);
    }
}
