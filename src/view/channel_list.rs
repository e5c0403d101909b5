//! The channels a viewer can show for a graph: the accumulation's planes, then each output
//! texture that can be shown (e.g. a denoiser's `denoised`).

use crate::graph::plan::Plan;
use crate::render::channels::{Channel, ChannelSelection};
use crate::render::output_texture::output_texture_format;

/// (label, selection) in key order: key 1 is the first.
pub fn channel_list(plan: &Plan) -> Vec<(String, ChannelSelection)> {
    let mut list: Vec<(String, ChannelSelection)> = [
        Channel::Sum,
        Channel::L0,
        Channel::Direct,
        Channel::Indirect,
        Channel::Ambient,
    ]
    .iter()
    .map(|c| (c.name().to_string(), ChannelSelection::Planes(vec![*c])))
    .collect();
    for r in &plan.resources {
        if r.output && output_texture_format(plan, &r.name).is_ok() {
            list.push((r.name.clone(), ChannelSelection::Texture(r.name.clone())));
        }
    }
    list
}
