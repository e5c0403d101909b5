//! Which accumulated channels an image shows: one layer, or a sum such as `l0+direct+indirect`.

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
/// `l0+direct+indirect` (everything but ambient).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChannelSelection(pub Vec<Channel>);

impl std::str::FromStr for ChannelSelection {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let mut channels = Vec::new();
        for part in s.split('+') {
            let part = part.trim();
            let Some(c) = Channel::ALL.iter().find(|c| c.name() == part) else {
                return Err(format!(
                    "unknown channel '{part}' (channels: sum, l0, direct, indirect, ambient, or a '+'-joined list)"
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
        Ok(ChannelSelection(channels))
    }
}

impl fmt::Display for ChannelSelection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.0.iter().map(|c| c.name()).collect();
        f.write_str(&names.join("+"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn physical_image_is_the_sum_of_three_channels() {
        let s: ChannelSelection = "l0+direct+indirect".parse().unwrap();
        assert_eq!(s.0, vec![Channel::L0, Channel::Direct, Channel::Indirect]);
        assert_eq!(s.to_string(), "l0+direct+indirect");
    }

    #[test]
    fn unknown_repeated_or_sum_combined_channels_are_rejected() {
        assert!("diffuse".parse::<ChannelSelection>().is_err());
        assert!("l0+l0".parse::<ChannelSelection>().is_err());
        assert!("sum+l0".parse::<ChannelSelection>().is_err());
    }
}
