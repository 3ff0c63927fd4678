//! The committed reference files (`tools/reference/*.json`) are complete and reproducible.

use super::*;

fn load_committed(m: &Material) -> ReferenceSet {
    let path = file_for(&source_dir(), &m.name);
    ReferenceSet::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Every material with a committed reference: the presets and the test materials.
fn committed_materials() -> Vec<Material> {
    acceptance_materials()
        .into_iter()
        .chain(test_materials())
        .collect()
}

#[test]
fn committed_reference_files_are_complete() {
    for m in committed_materials() {
        let set = load_committed(&m);
        assert_eq!(set.material, m.name);
        assert_eq!(set.eta, ETA);
        assert_eq!(set.g, 0.0);
        // The file's 6 significant digits (a test material's optics come from the albedo
        // table: a re-baked table that moves them beyond that needs new references).
        let same = |a: [f64; 3], b: [f64; 3]| (0..3).all(|c| (a[c] - b[c]).abs() <= 1e-5 * b[c]);
        assert!(
            same(set.sigma_a, m.sigma_a),
            "{}: σ_a {:?}",
            m.name,
            set.sigma_a
        );
        assert!(same(set.sigma_s_prime, m.sigma_s_prime), "{}: σ'_s", m.name);
        let scenes = standard_scenes(&m);
        assert_eq!(set.entries.len(), scenes.len(), "{}: entry count", m.name);
        for (scene, edges) in &scenes {
            let e = set
                .entry(scene)
                .unwrap_or_else(|| panic!("{}: no entry for {}", m.name, scene.label()));
            let what = format!("{} {}", m.name, scene.label());
            assert_eq!(&e.edges, edges, "{what}: edges differ from standard_scenes");
            scene.validate(&e.edges).unwrap();
            assert!(e.photons >= 10_000, "{what}: {} photons", e.photons);
            assert_eq!(e.values.len(), edges.len() - 1);
            assert_eq!(e.std_err.len(), edges.len() - 1);
            let mut scored = 0;
            for (v, s) in e.values.iter().zip(&e.std_err) {
                for c in 0..3 {
                    assert!(v[c].is_finite() && v[c] >= 0.0, "{what}: value {}", v[c]);
                    assert!(s[c].is_finite() && s[c] >= 0.0, "{what}: SE {}", s[c]);
                    if v[c] > 0.0 {
                        assert!(s[c] > 0.0, "{what}: a positive value without an SE");
                    }
                    if v[c] > metric::NOISE_FLOOR * s[c] && v[c] > 0.0 {
                        scored += 1;
                    }
                }
            }
            // Every channel of every scene has something to score against.
            assert!(
                scored >= 3,
                "{what}: only {scored} bins above the noise floor"
            );
        }
    }
}

#[test]
fn committed_reference_files_round_trip() {
    for m in committed_materials() {
        let path = file_for(&source_dir(), &m.name);
        let text = std::fs::read_to_string(&path).unwrap();
        let set = load_committed(&m);
        // Saving what was loaded reproduces the file byte for byte (already rounded).
        assert_eq!(
            set.to_json(),
            text,
            "{}: not in the saved format",
            path.display()
        );
    }
}

#[test]
fn regenerated_entry_agrees_with_the_committed_one() {
    // Cheap skin1 scenes (walks of a few dozen events) with few photons and a different
    // seed: every bin the small run resolves agrees with the stored value within 4
    // combined standard errors.
    let m = acceptance_material(&SKIN1);
    let set = load_committed(&m);
    for (scene, min_bins) in [
        (Scene::PointLight { h_mm: 5.0 }, 30),
        (Scene::ShadowEdge { theta_deg: 45.0 }, 30),
        (Scene::SlabBacklit { thickness_mm: 1.0 }, 3),
    ] {
        let stored = set.entry(&scene).expect("a standard scene");
        let fresh = generate_entry(&m, &scene, &stored.edges, 20_000, 0xC0FFEE, 2);
        let mut compared = 0;
        let mut worst: f64 = 0.0;
        let mut worst_at = String::new();
        for k in 0..stored.values.len() {
            for c in 0..3 {
                let (a, sa) = (fresh.values[k][c], fresh.std_err[k][c]);
                let (b, sb) = (stored.values[k][c], stored.std_err[k][c]);
                // Only bins the small run resolves to ≤ 10 % (≳ 100 photons: a normal SE).
                if !(a > 10.0 * sa && a > 0.0) {
                    continue;
                }
                let z = (a - b).abs() / (sa * sa + sb * sb).sqrt();
                if z > worst {
                    worst = z;
                    worst_at = format!("bin {k} ch {c}: {a:.5e} ± {sa:.2e} vs {b:.5e} ± {sb:.2e}");
                }
                assert!(
                    z < 4.0,
                    "{}: bin {k} channel {c}: {a} ± {sa} vs stored {b} ± {sb} (z {z:.1})",
                    scene.label()
                );
                compared += 1;
            }
        }
        eprintln!(
            "{}: regenerated {compared} bins, worst z {worst:.2} ({worst_at})",
            scene.label()
        );
        assert!(compared >= min_bins, "only {compared} bins compared");
    }
}

#[test]
fn test_materials_have_the_albedo_they_were_made_from() {
    // Made through the measured inversion: their multi-scatter albedo is what they name, and
    // they are not a preset's optics.
    let c = dermis_engine::shading::subsurface::exit_normalisation(ETA);
    for (m, a) in test_materials().iter().zip(TEST_ALBEDO_ENTERED) {
        let a = a.map(|x| x * c);
        let back = m
            .albedo()
            .map(|s| dermis_engine::shading::albedo::multi_scatter_albedo(s, m.eta, m.g));
        for c in 0..3 {
            assert!((back[c] - a[c]).abs() < 1e-9, "{}: {back:?}", m.name);
        }
        assert!(acceptance_materials()
            .iter()
            .all(|p| p.sigma_a != m.sigma_a));
    }
}

#[test]
fn scenes_validate_and_json_round_trips() {
    for m in committed_materials() {
        for (s, e) in standard_scenes(&m) {
            s.validate(&e)
                .unwrap_or_else(|err| panic!("{}: {err}", m.name));
            assert!(s.bin_weights(&e).iter().all(|&w| w > 0.0));
        }
    }
    assert!(Scene::ShadowEdge { theta_deg: 95.0 }
        .validate(&[0.0, 1.0])
        .is_err());
    assert!(Scene::Sphere { radius_mm: 1.0 }
        .validate(&[0.0, 190.0])
        .is_err());
    assert!(Scene::PointLight { h_mm: 0.0 }
        .validate(&[0.0, 1.0])
        .is_err());
    assert!(Scene::PointLight { h_mm: 1.0 }
        .validate(&[1.0, 0.5])
        .is_err());
    let j = serde_json::to_string(&Scene::Sphere { radius_mm: 20.0 }).unwrap();
    assert_eq!(j, r#"{"kind":"sphere","radius_mm":20.0}"#);
    // A tiny generated set survives save → load (values rounded to 6 digits, the optics
    // exact: a reference is matched to its material by them).
    let mut m = acceptance_material(&SKIN1);
    m.sigma_a[0] *= 1.0 + 1.23e-7;
    let scenes = vec![(Scene::SlabBacklit { thickness_mm: 1.0 }, vec![0.0, 1.0])];
    let mut calls = Vec::new();
    let set = ReferenceSet::generate(&m, &scenes, 2000, 5, 2, |d, t| calls.push((d, t)));
    assert_eq!(calls, vec![(0, 3), (1, 3), (2, 3), (3, 3)]);
    let dir = std::env::temp_dir().join(format!("dermis-ref-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = file_for(&dir, "tiny");
    set.save(&path).unwrap();
    let back = ReferenceSet::load(&path).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(back.seed, 5);
    assert_eq!(
        (back.sigma_a, back.sigma_s_prime),
        (m.sigma_a, m.sigma_s_prime)
    );
    assert_eq!(back.entries[0].photons, 2000);
    for c in 0..3 {
        let (a, b) = (set.entries[0].values[0][c], back.entries[0].values[0][c]);
        assert!((a / b - 1.0).abs() < 1e-5, "{a} vs {b}");
    }
    // Deterministic: same seed, other thread count, same numbers.
    let again = ReferenceSet::generate(&m, &scenes, 2000, 5, 1, |_, _| {});
    assert_eq!(again, set);
}
