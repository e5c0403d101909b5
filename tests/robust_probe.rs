use passgraph::render::session::{RenderSettings, Session};
use std::path::Path;
#[test]
fn probe() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let s = RenderSettings {
        graph: root.join("tests/fixtures/graphs/robust_signal.ron"),
        scene: root.join("tests/data/furnace/scene.ron"),
        size: [4, 4], seed: 0, set: vec![], adapter: None, max_frames: 100_000,
    };
    let mut session = Session::new(&s).unwrap();
    let t = std::time::Instant::now();
    for _ in 0..10_000 { session.render_frame().unwrap(); }
    let r = session.result().unwrap();
    eprintln!("10k frames: {:?} {:?}", t.elapsed(), r[0]);
}
