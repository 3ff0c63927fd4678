//! The frame's last pass: it draws into the 4× MSAA colour target, cleared, and resolves into
//! the output at its end (the depth target is never stored — the tile-friendly default on
//! phones). In a frame of one pass it is the scene's pass itself; in a frame with the
//! subsurface pass it follows the scene's pass and holds the gather and the UI. Tone mapping
//! happens at the end of every fragment shader that writes here (`finish` in `common.wgsl`).

use crate::render::prepared::PassCtx;
use crate::render::targets::depth_attachment;

/// Which of the frame's timestamps a pass writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timed {
    /// Both: the frame is this one pass.
    Whole,
    /// The end: an earlier pass wrote the start.
    End,
}

/// Opens the output pass (see the module docs).
pub fn output_pass<'e>(
    ctx: &'e mut PassCtx<'_>,
    clear: wgpu::Color,
    timed: Timed,
    label: &str,
) -> wgpu::RenderPass<'e> {
    let timestamp_writes = ctx.timer.map(|t| match timed {
        Timed::Whole => t.writes(),
        Timed::End => t.end_writes(),
    });
    ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &ctx.targets.msaa,
            depth_slice: None,
            resolve_target: Some(ctx.output),
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                store: wgpu::StoreOp::Discard,
            },
        })],
        depth_stencil_attachment: Some(depth_attachment(ctx.targets)),
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
