use super::*;

const SKIN1_SA: [f64; 3] = [0.032, 0.17, 0.48];
const SKIN1_SSP: [f64; 3] = [0.74, 0.88, 1.01];
const COAT_SA: [f64; 3] = [0.000905, 0.001083, 0.002038];
const COAT_SSP: [f64; 3] = [1.94, 1.94, 1.874];

/// Monte Carlo reference (`dermis_measure::mc`, g = 0, 200k photons, per entered power), table of the
/// task brief: (name, σ_a, σ'_s, η, R_d per channel, standard error per channel).
#[allow(clippy::type_complexity)]
fn mc_table() -> Vec<(&'static str, [f64; 3], [f64; 3], f64, [f64; 3], [f64; 3])> {
    vec![
        (
            "skin1",
            SKIN1_SA,
            SKIN1_SSP,
            1.4,
            [0.4018, 0.1872, 0.0987],
            [0.0008, 0.0006, 0.0004],
        ),
        (
            "skin1",
            SKIN1_SA,
            SKIN1_SSP,
            1.3,
            [0.4405, 0.2132, 0.1156],
            [0.0; 3],
        ),
        (
            "skin1",
            SKIN1_SA,
            SKIN1_SSP,
            1.0936,
            [0.5284, 0.2853, 0.1632],
            [0.0; 3],
        ),
        (
            "coat",
            COAT_SA,
            COAT_SSP,
            1.0936,
            [0.9326, 0.9269, 0.8992],
            [0.0; 3],
        ),
        (
            "coat",
            COAT_SA,
            COAT_SSP,
            1.4,
            [0.8973, 0.8886, 0.8482],
            [0.0; 3],
        ),
    ]
}

#[test]
fn quadratures_are_exact_to_their_degree() {
    for &(nc, nt, eta) in &[(16, 12, 1.4), (16, 12, 1.0), (5, 3, 2.0), (1, 0, 1.0)] {
        let (x, w, deg) = quadrature::hemisphere(nc, nt, eta);
        assert_eq!(x.len(), nc + nt);
        assert_eq!(*x.last().unwrap(), 1.0, "μ = 1 must be a node");
        assert!(x.windows(2).all(|p| p[0] < p[1]) && x[0] > 0.0);
        for d in 0..=deg {
            let q: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(d as i32)).sum();
            let exact = 1.0 / (d as f64 + 1.0);
            assert!(
                (q - exact).abs() < 1e-13,
                "n=({nc},{nt}) η={eta} degree {d}: {q}"
            );
        }
    }
}

#[test]
fn linalg_eigen_and_solve() {
    let n = 7;
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            a[i * n + j] = 1.0 / (1.0 + i as f64 + j as f64) + if i == j { 2.0 } else { 0.0 };
        }
    }
    let orig = a.clone();
    let (lam, v) = linalg::jacobi_eigen(&mut a, n);
    for m in 0..n {
        for i in 0..n {
            let av: f64 = (0..n).map(|k| orig[i * n + k] * v[k * n + m]).sum();
            assert!((av - lam[m] * v[i * n + m]).abs() < 1e-12);
        }
    }
    let l = linalg::cholesky(&orig, n).unwrap();
    for i in 0..n {
        for j in 0..n {
            let s: f64 = (0..n).map(|k| l[i * n + k] * l[j * n + k]).sum();
            assert!((s - orig[i * n + j]).abs() < 1e-12);
        }
    }
    let mut b: Vec<f64> = (0..n).map(|i| i as f64 - 2.0).collect();
    let b0 = b.clone();
    let x = linalg::solve(&mut orig.clone(), n, &mut b);
    for i in 0..n {
        let s: f64 = (0..n).map(|k| orig[i * n + k] * x[k]).sum();
        assert!((s - b0[i]).abs() < 1e-12);
    }
}

#[test]
fn matches_monte_carlo_table() {
    for (name, sa, ssp, eta, mc, se) in mc_table() {
        for c in 0..3 {
            let r = diffuse_reflectance(sa[c], ssp[c], 0.0, eta).per_entered;
            let rel = (r - mc[c]) / mc[c];
            let tol = (0.015 * mc[c]).max(3.0 * se[c]);
            assert!(
                (r - mc[c]).abs() < tol,
                "{name} η={eta} ch{c}: {r:.4} vs MC {:.4} ({:+.2} %)",
                mc[c],
                100.0 * rel
            );
        }
    }
}

#[test]
fn converged_in_quadrature() {
    for &eta in &[1.0, 1.0936, 1.4, 2.0] {
        for &(sa, ssp, g) in &[
            (0.48, 1.01, 0.0),
            (0.032, 0.74, 0.0),
            (0.001, 1.94, 0.0),
            (0.1, 1.0, 0.8),
            (0.01, 1.0, -0.3),
        ] {
            let a = diffuse_reflectance(sa, ssp, g, eta).per_entered;
            let b = diffuse_reflectance_with(sa, ssp, g, eta, 32, 32).per_entered;
            assert!(
                (a - b).abs() < 2e-4 * b.max(0.05),
                "η={eta} σa={sa} σs'={ssp} g={g}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn no_absorption_returns_everything() {
    for &eta in &[0.8, 1.0, 1.0936, 1.4, 2.0] {
        for &g in &[0.0, 0.5, -0.5, 0.9] {
            let r = diffuse_reflectance(0.0, 1.3, g, eta);
            assert!((r.per_entered - 1.0).abs() < 1e-6, "η={eta} g={g}: {r:?}");
            // Nearly conservative: continuous towards 1.
            let r = diffuse_reflectance(1e-12, 1.3, g, eta).per_entered;
            assert!((r - 1.0).abs() < 1e-4, "η={eta} g={g} σa=1e-12: {r}");
        }
    }
}

#[test]
fn specular_is_normal_fresnel() {
    for &eta in &[0.7, 1.0, 1.0936, 1.3, 1.4, 2.0] {
        let r = diffuse_reflectance(0.1, 1.0, 0.0, eta);
        let f = ((eta - 1.0) / (eta + 1.0)).powi(2);
        assert!((r.specular - f).abs() < 1e-15);
        assert!((r.specular - crate::shading::fresnel::reflectance(eta, 1.0)).abs() < 1e-12);
        assert!((r.per_incident - r.per_entered * (1.0 - f)).abs() < 1e-15);
    }
}

#[test]
fn monotone_in_albedo_and_decreasing_with_eta() {
    for &eta in &[1.0, 1.0936, 1.4, 2.0] {
        for &g in &[0.0, 0.7] {
            let mut prev = 0.0;
            for k in 0..=60 {
                // 1 − ω from 1 down to 1e-12, logarithmically.
                let omw = 10f64.powf(-12.0 * k as f64 / 60.0);
                let r = diffuse_reflectance(omw, (1.0 - omw) * (1.0 - g), g, eta).per_entered;
                assert!(r.is_finite() && (0.0..=1.0).contains(&r));
                assert!(r >= prev - 1e-9, "η={eta} g={g} 1−ω={omw}: {r} < {prev}");
                prev = r;
            }
        }
    }
    let mut prev = 1.0;
    for &eta in &[1.0, 1.0936, 1.2, 1.3, 1.4, 1.6, 2.0] {
        let r = diffuse_reflectance(0.1, 1.0, 0.0, eta).per_entered;
        assert!(r < prev);
        prev = r;
    }
}

#[test]
fn scale_invariant_and_safe_for_extreme_inputs() {
    let base = diffuse_reflectance(0.17, 0.88, 0.0, 1.4);
    for &s in &[1e-6, 1e-3, 1.0, 1e3, 1e6] {
        let r = diffuse_reflectance(0.17 * s, 0.88 * s, 0.0, 1.4);
        assert!((r.per_entered - base.per_entered).abs() < 1e-12);
    }
    let vals = [0.0, 1e-6, 1.0, 1e6, f64::INFINITY, f64::NAN, -1.0];
    for &sa in &vals {
        for &ss in &vals {
            for &g in &[0.0, 0.9, 1.0, -1.0, f64::NAN] {
                for &eta in &[1.0, 1.4, 2.0, 0.0, f64::NAN] {
                    let r = diffuse_reflectance(sa, ss, g, eta);
                    for v in [r.per_entered, r.per_incident, r.specular] {
                        assert!(
                            v.is_finite() && (0.0..=1.0).contains(&v),
                            "{sa} {ss} {g} {eta}: {r:?}"
                        );
                    }
                }
            }
        }
    }
    assert_eq!(
        diffuse_reflectance(f64::INFINITY, 1.0, 0.0, 1.4).per_entered,
        0.0
    );
    assert_eq!(
        diffuse_reflectance(1.0, f64::INFINITY, 0.0, 1.4).per_entered,
        1.0
    );
    assert!(diffuse_reflectance(1e6, 1e-6, 0.0, 1.4).per_entered < 1e-11);
}

#[test]
fn albedo_rgb_uses_material_parameters() {
    let mut m = crate::shading::material::SKIN1;
    m.eta = 1.4;
    let a = albedo_rgb(&m);
    for (c, &ac) in a.iter().enumerate() {
        let r = diffuse_reflectance(m.sigma_a[c], m.sigma_s_prime[c], m.g, m.eta);
        assert_eq!(ac, r.per_entered);
    }
    assert!(a[0] > a[1] && a[1] > a[2]);
}
