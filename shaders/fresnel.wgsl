// Fresnel transmittance for light crossing from outside (index 1) into a medium of relative
// index eta, at incidence cosine cos_i. CPU twin: engine/src/shading/fresnel.rs.
// Nondimensional (η, a cosine), so it is written in `real` (f32 in the renderer).
// Stable form: with q = η² cos²θ_t = (η − 1)(η + 1) + cos²θ_i, 1 − r_s² = 4c√q/(c + √q)² and
// 1 − r_p² = 4η²c√q/(η²c + √q)², so F_t = 2c√q (1/(c + √q)² + η²/(η²c + √q)²): a sum of
// positive terms. The textbook 1 − (r_s² + r_p²)/2 cancels at grazing incidence (r → −1) and
// 1 − (1 − c²)/η² rounds to 0 for c² below half an ulp (η = 1 then gave F_t = 0 instead of 1
// at 89.99°). Hard cases: cos_i ≤ 0 gives 0; past the critical angle (η < 1, q ≤ 0) gives 0;
// η = 1 gives 1 for every cos_i > 0. f16: accurate for cos_i ≥ 0.01 (q in the normal range).
#import real

fn fresnel_transmittance(eta: real, cos_i: real) -> real {
    let c = clamp(cos_i, 0.0, 1.0);
    let q = (eta - 1.0) * (eta + 1.0) + c * c;
    if (q <= 0.0 || c <= 0.0) {
        return 0.0;
    }
    let w = sqrt(q);
    let e2 = eta * eta;
    let a = c + w;
    let b = e2 * c + w;
    return clamp(2.0 * c * w * (1.0 / (a * a) + e2 / (b * b)), 0.0, 1.0);
}
