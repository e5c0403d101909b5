//! Culling: keep only passes whose writes reach an output, or a persistent resource that a
//! kept pass reads in the next frame.

use super::deps::{Dependencies, PassId, ReadSource, ResourceId};

/// `alive[p]` is true when pass `p` contributes to an output.
pub fn alive_passes(deps: &Dependencies, outputs: &[ResourceId]) -> Vec<bool> {
    let mut alive = vec![false; deps.reads.len()];
    let mut stack: Vec<PassId> = outputs
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::deps::{PassUse, dependencies};
    use crate::graph::interface::Access;

    fn u(resource: ResourceId, access: Access) -> PassUse {
        PassUse { resource, access }
    }

    #[test]
    fn a_pass_whose_output_nobody_reads_is_culled() {
        let uses = [
            vec![u(0, Access::Write)],
            vec![u(1, Access::Write)], // debug view, not an output
            vec![u(0, Access::Read), u(2, Access::Write)],
        ];
        let deps = dependencies(&uses, |_| false).unwrap();
        assert_eq!(alive_passes(&deps, &[2]), vec![true, false, true]);
    }

    #[test]
    fn an_overwritten_version_does_not_keep_its_writer_alive() {
        let uses = [vec![u(0, Access::Write)], vec![u(0, Access::Write)]];
        let deps = dependencies(&uses, |_| false).unwrap();
        assert_eq!(alive_passes(&deps, &[0]), vec![false, true]);
    }

    #[test]
    fn history_read_keeps_the_history_writer_alive() {
        // p0 reads last frame's history and writes out; p1 writes this frame's history.
        let uses = [
            vec![u(0, Access::Read), u(1, Access::Write)],
            vec![u(1, Access::Read), u(0, Access::Write)],
        ];
        let deps = dependencies(&uses, |r| r == 0).unwrap();
        assert_eq!(alive_passes(&deps, &[1]), vec![true, true]);
    }
}
