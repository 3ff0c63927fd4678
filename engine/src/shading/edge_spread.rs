//! The edge-spread function of a diffusion kernel: the fraction of the light a flat medium
//! returns at signed distance d (mm) from a straight shadow edge (d > 0 on the lit side),
//! relative to the fully lit medium. Exitance there is the kernel integrated over the lit
//! half-plane, ESF(d) = ∫_{x < d} LSF(x) dx / ∫ LSF, so the shadow bleeds as far as the
//! material carries light. A model with the `penumbra` effect reads it from a row of its LUT,
//! indexed by the distance the penumbra map gives (`render/passes/penumbra.rs`).

use super::bake::Bake;
use super::material::Material;

/// The LUT row spans d ∈ [−SPAN, SPAN] mm, quadratically (fine near the edge, where the
/// function turns; coarse in the tails, stored as log2 so exponential tails interpolate).
pub const SPAN_MM: f64 = 128.0;

/// The shadow test's ramp across a straight edge, in shadow-map texels: `light_visible_coord`
/// (`shaders/common.wgsl`) averages bilinear comparisons half this less a half texel either
/// side, so its visibility rises linearly over this width; `penumbra()` reads the edge's place
/// from it (and the renderer's shadow view sets its normal offset from it).
pub const SHADOW_RAMP_TEXELS: f32 = 2.0;

/// How many diffusion lengths into the shadow the edge-spread function is carried: its tail
/// falls off as e^(−d/ℓ), so past this many lengths what bleeds is under ~10⁻⁴ of the lit
/// plateau (the path-traced edge scenes are scored out to 10ℓ of the longest channel).
pub const REACH_LENGTHS: f64 = 12.0;

/// The longest diffusion length ℓ = 1/σ_tr of `m`'s channels (mm; the widest the shadow
/// bleeds), [`SPAN_MM`] for a medium that barely absorbs.
pub fn diffusion_length_mm(m: &Material) -> f64 {
    let longest = m
        .sigma_tr()
        .into_iter()
        .map(|s| if s > 0.0 { 1.0 / s } else { f64::INFINITY })
        .fold(0.0, f64::max);
    if longest.is_finite() {
        longest.min(SPAN_MM)
    } else {
        SPAN_MM
    }
}

/// How far from an edge (mm) `m`'s edge-spread function differs from a hard shadow by more
/// than its far tail: [`REACH_LENGTHS`] diffusion lengths, at most the LUT row's span.
pub fn reach_mm(m: &Material) -> f64 {
    (REACH_LENGTHS * diffusion_length_mm(m)).min(SPAN_MM)
}

/// Area of the part of a disk of radius `r` (centred at 0) with x < d.
fn disk_below(r: f64, d: f64) -> f64 {
    if d >= r {
        std::f64::consts::PI * r * r
    } else if d <= -r {
        0.0
    } else {
        r * r * (std::f64::consts::PI - (d / r).acos()) + d * (r * r - d * d).sqrt()
    }
}

/// ESF of channel `c` of the measured kernel `b` (power uniform over each ring's area).
pub fn esf(b: &Bake, c: usize, d: f64) -> f64 {
    let mut lit = 0.0;
    let mut total = 0.0;
    for (w, m) in b.edges.windows(2).zip(&b.mass) {
        let (a, o) = (w[0], w[1]);
        let area = std::f64::consts::PI * (o * o - a * a);
        if area <= 0.0 {
            continue;
        }
        lit += m[c] * (disk_below(o, d) - disk_below(a, d)) / area;
        total += m[c];
    }
    if total > 0.0 {
        (lit / total).clamp(0.0, 1.0)
    } else if d >= 0.0 {
        1.0
    } else {
        0.0
    }
}

/// The distance (mm) of LUT column `i` of `columns`.
pub fn column_distance(i: usize, columns: usize) -> f64 {
    let t = 2.0 * i as f64 / (columns - 1).max(1) as f64 - 1.0;
    SPAN_MM * t * t.abs()
}

/// The LUT row: log2 ESF per channel over [`column_distance`].
pub fn lut_row(b: &Bake, columns: usize) -> Vec<[f32; 4]> {
    (0..columns)
        .map(|i| {
            let d = column_distance(i, columns);
            let v = |c| (esf(b, c, d).max(1e-30)).log2() as f32;
            [v(0), v(1), v(2), 1.0]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::bake::RINGS;

    /// A kernel with the profile of a 2D exponential of length `ell` mm, in rings.
    fn kernel(ell: f64) -> Bake {
        let edges: Vec<f64> = (0..=RINGS + 1)
            .map(|k| 0.05 * 1.4f64.powi(k as i32) - 0.05)
            .collect();
        let mass = edges
            .windows(2)
            .map(|w| {
                // ∫ e^{-r/ℓ} 2πr dr over the ring, per unit total.
                let f = |r: f64| -(r / ell + 1.0) * (-r / ell).exp();
                let m = f(w[1]) - f(w[0]);
                [m, m, m]
            })
            .collect();
        Bake {
            edges,
            mass,
            oblique: [[1.0; 3]; crate::shading::bake::OBLIQUE_NODES],
            shift: [[0.0; 3]; crate::shading::bake::OBLIQUE_NODES],
            slab: [[0.0; 3]; crate::shading::bake::SLAB_NODES],
        }
    }

    #[test]
    fn half_at_the_edge_monotone_and_bounded() {
        let b = kernel(2.0);
        assert!((esf(&b, 0, 0.0) - 0.5).abs() < 1e-9);
        let mut last = 0.0;
        for i in 0..64 {
            let v = esf(&b, 0, column_distance(i, 64));
            assert!((0.0..=1.0).contains(&v) && v >= last, "column {i}: {v}");
            last = v;
        }
        // Symmetric: ESF(−d) = 1 − ESF(d).
        for d in [0.3, 1.0, 4.0, 10.0] {
            assert!((esf(&b, 0, -d) + esf(&b, 0, d) - 1.0).abs() < 1e-9);
        }
        assert!(esf(&b, 0, 40.0) > 0.999 && esf(&b, 0, -40.0) < 1e-3);
    }

    #[test]
    fn a_wider_kernel_bleeds_further_into_the_shadow() {
        let (narrow, wide) = (kernel(1.0), kernel(4.0));
        for d in [1.0, 3.0, 10.0] {
            assert!(esf(&wide, 0, -d) > esf(&narrow, 0, -d) * 1.5, "d {d}");
        }
        // The far tail falls off exponentially, not to zero at a filter's edge.
        let (a, b) = (esf(&wide, 0, -20.0), esf(&wide, 0, -30.0));
        assert!(a > 0.0 && b > 0.0 && b < a);
    }

    #[test]
    fn the_reach_follows_the_longest_diffusion_length() {
        use crate::shading::material::{SKIN1, WHITE_COAT};
        let l = diffusion_length_mm(&SKIN1);
        // Red is skin's longest channel: 1/sqrt(3 σ_a σ'_t).
        let red = 1.0 / (3.0 * SKIN1.sigma_a[0] * SKIN1.sigma_t_prime()[0]).sqrt();
        assert!((l - red).abs() < 1e-9, "{l} vs {red}");
        assert!((reach_mm(&SKIN1) - REACH_LENGTHS * red).abs() < 1e-9);
        // A medium that barely absorbs carries light across the whole row.
        assert!(diffusion_length_mm(&WHITE_COAT) > l);
        assert_eq!(reach_mm(&WHITE_COAT), SPAN_MM);
        let clear = Material {
            sigma_a: [0.0; 3],
            ..SKIN1
        };
        assert_eq!(diffusion_length_mm(&clear), SPAN_MM);
    }

    #[test]
    fn columns_span_both_sides_finely_near_the_edge() {
        assert_eq!(column_distance(0, 64), -SPAN_MM);
        assert_eq!(column_distance(63, 64), SPAN_MM);
        assert!(column_distance(32, 64) > 0.0 && column_distance(32, 64) < 0.1);
        let row = lut_row(&kernel(2.0), 64);
        assert_eq!(row.len(), 64);
        assert!(row.iter().all(|t| t[0].is_finite() && t[0] <= 0.0));
    }
}
