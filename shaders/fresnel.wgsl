// Fresnel transmittance for light crossing from outside (index 1) into a medium of relative
// index eta, at incidence cosine cos_i. CPU twin: core/src/shading/fresnel.rs.

fn fresnel_transmittance(eta: f32, cos_i: f32) -> f32 {
    let c = clamp(cos_i, 0.0, 1.0);
    let sin_t2 = (1.0 - c * c) / (eta * eta);
    if (sin_t2 >= 1.0) {
        return 0.0;
    }
    let cos_t = sqrt(1.0 - sin_t2);
    let rs = (c - eta * cos_t) / (c + eta * cos_t);
    let rp = (eta * c - cos_t) / (eta * c + cos_t);
    return clamp(1.0 - 0.5 * (rs * rs + rp * rp), 0.0, 1.0);
}
