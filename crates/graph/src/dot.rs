//! Graphviz output: passes as boxes clustered by stage, resources as ellipses, reads and writes
//! as edges; culled passes dashed.

use super::id::{Id, ResourceId};
use super::interface::Access;
use super::plan::{Plan, ResourceKind};
use std::fmt::Write;

/// A DOT string: backslashes and quotes escaped, line breaks as DOT's `\n` (centred lines).
fn quote(s: &str) -> String {
    format!(
        "\"{}\"",
        s.replace('\\', "\\\\")
            .replace('"', "\\\"")
            .replace('\n', "\\n")
    )
}

pub fn to_dot(plan: &Plan) -> String {
    let mut out =
        String::from("digraph passgraph {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n");
    for (s, passes) in plan.stages.iter().enumerate() {
        let _ = writeln!(
            out,
            "  subgraph cluster_stage{s} {{\n    label=\"stage {s}\";"
        );
        for &p in passes {
            let pass = &plan.passes[p];
            let _ = writeln!(
                out,
                "    {} [shape={}, label={}];",
                quote(&format!("pass:{}", pass.name)),
                // Raster passes stand out from compute passes.
                if pass.raster.is_some() {
                    "box3d"
                } else {
                    "box"
                },
                quote(&format!("{}\n{}", pass.name, pass.origin.file.display()))
            );
        }
        out.push_str("  }\n");
    }
    for c in &plan.culled {
        let _ = writeln!(
            out,
            "  {} [shape=box, style=dashed, color=gray, label={}];",
            quote(&format!("pass:{}", c.name)),
            quote(&format!("{} (culled)\n{}", c.name, c.origin.display()))
        );
    }
    for (i, r) in ResourceId::all(plan.resources.len()).zip(&plan.resources) {
        let used = plan
            .passes
            .iter()
            .any(|p| p.uses.iter().any(|&(u, _)| u == i))
            || plan
                .culled
                .iter()
                .any(|p| p.uses.iter().any(|&(u, _)| u == i));
        if !used {
            continue;
        }
        let shape = match r.kind {
            ResourceKind::Provided(_) => "note",
            _ if r.persistent => "doubleoctagon",
            _ => "ellipse",
        };
        let style = if r.output { ", style=bold" } else { "" };
        let _ = writeln!(
            out,
            "  {} [shape={shape}{style}, label={}];",
            quote(&format!("res:{}", r.name)),
            quote(&match &r.origin {
                Some(origin) => format!("{}\n{}\n{}", r.name, r.kind, origin.display()),
                None => format!("{}\n{}", r.name, r.kind),
            })
        );
    }
    let uses = plan
        .passes
        .iter()
        .map(|p| (&p.name, &p.uses))
        .chain(plan.culled.iter().map(|c| (&c.name, &c.uses)));
    for (pass, pass_uses) in uses {
        let p = quote(&format!("pass:{pass}"));
        for &(r, access) in pass_uses {
            let res = quote(&format!("res:{}", plan.resources[r].name));
            if access.reads() {
                let _ = writeln!(out, "  {res} -> {p};");
            }
            if access.writes() {
                let color = if access == Access::ReadWrite {
                    " [color=red]"
                } else {
                    ""
                };
                let _ = writeln!(out, "  {p} -> {res}{color};");
            }
        }
    }
    out.push_str("}\n");
    out
}
