//! Which channels an image shows: one layer of the accumulation, a sum such as
//! `l0+direct+indirect`, or a graph's output texture by name (e.g. `denoised`).

use std::fmt;

/// The layers of the path tracer's result buffer, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Channel {
    L0,
    Direct,
    Indirect,
    Ambient,
    Sum,
}

impl Channel {
    pub const ALL: [Channel; 5] = [
        Channel::L0,
        Channel::Direct,
        Channel::Indirect,
        Channel::Ambient,
        Channel::Sum,
    ];

    /// The plane index in the result buffer.
    pub fn layer(self) -> usize {
        self as usize
    }

    pub fn name(self) -> &'static str {
        match self {
            Channel::L0 => "l0",
            Channel::Direct => "direct",
            Channel::Indirect => "indirect",
            Channel::Ambient => "ambient",
            Channel::Sum => "sum",
        }
    }
}

/// A `+`-joined list of channels whose means are added, e.g. the physical image
/// `l0+direct+indirect` (everything but ambient), or any other single name: an output texture
/// of the graph, checked against the graph when the image is read
/// (see [`super::output_texture`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ChannelSelection {
    Planes(Vec<Channel>),
    Texture(String),
}

impl std::str::FromStr for ChannelSelection {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let single = s.trim();
        let known = |name: &str| Channel::ALL.iter().any(|c| c.name() == name);
        if !single.contains('+') && !single.is_empty() && !known(single) {
            return Ok(ChannelSelection::Texture(single.to_string()));
        }
        let mut channels = Vec::new();
        for part in s.split('+') {
            let part = part.trim();
            let Some(c) = Channel::ALL.iter().find(|c| c.name() == part) else {
                return Err(format!(
                    "unknown channel '{part}' in '{s}' (channels: sum, l0, direct, indirect, ambient, a '+'-joined list of them, or one output texture's name)"
                ));
            };
            if channels.contains(c) {
                return Err(format!("channel '{part}' appears twice in '{s}'"));
            }
            channels.push(*c);
        }
        if channels.contains(&Channel::Sum) && channels.len() > 1 {
            return Err(format!(
                "'sum' already includes every channel; it cannot be combined ('{s}')"
            ));
        }
        Ok(ChannelSelection::Planes(channels))
    }
}

impl fmt::Display for ChannelSelection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChannelSelection::Planes(channels) => {
                let names: Vec<&str> = channels.iter().map(|c| c.name()).collect();
                f.write_str(&names.join("+"))
            }
            ChannelSelection::Texture(name) => f.write_str(name),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn physical_image_is_the_sum_of_three_channels() {
        let s: ChannelSelection = "l0+direct+indirect".parse().unwrap();
        assert_eq!(
            s,
            ChannelSelection::Planes(vec![Channel::L0, Channel::Direct, Channel::Indirect])
        );
        assert_eq!(s.to_string(), "l0+direct+indirect");
    }

    #[test]
    fn a_single_other_name_is_an_output_texture() {
        let s: ChannelSelection = "denoised".parse().unwrap();
        assert_eq!(s, ChannelSelection::Texture("denoised".into()));
        assert_eq!(s.to_string(), "denoised");
    }

    #[test]
    fn unknown_repeated_or_sum_combined_channels_are_rejected() {
        assert!("l0+diffuse".parse::<ChannelSelection>().is_err());
        assert!("".parse::<ChannelSelection>().is_err());
        assert!("l0+l0".parse::<ChannelSelection>().is_err());
        assert!("sum+l0".parse::<ChannelSelection>().is_err());
    }
}
