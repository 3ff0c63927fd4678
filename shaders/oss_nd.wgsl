// OSS-stable's f_d on nondimensional inputs. CPU twin: engine/src/shading/oss.rs (`f_d_stable_nd`).
//   a = σ_a d, sp = σ'_s P(g) d (optical depths), f = F_dr(η):
//   f_d = (1 − f) (top + f e^{−(a + sp)}),  top = 1 − e^{−y} = y E(y),  y = sp E(2a),
//   E(x) = (1 − e^{−x})/x: sp E(2a) = σ'_s P ∫₀^d e^{−2σ_a x} dx.
// Both 1 − e^{−·} are formed as x E(x), so nothing cancels at d → 0; every term is in [0, 1].
#import real

// E(x) = (1 − e^{−x})/x for x ≥ 0, E(0) = 1: a degree-5 Taylor polynomial below 0.25
// (truncation ≤ 0.25⁶/5040 < 5e-8), the quotient above (cancellation ≤ 2 ulp / 0.22).
fn one_minus_exp_over_x(x: vec3<real>) -> vec3<real> {
    let series = 1.0 + x * (-0.5 + x * (1.0 / 6.0 + x * (-1.0 / 24.0 + x * (1.0 / 120.0 - x / 720.0))));
    let quotient = (1.0 - exp(-x)) / max(x, vec3<real>(0.25));
    return select(quotient, series, x < vec3<real>(0.25));
}

fn oss_fd_stable_nd(a: vec3<real>, sp: vec3<real>, f: real) -> vec3<real> {
    let y = sp * one_minus_exp_over_x(2.0 * a);
    let top = y * one_minus_exp_over_x(y);
    let bottom = f * exp(-(a + sp));
    return (1.0 - f) * (top + bottom);
}
