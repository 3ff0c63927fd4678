// Jensen's dipole R_d on nondimensional inputs (lengths in units of ℓ = 1/σ'_t).
// CPU twin: engine/src/shading/dipole.rs (`rd_nd`).
//   rho = r / ℓ = σ'_t r;  s = σ_tr ℓ = √(3 (1 − α')), with 1 − α' = σ_a/σ'_t (no
//   cancellation at α' → 1);  zv = z_v / ℓ = 1 + 4A/3;  so σ_tr r = s·rho.
//   Returns R_d ℓ² = α'/(4π) [ (s d_r + 1) e^{−s d_r} / d_r³ + zv (s d_v + 1) e^{−s d_v} / d_v³ ],
//   d_r = √(1 + rho²), d_v = √(zv² + rho²) (both ≥ 1: no singularity at r = 0).
// f32 domain: rho ≤ 1e18 (rho² must not overflow); f16 domain: rho ≤ 30 (d³ < 65504).
#import real

fn dipole_rd_nd(rho: vec3<real>, s: vec3<real>, zv: real, albedo: vec3<real>) -> vec3<real> {
    let rho2 = rho * rho;
    let dr = sqrt(1.0 + rho2);
    let dv = sqrt(zv * zv + rho2);
    let src = (s * dr + 1.0) * exp(-s * dr) / (dr * dr * dr);
    let virt = zv * (s * dv + 1.0) * exp(-s * dv) / (dv * dv * dv);
    return albedo * (0.25 * INV_PI) * (src + virt);
}
