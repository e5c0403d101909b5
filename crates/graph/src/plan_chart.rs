//! The plan as a pass x resource chart: for each resource, which passes write and read it, in
//! schedule order, and where it is alive between them; with the physical object each transient
//! resource lives in, so memory reuse can be read off the chart (`passgraph plan --chart`).

use super::id::{KeptPass, ResourceId, Stage};
use super::interface::Access;
use super::plan::{Plan, ResourceKind};
use super::plan_text::human_bytes;
use std::fmt::Write;

/// One cell of the chart.
fn cell(access: Option<Access>, alive: bool) -> &'static str {
    match (access, alive) {
        (Some(Access::Write), _) => "W",
        (Some(Access::Read), _) => "R",
        (Some(Access::ReadWrite), _) => "RW",
        (None, true) => "=",
        (None, false) => ".",
    }
}

/// The chart as text: a header of stages and passes, then one row per resource.
pub fn lifetime_chart(plan: &Plan) -> String {
    // Passes in schedule order, each with its stage.
    let columns: Vec<(Stage, KeptPass)> = plan
        .stages
        .iter_ids()
        .flat_map(|(stage, passes)| passes.iter().map(move |&p| (stage, p)))
        .collect();
    let width = |p: KeptPass| plan.passes[p].name.len().max(2);
    let name_width = plan
        .resources
        .iter()
        .map(|r| r.name.len())
        .max()
        .unwrap_or(0)
        .max(8);
    let mut out = String::new();
    let [w, h] = plan.output_size;
    let _ = writeln!(out, "lifetimes for {} at {w}x{h}", plan.graph.display());
    let _ = writeln!(
        out,
        "(W writes, R reads, RW both; = alive between its uses; . not allocated; | a stage \
         boundary, where barriers go)"
    );
    let mut header = format!("{:name_width$}", "");
    let mut stage_line = format!("{:name_width$}", "");
    let mut last_stage = None;
    for &(stage, p) in &columns {
        let sep = if last_stage.is_some_and(|s| s != stage) {
            " |"
        } else {
            ""
        };
        let label = if last_stage != Some(stage) {
            format!("{stage}")
        } else {
            String::new()
        };
        let _ = write!(header, "{sep} {:w$}", plan.passes[p].name, w = width(p));
        let _ = write!(stage_line, "{sep} {label:w$}", w = width(p));
        last_stage = Some(stage);
    }
    let _ = writeln!(out, "{}", format!("{stage_line}   stage").trim_end());
    let _ = writeln!(out, "{header}   memory");
    for (id, r) in plan.resources.iter().enumerate() {
        let mut row = format!("{:name_width$}", r.name);
        let mut last_stage = None;
        for &(stage, p) in &columns {
            let sep = if last_stage.is_some_and(|s| s != stage) {
                " |"
            } else {
                ""
            };
            let access = plan.passes[p]
                .uses
                .iter()
                .find(|(rid, _)| *rid == ResourceId(id))
                .map(|u| u.1);
            let alive = r
                .lifetime
                .is_some_and(|l| (l.first_stage..=l.last_stage).contains(&stage));
            let _ = write!(row, "{sep} {:w$}", cell(access, alive), w = width(p));
            last_stage = Some(stage);
        }
        let memory = match (&r.kind, r.physical) {
            (ResourceKind::Provided(_), _) => "provided".to_string(),
            (kind, Some(object)) => format!("{} object #{object}", human_bytes(kind.bytes())),
            (kind, None) => human_bytes(kind.bytes()),
        };
        let persistent = if r.persistent && !matches!(r.kind, ResourceKind::Provided(_)) {
            ", persistent"
        } else {
            ""
        };
        let _ = writeln!(out, "{row}   {memory}{persistent}");
    }
    out
}
