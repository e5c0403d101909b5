//! A bench variant on the command line: `[LABEL=]GRAPH[@CHANNEL][:INSTANCE.PARAM=VALUE,...]`.
//!
//! - `LABEL=` names the variant (letters, digits, `-`, `_`, `+`), e.g.
//!   `pcg=graphs/pathtracer.ron:intersect.sampler_kind=0,...`.
//! - `GRAPH` alone renders the graph and compares `--channel`.
//! - `@CHANNEL` compares that channel or output texture instead (e.g. the denoiser's
//!   `graphs/pathtracer-denoise.ron@denoised`).
//! - `:SET,SET` overrides params of this variant only, as `--set` does for all of them
//!   (`graphs/pathtracer.ron:intersect.sampler=1`). A vector value keeps its commas
//!   (`:direct.tint=1,0.5,0.5,accumulate.scale=2`): a piece that is not `INSTANCE.PARAM=...`
//!   continues the previous value.
//!
//! A path that exists as given is never split. Without `LABEL=`, the label (CSV file name,
//! table rows, chart legend) is the graph's file stem followed by what was given after it, so
//! variants of one graph stay apart: `pathtracer:intersect.sampler=1`.

use crate::render::channels::ChannelSelection;
use std::path::PathBuf;

#[derive(Clone, Debug)]
pub struct Variant {
    pub graph: PathBuf,
    /// The channel to compare instead of the bench's `--channel`.
    pub channel: Option<ChannelSelection>,
    /// This variant's `INSTANCE.PARAM=VALUE` overrides, applied after the bench's `--set`.
    pub set: Vec<String>,
    pub label: String,
}

/// `INSTANCE.PARAM=...`: the start of an assignment rather than a vector component.
fn starts_assignment(piece: &str) -> bool {
    piece
        .split_once('=')
        .and_then(|(target, _)| target.split_once('.'))
        .is_some_and(|(instance, param)| {
            let ident = |s: &str| {
                !s.is_empty()
                    && s.chars()
                        .all(|c| c.is_alphanumeric() || c == '_' || c == '-')
            };
            ident(instance) && ident(param)
        })
}

fn split_sets(text: &str) -> Result<Vec<String>, String> {
    let mut sets: Vec<String> = Vec::new();
    for piece in text.split(',') {
        match sets.last_mut() {
            Some(last) if !starts_assignment(piece) => {
                last.push(',');
                last.push_str(piece);
            }
            _ if starts_assignment(piece) => sets.push(piece.to_string()),
            _ => return Err(format!("'{piece}' is not INSTANCE.PARAM=VALUE")),
        }
    }
    Ok(sets)
}

impl std::str::FromStr for Variant {
    type Err = String;

    fn from_str(text: &str) -> Result<Variant, String> {
        let named = text.split_once('=').filter(|(name, _)| {
            !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '+'))
                && !PathBuf::from(text).exists()
        });
        let (name, text) = match named {
            Some((name, rest)) => (Some(name), rest),
            None => (None, text),
        };
        let whole = PathBuf::from(text);
        let (head, sets) = match text.split_once(':') {
            Some((head, sets)) if !whole.exists() => (head, split_sets(sets)?),
            _ => (text, Vec::new()),
        };
        let (graph, channel_name) = match head.rsplit_once('@') {
            Some((graph, name)) if !name.is_empty() && !PathBuf::from(head).exists() => {
                (PathBuf::from(graph), Some(name))
            }
            _ => (PathBuf::from(head), None),
        };
        let mut label = graph
            .file_stem()
            .map_or("graph".to_string(), |s| s.to_string_lossy().into_owned());
        if let Some(name) = channel_name {
            label = format!("{label}@{name}");
        }
        if !sets.is_empty() {
            label = format!("{label}:{}", sets.join(","));
        }
        if let Some(name) = name {
            label = name.to_string();
        }
        Ok(Variant {
            graph,
            channel: channel_name
                .map(str::parse::<ChannelSelection>)
                .transpose()?,
            set: sets,
            label,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Variant {
        text.parse().unwrap()
    }

    #[test]
    fn a_graph_alone_is_labelled_by_its_stem() {
        let v = parse("graphs/nonexistent-x.ron");
        assert_eq!(v.graph, PathBuf::from("graphs/nonexistent-x.ron"));
        assert!(v.channel.is_none() && v.set.is_empty());
        assert_eq!(v.label, "nonexistent-x");
    }

    #[test]
    fn channel_and_sets_split_and_label_the_variant() {
        let v = parse("g/denoise.ron@denoised:atrous1.step=2,remodulate.fade_frames=0");
        assert_eq!(v.graph, PathBuf::from("g/denoise.ron"));
        assert!(v.channel.is_some());
        assert_eq!(v.set, ["atrous1.step=2", "remodulate.fade_frames=0"]);
        assert_eq!(
            v.label,
            "denoise@denoised:atrous1.step=2,remodulate.fade_frames=0"
        );
        let v = parse("g/pt.ron:intersect.sampler=1");
        assert!(v.channel.is_none());
        assert_eq!(v.set, ["intersect.sampler=1"]);
        assert_eq!(v.label, "pt:intersect.sampler=1");
    }

    #[test]
    fn a_label_names_the_variant() {
        let v = parse("pcg=g/pt.ron@denoised:intersect.sampler_kind=0,direct.sampler_kind=0");
        assert_eq!(v.label, "pcg");
        assert_eq!(v.graph, PathBuf::from("g/pt.ron"));
        assert!(v.channel.is_some());
        assert_eq!(v.set, ["intersect.sampler_kind=0", "direct.sampler_kind=0"]);
        // The first '=' of a set is not a label: its left side has a '.' and a ':'.
        assert_eq!(parse("pt.ron:intersect.x=1").label, "pt:intersect.x=1");
    }

    #[test]
    fn vector_values_keep_their_commas() {
        let v = parse("g/pt.ron:direct.tint=1,0.5,0.5,accumulate.scale=2");
        assert_eq!(v.set, ["direct.tint=1,0.5,0.5", "accumulate.scale=2"]);
    }

    #[test]
    fn a_set_that_is_not_an_assignment_is_refused() {
        let err = "g/pt.ron:sampler".parse::<Variant>().unwrap_err();
        assert!(err.contains("INSTANCE.PARAM=VALUE"), "{err}");
    }
}
