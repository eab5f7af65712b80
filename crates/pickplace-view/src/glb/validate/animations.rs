//! Animations: samplers (keyframe times, interpolation, output counts) and channels (targets
//! and output types).

use super::buffers::Accessor;
use super::fields::{list, property, reference, rule};
use super::{AnimationSummary, ChannelSummary};
use crate::error::{GlbErrorKind, Result, glb_error};
use serde_json::Value;

/// What a checked sampler tells its channels.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Sampler {
    /// Keyframes (input count).
    pub(super) samples: u64,
    /// Output accessor type (`VEC3`, …).
    output_type: String,
    /// Output component type.
    output_component_type: u64,
    /// Last keyframe time (s).
    pub(super) end: f64,
}

/// Every animation: its samplers ([`check_sampler`]) and channels ([`check_channel`]).
pub(super) fn check_animations(
    root: &Value,
    accessors: &[Accessor],
    node_count: usize,
    bin: &[u8],
) -> Result<Vec<AnimationSummary>> {
    let mut animations = Vec::new();
    for (a, animation) in list(root, "animations")?.iter().enumerate() {
        let samplers = animation
            .get("samplers")
            .and_then(Value::as_array)
            .ok_or_else(|| property("animation", a, "samplers"))?
            .iter()
            .enumerate()
            .map(|(s, sampler)| check_sampler(a, s, sampler, accessors, bin))
            .collect::<Result<Vec<_>>>()?;
        let duration = samplers.iter().fold(0.0_f64, |d, s| d.max(s.end));
        let channels_json = animation
            .get("channels")
            .and_then(Value::as_array)
            .ok_or_else(|| property("animation", a, "channels"))?;
        let mut channels: Vec<ChannelSummary> = Vec::with_capacity(channels_json.len());
        for (c, channel) in channels_json.iter().enumerate() {
            let summary = check_channel(c, channel, &samplers, node_count)?;
            if channels
                .iter()
                .any(|other| other.node == summary.node && other.path == summary.path)
            {
                return Err(rule(
                    "animation channel",
                    c,
                    "two channels target the same node and path",
                ));
            }
            channels.push(summary);
        }
        let name = animation
            .get("name")
            .and_then(Value::as_str)
            .map(str::to_owned);
        animations.push(AnimationSummary {
            name,
            duration,
            channels,
        });
    }
    Ok(animations)
}

/// Sampler `s` of animation `a`: float scalar input times with min and max, non-negative and
/// strictly increasing; a known interpolation; as many outputs as it needs.
pub(super) fn check_sampler(
    a: usize,
    s: usize,
    sampler: &Value,
    accessors: &[Accessor],
    bin: &[u8],
) -> Result<Sampler> {
    let input = reference(sampler, "animation sampler", s, "input", accessors.len())?
        .ok_or_else(|| property("animation sampler", s, "input"))?;
    let output = reference(sampler, "animation sampler", s, "output", accessors.len())?
        .ok_or_else(|| property("animation sampler", s, "output"))?;
    let (input, output) = (&accessors[input], &accessors[output]);
    if input.type_name != "SCALAR" || input.component_type != 5126 || input.min.is_none() {
        return Err(rule(
            "animation sampler",
            s,
            "input must be float scalars with min and max",
        ));
    }
    let mut previous = -1.0;
    for e in 0..input.count {
        let t = input.component(bin, e, 0);
        if !(t >= 0.0 && t > previous) {
            return Err(rule(
                "animation sampler",
                s,
                "input times must be non-negative and strictly increasing",
            ));
        }
        previous = t;
    }
    let interpolation = sampler
        .get("interpolation")
        .and_then(Value::as_str)
        .unwrap_or("LINEAR");
    let expected = match interpolation {
        "LINEAR" | "STEP" => input.count,
        "CUBICSPLINE" => 3 * input.count,
        _ => return Err(property("animation sampler", s, "interpolation")),
    };
    if output.count != expected {
        return Err(glb_error(GlbErrorKind::SamplerCounts {
            animation: a,
            sampler: s,
            input: input.count,
            output: output.count,
        }));
    }
    Ok(Sampler {
        samples: input.count,
        output_type: output.type_name.clone(),
        output_component_type: output.component_type,
        end: previous,
    })
}

/// Channel `c`: a sampler and a target node in range, and a target path whose type the
/// sampler's output matches (float VEC3 for translation and scale, VEC4 for rotation, SCALAR
/// for weights).
pub(super) fn check_channel(
    c: usize,
    channel: &Value,
    samplers: &[Sampler],
    node_count: usize,
) -> Result<ChannelSummary> {
    let s = reference(channel, "animation channel", c, "sampler", samplers.len())?
        .ok_or_else(|| property("animation channel", c, "sampler"))?;
    let target = channel
        .get("target")
        .ok_or_else(|| property("animation channel", c, "target"))?;
    let node = reference(target, "animation channel", c, "node", node_count)?
        .ok_or_else(|| property("animation channel", c, "node"))?;
    let path = target
        .get("path")
        .and_then(Value::as_str)
        .ok_or_else(|| property("animation channel", c, "path"))?;
    let sampler = &samplers[s];
    let output_type = sampler.output_type.as_str();
    let ok = match path {
        "translation" | "scale" => output_type == "VEC3" && sampler.output_component_type == 5126,
        "rotation" => output_type == "VEC4",
        "weights" => output_type == "SCALAR",
        _ => return Err(property("animation channel", c, "path")),
    };
    if !ok {
        return Err(rule(
            "animation channel",
            c,
            "the output type does not match the target path",
        ));
    }
    Ok(ChannelSummary {
        node,
        path: path.to_owned(),
        samples: sampler.samples,
    })
}
