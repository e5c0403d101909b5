//! Property tests on random graphs: whatever the passes read and write, every stage is free of
//! hazards, the stage order respects every dependency and program order between conflicting
//! passes, and every conflicting hand-over between stages has a barrier.

use passgraph::graph::deps::{DependencyError, PassUse};
use passgraph::graph::id::{IdVec, KeptPass, PassIndex, ResourceId};
use passgraph::graph::interface::Access;
use passgraph::graph::schedule::{Usage, schedule};
use proptest::prelude::*;

const RESOURCES: usize = 6;

fn access() -> impl Strategy<Value = Access> {
    prop_oneof![
        Just(Access::Read),
        Just(Access::Write),
        Just(Access::ReadWrite)
    ]
}

/// A pass touches a random subset of resources, each once, with a random access.
fn pass() -> impl Strategy<Value = Vec<PassUse>> {
    proptest::collection::btree_map(0..RESOURCES, access(), 0..4).prop_map(|m| {
        m.into_iter()
            .map(|(resource, access)| PassUse {
                resource: ResourceId(resource),
                access,
            })
            .collect()
    })
}

fn usage(a: Access) -> Usage {
    match a {
        Access::Read => Usage::StorageRead,
        Access::Write => Usage::StorageWrite,
        Access::ReadWrite => Usage::StorageReadWrite,
    }
}

fn conflict(a: &[PassUse], b: &[PassUse]) -> Option<ResourceId> {
    a.iter().find_map(|x| {
        b.iter()
            .find(|y| y.resource == x.resource && (x.access.writes() || y.access.writes()))
            .map(|_| x.resource)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn stages_are_hazard_free_and_ordered(
        passes in proptest::collection::vec(pass(), 1..14),
        // Half the cases make everything persistent, so most graphs are valid and reach the
        // stage checks; the rest exercise read-before-write and cycle detection.
        persistent_mask in prop_oneof![Just((1u32 << RESOURCES) - 1), 0u32..(1 << RESOURCES)],
        output_mask in 1u32..(1 << RESOURCES),
    ) {
        let passes: IdVec<PassIndex, Vec<PassUse>> = IdVec::from(passes);
        let persistent = move |r: ResourceId| persistent_mask & (1 << r.0) != 0;
        // Outputs among the written resources, so an unwritten output does not cull everything.
        let outputs: Vec<ResourceId> = (0..RESOURCES)
            .filter(|&r| output_mask & (1 << r) != 0)
            .map(ResourceId)
            .filter(|&r| passes.iter().flatten().any(|u| u.resource == r && u.access.writes()))
            .collect();
        let usages: IdVec<PassIndex, Vec<(ResourceId, Usage)>> = passes
            .iter()
            .map(|p| p.iter().map(|u| (u.resource, usage(u.access))).collect())
            .collect();
        let s = match schedule(&passes, &usages, persistent, &outputs) {
            Ok(s) => s,
            Err(DependencyError::ReadBeforeWrite { pass, resource, later_writer }) => {
                // The error must be real: a transient read with no earlier write.
                prop_assert!(!persistent(resource));
                prop_assert!(passes[pass].iter().any(|u| u.resource == resource && u.access.reads()));
                prop_assert!(!passes.as_slice()[..pass.0].iter().flatten().any(|u| u.resource == resource && u.access.writes()));
                if let Some(w) = later_writer {
                    prop_assert!(w > pass);
                }
                return Ok(());
            }
            Err(DependencyError::Cycle { passes: cycle, via }) => {
                prop_assert_eq!(cycle.len(), via.len());
                prop_assert!(cycle.len() >= 2);
                return Ok(());
            }
        };
        let kept = &s.kept;
        // Every dependency edge goes to a strictly later stage.
        for e in s.deps.graph.raw_edges() {
            prop_assert!(s.levels[KeptPass(e.source().index())] < s.levels[KeptPass(e.target().index())]);
        }
        // Any two kept passes that conflict run in program order, in different stages.
        for i in 0..kept.len() {
            for j in i + 1..kept.len() {
                if conflict(&passes[kept[KeptPass(i)]], &passes[kept[KeptPass(j)]]).is_some() {
                    prop_assert!(s.levels[KeptPass(i)] < s.levels[KeptPass(j)], "passes {} and {} conflict", kept[KeptPass(i)], kept[KeptPass(j)]);
                }
            }
        }
        // Stages partition the kept passes in program order.
        let flat: Vec<KeptPass> = s.stages.iter().flatten().copied().collect();
        let mut sorted = flat.clone();
        sorted.sort();
        prop_assert_eq!(sorted, (0..kept.len()).map(KeptPass).collect::<Vec<_>>());
        // A conflicting hand-over from one stage to a later one has a barrier at or before the
        // later stage, after the earlier one.
        for i in 0..kept.len() {
            for j in i + 1..kept.len() {
                if let Some(r) = conflict(&passes[kept[KeptPass(i)]], &passes[kept[KeptPass(j)]]) {
                    let (a, b) = (s.levels[KeptPass(i)], s.levels[KeptPass(j)]);
                    prop_assert!(
                        s.barriers.iter().any(|x| x.resource == r && x.before_stage > a && x.before_stage <= b),
                        "no barrier for resource {} between stages {} and {}", r, a, b
                    );
                }
            }
        }
        // Every output is produced by a kept pass.
        for o in &outputs {
            if let Some(&w) = s.all.final_writer.get(o) {
                prop_assert!(s.alive[w]);
            }
        }
    }
}
