//! GPU timing with timestamp queries written at the start and end of a whole pass
//! (timestamps inside a pass are not meaningful on tilers or on lavapipe).
//!
//! * [`PassTimer`]: one query pair, read back blocking (`still`, `bench shading`).
//! * [`TimerRing`]: a ring of query pairs read back without ever waiting, for timing every
//!   frame of a running loop (the soak, `bench effects`).

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

use super::readback::read_mapped;
use super::Gpu;

/// A pair of timestamp queries with their resolve and readback buffers.
struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl Queries {
    fn new(device: &wgpu::Device, label: &'static str) -> Self {
        let buffer = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 16,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
        }
    }

    /// Resolves both queries and copies them to the readback buffer.
    fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.set, 0..2, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, 16);
    }
}

/// Milliseconds between the two timestamps in `data` (16 mapped bytes); `None` when they
/// are missing or out of order.
fn elapsed_ms(data: &[u8], period_ns: f64) -> Option<f64> {
    let tick = |i: usize| Some(u64::from_le_bytes(data.get(i..i + 8)?.try_into().ok()?));
    let dt = tick(8)?.checked_sub(tick(0)?)?;
    Some(dt as f64 * period_ns * 1e-6)
}

/// Blocking timing of one pass (or of a frame of several passes).
pub struct PassTimer {
    queries: Queries,
    period_ns: f32,
}

impl PassTimer {
    /// `None` when the device has no TIMESTAMP_QUERY.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Option<Self> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        Some(Self {
            queries: Queries::new(device, "pass timer"),
            period_ns: queue.get_timestamp_period(),
        })
    }

    pub fn writes(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries.set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    /// For a frame of several passes: the first pass writes the start …
    pub fn begin_writes(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries.set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: None,
        }
    }

    /// … and the last pass the end.
    pub fn end_writes(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries.set,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: Some(1),
        }
    }

    /// Call after the timed pass, before `finish`.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        self.queries.resolve(encoder);
    }

    /// Blocks until the submitted pass finished; returns its GPU time in milliseconds.
    pub fn read_ms(&self, device: &wgpu::Device) -> Option<f64> {
        let period_ns = self.period_ns as f64;
        read_mapped(device, &self.queries.readback, |data| {
            elapsed_ms(data, period_ns)
        })?
    }
}

const FREE: u8 = 0;
const PENDING: u8 = 1;
const MAPPED: u8 = 2;
const FAILED: u8 = 3;

struct Slot {
    queries: Queries,
    state: Arc<AtomicU8>,
    frame: usize,
}

/// Non-stalling GPU timing of every frame: a ring of [`Self::SLOTS`] query/readback buffer
/// pairs, mapped asynchronously; a frame's GPU time is read when its buffer is found mapped a
/// few frames later. Nothing waits for a readback: when every slot is still in flight the
/// frame goes untimed ([`Self::skipped`]).
///
/// Per frame: [`Self::begin`] → [`Self::start`] … timed passes … [`Self::end`] → submit →
/// [`Self::submitted`]; then, any time later, [`Self::harvest`].
pub struct TimerRing {
    slots: Vec<Slot>,
    period_ns: f64,
    next: usize,
    /// Frames that went untimed because every slot was in flight.
    pub skipped: u64,
}

impl TimerRing {
    /// Ring size (≥ 3: a frame's time arrives a few frames later).
    pub const SLOTS: usize = 4;

    /// `None` without TIMESTAMP_QUERY.
    pub fn new(gpu: &Gpu) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let slots = (0..Self::SLOTS)
            .map(|_| Slot {
                queries: Queries::new(&gpu.device, "soak timer"),
                state: Arc::new(AtomicU8::new(FREE)),
                frame: 0,
            })
            .collect();
        Some(Self {
            slots,
            period_ns: gpu.queue.get_timestamp_period() as f64,
            next: 0,
            skipped: 0,
        })
    }

    /// A free slot for `frame`, or `None` (frame untimed) when all are in flight.
    pub fn begin(&mut self, frame: usize) -> Option<usize> {
        let i = self.next;
        if self.slots[i].state.load(Ordering::Acquire) != FREE {
            self.skipped += 1;
            return None;
        }
        self.next = (i + 1) % Self::SLOTS;
        self.slots[i].frame = frame;
        Some(i)
    }

    /// An empty compute pass writing timestamp `index` (0: start, 1: end) of `slot`.
    fn marker(&self, encoder: &mut wgpu::CommandEncoder, slot: usize, index: u32) {
        let s = &self.slots[slot];
        let _ = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("soak timestamp"),
            timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                query_set: &s.queries.set,
                beginning_of_pass_write_index: (index == 0).then_some(0),
                end_of_pass_write_index: (index == 1).then_some(1),
            }),
        });
    }

    /// Before the timed passes.
    pub fn start(&self, encoder: &mut wgpu::CommandEncoder, slot: usize) {
        self.marker(encoder, slot, 0);
    }

    /// After the timed passes: the end timestamp, resolve and copy to the readback buffer.
    pub fn end(&self, encoder: &mut wgpu::CommandEncoder, slot: usize) {
        self.marker(encoder, slot, 1);
        self.slots[slot].queries.resolve(encoder);
    }

    /// After the submit: request the asynchronous map.
    pub fn submitted(&self, slot: usize) {
        let s = &self.slots[slot];
        s.state.store(PENDING, Ordering::Release);
        let state = Arc::clone(&s.state);
        s.queries
            .readback
            .map_async(wgpu::MapMode::Read, .., move |r| {
                state.store(if r.is_ok() { MAPPED } else { FAILED }, Ordering::Release);
            });
    }

    /// Reads every slot found mapped (never waits): `f(frame, gpu_ms)`.
    pub fn harvest(&mut self, mut f: impl FnMut(usize, f64)) {
        for s in &mut self.slots {
            match s.state.load(Ordering::Acquire) {
                MAPPED => {
                    let readback = &s.queries.readback;
                    let ms = readback
                        .get_mapped_range(..)
                        .ok()
                        .and_then(|d| elapsed_ms(&d, self.period_ns));
                    readback.unmap();
                    s.state.store(FREE, Ordering::Release);
                    if let Some(ms) = ms {
                        f(s.frame, ms);
                    }
                }
                FAILED => s.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
    }

    /// The oldest frame still in flight.
    pub fn oldest_pending(&self) -> Option<usize> {
        self.slots
            .iter()
            .filter(|s| s.state.load(Ordering::Acquire) != FREE)
            .map(|s| s.frame)
            .min()
    }
}

#[cfg(test)]
mod tests {
    use super::elapsed_ms;

    #[test]
    fn elapsed_ticks_to_ms() {
        let bytes = |t0: u64, t1: u64| [t0.to_le_bytes(), t1.to_le_bytes()].concat();
        let ms = |t0, t1, period| elapsed_ms(&bytes(t0, t1), period).unwrap_or(f64::NAN);
        assert!((ms(1_000, 3_000_000, 1.0) - 2.999).abs() < 1e-12);
        assert!((ms(0, 1_000_000, 2.0) - 2.0).abs() < 1e-12);
        // Out of order or short: no time.
        assert_eq!(elapsed_ms(&bytes(5, 4), 1.0), None);
        assert_eq!(elapsed_ms(&[0; 12], 1.0), None);
    }
}
