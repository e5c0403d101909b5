//! Graph tests without a GPU: fixture graphs compile to the expected stages, barriers,
//! culling, lifetimes and reuse.

mod common;

use common::{Scratch, compile_fixture};
use passgraph::graph::interface::Access;
use passgraph::graph::param::ParamValue;
use passgraph::graph::plan::{Plan, ResourceKind};
use passgraph::graph::schedule::Usage;

fn barrier_list(plan: &Plan) -> Vec<(usize, String, Vec<Usage>, Vec<Usage>)> {
    plan.barriers
        .iter()
        .map(|b| {
            (
                b.before_stage.0,
                plan.resources[b.resource].name.clone(),
                b.from.clone(),
                b.to.clone(),
            )
        })
        .collect()
}

#[test]
fn seed_graph_runs_the_three_lighting_passes_in_one_stage() {
    let plan = compile_fixture("seed.ron");
    assert_eq!(
        plan.stage_names(),
        vec![
            vec!["intersect"],
            vec!["ambient", "direct", "indirect"],
            vec!["accumulate"]
        ]
    );
    assert!(plan.culled.is_empty());
}

#[test]
fn seed_graph_barriers_are_the_ray_and_seed_hand_off_then_the_channels() {
    use Usage::*;
    let plan = compile_fixture("seed.ron");
    let s = |x: &str| x.to_string();
    assert_eq!(
        barrier_list(&plan),
        vec![
            (1, s("rays"), vec![StorageWrite], vec![StorageRead]),
            (1, s("seeds"), vec![StorageReadWrite], vec![StorageRead]),
            (2, s("ambient"), vec![StorageWrite], vec![Sampled]),
            (2, s("direct"), vec![StorageWrite], vec![Sampled]),
            (2, s("indirect"), vec![StorageWrite], vec![Sampled]),
            (2, s("l0"), vec![StorageWrite], vec![Sampled]),
        ]
    );
}

#[test]
fn seed_graph_packs_params_and_sizes_dispatches_from_the_shader() {
    let plan = compile_fixture("seed.ron");
    let ambient = plan.pass("ambient").unwrap();
    assert_eq!(ambient.workgroups, [32, 32, 1]);
    assert_eq!(
        ambient.params["ambient_color"],
        ParamValue::Vec3(0.1, 0.1, 0.1)
    );
    let uniform = ambient.params_uniform.as_ref().unwrap();
    assert_eq!(uniform.bytes.len(), 16);
    let f = |at: usize| f32::from_le_bytes(uniform.bytes[at..at + 4].try_into().unwrap());
    assert_eq!([f(0), f(4), f(8), f(12)], [0.1, 0.1, 0.1, 1e30]);
    // The default holds where the graph does not override it.
    assert_eq!(ambient.params["radius"], ParamValue::F32(1e30));
}

#[test]
fn seed_graph_resources_follow_the_output_size_and_persistence() {
    let plan = compile_fixture("seed.ron");
    let res = |n: &str| &plan.resources[plan.resource_id(n).unwrap()];
    assert_eq!(
        res("rays").kind,
        ResourceKind::Texture {
            format: passgraph::graph::format::TextureFormat::Rgba32Float,
            width: 256,
            height: 256,
            layers: 3
        }
    );
    assert_eq!(
        res("result").kind,
        ResourceKind::Buffer {
            size: 256 * 256 * 80
        }
    );
    assert!(res("seeds").persistent && res("result").persistent);
    assert!(res("result").output);
    // Provided resources are bound but not allocated by the graph.
    assert!(res("scene.bvh").lifetime.is_some() && res("scene.bvh").physical.is_none());
    assert!(res("camera").physical.is_none());
}

#[test]
fn chain_runs_one_pass_per_stage() {
    let plan = compile_fixture("chain.ron");
    assert_eq!(
        plan.stage_names(),
        vec![vec!["fill"], vec!["copy1"], vec!["copy2"]]
    );
    assert_eq!(plan.barriers.len(), 2);
}

#[test]
fn diamond_runs_its_branches_together() {
    let plan = compile_fixture("diamond.ron");
    assert_eq!(
        plan.stage_names(),
        vec![vec!["fill"], vec!["left", "right"], vec!["join"]]
    );
    let src = plan.resource_id("src").unwrap();
    let src_barriers: Vec<_> = plan.barriers.iter().filter(|b| b.resource == src).collect();
    assert_eq!(src_barriers.len(), 1, "one barrier for both readers");
}

#[test]
fn culling_drops_the_unread_debug_view_and_the_overwritten_fill() {
    let plan = compile_fixture("culling.ron");
    let culled: Vec<&str> = plan.culled.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(culled, vec!["overwritten", "debug_view"]);
    assert_eq!(plan.stage_names(), vec![vec!["fill"], vec!["final"]]);
    let debug = plan.resource_id("debug").unwrap();
    assert_eq!(plan.resources[debug].physical, None, "nothing allocated");
    assert!(plan.culled[1].reason.contains("'debug'"));
}

#[test]
fn culling_a_pass_does_not_merge_stages_it_separated() {
    // 'reader' reads a, the culled 'mid' overwrites a, 'writer' writes a again (the output).
    // Without 'mid', reader and writer still conflict on 'a' and must stay ordered.
    let s = Scratch::new();
    s.write(
        "graphs/war.ron",
        r#"Graph(
            resources: { "a": Texture(format: Rgba16Float, persistent: true), "b": Texture(format: Rgba16Float) },
            passes: [
                (name: "reader", pass: "copy", bind: { "src": "a", "dst": "b" }),
                (name: "mid", pass: "fill", bind: { "dst": "a" }),
                (name: "writer", pass: "fill", bind: { "dst": "a" }),
            ],
            outputs: ["a", "b"],
        )"#,
    );
    let plan = s.compile("graphs/war.ron").unwrap();
    assert_eq!(plan.stage_names(), vec![vec!["reader"], vec!["writer"]]);
    assert_eq!(plan.culled[0].name, "mid");
}

#[test]
fn history_reads_the_previous_frame_and_keeps_its_writer() {
    let plan = compile_fixture("history.ron");
    assert!(plan.culled.is_empty(), "store_history feeds next frame");
    assert_eq!(
        plan.stage_names(),
        vec![vec!["fill"], vec!["temporal"], vec!["store_history"]]
    );
    let history = plan.resource_id("history").unwrap();
    let temporal = plan.pass("temporal").unwrap();
    assert!(temporal.uses.contains(&(history, Access::Read)));
    assert_eq!(
        temporal.overrides,
        vec![("HISTORY_WEIGHT".to_string(), 0.75)]
    );
}

#[test]
fn history_writer_is_culled_when_nobody_reads_the_history() {
    let s = Scratch::new();
    s.edit(
        "graphs/history.ron",
        r#"bind: { "history": "history", "current": "current", "dst": "out" }"#,
        r#"bind: { "history": "current", "current": "current", "dst": "out" }"#,
    );
    let plan = s.compile("graphs/history.ron").unwrap();
    let culled: Vec<&str> = plan.culled.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(culled, vec!["store_history"]);
}

#[test]
fn transient_textures_with_disjoint_lifetimes_share_objects() {
    let plan = compile_fixture("reuse.ron");
    let object = |n: &str| plan.resources[plan.resource_id(n).unwrap()].physical;
    assert_eq!(object("t1"), object("t3"));
    assert_eq!(object("t1"), object("t4"));
    assert_ne!(
        object("t1"),
        object("t2"),
        "t1 and t2 are both live in stage 1"
    );
    assert_ne!(object("half"), object("t2"), "different size, never shared");
    assert_ne!(object("out"), object("t2"), "outputs keep their own object");
    let full = 256 * 256 * 8;
    let half = 128 * 128 * 8;
    assert_eq!(plan.bytes_without_reuse(), 5 * full + half);
    assert_eq!(plan.bytes_allocated(), 3 * full + half);
}

#[test]
fn a_shared_object_carries_the_usages_of_all_its_users() {
    let plan = compile_fixture("reuse.ron");
    let t1 = plan.resource_id("t1").unwrap();
    let object = &plan.physical[plan.resources[t1].physical.unwrap()];
    assert_eq!(object.usages, vec![Usage::Sampled, Usage::StorageWrite]);
    assert_eq!(object.users.len(), 3);
}

#[test]
fn five_instances_of_one_pass_keep_their_own_params() {
    let plan = compile_fixture("denoise.ron");
    let steps: Vec<ParamValue> = (1..=5)
        .map(|i| plan.pass(&format!("atrous{i}")).unwrap().params["step"].clone())
        .collect();
    assert_eq!(steps, [1, 2, 4, 8, 16].map(ParamValue::U32).to_vec(),);
    let weight = &plan.pass("atrous5").unwrap().params["weight"];
    assert_eq!(*weight, ParamValue::F32(0.25));
    assert_eq!(plan.stages.len(), 6, "each level reads the previous one");
    let bytes = &plan
        .pass("atrous3")
        .unwrap()
        .params_uniform
        .as_ref()
        .unwrap()
        .bytes;
    assert_eq!(u32::from_le_bytes(bytes[0..4].try_into().unwrap()), 4);
}

#[test]
fn plan_text_shows_stages_barriers_culling_and_memory() {
    let text = compile_fixture("seed.ron").to_string();
    common::assert_mentions(
        &text,
        &[
            "0: intersect",
            "1: ambient, direct, indirect",
            "2: accumulate",
            "before stage 1: rays: storage write -> storage read",
            "before stage 2: l0: storage write -> sampled",
            "memory:",
        ],
    );
    let culled = compile_fixture("culling.ron").to_string();
    common::assert_mentions(&culled, &["debug_view: ", "overwritten: "]);
}

#[test]
fn dot_output_has_every_pass_and_marks_culled_ones() {
    let dot = passgraph::to_dot(&compile_fixture("culling.ron"));
    assert!(dot.starts_with("digraph"));
    common::assert_mentions(
        &dot,
        &[
            "\"pass:fill\"",
            "\"pass:final\"",
            "debug_view (culled)",
            "cluster_stage1",
        ],
    );
}

#[test]
fn provided_overrides_need_no_param_and_are_listed_for_the_executor() {
    let s = Scratch::new();
    s.edit(
        "shaders/direct.wgsl",
        "@compute @workgroup_size(8, 8)",
        "override scene_light_count: u32;\n\n@compute @workgroup_size(8, 8)",
    );
    s.edit(
        "shaders/direct.wgsl",
        "light * u, 1.0)",
        "light * u * f32(scene_light_count), 1.0)",
    );
    let plan = s.compile("graphs/seed.ron").unwrap();
    let direct = plan.pass("direct").unwrap();
    assert_eq!(
        direct.provided_overrides,
        vec!["scene_light_count".to_string()]
    );
    assert!(direct.overrides.is_empty());
}

#[test]
fn lifetime_chart_shows_each_resource_written_read_and_alive_by_pass() {
    let plan =
        passgraph::compile_file(&common::root().join("graphs/pathtracer.ron"), [64, 64]).unwrap();
    let chart = passgraph::graph::plan_chart::lifetime_chart(&plan);
    let row = |name: &str| -> Vec<String> {
        let line = chart
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("no row for {name} in\n{chart}"));
        line.split_whitespace()
            .skip(1)
            .take(7)
            .map(str::to_string)
            .collect()
    };
    // Columns: intersect | ambient direct indirect | accumulate.
    let header: Vec<&str> = chart.lines().nth(3).unwrap().split_whitespace().collect();
    assert_eq!(
        header,
        [
            "intersect",
            "|",
            "ambient",
            "direct",
            "indirect",
            "|",
            "accumulate",
            "memory"
        ]
    );
    // The ray texture: written in stage 0, read by the three lighting passes, then freed.
    assert_eq!(row("rays"), ["W", "|", "R", "R", "R", "|", "."]);
    // A channel: written by its pass, alive across its stage, read by accumulate.
    assert_eq!(row("l0"), [".", "|", "=", "W", "=", "|", "R"]);
    assert_eq!(row("result"), ["=", "|", "=", "=", "=", "|", "RW"]);
    assert!(chart.contains("persistent"), "{chart}");
}

/// A viewer keeps every texture a kept pass uses (`keep_used_textures`): the same plan as
/// listing them as outputs, while a culled pass's texture stays unkept and its pass culled.
#[test]
fn keeping_used_textures_marks_the_kept_passes_textures_as_outputs_and_culls_nothing_more() {
    let path = common::fixtures().join("graphs/culling.ron");
    let mut keep = passgraph::load_graph(&path).unwrap();
    keep.keep_used_textures = true;
    let kept = passgraph::compile(&keep, [32, 32]).unwrap();
    let outputs: Vec<&str> = kept
        .resources
        .iter()
        .filter(|r| r.output)
        .map(|r| r.name.as_str())
        .collect();
    assert_eq!(outputs, ["a", "out"]);
    let culled: Vec<&str> = kept.culled.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(culled, ["overwritten", "debug_view"]);

    let mut listed = passgraph::load_graph(&path).unwrap();
    listed.decl.outputs.push("a".into());
    let listed = passgraph::compile(&listed, [32, 32]).unwrap();
    assert_eq!(kept.to_string(), listed.to_string());
}
