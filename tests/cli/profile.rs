//! `dermis profile` through the real renderer (lavapipe) against the stored Monte Carlo
//! reference: the measured-profile model follows the path-traced point-light profile, the
//! Ward BRDF (a local model: the exitance where the light falls) decays much faster.

use std::process::Command;

use dermis_measure::ground_truth::{self, metric, ReferenceSet, Scene};
use serde_json::Value;

#[test]
fn profile_of_tabulated_and_ward_against_the_point_light_reference() {
    let [m, _] = ground_truth::acceptance_materials();
    let set = ReferenceSet::load(&ground_truth::file_for(
        &ground_truth::source_dir(),
        &m.name,
    ))
    .unwrap_or_else(|e| panic!("{e}"));
    let entry = set
        .entry(&Scene::PointLight { h_mm: 5.0 })
        .expect("skin1 has the h = 5 mm point light");
    let edges: Vec<String> = entry.edges.iter().map(|e| e.to_string()).collect();
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args([
            "profile",
            "--shading",
            "tabulated,ward",
            "--material",
            "skin1",
        ])
        .args(["--eta", &set.eta.to_string(), "--g", &set.g.to_string()])
        .args([
            "--light-height-mm",
            "5",
            "--edges-mm",
            &edges.join(","),
            "--json",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "dermis profile failed: {stderr}");
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");

    // Shape: {"edges_mm": [...], "models": {"<name>": {"exitance": [[r, g, b], ...]}}}.
    let obj = report.as_object().unwrap();
    assert_eq!(obj.len(), 2, "{report}");
    let echoed: Vec<f64> = serde_json::from_value(report["edges_mm"].clone()).unwrap();
    assert_eq!(echoed, entry.edges);
    let models = report["models"].as_object().unwrap();
    assert_eq!(models.len(), 2);
    let profile = |name: &str| -> Vec<[f64; 3]> {
        let m = models[name].as_object().unwrap();
        assert_eq!(m.len(), 1, "{name}: only `exitance`");
        let rows: Vec<[f64; 3]> = serde_json::from_value(m["exitance"].clone()).unwrap();
        assert_eq!(
            rows.len(),
            entry.edges.len() - 1,
            "{name}: one row per annulus"
        );
        for r in &rows {
            assert!(r.iter().all(|x| x.is_finite() && *x > 0.0), "{name}: {r:?}");
        }
        rows
    };
    let (tab, ward) = (profile("tabulated"), profile("ward"));

    // Tabulated: within 25 % of the Monte Carlo in every bin the MC resolves (above its noise
    // floor, relative SE under 5 %).
    let mut checked = 0;
    for (k, (t, (v, s))) in tab
        .iter()
        .zip(entry.values.iter().zip(&entry.std_err))
        .enumerate()
    {
        for c in 0..3 {
            if metric::scored(entry, k, c) && s[c] < 0.05 * v[c] {
                let ratio = t[c] / v[c];
                assert!(
                    (0.75..=1.25).contains(&ratio),
                    "tabulated bin {k} ({}–{} mm) channel {c}: {} vs MC {} (×{ratio:.3})",
                    entry.edges[k],
                    entry.edges[k + 1],
                    t[c],
                    v[c]
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 45, "only {checked} bins checked");

    // The profile's fall-off from the first to the last annulus, relative to the MC's: about
    // 1 for the measured profile; Ward's (the irradiance's r⁻³ tail instead of light carried
    // sideways under the skin) falls at least 1.4× further in every channel.
    let n = tab.len() - 1;
    let v = &entry.values;
    for c in 0..3 {
        let mc = v[n][c] / v[0][c];
        let t = tab[n][c] / tab[0][c] / mc;
        let w = ward[n][c] / ward[0][c] / mc;
        assert!(
            (0.8..1.25).contains(&t),
            "channel {c}: tabulated fall-off ×{t:.3} of the MC's"
        );
        assert!(
            w < 1.0 / 1.4,
            "channel {c}: Ward's fall-off ×{w:.3} of the MC's"
        );
    }
}

/// `profile --json` for `medium` (flags) through Burley (spatial, and it reads no measured
/// table).
fn profile_of(medium: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args([
            "profile",
            "--shading",
            "ward,burley",
            "--light-height-mm",
            "5",
        ])
        .args(medium)
        .arg("--json")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "dermis profile {medium:?}: {stderr}");
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

#[test]
fn any_medium_reaches_the_renderer_by_its_numbers() {
    // skin1 by name and by its coefficients (σ_s = σ'_s at g = 0) render the same profile.
    let m = dermis_engine::shading::material::SKIN1;
    let rgb = |v: [f64; 3]| format!("{},{},{}", v[0], v[1], v[2]);
    let (a, s) = (rgb(m.sigma_a), rgb(m.sigma_s_prime));
    let eta = m.eta.to_string();
    let named = profile_of(&["--material", "skin1"]);
    let numbers = profile_of(&["--sigma-a", &a, "--sigma-s", &s, "--eta", &eta]);
    assert_eq!(named["models"], numbers["models"]);
    // A paler medium given by its albedo and mean free path reflects more in every channel.
    let pale = profile_of(&["--albedo", "0.8,0.7,0.6", "--mfp-mm", "1.2,1.0,0.9"]);
    let total = |v: &Value, model: &str| -> [f64; 3] {
        let rows: Vec<[f64; 3]> =
            serde_json::from_value(v["models"][model]["exitance"].clone()).unwrap();
        std::array::from_fn(|c| rows.iter().map(|r| r[c]).sum())
    };
    for model in ["burley"] {
        let (skin, p) = (total(&named, model), total(&pale, model));
        for c in 0..3 {
            assert!(
                p[c] > skin[c],
                "{model} channel {c}: {} vs skin1 {}",
                p[c],
                skin[c]
            );
        }
    }
}
