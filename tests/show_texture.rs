//! Any texture a graph computes can be shown: `render --channel NAME[LAYER]` keeps the texture
//! it shows, and a viewer's session (`Keep::EveryTexture`) keeps and lists every texture its
//! kept passes use, one channel per layer, without changing what the graph renders.

mod common;

use common::render::{image, render, settings};
use passgraph::render::channels::ChannelSelection;
use passgraph::render::session::{Keep, RenderSettings, Session};
use passgraph::view::channel_list::channel_list;

const CORNELL: &str = "scenes/cornell/scene.ron";

#[test]
fn render_keeps_the_texture_it_shows_and_decodes_the_layer_asked_for() {
    // Layer 1 of the ray texture holds each pixel's primary ray direction (shaders/lib/
    // ray_texture.wgsl): a unit vector everywhere. `rays` is not an output of pathtracer.ron.
    let channel: ChannelSelection = "rays[1]".parse().unwrap();
    let s = settings("graphs/pathtracer.ron", CORNELL, 16, 1, &[]);
    let mut session = Session::builder(&s).showing(&channel).build().unwrap();
    session.render_frame().unwrap();
    let directions = session.image(&channel).unwrap();
    assert_eq!(directions.pixels.len(), 16 * 16);
    for p in &directions.pixels {
        let length = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        assert!((length - 1.0).abs() < 1e-5, "{p:?} is not a direction");
    }
    // A layer the texture lacks is an error naming the layers it has.
    let error = Session::builder(&s)
        .showing(&"rays[3]".parse().unwrap())
        .build()
        .err()
        .expect("rays has 3 layers");
    assert!(error.to_string().contains("rays[0] to rays[2]"), "{error}");
}

#[test]
fn a_viewer_session_lists_every_texture_layer_and_renders_the_same_image() {
    let shown = RenderSettings {
        keep: Keep::EveryTexture,
        ..settings("graphs/pathtracer-denoise.ron", CORNELL, 16, 2, &[])
    };
    let plain = settings("graphs/pathtracer-denoise.ron", CORNELL, 16, 2, &[]);
    let (kept, outputs_only) = (render(&shown, 2), render(&plain, 2));
    let names: Vec<String> = channel_list(kept.plan())
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    for expected in [
        "sum",
        "rays[0]",
        "rays[2]",
        "l0",
        "l0 (texture)",
        "denoise/atrous_a",
        "denoise/guide_normal",
        "denoised",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} not in {names:?}"
        );
    }
    // Each can be read as an image of the output size.
    for (name, selection) in channel_list(kept.plan()) {
        let shown = kept
            .image(&selection)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(shown.pixels.len(), 16 * 16, "{name}");
    }
    // Keeping textures changes where they live, not what is computed.
    for channel in ["sum", "denoised"] {
        assert_eq!(
            image(&kept, channel).pixels,
            image(&outputs_only, channel).pixels,
            "{channel}"
        );
    }
    // Without Keep::EveryTexture only the outputs are offered.
    let offered: Vec<String> = channel_list(outputs_only.plan())
        .into_iter()
        .map(|(name, _)| name)
        .collect();
    assert!(
        !offered.iter().any(|n| n.starts_with("rays")),
        "{offered:?}"
    );
}

#[test]
fn every_channel_a_viewer_lists_for_the_raster_graph_can_be_shown() {
    // Its visibility buffer is a colour attachment (shown like any texture); its depth
    // attachment is not read back, so it is neither kept nor listed.
    let shown = RenderSettings {
        keep: Keep::EveryTexture,
        ..settings("graphs/pathtracer-raster.ron", CORNELL, 16, 2, &[])
    };
    let session = render(&shown, 1);
    let list = channel_list(session.plan());
    assert!(list.iter().any(|(name, _)| name == "vbuffer"), "{list:?}");
    for (name, selection) in list {
        let image = session
            .image(&selection)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(image.pixels.len(), 16 * 16, "{name}");
    }
}
