//! Stages (passes at the same dependency level, free of hazards between them) and the
//! barriers between stages.

use super::cull::alive_passes;
use super::deps::{Dependencies, DependencyError, PassUse, dependencies};
use super::id::{Id, IdVec, KeptPass, PassIndex, ResourceId, Stage};
use super::interface::BindingKind;
use petgraph::Direction;
use petgraph::graph::{DiGraph, NodeIndex};
use std::collections::BTreeMap;
use std::fmt;

/// How a resource is used by a binding; a barrier is needed when this changes or writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Usage {
    Uniform,
    Sampled,
    StorageRead,
    StorageWrite,
    StorageReadWrite,
    /// A raster pass's colour attachment (written; also read when the pass loads it).
    ColorAttachment,
    DepthAttachment,
    /// The workgroup counts of an `Indirect` dispatch (read).
    Indirect,
}

impl Usage {
    pub fn of(kind: &BindingKind) -> Usage {
        use super::interface::Access;
        match kind {
            BindingKind::Uniform { .. } => Usage::Uniform,
            BindingKind::SampledTexture { .. } => Usage::Sampled,
            BindingKind::Storage { access, .. } | BindingKind::StorageTexture { access, .. } => {
                match access {
                    Access::Read => Usage::StorageRead,
                    Access::Write => Usage::StorageWrite,
                    Access::ReadWrite => Usage::StorageReadWrite,
                }
            }
        }
    }

    pub fn writes(self) -> bool {
        matches!(
            self,
            Usage::StorageWrite
                | Usage::StorageReadWrite
                | Usage::ColorAttachment
                | Usage::DepthAttachment
        )
    }
}

impl fmt::Display for Usage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Usage::Uniform => "uniform",
            Usage::Sampled => "sampled",
            Usage::StorageRead => "storage read",
            Usage::StorageWrite => "storage write",
            Usage::StorageReadWrite => "storage read_write",
            Usage::ColorAttachment => "color attachment",
            Usage::DepthAttachment => "depth attachment",
            Usage::Indirect => "indirect",
        })
    }
}

/// The usages of one resource within one stage (several only when all are reads).
pub type UsageSet = Vec<Usage>;

/// A transition before `before_stage`: `resource` was last used as `from`, now as `to`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Barrier {
    pub before_stage: Stage,
    pub resource: ResourceId,
    pub from: UsageSet,
    pub to: UsageSet,
}

/// The whole scheduling of one frame, over pass and resource indices.
#[derive(Clone, Debug)]
pub struct Schedule {
    /// Dependencies among all passes (before culling).
    pub all: Dependencies,
    /// `alive[p]`: pass `p` contributes to an output.
    pub alive: IdVec<PassIndex, bool>,
    /// Kept passes in program order: `kept[k]` is kept pass `k`.
    pub kept: IdVec<KeptPass, PassIndex>,
    /// Dependencies among kept passes only.
    pub deps: Dependencies<KeptPass>,
    /// `levels[k]`: the stage of kept pass `k`.
    pub levels: IdVec<KeptPass, Stage>,
    pub stages: IdVec<Stage, Vec<KeptPass>>,
    pub barriers: Vec<Barrier>,
}

/// Dependencies, culling, stages and barriers. `usages[p]` are pass `p`'s (resource, usage)
/// pairs, `persistent(r)` whether `r` may be read before this frame writes it. An error names
/// passes in program order.
pub fn schedule(
    uses: &IdVec<PassIndex, Vec<PassUse>>,
    usages: &IdVec<PassIndex, Vec<(ResourceId, Usage)>>,
    persistent: impl Fn(ResourceId) -> bool + Copy,
    outputs: &[ResourceId],
) -> Result<Schedule, DependencyError> {
    let all = dependencies(uses, persistent)?;
    let alive = alive_passes(&all, outputs);
    let kept: IdVec<KeptPass, PassIndex> =
        PassIndex::all(uses.len()).filter(|&p| alive[p]).collect();
    // Hazards are recomputed among the kept passes: a culled pass may have been the only
    // link between two passes that still conflict with each other.
    let kept_uses: IdVec<KeptPass, Vec<PassUse>> = kept.iter().map(|&p| uses[p].clone()).collect();
    let deps = dependencies(&kept_uses, persistent).map_err(|e| in_program_order(e, &kept))?;
    let levels = stage_of_each_pass(&deps.graph);
    let stages = stages(&levels);
    let kept_usages: IdVec<KeptPass, _> = kept.iter().map(|&p| usages[p].clone()).collect();
    let barriers = barriers(&stages, &kept_usages);
    Ok(Schedule {
        all,
        alive,
        kept,
        deps,
        levels,
        stages,
        barriers,
    })
}

/// An error among the kept passes, its passes named by their place in program order. (Kept
/// passes have no hazards the whole graph lacks, so this is not expected to happen.)
fn in_program_order(
    e: DependencyError<KeptPass>,
    kept: &IdVec<KeptPass, PassIndex>,
) -> DependencyError {
    match e {
        DependencyError::ReadBeforeWrite {
            pass,
            resource,
            later_writer,
        } => DependencyError::ReadBeforeWrite {
            pass: kept[pass],
            resource,
            later_writer: later_writer.map(|k| kept[k]),
        },
        DependencyError::Cycle { passes, via } => DependencyError::Cycle {
            passes: passes.into_iter().map(|k| kept[k]).collect(),
            via,
        },
    }
}

/// Level of each pass: one more than the highest level among its dependencies. Edges run from
/// earlier to later passes, so one pass in program order suffices.
pub fn stage_of_each_pass<P: Id, E>(graph: &DiGraph<P, E>) -> IdVec<P, Stage> {
    let mut level = vec![0; graph.node_count()];
    for p in 0..graph.node_count() {
        level[p] = graph
            .neighbors_directed(NodeIndex::new(p), Direction::Incoming)
            .map(|q| level[q.index()] + 1)
            .max()
            .unwrap_or(0);
    }
    level.into_iter().map(Stage).collect()
}

/// Groups passes by level (`levels[i]` is pass `P::new(i)`'s), each stage in program order.
pub fn stages<P: Id>(levels: &IdVec<P, Stage>) -> IdVec<Stage, Vec<P>> {
    let count = levels.iter().max().map_or(0, |m| m.index() + 1);
    let mut stages: IdVec<Stage, Vec<P>> = vec![Vec::new(); count].into();
    for (p, &l) in levels.iter_ids() {
        stages[l].push(p);
    }
    stages
}

/// One barrier per resource whose usage changes, or is written, across a stage boundary.
/// `usages[i]` lists (resource, usage) for pass `P::new(i)`.
pub fn barriers<P: Id>(
    stages: &IdVec<Stage, Vec<P>>,
    usages: &IdVec<P, Vec<(ResourceId, Usage)>>,
) -> Vec<Barrier> {
    let mut last: BTreeMap<ResourceId, UsageSet> = BTreeMap::new();
    let mut out = Vec::new();
    for (s, passes) in stages.iter_ids() {
        let mut here: BTreeMap<ResourceId, UsageSet> = BTreeMap::new();
        for &p in passes {
            for &(r, usage) in &usages[p] {
                let set = here.entry(r).or_default();
                if !set.contains(&usage) {
                    set.push(usage);
                    set.sort();
                }
            }
        }
        for (r, to) in here {
            if let Some(from) = last.get(&r) {
                let writes = from.iter().chain(&to).any(|u| u.writes());
                if writes || *from != to {
                    out.push(Barrier {
                        before_stage: s,
                        resource: r,
                        from: from.clone(),
                        to: to.clone(),
                    });
                }
            }
            last.insert(r, to);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: ResourceId = ResourceId(0);
    const S: ResourceId = ResourceId(1);

    fn stages(list: &[&[usize]]) -> IdVec<Stage, Vec<KeptPass>> {
        list.iter()
            .map(|s| s.iter().map(|&k| KeptPass(k)).collect())
            .collect()
    }

    #[test]
    fn read_after_read_of_the_same_kind_needs_no_barrier() {
        let usages: IdVec<KeptPass, _> = IdVec::from(vec![
            vec![(R, Usage::StorageWrite)],
            vec![(R, Usage::StorageRead)],
            vec![(R, Usage::StorageRead)],
        ]);
        let b = barriers(&stages(&[&[0], &[1], &[2]]), &usages);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].before_stage, Stage(1));
        assert_eq!(b[0].from, vec![Usage::StorageWrite]);
        assert_eq!(b[0].to, vec![Usage::StorageRead]);
    }

    #[test]
    fn write_after_write_gets_a_barrier_though_the_usage_is_unchanged() {
        let usages: IdVec<KeptPass, _> = IdVec::from(vec![
            vec![(R, Usage::StorageWrite)],
            vec![(R, Usage::StorageWrite)],
        ]);
        assert_eq!(barriers(&stages(&[&[0], &[1]]), &usages).len(), 1);
    }

    #[test]
    fn a_resource_skipping_a_stage_gets_its_barrier_where_it_is_next_used() {
        let usages: IdVec<KeptPass, _> = IdVec::from(vec![
            vec![(R, Usage::StorageWrite)],
            vec![(S, Usage::StorageWrite)],
            vec![(R, Usage::Sampled)],
        ]);
        let b = barriers(&stages(&[&[0], &[1], &[2]]), &usages);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].before_stage, Stage(2));
    }
}
