//! Dependencies between passes from their reads and writes in program order.
//!
//! Pure data over indices, so the scheduling rules can be tested (and property-tested) without
//! shaders or files. Each write makes a new version of a resource; a read sees the latest version.
//! Passes are indexed by `P`: the compiler builds dependencies among all passes (`PassIndex`)
//! and again among the kept ones (`KeptPass`).

use super::id::{Id, IdVec, PassIndex, ResourceId};
use super::interface::Access;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::EdgeFiltered;
use std::collections::BTreeMap;

/// One resource a pass touches, with the union of its bindings' accesses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassUse {
    pub resource: ResourceId,
    pub access: Access,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Hazard {
    ReadAfterWrite,
    WriteAfterRead,
    WriteAfterWrite,
}

/// An edge `from -> to`: `to` must run after `from` because of `resource`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dependency {
    pub resource: ResourceId,
    pub hazard: Hazard,
}

/// Which version of a resource a read sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReadSource<P = PassIndex> {
    /// Written earlier this frame by that pass.
    Pass(P),
    /// Persistent (or provided) content from before this frame.
    PreviousFrame,
}

#[derive(Clone, Debug)]
pub struct Dependencies<P = PassIndex> {
    /// Node `i` is pass `i`; edges always go from an earlier to a later pass.
    pub graph: DiGraph<P, Dependency>,
    /// For each pass, each resource it reads and where that version comes from.
    pub reads: IdVec<P, Vec<(ResourceId, ReadSource<P>)>>,
    /// The last pass writing each resource this frame.
    pub final_writer: BTreeMap<ResourceId, P>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DependencyError<P = PassIndex> {
    /// A transient resource read before any write; `later_writer` is the first pass that writes it.
    ReadBeforeWrite {
        pass: P,
        resource: ResourceId,
        later_writer: Option<P>,
    },
    /// `passes[0]` reads what `passes[last]` writes, and that writer needs `passes[0]`'s output.
    /// `via[i]` carries `passes[i] -> passes[i+1]` (the last: back to `passes[0]`).
    Cycle {
        passes: Vec<P>,
        via: Vec<ResourceId>,
    },
}

struct ResourceState<P> {
    last_writer: Option<P>,
    readers_since_write: Vec<P>,
}

impl<P> Default for ResourceState<P> {
    fn default() -> Self {
        ResourceState {
            last_writer: None,
            readers_since_write: Vec::new(),
        }
    }
}

/// Builds the dependency DAG. `persistent(r)` says whether reading `r` before any write this
/// frame is allowed (it then reads the previous frame's content). `uses[i]` is pass `P::new(i)`'s.
pub fn dependencies<P: Id>(
    uses: &IdVec<P, Vec<PassUse>>,
    persistent: impl Fn(ResourceId) -> bool,
) -> Result<Dependencies<P>, DependencyError<P>> {
    let mut graph = DiGraph::new();
    for p in P::all(uses.len()) {
        graph.add_node(p);
    }
    let mut state: BTreeMap<ResourceId, ResourceState<P>> = BTreeMap::new();
    let mut reads: IdVec<P, Vec<_>> = vec![Vec::new(); uses.len()].into();
    let mut first_error = None;
    let add = |g: &mut DiGraph<P, Dependency>, from: P, to: P, d: Dependency| {
        let (from, to) = (NodeIndex::new(from.index()), NodeIndex::new(to.index()));
        let exists = g
            .edges_connecting(from, to)
            .any(|e| e.weight().resource == d.resource);
        if from != to && !exists {
            g.add_edge(from, to, d);
        }
    };
    for (p, pass_uses) in P::all(uses.len()).zip(uses) {
        for u in pass_uses {
            let s = state.entry(u.resource).or_default();
            if u.access.reads() {
                match s.last_writer {
                    Some(w) => {
                        let dep = Dependency {
                            resource: u.resource,
                            hazard: Hazard::ReadAfterWrite,
                        };
                        add(&mut graph, w, p, dep);
                        reads[p].push((u.resource, ReadSource::Pass(w)));
                    }
                    None => {
                        if !persistent(u.resource) && first_error.is_none() {
                            first_error = Some((p, u.resource));
                        }
                        reads[p].push((u.resource, ReadSource::PreviousFrame));
                    }
                }
            }
            if u.access.writes() {
                for &r in &s.readers_since_write {
                    let dep = Dependency {
                        resource: u.resource,
                        hazard: Hazard::WriteAfterRead,
                    };
                    add(&mut graph, r, p, dep);
                }
                if let Some(w) = s.last_writer {
                    let dep = Dependency {
                        resource: u.resource,
                        hazard: Hazard::WriteAfterWrite,
                    };
                    add(&mut graph, w, p, dep);
                }
                s.last_writer = Some(p);
                s.readers_since_write.clear();
            } else {
                s.readers_since_write.push(p);
            }
        }
    }
    if let Some((pass, resource)) = first_error {
        return Err(read_before_write(&graph, uses, pass, resource));
    }
    let final_writer = state
        .iter()
        .filter_map(|(&r, s)| s.last_writer.map(|w| (r, w)))
        .collect();
    Ok(Dependencies {
        graph,
        reads,
        final_writer,
    })
}

/// Explains a read before write: a cycle if the later writer needs this pass's output
/// (through read-after-write edges), otherwise a misordering.
fn read_before_write<P: Id>(
    graph: &DiGraph<P, Dependency>,
    uses: &IdVec<P, Vec<PassUse>>,
    pass: P,
    resource: ResourceId,
) -> DependencyError<P> {
    let later_writer = (pass.index() + 1..uses.len()).map(P::new).find(|&q| {
        uses[q]
            .iter()
            .any(|u| u.resource == resource && u.access.writes())
    });
    let Some(writer) = later_writer else {
        return DependencyError::ReadBeforeWrite {
            pass,
            resource,
            later_writer,
        };
    };
    let data_flow = EdgeFiltered::from_fn(graph, |e| e.weight().hazard == Hazard::ReadAfterWrite);
    let path = petgraph::algo::astar(
        &data_flow,
        NodeIndex::new(pass.index()),
        |n| n.index() == writer.index(),
        |_| 1,
        |_| 0,
    );
    match path {
        Some((_, nodes)) => {
            let passes: Vec<P> = nodes.iter().map(|n| P::new(n.index())).collect();
            let mut via: Vec<ResourceId> = nodes
                .windows(2)
                .map(|w| {
                    graph
                        .edges_connecting(w[0], w[1])
                        .find(|e| e.weight().hazard == Hazard::ReadAfterWrite)
                        .map(|e| e.weight().resource)
                        .unwrap_or(resource)
                })
                .collect();
            via.push(resource);
            DependencyError::Cycle { passes, via }
        }
        None => DependencyError::ReadBeforeWrite {
            pass,
            resource,
            later_writer,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn u(resource: usize, access: Access) -> PassUse {
        PassUse {
            resource: ResourceId(resource),
            access,
        }
    }

    fn deps(uses: &[Vec<PassUse>], persistent: bool) -> Result<Dependencies, DependencyError> {
        dependencies(&IdVec::from(uses.to_vec()), |_| persistent)
    }

    #[test]
    fn read_after_write_orders_reader_after_writer() {
        let deps = deps(
            &[vec![u(0, Access::Write)], vec![u(0, Access::Read)]],
            false,
        )
        .unwrap();
        assert_eq!(deps.graph.edge_count(), 1);
        assert_eq!(
            deps.reads[PassIndex(1)],
            vec![(ResourceId(0), ReadSource::Pass(PassIndex(0)))]
        );
    }

    #[test]
    fn write_after_read_keeps_the_reader_before_the_overwrite() {
        let uses = [vec![u(0, Access::Read)], vec![u(0, Access::Write)]];
        let deps = deps(&uses, true).unwrap();
        let e = deps.graph.edge_weights().next().unwrap();
        assert_eq!(e.hazard, Hazard::WriteAfterRead);
        assert_eq!(
            deps.reads[PassIndex(0)],
            vec![(ResourceId(0), ReadSource::PreviousFrame)]
        );
    }

    #[test]
    fn transient_read_before_write_names_the_later_writer() {
        let uses = [vec![u(0, Access::Read)], vec![u(0, Access::Write)]];
        let err = deps(&uses, false).unwrap_err();
        assert_eq!(
            err,
            DependencyError::ReadBeforeWrite {
                pass: PassIndex(0),
                resource: ResourceId(0),
                later_writer: Some(PassIndex(1))
            }
        );
    }

    #[test]
    fn mutual_data_dependence_is_reported_as_a_cycle() {
        // a reads x (written by b later) and writes y; b reads y and writes x.
        let uses = [
            vec![u(0, Access::Read), u(1, Access::Write)],
            vec![u(1, Access::Read), u(0, Access::Write)],
        ];
        let err = deps(&uses, false).unwrap_err();
        assert_eq!(
            err,
            DependencyError::Cycle {
                passes: vec![PassIndex(0), PassIndex(1)],
                via: vec![ResourceId(1), ResourceId(0)]
            }
        );
    }
}
