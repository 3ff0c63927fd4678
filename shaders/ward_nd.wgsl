// Ward's specular lobe, Walter's half-vector form, on nondimensional inputs.
// CPU twin: engine/src/shading/ward.rs (`lobe_nd`).
//   nl = n·l, nv = n·v (cosines); (ht, hb, hn) = h·(t, b, n) with h = l + v unnormalised;
//   f = ρ_s / (4π α_x α_y √(max(nl nv, c))) · exp(−((ht/α_x)² + (hb/α_y)²) / hn²),
//   c = WARD_COS_PRODUCT_MIN.
// Guards (hard cases of issue 4 §2):
// * cosθ_i cosθ_o → 0: the √ is taken of max(nl nv, c) (the lobe stays bounded at grazing);
// * h ∥ n: no azimuth is ever formed (φ_h undefined is harmless: ht = hb = 0 gives e = 0);
// * θ_h → 90° (hn → 0): hn ≤ 1e-6 (also l = −v) returns 0; otherwise e → −∞ and exp → 0;
// * tiny α: α is clamped to WARD_ALPHA_MIN so α_x α_y never underflows (no ∞·0).
#import real

fn ward_lobe_nd(nl: real, nv: real, ht: real, hb: real, hn: real, rho_s: real, ax: real,
                ay: real) -> real {
    if (nl <= 0.0 || nv <= 0.0 || hn <= 1e-6) {
        return 0.0;
    }
    let axc = max(ax, WARD_ALPHA_MIN);
    let ayc = max(ay, WARD_ALPHA_MIN);
    let x = ht / axc;
    let y = hb / ayc;
    let e = -(x * x + y * y) / (hn * hn);
    return rho_s / (4.0 * PI * axc * ayc * sqrt(max(nl * nv, WARD_COS_PRODUCT_MIN))) * exp(e);
}
