// Christensen–Burley's normalised diffusion on nondimensional inputs.
// CPU twin: core/src/shading/burley.rs (`rd_nd`).
//   x = k r (k = s/ℓ), a = surface albedo A; returns R / k² = A (e^{−x} + e^{−x/3}) / (8π x).
// Domain x > 0 (the caller clamps r ≥ R_MIN_MM); f16: x ≥ 1e-3.
#import real

fn burley_rd_nd(x: vec3<real>, a: vec3<real>) -> vec3<real> {
    return a * (exp(-x) + exp(-x / 3.0)) / (8.0 * ND_PI * x);
}
