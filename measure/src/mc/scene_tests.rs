//! Checks of the scene estimators (oblique beam, shadow edge, sphere, backlit slab) against
//! what must hold exactly or in a known limit. Statistical bounds are z < 4 on combined
//! standard errors of independent runs. Photon counts are small: the crate is unoptimised
//! in debug test builds.

use super::*;

fn z(a: Estimate, b: Estimate) -> f64 {
    (a.mean - b.mean).abs() / (a.std_err.powi(2) + b.std_err.powi(2)).sqrt()
}

fn est(p: &Profile, k: usize) -> Estimate {
    Estimate {
        mean: p.values[k],
        std_err: p.std_err[k],
    }
}

#[test]
fn collimated_normal_beam_is_the_normal_source() {
    let m = Medium::new(0.1, 1.0, 0.0, 1.4);
    let det = Detectors {
        edges: vec![0.0, 0.5, 1.0, 3.0],
        ..Default::default()
    };
    let a = simulate(&m, Geometry::SemiInfinite, Source::Normal, &det, 3000, 5, 2);
    let b = simulate(
        &m,
        Geometry::SemiInfinite,
        Source::Collimated { mu: 1.0 },
        &det,
        3000,
        5,
        2,
    );
    assert_eq!(a, b);
}

#[test]
fn oblique_reflectance_grows_toward_grazing_and_specular_is_fresnel() {
    let m = Medium::new(0.1, 1.0, 0.0, 1.4);
    let normal = oblique_reflectance(&m, 1.0, 20_000, 1, 2);
    let r = simulate(
        &m,
        Geometry::SemiInfinite,
        Source::Collimated { mu: 0.3 },
        &Detectors::default(),
        20_000,
        2,
        2,
    );
    let f = fresnel::fresnel(0.3, 1.4).0;
    assert!(
        (r.specular.mean - f).abs() < 1e-12,
        "the specular part is deterministic"
    );
    // Per entered power, an oblique beam enters shallower and more of it comes back out.
    let per_entered = r.reflectance.scaled(1.0 / (1.0 - f));
    let normal_entered = normal.scaled(1.0 / (1.0 - fresnel::fresnel(1.0, 1.4).0));
    eprintln!("R_d per entered: μ=1 {normal_entered:?}, μ=0.3 {per_entered:?}");
    assert!(per_entered.mean - normal_entered.mean > 4.0 * per_entered.std_err);
}

#[test]
fn shadow_edge_limits_far_lit_far_shadow() {
    // Diffusion length 1/σ_tr ≈ 1.7 mm: 20 mm from the edge is ~11 diffusion lengths.
    let m = Medium::new(0.1, 1.0, 0.0, 1.4);
    let mu = std::f64::consts::FRAC_1_SQRT_2;
    let edges = [-30.0, -20.0, -2.0, -0.5, 0.0, 0.5, 2.0, 20.0, 30.0];
    let e = shadow_edge(&m, mu, &edges, 20_000, 7, 2);
    let last = edges.len() - 2;
    let far_lit = est(&e.strips, last);
    let reference = oblique_reflectance(&m, mu, 20_000, 8, 2);
    let zz = z(far_lit, reference);
    eprintln!("far lit {far_lit:?} vs oblique R {reference:?} ({zz:.2} SE)");
    assert!(zz < 4.0);
    // Same photons: the far-lit strip is the run's own total reflectance (less a tail
    // e^{−11} that does not show at this precision).
    assert!((far_lit.mean / e.reflectance.mean - 1.0).abs() < 1e-6);
    assert!(
        e.strips.values[0] < 1e-6 * reference.mean,
        "far shadow must be dark"
    );
    // Monotone across the edge (coarse strips; the differences are many SE).
    let v = &e.strips.values;
    for k in 1..v.len() {
        assert!(
            v[k] >= v[k - 1],
            "strips must brighten toward the lit side: {v:?}"
        );
    }
    // The oblique beam travels toward −x, so light spills further into the shadow than a
    // normal beam's does.
    let n = shadow_edge(&m, 1.0, &edges, 20_000, 9, 2);
    let rel = |r: &EdgeResults, k: usize| r.strips.values[k] / r.reflectance.mean;
    assert!(
        rel(&e, 3) > rel(&n, 3),
        "oblique spill {} vs normal {}",
        rel(&e, 3),
        rel(&n, 3)
    );
}

#[test]
fn shadow_edge_at_normal_incidence_is_half_at_the_edge() {
    // The line-spread function of a normal beam is even, so M(x) + M(−x) = R and any strip
    // symmetric about the edge averages R/2.
    let m = Medium::new(0.05, 1.0, 0.0, 1.4);
    let edges = [-40.0, -1.0, 1.0, 40.0];
    let e = shadow_edge(&m, 1.0, &edges, 20_000, 11, 2);
    let half = total_reflectance(&m, 20_000, 12, 2).scaled(0.5);
    let edge = est(&e.strips, 1);
    let zz = z(edge, half);
    eprintln!("edge strip {edge:?} vs R/2 {half:?} ({zz:.2} SE)");
    assert!(zz < 4.0);
    // Symmetry of the two outer strips: M(lit) + M(shadow) = R over mirror strips.
    let sum = Estimate {
        mean: e.strips.values[0] + e.strips.values[2],
        std_err: e.strips.std_err[0] + e.strips.std_err[2],
    };
    assert!(z(sum, half.scaled(2.0)) < 4.0);
}

#[test]
fn shadow_edge_is_deterministic_across_threads() {
    let m = Medium::new(0.1, 1.0, 0.5, 1.3);
    let edges = [-5.0, -1.0, 0.0, 1.0, 5.0];
    let n = 2 * BATCH_SIZE + 17;
    let a = shadow_edge(&m, 0.6, &edges, n, 3, 1);
    assert_eq!(a, shadow_edge(&m, 0.6, &edges, n, 3, 2));
    assert_eq!(a, shadow_edge(&m, 0.6, &edges, n, 3, 5));
    assert_ne!(
        a.reflectance,
        shadow_edge(&m, 0.6, &edges, n, 4, 2).reflectance
    );
}

fn band_edges(step: f64) -> Vec<f64> {
    let n = (180.0 / step).round() as usize;
    (0..=n).map(|k| k as f64 * step).collect()
}

#[test]
fn sphere_conserves_energy() {
    let m = Medium::new(0.05, 1.0, 0.0, 1.4);
    let edges = band_edges(30.0);
    let s = sphere(&m, 3.0, &edges, 10_000, 21, 2);
    // The bands cover the whole sphere: their area-weighted sum is the total exitance
    // (per unit incident power: band exitance × 2(cos a − cos b)).
    let sum: f64 = edges
        .windows(2)
        .zip(&s.bands.values)
        .map(|(w, v)| v * 2.0 * (w[0].to_radians().cos() - w[1].to_radians().cos()))
        .sum();
    assert!(
        (sum / s.exitance.mean - 1.0).abs() < 1e-9,
        "{sum} vs {:?}",
        s.exitance
    );
    // Exit + absorbed + capped = entered, in expectation (roulette conserves weight only on
    // average); the SE of the sum is at most the sum of the SEs.
    let total = s.exitance.mean + s.absorbed.mean + s.capped.mean;
    let se = s.exitance.std_err + s.absorbed.std_err + s.capped.std_err + s.entered.std_err;
    eprintln!(
        "sphere: exit {:?} absorbed {:?} capped {:?} entered {}",
        s.exitance, s.absorbed, s.capped, s.entered.mean
    );
    assert!(
        (total - s.entered.mean).abs() < 4.0 * se,
        "{total} vs {}",
        s.entered.mean
    );
    // The weighted entry sampling is unbiased for uniform disk illumination: the specular
    // part is the disk average of the Fresnel reflectance, 2∫F(μ)μ dμ, and specular +
    // entered is the incident power, 1.
    let k = 20_000;
    let exact: f64 = (0..k)
        .map(|i| {
            let mu = (i as f64 + 0.5) / k as f64;
            2.0 * mu * fresnel::fresnel(mu, 1.4).0 / k as f64
        })
        .sum();
    eprintln!("sphere specular {:?} vs exact {exact:.6}", s.specular);
    assert!((s.specular.mean - exact).abs() < 4.0 * s.specular.std_err);
    let incident = s.specular.mean + s.entered.mean;
    assert!((incident - 1.0).abs() < 4.0 * (s.specular.std_err + s.entered.std_err));
    // The lit pole is brighter than the terminator, which is brighter than the dark pole.
    let v = &s.bands.values;
    assert!(v[0] > v[3] && v[3] > v[5], "{v:?}");
}

#[test]
fn conservative_sphere_returns_everything_that_entered() {
    for &g in &[0.0, 0.8] {
        let m = Medium::new(0.0, 1.0, g, 1.4);
        let s = sphere(&m, 2.0, &band_edges(45.0), 3000, 22, 2);
        assert_eq!(s.absorbed.mean, 0.0);
        let sum = s.exitance.mean + s.capped.mean;
        assert!(
            (sum - s.entered.mean).abs() < 1e-12,
            "g={g}: {sum} vs {}",
            s.entered.mean
        );
        assert!(s.capped.mean < 1e-3, "g={g}: capped {:?}", s.capped);
    }
}

#[test]
fn large_sphere_lit_pole_matches_the_flat_half_space() {
    // R = 200 mm against a diffusion length of 1.2 mm: the band θ < 30° is locally flat. In
    // the flat limit its exitance per unit beam irradiance is ∫ R_d(cos θ) cos θ dA / A
    // = (1 + cos θ₁)/2 × the reflectance under cosine-weighted incidence within the cone
    // cos θ ≥ cos θ₁ (μ² uniform in [cos²θ₁, 1], as on the sphere).
    let m = Medium::new(0.2, 1.0, 0.0, 1.4);
    let theta1: f64 = 30.0;
    let s = sphere(&m, 200.0, &[0.0, theta1, 180.0], 40_000, 31, 2);
    let mu1 = theta1.to_radians().cos();
    let flat = simulate(
        &m,
        Geometry::SemiInfinite,
        Source::Cone { mu_min: mu1 },
        &Detectors::default(),
        40_000,
        32,
        2,
    )
    .reflectance
    .scaled(0.5 * (1.0 + mu1));
    let pole = est(&s.bands, 0);
    let zz = z(pole, flat);
    eprintln!("sphere R=200 band [0, 30°): {pole:?} vs flat {flat:?} ({zz:.2} SE)");
    assert!(zz < 4.0);
    // And against the plain normal-incidence value, which it approaches as θ₁ → 0.
    let normal = total_reflectance(&m, 20_000, 33, 2);
    assert!((pole.mean / normal.mean - 1.0).abs() < 0.1);
}

#[test]
fn sphere_is_deterministic_across_threads() {
    let m = Medium::new(0.1, 1.0, 0.5, 1.3);
    let edges = band_edges(20.0);
    let n = 2 * BATCH_SIZE + 5;
    let a = sphere(&m, 4.0, &edges, n, 5, 1);
    assert_eq!(a, sphere(&m, 4.0, &edges, n, 5, 2));
    assert_eq!(a, sphere(&m, 4.0, &edges, n, 5, 5));
    assert_eq!(a.photons, n);
    assert_ne!(a.exitance, sphere(&m, 4.0, &edges, n, 6, 2).exitance);
}

#[test]
fn backlit_slab_diffuse_transmittance() {
    let m = Medium::new(0.1, 1.0, 0.0, 1.4);
    let d = 1.0;
    // Same photons as the slab run: diffuse + unscattered = total transmittance.
    let diffuse = slab_diffuse_transmittance(&m, d, 5000, 41, 2);
    let r = simulate(
        &m,
        Geometry::Slab { d },
        Source::Normal,
        &Detectors::default(),
        5000,
        41,
        2,
    );
    assert!((diffuse.mean + r.unscattered.mean - r.transmittance.mean).abs() < 1e-12);
    assert!(diffuse.std_err > 0.0 && diffuse.std_err < r.transmittance.std_err * 1.5);
    // σ_a = 0: R + T_diffuse + T_unscattered + specular = 1.
    let m0 = Medium::new(0.0, 1.0, 0.0, 1.4);
    let s = slab(&m0, d, 3000, 42, 2);
    let td = slab_diffuse_transmittance(&m0, d, 3000, 42, 2);
    let un = simulate(
        &m0,
        Geometry::Slab { d },
        Source::Normal,
        &Detectors::default(),
        3000,
        42,
        2,
    )
    .unscattered;
    assert!((s.r.mean + td.mean + un.mean + s.specular - 1.0).abs() < 1e-12);
}
