//! `passgraph merge`: partial files of consecutive sample ranges into one image and partial.

use crate::output::*;
use crate::render::check_partial_path;
use passgraph::render::channels::ChannelSelection;
use passgraph::render::image::RgbImage;
use passgraph::render::image::check_output_path;
use passgraph::render::partial::Packing;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub(crate) struct MergeArgs {
    /// Partial files of one render whose sample ranges join without gaps or overlaps, in any
    /// order.
    #[arg(required = true, value_name = "PART.exr")]
    pub(crate) partials: Vec<PathBuf>,
    /// Output image: .png (sRGB, clamped) or .exr (linear float32). Repeatable.
    #[arg(long = "out")]
    pub(crate) out: Vec<PathBuf>,
    /// Also write the merged partial (of the union of the ranges), itself mergeable.
    #[arg(long, value_name = "OUT.exr")]
    pub(crate) partial: Option<PathBuf>,
    /// Channel(s) to write: sum, l0, direct, indirect, ambient, or a '+'-joined list.
    #[arg(long, default_value = "sum")]
    pub(crate) channel: ChannelSelection,
}

/// `passgraph merge`: reads every partial (each checked, errors naming the file), merges them
/// in range order and writes the image(s) and the merged partial as one set.
pub(crate) fn merge(args: MergeArgs) -> Result<(), Failure> {
    if args.out.is_empty() && args.partial.is_none() {
        return Err(Failure::Usage(
            "merge writes nothing: give --out IMAGE (.png or .exr) and/or --partial OUT.exr".into(),
        ));
    }
    let ChannelSelection::Planes(planes) = &args.channel else {
        return Err(Failure::Usage(format!(
            "--channel {}: a partial holds the accumulation's channels only (sum, l0, direct, indirect, ambient)",
            args.channel
        )));
    };
    for path in &args.out {
        check_output_path(path).map_err(Failure::Usage)?;
    }
    if let Some(path) = &args.partial {
        check_partial_path(path, &args.out).map_err(Failure::Usage)?;
    }
    let outputs: Vec<&Path> = args
        .out
        .iter()
        .chain(&args.partial)
        .map(PathBuf::as_path)
        .collect();
    let inputs: Vec<(&str, &Path)> = args
        .partials
        .iter()
        .map(|p| ("the partial", p.as_path()))
        .collect();
    passgraph::atomic_write::refuse_outputs_that_are_inputs(&outputs, &inputs)
        .map_err(Failure::Usage)?;
    let merged = passgraph::render::merge::merge_files(&args.partials)?;
    let [w, h] = merged.size;
    let image = RgbImage::from_result(&merged.to_result(), w, h, planes);
    let mut encoded = args
        .out
        .iter()
        .map(|path| Ok((path.as_path(), image.encode_for(path)?)))
        .collect::<Result<Vec<_>, String>>()?;
    if let Some(path) = &args.partial {
        encoded.push((
            path.as_path(),
            merged
                .encode(Packing::Small)
                .map_err(|e| format!("{}: {e}", path.display()))?,
        ));
    }
    write_files(&encoded)?;
    say_line(&format!(
        "merged {} partials: samples {}, {w}x{h}, {} dropped samples; wrote {}",
        args.partials.len(),
        merged.samples,
        merged.dropped,
        encoded
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    ))?;
    Ok(())
}
