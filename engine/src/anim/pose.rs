//! A pose: every node's local transform and world matrix. Allocates only in [`Pose::new`].

use glam::Mat4;

use super::sample::{sample_quat, sample_vec3, slerp_shortest};
use crate::asset::{AnimationClip, Model, Property, Transform};

#[derive(Clone, Debug)]
pub struct Pose {
    /// Local transform of each node (rest pose overridden by animation).
    pub locals: Vec<Transform>,
    /// World matrix of each node (valid after [`Pose::update_world`]).
    pub worlds: Vec<Mat4>,
    /// Nodes ordered parents before children (depth-first from the parentless nodes).
    order: Vec<usize>,
}

impl Pose {
    /// The rest pose of `model`, with world matrices computed.
    pub fn new(model: &Model) -> Self {
        let n = model.nodes.len();
        let mut order = Vec::with_capacity(n);
        let mut stack: Vec<usize> = (0..n)
            .rev()
            .filter(|&i| model.nodes[i].parent.is_none())
            .collect();
        while let Some(i) = stack.pop() {
            order.push(i);
            stack.extend(
                model.nodes[i]
                    .children
                    .iter()
                    .rev()
                    .copied()
                    .filter(|&c| c < n),
            );
        }
        let mut pose = Self {
            locals: model.nodes.iter().map(|nd| nd.local).collect(),
            worlds: vec![Mat4::IDENTITY; n],
            order,
        };
        pose.update_world(model);
        pose
    }

    /// Back to the rest pose (world matrices not updated).
    pub fn reset(&mut self, model: &Model) {
        for (l, nd) in self.locals.iter_mut().zip(&model.nodes) {
            *l = nd.local;
        }
    }

    /// Overwrites the properties `clip` animates with their values at `t` (clamped to
    /// `[0, duration]`; the caller wraps for looping).
    pub fn apply_clip(&mut self, clip: &AnimationClip, t: f32) {
        let t = clamp_time(clip, t);
        for ch in &clip.channels {
            let Some(l) = self.locals.get_mut(ch.node) else {
                continue;
            };
            match ch.property {
                Property::Translation => l.translation = sample_vec3(ch, t),
                Property::Rotation => l.rotation = sample_quat(ch, t),
                Property::Scale => l.scale = sample_vec3(ch, t),
            }
        }
    }

    /// Crossfade: moves the animated properties toward the clip's values at `t` by `weight`
    /// (0 = unchanged, 1 = same as [`Pose::apply_clip`]); lerp for T/S, slerp for R.
    pub fn blend_clip(&mut self, clip: &AnimationClip, t: f32, weight: f32) {
        let t = clamp_time(clip, t);
        let w = if weight.is_nan() {
            0.0
        } else {
            weight.clamp(0.0, 1.0)
        };
        for ch in &clip.channels {
            let Some(l) = self.locals.get_mut(ch.node) else {
                continue;
            };
            match ch.property {
                Property::Translation => l.translation = l.translation.lerp(sample_vec3(ch, t), w),
                Property::Rotation => {
                    l.rotation = slerp_shortest(l.rotation, sample_quat(ch, t), w)
                }
                Property::Scale => l.scale = l.scale.lerp(sample_vec3(ch, t), w),
            }
        }
    }

    /// Recomputes world matrices, parents before children. No allocation.
    pub fn update_world(&mut self, model: &Model) {
        for &i in &self.order {
            let local = self.locals[i].matrix();
            self.worlds[i] = match model.nodes.get(i).and_then(|n| n.parent) {
                Some(p) if p < self.worlds.len() => self.worlds[p] * local,
                _ => local,
            };
        }
    }
}

fn clamp_time(clip: &AnimationClip, t: f32) -> f32 {
    if t.is_nan() {
        0.0
    } else {
        t.clamp(0.0, clip.duration.max(0.0))
    }
}
