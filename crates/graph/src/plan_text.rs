//! The human-readable plan that `passgraph plan` prints.

use super::plan::{Plan, PlannedResource, ResourceKind};
use super::provided::ProvidedKind;
use super::schedule::UsageSet;
use std::fmt::{self, Write};

fn usages(set: &UsageSet) -> String {
    set.iter()
        .map(|u| u.to_string())
        .collect::<Vec<_>>()
        .join(" + ")
}

/// Bytes in binary units, to one decimal.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["B", "KiB", "MiB", "GiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

impl fmt::Display for ResourceKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ResourceKind::Texture {
                format,
                width,
                height,
                layers,
            } => {
                write!(f, "texture {width}x{height}")?;
                if *layers > 1 {
                    write!(f, "x{layers}")?;
                }
                write!(f, " {format}")
            }
            ResourceKind::Buffer { size } => write!(f, "buffer {}", human_bytes(*size)),
            ResourceKind::Provided(ProvidedKind::StorageBuffer) => {
                f.write_str("provided storage buffer")
            }
            ResourceKind::Provided(ProvidedKind::Uniform) => f.write_str("provided uniform"),
        }
    }
}

/// ` (from FILE)` for a graph-owned resource.
fn from(r: &PlannedResource) -> String {
    r.origin
        .as_ref()
        .map_or(String::new(), |f| format!(" (from {})", f.display()))
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [w, h] = self.output_size;
        writeln!(f, "plan for {} at {w}x{h}", self.graph.display())?;
        if self.graph_files.len() > 1 {
            let files: Vec<String> = self
                .graph_files
                .iter()
                .map(|p| p.display().to_string())
                .collect();
            writeln!(f, "composed of {}", files.join(", "))?;
        }
        writeln!(f, "\nstages ({}):", self.stages.len())?;
        for (s, names) in self.stage_names().iter().enumerate() {
            writeln!(f, "  {s}: {}", names.join(", "))?;
        }

        writeln!(f, "\npasses:")?;
        for p in &self.passes {
            let [x, y, z] = p.workgroups;
            let work = match &p.raster {
                Some(r) => format!(
                    "raster {}/{}, {} triangles",
                    r.vertex, r.fragment, r.triangles
                ),
                None => match p.indirect {
                    Some((r, offset)) => format!(
                        "workgroups from {} at byte {offset}",
                        self.resources[r].name
                    ),
                    None => format!("{x}x{y}x{z} workgroups"),
                },
            };
            let mut line = format!(
                "  {} (stage {}, {}, {work})",
                p.name,
                p.stage,
                p.pass_file.display()
            );
            let _ = write!(line, " from {}", p.origin.file.display());
            // Params set by another file than the pass's own, grouped by that file.
            let mut changed: Vec<(String, Vec<&str>)> = Vec::new();
            for (param, file) in &p.origin.params {
                let file = file.display().to_string();
                match changed.iter_mut().find(|(f, _)| *f == file) {
                    Some((_, params)) => params.push(param),
                    None => changed.push((file, vec![param])),
                }
            }
            for (file, params) in changed {
                let _ = write!(line, ", {} from {file}", params.join(", "));
            }
            if !p.params.is_empty() {
                let params: Vec<String> =
                    p.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
                let _ = write!(line, " params: {}", params.join(", "));
            }
            writeln!(f, "{line}")?;
            for b in &p.bindings {
                writeln!(
                    f,
                    "      @group({}) @binding({}) {:<12} {:<40} <- {}",
                    b.group, b.binding, b.name, b.kind, self.resources[b.resource].name
                )?;
            }
            if let Some(r) = &p.raster {
                let load = match r.load {
                    super::decl::LoadOp::Clear => "clear",
                    super::decl::LoadOp::Load => "load",
                };
                let color = r
                    .color
                    .iter()
                    .enumerate()
                    .map(|(i, a)| (format!("color {i}"), a));
                for (what, (name, id)) in color.chain(r.depth.iter().map(|a| ("depth".into(), a))) {
                    writeln!(
                        f,
                        "      {what:<21} {name:<12} {:<40} <- {}",
                        format!("attachment ({load})"),
                        self.resources[*id].name
                    )?;
                }
            }
        }

        writeln!(f, "\nbarriers:")?;
        if self.barriers.is_empty() {
            writeln!(f, "  none")?;
        }
        for b in &self.barriers {
            writeln!(
                f,
                "  before stage {}: {}: {} -> {}",
                b.before_stage,
                self.resources[b.resource].name,
                usages(&b.from),
                usages(&b.to)
            )?;
        }

        writeln!(f, "\nculled:")?;
        if self.culled.is_empty() {
            writeln!(f, "  none")?;
        }
        for c in &self.culled {
            writeln!(
                f,
                "  {}: {} (from {})",
                c.name,
                c.reason,
                c.origin.display()
            )?;
        }

        writeln!(f, "\nresources:")?;
        for r in &self.resources {
            let Some(life) = r.lifetime else {
                if !matches!(r.kind, ResourceKind::Provided(_)) {
                    writeln!(
                        f,
                        "  {:<16} {} (unused by kept passes){}",
                        r.name,
                        r.kind,
                        from(r)
                    )?;
                }
                continue;
            };
            let mut tags = Vec::new();
            if r.persistent && !matches!(r.kind, ResourceKind::Provided(_)) {
                tags.push("persistent".to_string());
            }
            if r.output {
                tags.push("output".to_string());
            }
            if let Some(s) = r.physical {
                tags.push(format!("object #{s}"));
            }
            let line = format!(
                "  {:<16} {:<32} stages {}-{}  {}{}",
                r.name,
                r.kind.to_string(),
                life.first_stage,
                life.last_stage,
                tags.join(", "),
                from(r)
            );
            writeln!(f, "{}", line.trim_end())?;
        }
        for (i, p) in self.physical.iter().enumerate() {
            if p.users.len() > 1 {
                let names: Vec<&str> = p
                    .users
                    .iter()
                    .map(|&r| self.resources[r].name.as_str())
                    .collect();
                writeln!(f, "  object #{i} is shared by {}", names.join(", "))?;
            }
        }
        let before = self.bytes_without_reuse();
        let after = self.bytes_allocated();
        writeln!(
            f,
            "\nmemory: {} without reuse, {} allocated ({} saved by reuse)",
            human_bytes(before),
            human_bytes(after),
            human_bytes(before - after)
        )
    }
}
