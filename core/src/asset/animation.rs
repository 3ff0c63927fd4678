//! Animations: T/R/S channels with validated key times and matching sampler output counts.
//! Morph-target weight channels are skipped with a warning.

use gltf::accessor::{DataType, Dimensions};
use gltf::animation::Property as GProperty;

use super::accessor::{expect_dims, read_f32, Buffers};
use super::{AnimationClip, Channel, Interpolation, Property};

pub(crate) fn load_animation(
    buffers: &Buffers<'_>,
    anim: &gltf::Animation<'_>,
    node_count: usize,
) -> Result<AnimationClip, String> {
    let ai = anim.index();
    let mut channels = Vec::new();
    let mut duration = 0.0f32;
    for ch in anim.channels() {
        let label = format!("animation {ai} channel {}", ch.index());
        let node = ch.target().node().index();
        if node >= node_count {
            return Err(format!("{label} targets missing node {node}"));
        }
        let (property, dims) = match ch.target().property() {
            GProperty::Translation => (Property::Translation, Dimensions::Vec3),
            GProperty::Rotation => (Property::Rotation, Dimensions::Vec4),
            GProperty::Scale => (Property::Scale, Dimensions::Vec3),
            GProperty::MorphTargetWeights => {
                log::warn!("{label}: morph target weight channel ignored");
                continue;
            }
        };
        let sampler = ch.sampler();
        let interpolation = match sampler.interpolation() {
            gltf::animation::Interpolation::Step => Interpolation::Step,
            gltf::animation::Interpolation::Linear => Interpolation::Linear,
            gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
        };
        let input = sampler.input();
        let output = sampler.output();
        expect_dims(&input, "animation input", Dimensions::Scalar)?;
        if input.data_type() != DataType::F32 {
            return Err(format!("{label}: key times must be float"));
        }
        expect_dims(&output, "animation output", dims)?;
        if property != Property::Rotation && output.data_type() != DataType::F32 {
            return Err(format!("{label}: translation/scale output must be float"));
        }
        let keys = input.count();
        if keys == 0 {
            return Err(format!("{label}: sampler has no keys"));
        }
        let per_key = if interpolation == Interpolation::CubicSpline { 3 } else { 1 };
        if output.count() != keys.saturating_mul(per_key) {
            return Err(format!(
                "{label}: sampler input/output count mismatch: {keys} key times but {} outputs \
                 (expected {})",
                output.count(),
                keys.saturating_mul(per_key)
            ));
        }
        let times = read_f32(buffers, &input, "animation input")?;
        for (k, &t) in times.iter().enumerate() {
            if !t.is_finite() || t < 0.0 {
                return Err(format!("{label}: key time {k} is negative or NaN/Inf ({t})"));
            }
            if k > 0 && t <= times[k - 1] {
                return Err(format!(
                    "{label}: key times not strictly increasing at key {k} ({} then {t})",
                    times[k - 1]
                ));
            }
        }
        let values = read_f32(buffers, &output, "animation output")?;
        if values.iter().any(|v| !v.is_finite()) {
            return Err(format!("{label}: NaN/Inf in sampler output"));
        }
        duration = duration.max(*times.last().unwrap_or(&0.0));
        channels.push(Channel { node, property, interpolation, times, values });
    }
    Ok(AnimationClip { name: anim.name().map(str::to_owned), duration, channels })
}
