//! The multi-scatter albedo A of a material and its reduced single-scatter albedo
//! α' = σ'_s/σ'_t, both ways, **measured by the project's Monte Carlo** (the table
//! `assets/sss/albedo.table`, baked by `dermis lut --out assets/sss --albedo-only`,
//! `dermis_measure::mc::albedo`).
//!
//! **A, precisely**: the total diffuse reflectance of the semi-infinite medium under uniform
//! (diffuse, cosine-weighted) incident light, behind a smooth Fresnel boundary of relative
//! index η, specular reflection excluded, per unit **incident** power — the colour a user sees
//! and means by "this skin's albedo", and what a texel of a skin's albedo map is in the
//! renderer (`subsurface::uniform_albedo`: the pigment's T² = A / the tier's own uniform-light
//! reflectance). Light that enters comes back with probability A_e(α', η) (the table: A_e = 1
//! for α' = 1, 0 for α' = 0); a fraction C(η) = 2∫F_t(μ)μ dμ of uniform light enters
//! ([`super::subsurface::exit_normalisation`]), so A = C(η)·A_e. A white medium reflects
//! C(η) (0.923 at η = 1.4; the rest is the boundary's specular reflection): a larger A is
//! clamped to α' = 1.
//!
//! **The table**: A_e at the η rows [`ETA_ROWS`] and α' = 1 − s², s = k/128 (dense toward
//! α' → 1, where A_e changes fastest: A_e ≈ 1 − k·s there), each row one white Monte Carlo run
//! whose nodes share their photons, so each row is monotone. The rows are 1.0, 1.1, …, 1.6
//! plus five just above η = 1 (t = √(η − 1) = 0.05, 0.10, …, 0.25): total internal
//! reflection sets in there, and A_e moves like powers of √(η − 1), so a cubic across the
//! rows 1.0/1.1/1.2 alone was up to 1.7 % off between η 1.01 and 1.07. Between η rows: cubic
//! Lagrange interpolation in t over the four nearest rows; along s: monotone cubic
//! (Fritsch–Carlson, [`super::interp`]) interpolation, inverted by bisection, so A ↔ α' is one
//! monotone map both ways.
//!
//! g: by the similarity relation the diffuse reflectance depends on the reduced albedo, so
//! α' is the same for any g (the file's anisotropy sets σ_s = σ'_s/(1 − g)); the table is
//! measured at g = 0. η outside [1.0, 1.6] is clamped to it (NaN: 1.0).

/// η of each row, rising: five rows just above 1 (t = √(η − 1) = 0.05 … 0.25), then 1.1 … 1.6.
pub const ETA_ROWS: [f64; ETA_NODES] = [
    1.0, 1.0025, 1.01, 1.0225, 1.04, 1.0625, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6,
];
/// Rows (η).
pub const ETA_NODES: usize = 12;
/// The seed offset of each row's walk: the rows 1.0, 1.1, …, 1.6 keep those they were first
/// baked with (0 … 6), the rows added near 1 take the next ones.
pub const ROW_SEED: [u64; ETA_NODES] = [0, 7, 8, 9, 10, 11, 1, 2, 3, 4, 5, 6];
/// Intervals in s = √(1 − α') over [0, 1].
pub const S_STEPS: usize = 128;
/// Nodes per row, s = k/S_STEPS (k = 0: α' = 1, A = 1; k = S_STEPS: α' = 0, A = 0).
pub const S_NODES: usize = S_STEPS + 1;

const MAGIC: &[u8; 8] = b"DERMALB2";
/// Bytes before the values: magic, rows and intervals (u32), photons per row and seed (u64),
/// the η of every row (f64).
const HEADER: usize = 8 + 4 + 4 + 8 + 8 + 8 * ETA_NODES;
/// The file's size: the header, then A and its standard error (f32) per row and node.
pub const FILE_SIZE: usize = HEADER + 2 * 4 * ETA_NODES * S_NODES;

/// The table: A and its Monte Carlo standard error per η row and s node.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub multi: [[f32; S_NODES]; ETA_NODES],
    pub std_err: [[f32; S_NODES]; ETA_NODES],
    /// Photons per row and the seed it was measured with.
    pub photons: u64,
    pub seed: u64,
}

/// The reduced albedo of node k.
pub fn node_albedo(k: usize) -> f64 {
    let s = k as f64 / S_STEPS as f64;
    1.0 - s * s
}

/// η of row i.
pub fn row_eta(i: usize) -> f64 {
    ETA_ROWS[i]
}

/// The interpolation axis across rows: t = √(η − 1) (0 for η ≤ 1 and NaN).
fn row_axis(eta: f64) -> f64 {
    if eta > 1.0 {
        (eta - 1.0).sqrt()
    } else {
        0.0
    }
}

const fn le(b: &[u8], at: usize, n: usize) -> u64 {
    let mut v = 0u64;
    let mut i = 0;
    while i < n {
        v |= (b[at + i] as u64) << (8 * i);
        i += 1;
    }
    v
}

/// Reads a table written by [`Table::to_bytes`] at compile time: a file of another layout
/// (magic, grid, size) stops the build, naming the command that bakes it.
const fn parse(b: &[u8]) -> Table {
    assert!(
        b.len() == FILE_SIZE,
        "albedo.table: wrong size (`dermis lut`)"
    );
    let mut i = 0;
    while i < 8 {
        assert!(b[i] == MAGIC[i], "albedo.table: not an albedo table");
        i += 1;
    }
    assert!(le(b, 8, 4) == ETA_NODES as u64 && le(b, 12, 4) == S_STEPS as u64);
    let mut r = 0;
    while r < ETA_NODES {
        assert!(
            le(b, 32 + 8 * r, 8) == ETA_ROWS[r].to_bits(),
            "albedo.table: other η rows (`dermis lut --albedo-only`)"
        );
        r += 1;
    }
    let mut t = Table {
        multi: [[0.0; S_NODES]; ETA_NODES],
        std_err: [[0.0; S_NODES]; ETA_NODES],
        photons: le(b, 16, 8),
        seed: le(b, 24, 8),
    };
    let mut r = 0;
    while r < ETA_NODES {
        let mut k = 0;
        while k < S_NODES {
            let at = HEADER + 4 * (r * S_NODES + k);
            t.multi[r][k] = f32::from_bits(le(b, at, 4) as u32);
            t.std_err[r][k] = f32::from_bits(le(b, at + 4 * ETA_NODES * S_NODES, 4) as u32);
            k += 1;
        }
        r += 1;
    }
    t
}

/// The shipped table.
pub static TABLE: Table = parse(include_bytes!("../../../assets/sss/albedo.table"));

impl Table {
    /// The file [`parse`] reads.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        out.extend((ETA_NODES as u32).to_le_bytes());
        out.extend((S_STEPS as u32).to_le_bytes());
        out.extend(self.photons.to_le_bytes());
        out.extend(self.seed.to_le_bytes());
        for eta in ETA_ROWS {
            out.extend(eta.to_le_bytes());
        }
        for v in self.multi.iter().chain(&self.std_err).flatten() {
            out.extend(v.to_le_bytes());
        }
        out
    }

    /// Reads bytes [`Table::to_bytes`] wrote (None for any other layout).
    pub fn from_bytes(b: &[u8]) -> Option<Table> {
        let ok = b.len() == FILE_SIZE
            && b.starts_with(MAGIC)
            && le(b, 8, 4) == ETA_NODES as u64
            && le(b, 12, 4) == S_STEPS as u64
            && (0..ETA_NODES).all(|r| le(b, 32 + 8 * r, 8) == ETA_ROWS[r].to_bits());
        ok.then(|| parse(b))
    }

    /// A at every s node for relative index `eta` (clamped to the table's range): cubic
    /// Lagrange interpolation in t = √(η − 1) over the four nearest rows.
    pub fn row(&self, eta: f64) -> [f64; S_NODES] {
        let (first, w) = super::interp::lagrange4_at(row_axis(eta), &ETA_ROWS.map(row_axis));
        std::array::from_fn(|k| {
            (0..4)
                .map(|i| w[i] * f64::from(self.multi[first + i][k]))
                .sum::<f64>()
                .clamp(0.0, 1.0)
        })
    }
}

/// The monotone cubic through a row at s ∈ [0, 1].
fn hermite(y: &[f64; S_NODES], s: f64) -> f64 {
    super::interp::monotone(y, s.clamp(0.0, 1.0) * S_STEPS as f64)
}

/// A clean albedo in [0, 1] (NaN → 0).
fn unit(x: f64) -> f64 {
    if x > 0.0 {
        x.min(1.0)
    } else {
        0.0
    }
}

/// η clamped to the table's rows (NaN → the first).
fn table_eta(eta: f64) -> f64 {
    let (first, last) = (ETA_ROWS[0], ETA_ROWS[ETA_NODES - 1]);
    if eta > first {
        eta.min(last)
    } else {
        first
    }
}

/// The multi-scatter albedo A (per incident power, see the module docs) of a medium with
/// reduced single-scatter albedo `single` = α' = σ'_s/σ'_t, relative index `eta` and
/// anisotropy `g` (the same A for any g: similarity). Inputs are clamped: α' to [0, 1]
/// (NaN → 0), η to [1.0, 1.6]. The result is in [0, C(η)].
pub fn multi_scatter_albedo(single: f64, eta: f64, g: f64) -> f64 {
    let _ = g;
    let eta = table_eta(eta);
    let y = TABLE.row(eta);
    let entered = hermite(&y, (1.0 - unit(single)).sqrt()).clamp(0.0, 1.0);
    entered * super::subsurface::exit_normalisation(eta)
}

/// The reduced single-scatter albedo α' = σ'_s/σ'_t whose medium has multi-scatter albedo
/// `multi` = A (per incident power) at relative index `eta`, anisotropy `g`: the inverse of
/// [`multi_scatter_albedo`]. A is clamped to [0, 1] (NaN → 0), η to [1.0, 1.6]; A ≥ C(η)
/// (more than a white medium reflects) gives α' = 1.
pub fn single_scatter_albedo(multi: f64, eta: f64, g: f64) -> f64 {
    let _ = g;
    let eta = table_eta(eta);
    let a = unit(multi) / super::subsurface::exit_normalisation(eta);
    if a >= 1.0 {
        return 1.0;
    }
    let y = TABLE.row(eta);
    // A falls with s: bisection on the monotone interpolant.
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if hermite(&y, mid) > a {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let s = 0.5 * (lo + hi);
    (1.0 - s * s).clamp(0.0, 1.0)
}

/// A homogeneous material made from its multi-scatter albedo `multi` (per channel, per
/// incident power) and reduced mean free path `mfp_mm` = 1/σ'_t (mm, per channel) at relative
/// index `eta` and anisotropy `g`: α' = [`single_scatter_albedo`], σ'_s = α'σ'_t,
/// σ_a = (1 − α')σ'_t. A non-positive or non-finite mean free path counts as 1 mm.
pub fn material(
    name: &'static str,
    multi: [f64; 3],
    mfp_mm: [f64; 3],
    eta: f64,
    g: f64,
) -> super::Material {
    let sigma_t = mfp_mm.map(|l| {
        if l > 0.0 && l.is_finite() {
            1.0 / l
        } else {
            1.0
        }
    });
    let single: [f64; 3] = std::array::from_fn(|c| single_scatter_albedo(multi[c], eta, g));
    super::Material {
        name: name.into(),
        origin: super::material::Origin::Builtin,
        sigma_a: std::array::from_fn(|c| (1.0 - single[c]) * sigma_t[c]),
        sigma_s_prime: std::array::from_fn(|c| single[c] * sigma_t[c]),
        eta,
        g,
        textured: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_table_is_complete_monotone_and_pinned_at_its_ends() {
        for (r, row) in TABLE.multi.iter().enumerate() {
            assert_eq!(row[0], 1.0, "row {r}: A(α' = 1) = 1");
            assert_eq!(row[S_NODES - 1], 0.0, "row {r}: A(α' = 0) = 0");
            assert!(row.windows(2).all(|p| p[0] >= p[1]), "row {r} not monotone");
        }
        // A higher index keeps more light inside to be absorbed: A falls with η.
        for k in 1..S_NODES - 1 {
            assert!(
                TABLE.multi[ETA_NODES - 1][k] < TABLE.multi[0][k],
                "node {k}"
            );
        }
        assert!(TABLE.photons >= 100_000);
        assert_eq!(Table::from_bytes(&TABLE.to_bytes()).as_ref(), Some(&TABLE));
        assert_eq!(Table::from_bytes(&TABLE.to_bytes()[1..]), None);
    }

    #[test]
    fn the_two_ways_invert_each_other() {
        for eta in [1.0, 1.05, 1.3, 1.4, 1.55, 1.6] {
            let white = crate::shading::subsurface::exit_normalisation(eta);
            assert!((multi_scatter_albedo(1.0, eta, 0.0) - white).abs() < 1e-12);
            // More than a white medium reflects is white.
            assert_eq!(single_scatter_albedo(white + 1e-6, eta, 0.0), 1.0);
            let mut last = -1.0;
            for i in 0..200 {
                let a = white * i as f64 / 200.0;
                let s = single_scatter_albedo(a, eta, 0.0);
                assert!(s >= last, "η {eta}: α' must rise with A");
                last = s;
                let back = multi_scatter_albedo(s, eta, 0.0);
                assert!((back - a).abs() < 1e-9, "η {eta}: A {a} → α' {s} → {back}");
            }
        }
        assert_eq!(single_scatter_albedo(1.0, 1.4, 0.0), 1.0);
        assert_eq!(single_scatter_albedo(0.0, 1.4, 0.0), 0.0);
    }

    #[test]
    fn a_material_made_from_its_albedo_has_it() {
        let m = material("t", [0.2, 0.5, 0.9], [1.0, 0.5, 2.0], 1.4, 0.0);
        let back = m.albedo().map(|a| multi_scatter_albedo(a, 1.4, 0.0));
        for c in 0..3 {
            assert!((back[c] - [0.2, 0.5, 0.9][c]).abs() < 1e-9);
        }
        assert!((m.sigma_t_prime()[1] - 2.0).abs() < 1e-12);
        let bad = material("t", [0.5; 3], [0.0, f64::NAN, -1.0], 1.4, 0.0);
        assert!(bad.sigma_t_prime().iter().all(|t| (t - 1.0).abs() < 1e-12));
    }

    #[test]
    fn absurd_inputs_are_clamped_not_propagated() {
        for x in [f64::NAN, -1.0, 2.0, f64::INFINITY, f64::NEG_INFINITY] {
            for eta in [f64::NAN, 0.0, -1.0, 1e9, 1.4] {
                let (a, s) = (
                    multi_scatter_albedo(x, eta, x),
                    single_scatter_albedo(x, eta, x),
                );
                assert!((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&s));
            }
        }
        assert_eq!(
            multi_scatter_albedo(0.9, 2.5, 0.0),
            multi_scatter_albedo(0.9, 1.6, 0.0)
        );
    }
    #[test]
    fn the_measured_spatial_tiers_reflect_the_tables_albedo_under_uniform_light() {
        // The tiers built from the Monte Carlo's tables (skin1 at η = 1.4, shipped) reflect,
        // under uniform light, what the albedo table says this medium reflects: A per
        // incident power (`subsurface::uniform_albedo`, the renderer's pigment normalisation),
        // within 4 % (measured: −0.8/−1.1/−3.0 % in R/G/B, both tiers: they share the tables'
        // per-pixel part; the kernel's rings and q(μ)'s seven nodes).
        use crate::shading::material::SKIN1;
        use crate::shading::subsurface::SubsurfaceUniform;
        use crate::shading::ShadingModel;
        let m = crate::shading::Material { eta: 1.4, ..SKIN1 };
        let a = m.albedo().map(|s| multi_scatter_albedo(s, m.eta, 0.0));
        for model in [ShadingModel::Tabulated, ShadingModel::Preintegrated] {
            let p = model.params(&m);
            let u: &SubsurfaceUniform = p.uniform();
            for (ch, (r, want)) in u.uniform_albedo.iter().zip(a).enumerate() {
                let r = f64::from(*r);
                assert!(
                    (r / want - 1.0).abs() < 0.04,
                    "{model} ch{ch}: {r} vs A {want}"
                );
            }
        }
    }
}
