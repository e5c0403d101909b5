//! Culling: keep only passes whose writes reach an output, or a persistent resource that a
//! kept pass reads in the next frame; and why each other pass was culled.

use super::deps::{Dependencies, PassUse, ReadSource};
use super::id::{Id, IdVec, PassIndex, ResourceId};

/// `alive[p]` is true when pass `p` contributes to an output.
pub fn alive_passes(deps: &Dependencies, outputs: &[ResourceId]) -> IdVec<PassIndex, bool> {
    let mut alive: IdVec<PassIndex, bool> = vec![false; deps.reads.len()].into();
    let mut stack: Vec<PassIndex> = outputs
        .iter()
        .filter_map(|r| deps.final_writer.get(r).copied())
        .collect();
    while let Some(p) = stack.pop() {
        if std::mem::replace(&mut alive[p], true) {
            continue;
        }
        for &(resource, source) in &deps.reads[p] {
            match source {
                ReadSource::Pass(w) => stack.push(w),
                // Reading last frame's content keeps alive whoever writes it this frame.
                ReadSource::PreviousFrame => stack.extend(deps.final_writer.get(&resource)),
            }
        }
    }
    alive
}

/// What the cull reason needs to know of a resource.
pub struct ResourceFacts<'a> {
    pub name: &'a str,
    pub persistent: bool,
}

/// Why pass `p` was culled, resource by resource: what became of each version it wrote.
/// `uses[q]` are pass `q`'s uses, `all` the dependencies among every pass.
pub fn cull_reason<'a>(
    p: PassIndex,
    uses: &IdVec<PassIndex, Vec<PassUse>>,
    all: &Dependencies,
    pass_name: impl Fn(PassIndex) -> &'a str,
    resource: impl Fn(ResourceId) -> ResourceFacts<'a>,
) -> String {
    let written: Vec<ResourceId> = uses[p]
        .iter()
        .filter(|u| u.access.writes())
        .map(|u| u.resource)
        .collect();
    if written.is_empty() {
        return "it writes nothing".to_string();
    }
    let name = |q: PassIndex| format!("'{}'", pass_name(q));
    let reasons: Vec<String> = written
        .iter()
        .map(|&r| {
            let facts = resource(r);
            let resource = facts.name;
            let readers: Vec<PassIndex> = PassIndex::all(all.reads.len())
                .filter(|&q| all.reads[q].contains(&(r, ReadSource::Pass(p))))
                .collect();
            let overwriter = (p.index() + 1..uses.len())
                .map(PassIndex)
                .find(|&q| uses[q].iter().any(|u| u.resource == r && u.access.writes()));
            if !readers.is_empty() {
                let names: Vec<String> = readers.into_iter().map(name).collect();
                format!(
                    "'{resource}' is read only by culled passes ({})",
                    names.join(", ")
                )
            } else if let Some(q) = overwriter {
                format!(
                    "'{resource}' is overwritten by {} before anything reads it",
                    name(q)
                )
            } else if facts.persistent {
                format!("'{resource}' is persistent, but no kept pass reads it next frame")
            } else {
                format!("nothing reads '{resource}' and it is not an output")
            }
        })
        .collect();
    reasons.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deps::dependencies;
    use crate::interface::Access;

    fn u(resource: usize, access: Access) -> PassUse {
        PassUse {
            resource: ResourceId(resource),
            access,
        }
    }

    fn alive(uses: &[Vec<PassUse>], persistent: &[usize], outputs: &[usize]) -> Vec<bool> {
        let uses = IdVec::from(uses.to_vec());
        let deps = dependencies(&uses, |r: ResourceId| persistent.contains(&r.0)).unwrap();
        let outputs: Vec<ResourceId> = outputs.iter().map(|&r| ResourceId(r)).collect();
        alive_passes(&deps, &outputs).into_vec()
    }

    #[test]
    fn a_pass_whose_output_nobody_reads_is_culled() {
        let uses = [
            vec![u(0, Access::Write)],
            vec![u(1, Access::Write)], // debug view, not an output
            vec![u(0, Access::Read), u(2, Access::Write)],
        ];
        assert_eq!(alive(&uses, &[], &[2]), vec![true, false, true]);
    }

    #[test]
    fn an_overwritten_version_does_not_keep_its_writer_alive() {
        let uses = [vec![u(0, Access::Write)], vec![u(0, Access::Write)]];
        assert_eq!(alive(&uses, &[], &[0]), vec![false, true]);
    }

    #[test]
    fn history_read_keeps_the_history_writer_alive() {
        // p0 reads last frame's history and writes out; p1 writes this frame's history.
        let uses = [
            vec![u(0, Access::Read), u(1, Access::Write)],
            vec![u(1, Access::Read), u(0, Access::Write)],
        ];
        assert_eq!(alive(&uses, &[0], &[1]), vec![true, true]);
    }
}
