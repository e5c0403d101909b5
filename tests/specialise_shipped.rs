//! Every shipped pass specialises (crates/gpu/src/specialise.rs): its pipeline is built from the
//! module with the scene's override values substituted and dead branches removed, not from the
//! WGSL as written. A pass that fell back would render the same image with a pipeline several
//! times slower to create (0.5-0.6 s against 0.15-0.19 s for the path pass on lavapipe), so
//! nothing else would catch it; `render` prints a warning naming such a pass and why.
//! No GPU is needed: specialisation is naga's work on the CPU.

mod common;

use common::root;
use passgraph::gpu::{pass_constants, specialise_pass};
use passgraph::graph::compile::compile;
use passgraph::load_graph;
use passgraph::render::provided::{ProvidedInputs, path_tracer, provided_data};
use passgraph::render::tiling::Tile;
use passgraph::scene::load_scene;

/// Scenes whose override values differ: Lambert only with one light (Cornell), every material
/// model with textures (materials), an environment and a sun (outdoor), many lights, glTF.
const SCENES: [&str; 5] = [
    "scenes/cornell/scene.ron",
    "scenes/materials/scene.ron",
    "scenes/outdoor/scene.ron",
    "scenes/cornell-many-lights/scene.ron",
    "scenes/gltf/showcase.ron",
];

#[test]
fn every_pass_of_every_shipped_graph_specialises_on_every_shipped_scene() {
    let mut graphs: Vec<_> = std::fs::read_dir(root().join("graphs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    graphs.sort();
    let mut checked = 0;
    let mut failures = Vec::new();
    for scene_path in SCENES {
        let scene = load_scene(&root().join(scene_path)).unwrap_or_else(|e| panic!("{e}"));
        let gpu = scene.to_gpu();
        let provided = provided_data(&ProvidedInputs {
            scene: &scene,
            gpu: &gpu,
            tile: Tile::whole([32, 32]),
            seed: 0,
        });
        for graph_path in &graphs {
            let graph = load_graph(graph_path).unwrap_or_else(|e| panic!("{e}"));
            if !graph.decl.inputs.is_empty() {
                // A subgraph (graphs/denoiser.ron): its passes are checked where it is included.
                continue;
            }
            let plan = compile(&graph, [32, 32], path_tracer()).unwrap_or_else(|e| panic!("{e}"));
            for pass in &plan.passes {
                let constants = pass_constants(pass, &provided).unwrap_or_else(|e| panic!("{e}"));
                if let Err(why) = specialise_pass(pass, &constants) {
                    failures.push(format!(
                        "{} on {scene_path}: pass '{}' ({}): {why}",
                        graph_path.display(),
                        pass.name,
                        pass.shader.path.display()
                    ));
                }
                checked += 1;
            }
        }
    }
    assert!(
        failures.is_empty(),
        "not specialised:\n{}",
        failures.join("\n")
    );
    // 8 graphs of 3 to 9 passes each, on 5 scenes: a walk that found no passes proves nothing.
    assert!(checked >= 5 * 8 * 3, "only {checked} passes checked");
}
