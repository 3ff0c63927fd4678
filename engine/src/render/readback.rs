//! Blocking GPU → CPU readback: the one place that maps a buffer and waits for it
//! (offscreen images, the pass timer, the conformance harness). The soak's non-blocking
//! timestamp ring maps asynchronously instead (`timer.rs`).

use super::Gpu;

/// Maps `buffer` (`MAP_READ`, its copy already submitted) for reading, waits for the device,
/// hands the mapped bytes to `read` and unmaps. `None` when the buffer could not be mapped.
pub fn read_mapped<R>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    read: impl FnOnce(&[u8]) -> R,
) -> Option<R> {
    let slice = buffer.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    let _ = device.poll(wgpu::PollType::wait_indefinitely());
    let out = {
        let data = slice.get_mapped_range().ok()?;
        read(&data)
    };
    buffer.unmap();
    Some(out)
}

/// Copies the first `size` bytes of `buffer` (`COPY_SRC`, its writes already submitted)
/// into a staging buffer, waits, and hands them to `read` (aligned as the GPU wrote them).
pub fn read_buffer<R>(
    gpu: &Gpu,
    buffer: &wgpu::Buffer,
    size: u64,
    read: impl FnOnce(&[u8]) -> R,
) -> R {
    let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    gpu.queue.submit([encoder.finish()]);
    read_mapped(&gpu.device, &staging, read).expect("readback buffer was mapped above")
}
