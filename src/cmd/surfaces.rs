//! `dermis surfaces --count N` (hidden self-test): creates, presents to and drops N real
//! window surfaces in turn, like an Android activity's InitWindow / TermWindow, and prints
//! wgpu's live-object counts before and after as JSON.

use std::sync::Arc;

use dermis_engine::render::{Gpu, LiveObjects, SurfaceOptions, SurfaceTarget};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

struct App {
    count: u32,
    gpu: Option<Gpu>,
    before: Option<LiveObjects>,
    presented: u32,
    created: u32,
    error: Option<String>,
}

impl App {
    fn cycle(&mut self, event_loop: &ActiveEventLoop) -> Result<(), String> {
        let attrs =
            Window::default_attributes().with_inner_size(winit::dpi::PhysicalSize::new(160, 120));
        let window = Arc::new(event_loop.create_window(attrs).map_err(|e| e.to_string())?);
        if self.gpu.is_none() {
            let (gpu, surface) = Gpu::with_surface(|| window.clone()).map_err(|e| e.to_string())?;
            drop(surface);
            gpu.wait();
            self.gpu = Some(gpu);
        }
        let gpu = self.gpu.as_ref().expect("created above");
        let surface = gpu
            .instance
            .create_surface(window.clone())
            .map_err(|e| e.to_string())?;
        self.created += 1;
        let size = window.inner_size();
        let mut target = SurfaceTarget::new(
            gpu,
            surface,
            size.width,
            size.height,
            SurfaceOptions {
                present_mode: wgpu::PresentMode::Fifo,
                ..SurfaceOptions::default()
            },
        )?;
        if let Ok((frame, status)) = target.acquire(gpu) {
            let view = frame.texture.create_view(&Default::default());
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            {
                let _pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: None,
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &target.targets.msaa,
                        depth_slice: None,
                        resolve_target: Some(&view),
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLUE),
                            store: wgpu::StoreOp::Discard,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
            }
            gpu.queue.submit([encoder.finish()]);
            drop(view);
            target.present(gpu, frame, status);
            self.presented += 1;
        }
        gpu.wait();
        drop(target);
        drop(window);
        gpu.wait();
        if self.before.is_none() {
            // After one full warm-up cycle (wgpu keeps some staging state from then on).
            self.before = Some(LiveObjects::read(&gpu.device));
            self.created = 0;
            self.presented = 0;
            return self.cycle(event_loop);
        }
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        for _ in 0..self.count {
            if let Err(e) = self.cycle(event_loop) {
                self.error = Some(e);
                break;
            }
        }
        event_loop.exit();
    }

    fn window_event(&mut self, _: &ActiveEventLoop, _: WindowId, _: WindowEvent) {}
}

pub fn run(count: u32) -> Result<(), String> {
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    let mut app = App {
        count,
        gpu: None,
        before: None,
        presented: 0,
        created: 0,
        error: None,
    };
    event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
    if let Some(e) = app.error {
        return Err(e);
    }
    let gpu = app.gpu.as_ref().ok_or("no GPU")?;
    gpu.wait();
    let after = LiveObjects::read(&gpu.device);
    let report = serde_json::json!({
        "surfaces": app.created,
        "presented": app.presented,
        "before": app.before,
        "after": after,
    });
    println!("{report}");
    Ok(())
}
