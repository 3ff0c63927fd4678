// The Ward anisotropic specular lobe (eq. 1), shared by `ward` and `oss`.
// CPU twin: engine/src/shading/ward.rs (`specular`, `specular_printed`); the standard form's
// maths is `ward_lobe_nd` (ward_nd.wgsl) on the cosines of the shading frame.
#import common
#import ward_nd

fn ward_specular(s: Surface, rho_s: f32, ax: f32, ay: f32) -> f32 {
    let nl = dot(s.n, s.l);
    let nv = dot(s.n, s.v);
    if (nl <= 0.0 || nv <= 0.0) {
        return 0.0;
    }
    let h = s.l + s.v;
    let hn = dot(h, s.n);
    // h ∥ -n or l = -v: no lobe (and no 0/0).
    if (hn <= 1e-6) {
        return 0.0;
    }
#ifdef WARD_PRINTED
    // As printed: tan²θ_h (cos²φ_i/α_x² + sin²φ_o/α_y²), azimuths of l and v.
    let hh = normalize(h);
    let cos_h = dot(hh, s.n);
    let tan2_h = max(1.0 - cos_h * cos_h, 0.0) / (cos_h * cos_h);
    let li = vec2<f32>(dot(s.l, s.t), dot(s.l, s.b));
    let vo = vec2<f32>(dot(s.v, s.t), dot(s.v, s.b));
    let cos2_phi_i = select(1.0, li.x * li.x / dot(li, li), dot(li, li) > 1e-12);
    let sin2_phi_o = 1.0 - select(1.0, vo.x * vo.x / dot(vo, vo), dot(vo, vo) > 1e-12);
    let e = -tan2_h * (cos2_phi_i / (ax * ax) + sin2_phi_o / (ay * ay));
    return rho_s / (4.0 * PI * ax * ay * sqrt(max(nl * nv, WARD_COS_PRODUCT_MIN))) * exp(e);
#else
    // Walter's half-vector form without angles: φ_h never needs to be defined.
    return ward_lobe_nd(nl, nv, dot(h, s.t), dot(h, s.b), hn, rho_s, ax, ay);
#endif
}
