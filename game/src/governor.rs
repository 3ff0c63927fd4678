//! Per-frame choice of the character's shading tier, and the frame-time governor.
//!
//! Pure logic (no GPU, no clock): callers feed it what the frame needs and what frames cost,
//! so tests drive it with a simulated cost model.
//!
//! # Tiers
//! An ordered list, richest first: the player's chosen model, then the models of the measured
//! accuracy–cost front ([`front`], as `bench shading` measured it) that are cheaper than
//! it. `dermis bench shading` measures every model's error against the path-traced
//! references and its Mali-G57 cycles per pixel at close-up, and writes the front, richest
//! first, to `docs/results/governor-front.txt`, which this module embeds: nothing here is
//! copied by hand. The front weighs the scanned face as well as the probes: a model on the
//! probes' front that is worse on the face than a cheaper tier below it is left off, so a
//! step down never makes the face look better. A choice on the front steps down to the front models after it; a
//! screen-space choice off the front to the one-pass front models; any other to the front's
//! floor, the front's last tier, a plain BRDF. Every tier's pipeline is built at load by the
//! renderer, so a tier change creates nothing on the GPU.
//!
//! # What a frame needs ([`Needs`])
//! - **coverage**: the character's projected screen coverage (fraction of the frame covered by
//!   its projected bounding box, [`projected_coverage`]). Below [`GovernorConfig::mid_coverage`]
//!   (1 %: at 720p a box of about 45 × 200 px, a 1.8 m character at ~9 mm of skin per pixel,
//!   wider than skin's diffusion radius of a few mm) the chosen model's subsurface detail is
//!   not resolvable and the middle tier is used; below [`GovernorConfig::low_coverage`]
//!   (0.2 %) or off screen, the cheapest tier. The runner's play camera keeps the character at
//!   about 2 % of the frame, so in play the chosen model is drawn unless the budget says no. Both thresholds
//!   have a hysteresis band ([`GovernorConfig::coverage_band`]) so a character hovering at a
//!   threshold does not flip every frame.
//! - **lit**: whether the point light reaches the character ([`light_reaches`]); unlit skin
//!   shows no transmitted light, so it takes the cheapest tier.
//! - the **frame budget**: the frame-time governor below.
//!
//! The tier drawn is the cheapest (largest index) of the coverage tier and the governor's tier.
//!
//! # Frame-time governor
//! It tracks an exponential moving average (EMA) of the frame cost. Time is the sum of the
//! `dt` it is given, never the wall clock.
//! - **Down**: when the EMA exceeds `target_ms × down_ratio` and at least `window_s` has passed
//!   since the last change, it steps one tier cheaper.
//! - **Up**: when the EMA, scaled by the cost ratio between the richer tier and this one
//!   (learnt from the EMA of the windows just before and just after the last change between
//!   them, or `assumed_step_ratio` when never measured), would stay under
//!   `target_ms × up_ratio`, and at least the up-dwell has passed since the last change, it
//!   steps one tier richer. The up-dwell starts at `2 × window_s` and doubles (up to
//!   `max_up_dwell_s`) each time a step up is undone within `revert_s`: a tier that does not
//!   fit is retried ever more rarely, so the governor does not oscillate.
//! - At most one change per `window_s` (the hysteresis window), in either direction.
//! - After a change the EMA restarts from the next sample, so the decision after a change
//!   uses frames of the new tier only.

use glam::{Mat4, Vec3, Vec4};

use dermis_engine::scene::CHARACTER;
use dermis_engine::shading::ShadingModel;

/// The most tiers a list holds.
pub const MAX_TIERS: usize = 3;

/// The measured accuracy–cost front, richest first, as `dermis bench shading` wrote it
/// (overall error against Mali-G57 cycles, less any model worse on the face than a cheaper
/// tier): the tiers a choice steps down to.
const FRONT_FILE: &str = include_str!("../../docs/results/governor-front.txt");

/// [`FRONT_FILE`]'s models (at most [`MAX_TIERS`]; names the registry does not know are
/// skipped, so a stale file degrades to fewer tiers, never to a wrong one).
pub fn front() -> &'static [ShadingModel] {
    static FRONT: std::sync::OnceLock<Vec<ShadingModel>> = std::sync::OnceLock::new();
    FRONT.get_or_init(|| parse_front(FRONT_FILE))
}

/// The models of a front file: one name per line, `#` comments.
pub fn parse_front(text: &str) -> Vec<ShadingModel> {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .filter_map(|l| l.parse().ok())
        .take(MAX_TIERS)
        .collect()
}

/// The ordered tier list, richest first (no allocation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tiers {
    models: [ShadingModel; MAX_TIERS],
    len: usize,
}

impl Tiers {
    /// `[chosen]` followed by the [`front`] models cheaper than it: those after it on the
    /// front; for a model off the front, the one-pass front models if it is screen-space,
    /// else the front's floor (see the module docs).
    pub fn for_choice(chosen: ShadingModel) -> Self {
        let mut t = Tiers {
            models: [chosen; MAX_TIERS],
            len: 1,
        };
        let front = front();
        let on_front = front.iter().position(|&m| m == chosen);
        let cheaper = front.iter().enumerate().filter(|&(i, m)| match chosen {
            // A model with no subsurface transport (a plain BRDF) is already the floor.
            c if !c.effects().subsurface => false,
            _ if on_front.is_some() => Some(i) > on_front,
            c if c.effects().screen_space => !m.effects().screen_space,
            _ => i + 1 == front.len(),
        });
        for (_, &m) in cheaper {
            if t.len < MAX_TIERS && !t.models[..t.len].contains(&m) {
                t.models[t.len] = m;
                t.len += 1;
            }
        }
        t
    }

    /// A list of 1..=MAX_TIERS models, richest first.
    pub fn new(models: &[ShadingModel]) -> Self {
        assert!(!models.is_empty() && models.len() <= MAX_TIERS);
        let mut t = Tiers {
            models: [models[0]; MAX_TIERS],
            len: models.len(),
        };
        t.models[..models.len()].copy_from_slice(models);
        t
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn as_slice(&self) -> &[ShadingModel] {
        &self.models[..self.len]
    }

    /// The model of tier `i` (clamped to the cheapest).
    pub fn model(&self, i: usize) -> ShadingModel {
        self.models[i.min(self.len - 1)]
    }

    /// Index of the cheapest tier.
    pub fn last(&self) -> usize {
        self.len - 1
    }
}

/// What this frame needs from the character's shading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Needs {
    /// Projected screen coverage of the character, 0..=1 (0: off screen).
    pub coverage: f32,
    /// Whether a light reaches the character.
    pub lit: bool,
}

impl Needs {
    /// What a frame needs for a character standing at `feet` (the player transform's origin)
    /// seen through `view_proj`: the coverage of its [`character_box`], and whether a point
    /// light of `light_intensity` at `light_pos` delivers [`MIN_IRRADIANCE`] to its chest.
    pub fn of_character(
        view_proj: Mat4,
        feet: Vec3,
        light_pos: Vec3,
        light_intensity: f32,
    ) -> Self {
        let (min, max) = character_box(feet);
        let chest = CHARACTER.chest_at(feet);
        Self {
            coverage: projected_coverage(view_proj, min, max),
            lit: light_reaches(light_pos, light_intensity, chest, MIN_IRRADIANCE),
        }
    }
}

/// Minimum irradiance (W/m² at the character's chest) for "a light reaches it".
pub const MIN_IRRADIANCE: f32 = 0.2;

/// The character's bounding box (feet at the origin of the player transform): the one
/// [`CHARACTER`] bound's.
pub fn character_box(feet: Vec3) -> (Vec3, Vec3) {
    CHARACTER.box_at(feet)
}

impl Default for Needs {
    fn default() -> Self {
        Self {
            coverage: 1.0,
            lit: true,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GovernorConfig {
    /// Frame budget (ms), e.g. 16.67 at 60 FPS.
    pub target_ms: f64,
    /// Step down when the EMA exceeds `target_ms × down_ratio`.
    pub down_ratio: f64,
    /// Step up only when the predicted cost of the richer tier stays under `target_ms × up_ratio`.
    pub up_ratio: f64,
    /// Hysteresis window (s): at most one tier change per window.
    pub window_s: f64,
    /// EMA weight of a new sample.
    pub ema_alpha: f64,
    /// Cost ratio richer/cheaper tier assumed before it was measured.
    pub assumed_step_ratio: f64,
    /// A step up undone within this time (s) doubles the up-dwell.
    pub revert_s: f64,
    /// Longest up-dwell (s).
    pub max_up_dwell_s: f64,
    /// Coverage below which the middle tier is used.
    pub mid_coverage: f32,
    /// Coverage below which the cheapest tier is used.
    pub low_coverage: f32,
    /// Relative hysteresis band of the coverage thresholds (0.25: leave a tier at
    /// `threshold`, come back above `threshold × 1.25`).
    pub coverage_band: f32,
}

impl GovernorConfig {
    pub fn for_fps(fps: f64) -> Self {
        Self {
            target_ms: 1000.0 / fps,
            down_ratio: 1.0,
            up_ratio: 0.9,
            window_s: 1.0,
            ema_alpha: 0.1,
            assumed_step_ratio: 1.5,
            revert_s: 4.0,
            max_up_dwell_s: 32.0,
            mid_coverage: 0.01,
            low_coverage: 0.002,
            coverage_band: 0.25,
        }
    }
}

/// A tier change the governor made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    Down,
    Up,
}

/// Tier selection + frame-time governor for one character.
#[derive(Clone, Debug)]
pub struct Governor {
    pub config: GovernorConfig,
    tiers: Tiers,
    /// Whether the frame-time governor acts (off: only coverage / light choose).
    pub enabled: bool,
    /// Whether coverage and light choose (off: only the governor).
    pub scheduling: bool,
    budget_tier: usize,
    coverage_tier: usize,
    /// The tier `select` last returned.
    drawn: usize,
    ema: Option<f64>,
    /// Cost of tier `i` over tier `i + 1`, learnt from the windows either side of a change.
    step_ratio: [f64; MAX_TIERS],
    /// After a change: (richer tier of the pair, whether the change went down, EMA before).
    learning: Option<(usize, bool, f64)>,
    time_s: f64,
    last_change_s: f64,
    last_up_s: f64,
    up_dwell_s: f64,
    changes: u64,
}

impl Governor {
    pub fn new(tiers: Tiers, config: GovernorConfig) -> Self {
        Self {
            config,
            tiers,
            enabled: true,
            scheduling: true,
            budget_tier: 0,
            coverage_tier: 0,
            drawn: 0,
            ema: None,
            step_ratio: [f64::NAN; MAX_TIERS],
            learning: None,
            time_s: 0.0,
            last_change_s: f64::NEG_INFINITY,
            last_up_s: f64::NEG_INFINITY,
            up_dwell_s: 2.0 * config.window_s,
            changes: 0,
        }
    }

    pub fn tiers(&self) -> &Tiers {
        &self.tiers
    }

    /// Starts over with `tiers` (the player chose another model), keeping the configuration
    /// and the switches.
    pub fn retier(&mut self, tiers: Tiers) {
        let (enabled, scheduling) = (self.enabled, self.scheduling);
        *self = Self::new(tiers, self.config);
        self.enabled = enabled;
        self.scheduling = scheduling;
    }

    /// The tier [`Self::select`] returned last.
    pub fn drawn(&self) -> usize {
        self.drawn
    }

    /// The tier index to draw this frame (call before rendering it).
    pub fn select(&mut self, needs: Needs) -> usize {
        if self.scheduling {
            self.coverage_tier = self.coverage_tier_for(needs);
        } else {
            self.coverage_tier = 0;
        }
        let budget = if self.enabled { self.budget_tier } else { 0 };
        self.drawn = self.coverage_tier.max(budget).min(self.tiers.last());
        self.drawn
    }

    /// The model to draw this frame.
    pub fn select_model(&mut self, needs: Needs) -> ShadingModel {
        let i = self.select(needs);
        self.tiers.model(i)
    }

    fn coverage_tier_for(&self, needs: Needs) -> usize {
        let last = self.tiers.last();
        if !needs.lit || needs.coverage <= 0.0 {
            return last;
        }
        let c = &self.config;
        let band = 1.0 + c.coverage_band;
        // Thresholds for tier 0 (≥ mid) and tier 1 (≥ low); a tier is left when coverage
        // drops below its threshold and re-entered only above threshold × band.
        let want = |cur: usize| -> usize {
            let (mid, low) = (c.mid_coverage, c.low_coverage);
            let mid_t = if cur >= 1 { mid * band } else { mid };
            let low_t = if cur >= 2 { low * band } else { low };
            if needs.coverage >= mid_t {
                0
            } else if needs.coverage >= low_t {
                1
            } else {
                2
            }
        };
        want(self.coverage_tier).min(last)
    }

    /// The governor's own tier (frame budget only).
    pub fn budget_tier(&self) -> usize {
        self.budget_tier
    }

    /// Sustained frame cost (EMA, ms); `None` right after a change.
    pub fn ema_ms(&self) -> Option<f64> {
        self.ema
    }

    /// Tier changes made by the frame-time governor so far.
    pub fn changes(&self) -> u64 {
        self.changes
    }

    /// Feeds the cost `frame_ms` (NaN when unknown) of the frame drawn at the tier `select`
    /// returned last, and the time it covered (`dt_s`). Returns the change made, if any.
    pub fn record(&mut self, frame_ms: f64, dt_s: f64) -> Option<Change> {
        self.time_s += dt_s.max(0.0);
        if !frame_ms.is_finite() || !self.enabled {
            return None;
        }
        let a = self.config.ema_alpha;
        let ema = match self.ema {
            Some(e) => e + a * (frame_ms - e),
            None => frame_ms,
        };
        self.ema = Some(ema);
        let since = self.time_s - self.last_change_s;
        let c = self.config;
        // While coverage or light force a cheaper tier than the budget's, frame costs say
        // nothing about the budget's tier: no change.
        if since < c.window_s || self.drawn != self.budget_tier {
            return None;
        }
        // The first full window after a change, at (nearly) the same load as the window
        // before it: learn the cost ratio of the pair.
        if let Some((richer, down, before)) = self.learning.take() {
            let ratio = if down { before / ema } else { ema / before };
            if ratio.is_finite() && ratio > 0.0 {
                self.step_ratio[richer] = ratio.max(1.0);
            }
        }
        if ema > c.target_ms * c.down_ratio && self.budget_tier < self.tiers.last() {
            if self.time_s - self.last_up_s < c.revert_s {
                self.up_dwell_s = (self.up_dwell_s * 2.0).min(c.max_up_dwell_s);
            }
            self.learning = Some((self.budget_tier, true, ema));
            self.budget_tier += 1;
            return Some(self.changed(Change::Down));
        }
        if self.budget_tier > 0 && since >= self.up_dwell_s {
            let learnt = self.step_ratio[self.budget_tier - 1];
            let ratio = if learnt.is_finite() {
                learnt
            } else {
                c.assumed_step_ratio
            };
            if ema * ratio < c.target_ms * c.up_ratio {
                self.budget_tier -= 1;
                self.learning = Some((self.budget_tier, false, ema));
                self.last_up_s = self.time_s;
                return Some(self.changed(Change::Up));
            }
        }
        None
    }

    fn changed(&mut self, change: Change) -> Change {
        self.last_change_s = self.time_s;
        self.ema = None;
        self.changes += 1;
        change
    }
}

/// Fraction of the frame (0..=1) covered by the screen-space bounding rectangle of the
/// projected box `min..max`. 0 when the box is entirely behind the camera or off screen; a
/// box straddling the camera plane counts as covering the whole frame.
pub fn projected_coverage(view_proj: Mat4, min: Vec3, max: Vec3) -> f32 {
    let (mut lo, mut hi) = (
        glam::Vec2::splat(f32::INFINITY),
        glam::Vec2::splat(-f32::INFINITY),
    );
    let mut behind = 0;
    for i in 0..8 {
        let p = Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        );
        let c = view_proj * Vec4::new(p.x, p.y, p.z, 1.0);
        if c.w <= 1e-6 {
            behind += 1;
            continue;
        }
        let ndc = glam::Vec2::new(c.x / c.w, c.y / c.w);
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    if behind == 8 {
        return 0.0;
    }
    if behind > 0 {
        return 1.0;
    }
    let lo = lo.max(glam::Vec2::splat(-1.0));
    let hi = hi.min(glam::Vec2::splat(1.0));
    let size = (hi - lo).max(glam::Vec2::ZERO);
    (size.x * size.y / 4.0).clamp(0.0, 1.0)
}

/// Whether a point light of `intensity` (irradiance at 1 m) at `light_pos` delivers at least
/// `min_irradiance` to `target` (inverse-square falloff; no shadowing in this renderer).
pub fn light_reaches(light_pos: Vec3, intensity: f32, target: Vec3, min_irradiance: f32) -> bool {
    let d2 = light_pos.distance_squared(target).max(1e-4);
    intensity > 0.0 && intensity / d2 >= min_irradiance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_front_parses_and_ends_on_a_one_pass_model() {
        let f = front();
        assert!(f.len() >= 2, "{f:?}");
        assert!(!f[f.len() - 1].effects().screen_space);
        // Comments, blank lines and unknown names are skipped; names are trimmed.
        let (a, b) = (ShadingModel::ALL[0], ShadingModel::DEFAULT);
        assert_eq!(
            parse_front(&format!("# c\n\n{a}\nnot-a-model\n {b} \n")),
            vec![a, b]
        );
        // Every choice starts its own list, and nothing repeats.
        for m in ShadingModel::ALL {
            let t = Tiers::for_choice(m);
            let models = t.as_slice();
            assert_eq!(models[0], m);
            for (i, a) in models.iter().enumerate() {
                assert!(!models[i + 1..].contains(a), "{m}: {models:?}");
            }
        }
    }

    #[test]
    fn a_character_in_view_under_the_light_is_covered_and_lit() {
        let view_proj =
            dermis_engine::camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::Y, 1.0, 16.0 / 9.0);
        let light = dermis_engine::scene::KEY_LIGHT_OFFSET;
        let seen = Needs::of_character(view_proj, Vec3::ZERO, light, 30.0);
        let (min, max) = character_box(Vec3::ZERO);
        assert_eq!(seen.coverage, projected_coverage(view_proj, min, max));
        assert!(seen.coverage > 0.01 && seen.lit);
        // Behind the camera, and out of a weak light's reach.
        let behind = Needs::of_character(view_proj, Vec3::new(0.0, 0.0, 20.0), light, 0.1);
        assert_eq!(behind.coverage, 0.0);
        assert!(!behind.lit);
    }
}
