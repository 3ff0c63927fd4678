//! Per-photon accumulators, estimates with standard errors, and the deterministic batch
//! runner (fixed-size batches, one RNG stream per batch, batches summed in batch order).

use super::rng::Rng;

/// A Monte Carlo estimate: the sample mean per photon and its standard error.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimate {
    pub mean: f64,
    pub std_err: f64,
}

impl Estimate {
    /// Both mean and standard error multiplied by `k` (a deterministic factor).
    pub fn scaled(self, k: f64) -> Estimate {
        Estimate {
            mean: self.mean * k,
            std_err: self.std_err * k.abs(),
        }
    }
    /// Number of standard errors between this estimate and `x` (∞ if the SE is 0 and x differs).
    pub fn z_score(&self, x: f64) -> f64 {
        let d = (self.mean - x).abs();
        if d == 0.0 {
            0.0
        } else {
            d / self.std_err
        }
    }
}

/// Sum and sum of squares of per-photon contributions (a photon that does not contribute
/// adds nothing; zeros are implied by the photon count).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Acc {
    pub s1: f64,
    pub s2: f64,
}

impl Acc {
    #[inline]
    pub fn add(&mut self, x: f64) {
        self.s1 += x;
        self.s2 += x * x;
    }
    #[inline]
    pub fn merge(&mut self, o: &Acc) {
        self.s1 += o.s1;
        self.s2 += o.s2;
    }
    /// Mean per photon over `n` photons and its standard error
    /// sqrt((⟨x²⟩ − ⟨x⟩²)/(n − 1)).
    pub fn estimate(&self, n: u64) -> Estimate {
        if n == 0 {
            return Estimate::default();
        }
        let nf = n as f64;
        let mean = self.s1 / nf;
        let var = if n > 1 {
            ((self.s2 / nf - mean * mean).max(0.0)) / (nf - 1.0)
        } else {
            0.0
        };
        Estimate {
            mean,
            std_err: var.sqrt(),
        }
    }
}

/// Everything one batch of photons records.
#[derive(Clone, Debug, Default)]
pub(crate) struct Tally {
    pub n: u64,
    /// Events (free flights + boundary hits) over all photons, for performance reports.
    pub events: u64,
    /// Specularly reflected weight at entry (excluded from the diffuse reflectance).
    pub specular: Acc,
    /// Weight leaving through the top surface (z = 0): diffuse reflectance.
    pub refl: Acc,
    /// Weight leaving through the bottom surface (z = d): transmittance.
    pub trans: Acc,
    pub absorbed: Acc,
    /// Weight still inside when the event cap was hit (a bias bound).
    pub capped: Acc,
    /// Weight leaving the top with outside exit cosine ≥ the detector's `cone_mu`.
    pub cone: Acc,
    /// Weight leaving through the bottom surface without any scattering event (collimated
    /// transmittance of a slab).
    pub unscattered: Acc,
    /// Weight that entered the medium (sphere only, where entry weights vary per photon).
    pub entered: Acc,
    pub refl_bins: Vec<Acc>,
    pub trans_bins: Vec<Acc>,
    /// Weight arriving at the surface from the source, before Fresnel (point light only).
    pub inc_bins: Vec<Acc>,
}

impl Tally {
    pub fn new(nbins: usize) -> Self {
        Tally {
            refl_bins: vec![Acc::default(); nbins],
            trans_bins: vec![Acc::default(); nbins],
            inc_bins: vec![Acc::default(); nbins],
            ..Default::default()
        }
    }
    /// Adds a photon's events and the weight it lost to absorption (when any).
    #[inline]
    pub fn finish_photon(&mut self, events: u64, absorbed: f64) {
        self.events += events;
        if absorbed != 0.0 {
            self.absorbed.add(absorbed);
        }
    }
    pub fn merge(&mut self, o: &Tally) {
        self.n += o.n;
        self.events += o.events;
        self.specular.merge(&o.specular);
        self.refl.merge(&o.refl);
        self.trans.merge(&o.trans);
        self.absorbed.merge(&o.absorbed);
        self.capped.merge(&o.capped);
        self.cone.merge(&o.cone);
        self.unscattered.merge(&o.unscattered);
        self.entered.merge(&o.entered);
        for (a, b) in self.refl_bins.iter_mut().zip(&o.refl_bins) {
            a.merge(b);
        }
        for (a, b) in self.trans_bins.iter_mut().zip(&o.trans_bins) {
            a.merge(b);
        }
        for (a, b) in self.inc_bins.iter_mut().zip(&o.inc_bins) {
            a.merge(b);
        }
    }
}

/// Runs `nbatches` batches over `threads` scoped threads, taking them dynamically, and hands
/// each result to `fold` in batch order as soon as every earlier one has been folded (a small
/// reorder buffer), so what `fold` accumulates is bit-identical for any thread count and no
/// more than a few batch results are held at once.
pub(crate) fn run_batches_ordered<T, R, F>(nbatches: usize, threads: usize, run: R, fold: F)
where
    T: Send,
    R: Fn(usize) -> T + Sync,
    F: FnMut(usize, T) + Send,
{
    let threads = threads.max(1).min(nbatches.max(1));
    let state = std::sync::Mutex::new((0usize, std::collections::BTreeMap::new(), fold));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let work = || loop {
        let b = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if b >= nbatches {
            break;
        }
        let t = run(b);
        let mut guard = state.lock().unwrap_or_else(|e| e.into_inner());
        let (ref mut due, ref mut pending, ref mut fold) = *guard;
        pending.insert(b, t);
        while let Some(t) = pending.remove(due) {
            fold(*due, t);
            *due += 1;
        }
    };
    if threads == 1 {
        work();
    } else {
        std::thread::scope(|s| {
            for _ in 0..threads {
                s.spawn(work);
            }
        });
    }
}

/// Photons per batch. Fixed: changing it changes the random streams (and so the digits).
pub const BATCH_SIZE: u64 = 4096;

/// Runs `photons` photons in batches of [`BATCH_SIZE`]; batch `b` uses `Rng::new(seed, b)`
/// and `run_one(rng, tally)` per photon. Batches are spread over `threads` scoped threads
/// (dynamically) but always summed in batch order, so the result is bit-identical for any
/// thread count.
pub(crate) fn run_batches<F>(
    photons: u64,
    seed: u64,
    threads: usize,
    nbins: usize,
    run_one: F,
) -> Tally
where
    F: Fn(&mut Rng, &mut Tally) + Sync,
{
    let nbatches = photons.div_ceil(BATCH_SIZE) as usize;
    let run_batch = |b: usize| -> Tally {
        let mut rng = Rng::new(seed, b as u64);
        let mut t = Tally::new(nbins);
        let start = b as u64 * BATCH_SIZE;
        let n = BATCH_SIZE.min(photons - start);
        for _ in 0..n {
            run_one(&mut rng, &mut t);
        }
        t.n = n;
        t
    };
    let threads = threads.max(1).min(nbatches.max(1));
    let mut results: Vec<Option<Tally>> = vec![None; nbatches];
    if threads == 1 {
        for (b, r) in results.iter_mut().enumerate() {
            *r = Some(run_batch(b));
        }
    } else {
        let next = std::sync::atomic::AtomicUsize::new(0);
        let parts: Vec<Vec<(usize, Tally)>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..threads)
                .map(|_| {
                    s.spawn(|| {
                        let mut mine = Vec::new();
                        loop {
                            let b = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            if b >= nbatches {
                                break;
                            }
                            mine.push((b, run_batch(b)));
                        }
                        mine
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("mc worker panicked"))
                .collect()
        });
        for (b, t) in parts.into_iter().flatten() {
            results[b] = Some(t);
        }
    }
    let mut total = Tally::new(nbins);
    for t in results.into_iter().flatten() {
        total.merge(&t);
    }
    total
}
