//! Hot reload without a window: a Reloader over a scratch copy of graphs/, passes/ and shaders/
//! sees edits when polled, keeps the last good session on a broken edit, and builds a new one
//! when the files are good again. Runs on lavapipe.

mod common;

use common::{copy_dir, root};
use passgraph::gpu::GpuContext;
use passgraph::render::channels::{Channel, ChannelSelection};
use passgraph::render::session::{RenderSettings, Session};
use passgraph::view::reload::{ReloadOutcome, Reloader};
use std::path::Path;

const SIZE: [u32; 2] = [32, 32];

/// Renders a few frames and returns the mean of a channel.
fn render_mean(session: &mut Session, channel: Channel) -> [f64; 3] {
    for _ in 0..4 {
        session.render_frame().unwrap();
    }
    session
        .image(&ChannelSelection::Planes(vec![channel]))
        .unwrap()
        .mean()
}

fn edit(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{} has no '{from}'", path.display());
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}

#[test]
fn reloader_keeps_the_last_good_graph_and_picks_up_fixes_and_edits() {
    let root = root();
    let dir = tempfile::tempdir().unwrap();
    for sub in ["graphs", "passes", "shaders"] {
        copy_dir(&root.join(sub), &dir.path().join(sub));
    }
    let settings = RenderSettings {
        size: SIZE,
        ..RenderSettings::new(
            dir.path().join("graphs/pathtracer.ron"),
            root.join("scenes/cornell/scene.ron"),
        )
    };
    let ctx = GpuContext::new(None).unwrap_or_else(|e| panic!("{e}"));
    let (mut reloader, mut session) = Reloader::new(ctx, settings).unwrap();
    let camera = session.scene_description().camera;
    let rng = dir.path().join("shaders/lib/rng.wgsl");
    assert!(
        reloader.watched_files().any(|f| f == rng),
        "includes are watched"
    );
    assert!(matches!(reloader.poll(camera), ReloadOutcome::Unchanged));
    assert!(render_mean(&mut session, Channel::Sum)[0] > 0.01);

    // Break an include: the error names it, and the old session still renders.
    let good = std::fs::read_to_string(&rng).unwrap();
    std::fs::write(&rng, format!("{good}\nfn broken( {{\n")).unwrap();
    match reloader.poll(camera) {
        ReloadOutcome::Failed { message, changed } => {
            assert!(message.contains("rng.wgsl"), "{message}");
            assert_eq!(changed, vec![rng.clone()]);
        }
        _ => panic!("a broken include must fail to reload"),
    }
    // Reported once per edit, not once per poll.
    assert!(matches!(reloader.poll(camera), ReloadOutcome::Unchanged));
    session.reset();
    assert!(render_mean(&mut session, Channel::Sum)[0] > 0.01);

    // Fixed: a new session that renders.
    std::fs::write(&rng, &good).unwrap();
    session = match reloader.poll(camera) {
        ReloadOutcome::Reloaded { session, changed } => {
            assert_eq!(changed, vec![rng.clone()]);
            *session
        }
        ReloadOutcome::Failed { message, .. } => panic!("the fix must reload: {message}"),
        ReloadOutcome::Unchanged => panic!("the fix must be seen"),
    };
    assert_eq!(render_mean(&mut session, Channel::Ambient), [0.0; 3]);

    // A new, broken library included from a watched file: once named by the error it is
    // watched too, so fixing it alone reloads.
    let extra = dir.path().join("shaders/lib/extra.wgsl");
    std::fs::write(&extra, "fn extra( {\n").unwrap();
    std::fs::write(&rng, format!("{good}\n#include \"extra.wgsl\"\n")).unwrap();
    match reloader.poll(camera) {
        ReloadOutcome::Failed { message, .. } => {
            assert!(message.contains("extra.wgsl"), "{message}")
        }
        _ => panic!("a broken new include must fail to reload"),
    }
    std::fs::write(&extra, "fn extra() {}\n").unwrap();
    session = match reloader.poll(camera) {
        ReloadOutcome::Reloaded { session, changed } => {
            assert_eq!(changed, vec![extra.clone()]);
            *session
        }
        ReloadOutcome::Failed { message, .. } => panic!("the fixed include must load: {message}"),
        ReloadOutcome::Unchanged => panic!("the fixed include must be seen"),
    };
    assert!(reloader.watched_files().any(|f| f == extra));
    assert!(render_mean(&mut session, Channel::Sum)[0] > 0.01);

    // A pass RON edit takes effect: ambient light turns on.
    let ambient = dir.path().join("passes/ambient.ron");
    edit(&ambient, "Vec3(0.0, 0.0, 0.0)", "Vec3(0.5, 0.5, 0.5)");
    session = match reloader.poll(camera) {
        ReloadOutcome::Reloaded { session, .. } => *session,
        _ => panic!("a pass edit must reload"),
    };
    assert!(render_mean(&mut session, Channel::Ambient)[0] > 0.01);
}
