//! The channels a viewer can show for a graph: the accumulation's planes, then each texture
//! the graph keeps, one entry per layer (`rays[0]`, `rays[1]`, ...): its outputs (e.g. a
//! denoiser's `denoised`) and, in a viewer's session (`Keep::EveryTexture`), every texture a
//! kept pass uses.

use crate::graph::plan::{Plan, ResourceKind};
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
        let ResourceKind::Texture { layers, .. } = r.kind else {
            continue;
        };
        for layer in 0..layers {
            let name = if layers == 1 {
                r.name.clone()
            } else {
                format!("{}[{layer}]", r.name)
            };
            if output_texture_format(plan, &name).is_ok() {
                // The path tracer's channel textures share their names with the planes.
                let label = if Channel::ALL.iter().any(|c| c.name() == name) {
                    format!("{name} (texture)")
                } else {
                    name.clone()
                };
                list.push((label, ChannelSelection::Texture(name)));
            }
        }
    }
    list
}

/// The channels of a viewer's graph and the one shown.
pub struct ChannelChoice {
    list: Vec<(String, ChannelSelection)>,
    current: usize,
}

impl ChannelChoice {
    /// The first channel (the sum) shown.
    pub fn new(plan: &Plan) -> ChannelChoice {
        ChannelChoice {
            list: channel_list(plan),
            current: 0,
        }
    }

    pub fn len(&self) -> usize {
        self.list.len()
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    pub fn current(&self) -> usize {
        self.current
    }

    /// The shown channel's label and selection.
    pub fn shown(&self) -> &(String, ChannelSelection) {
        &self.list[self.current]
    }

    /// Shows channel `i` (which must exist).
    pub fn select(&mut self, i: usize) {
        self.current = i;
    }

    /// The channels of a reloaded graph, still showing the same label where it has one.
    pub fn refresh(&mut self, plan: &Plan) {
        let label = self.shown().0.clone();
        self.list = channel_list(plan);
        self.current = self.list.iter().position(|(l, _)| *l == label).unwrap_or(0);
    }
}
