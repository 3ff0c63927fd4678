//! Animations: T/R/S channels with validated key times and matching sampler output counts.
//! Morph-target weight channels are skipped with a warning.

use gltf::accessor::{DataType, Dimensions};
use gltf::json::animation::{Interpolation as JInterpolation, Property as JProperty};
use gltf::json::validation::Checked;

use super::accessor::{expect_dims, read_f32, Buffers};
use super::{AnimationClip, Channel, Interpolation, Property};

/// Loads animation `ai`. Works on the raw JSON: the gltf crate's validation does not check
/// channel targets, so its wrappers could panic on them.
pub(crate) fn load_animation(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    ai: usize,
    node_count: usize,
) -> Result<AnimationClip, String> {
    let anim = doc
        .as_json()
        .animations
        .get(ai)
        .ok_or_else(|| format!("missing animation {ai}"))?;
    let accessor = |i: usize, label: &str| {
        doc.accessors()
            .nth(i)
            .ok_or_else(|| format!("{label}: missing accessor {i}"))
    };
    let mut channels = Vec::new();
    let mut duration = 0.0f32;
    for (ci, ch) in anim.channels.iter().enumerate() {
        let label = format!("animation {ai} channel {ci}");
        let node = ch.target.node.value();
        if node >= node_count {
            return Err(format!("{label} targets missing node {node}"));
        }
        let (property, dims) = match ch.target.path {
            Checked::Valid(JProperty::Translation) => (Property::Translation, Dimensions::Vec3),
            Checked::Valid(JProperty::Rotation) => (Property::Rotation, Dimensions::Vec4),
            Checked::Valid(JProperty::Scale) => (Property::Scale, Dimensions::Vec3),
            Checked::Valid(JProperty::MorphTargetWeights) => {
                log::warn!("{label}: morph target weight channel ignored");
                continue;
            }
            Checked::Invalid => return Err(format!("{label}: invalid target path")),
        };
        let si = ch.sampler.value();
        let sampler = anim
            .samplers
            .get(si)
            .ok_or_else(|| format!("{label} references missing sampler {si}"))?;
        let interpolation = match sampler.interpolation {
            Checked::Valid(JInterpolation::Step) => Interpolation::Step,
            Checked::Valid(JInterpolation::Linear) => Interpolation::Linear,
            Checked::Valid(JInterpolation::CubicSpline) => Interpolation::CubicSpline,
            Checked::Invalid => return Err(format!("{label}: invalid sampler interpolation")),
        };
        let input = accessor(sampler.input.value(), &label)?;
        let output = accessor(sampler.output.value(), &label)?;
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
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
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
                return Err(format!(
                    "{label}: key time {k} is negative or NaN/Inf ({t})"
                ));
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
        channels.push(Channel {
            node,
            property,
            interpolation,
            times,
            values,
        });
    }
    Ok(AnimationClip {
        name: anim.name.clone(),
        duration,
        channels,
    })
}
