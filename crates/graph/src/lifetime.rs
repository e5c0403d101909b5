//! Resource lifetimes and reuse: transient resources with equal descriptors and disjoint
//! lifetimes share one GPU object (WebGPU has no memory aliasing, so sharing is whole objects).

use super::id::{IdVec, ResourceId, Stage};

/// The stages in which a resource is used, inclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lifetime {
    pub first_stage: Stage,
    pub last_stage: Stage,
}

impl Lifetime {
    pub fn extend(self, stage: Stage) -> Lifetime {
        Lifetime {
            first_stage: self.first_stage.min(stage),
            last_stage: self.last_stage.max(stage),
        }
    }
}

/// Whether a resource's content outlives the stages that use it.
#[derive(Clone, Copy, Debug)]
pub struct Role {
    /// Kept across frames: it lives the whole frame.
    pub persistent: bool,
    /// Read back after the last stage.
    pub output: bool,
}

/// The lifetime of each resource (`roles[i]` is resource `i`'s) from `used_in`, every
/// (resource, stage) in which a kept pass uses it; `None` for a resource no kept pass uses.
pub fn lifetimes(
    roles: &[Role],
    used_in: impl IntoIterator<Item = (ResourceId, Stage)>,
    last_stage: Stage,
) -> IdVec<ResourceId, Option<Lifetime>> {
    let mut out: IdVec<ResourceId, Option<Lifetime>> = vec![None; roles.len()].into();
    for (r, stage) in used_in {
        out[r] = Some(out[r].map_or(
            Lifetime {
                first_stage: stage,
                last_stage: stage,
            },
            |l| l.extend(stage),
        ));
    }
    for (lifetime, role) in out.iter_mut().zip(roles) {
        *lifetime = lifetime.map(|l| {
            if role.persistent {
                l.extend(Stage(0)).extend(last_stage)
            } else if role.output {
                l.extend(last_stage)
            } else {
                l
            }
        });
    }
    out
}

/// What the allocator needs to know about one logical resource.
#[derive(Clone, Debug)]
pub struct LogicalResource<D> {
    pub descriptor: D,
    /// `None` when no kept pass uses it: nothing is allocated.
    pub lifetime: Option<Lifetime>,
    /// Persistent resources and outputs keep their own object.
    pub shareable: bool,
}

/// The physical objects to create and which one each logical resource uses.
#[derive(Clone, Debug, PartialEq)]
pub struct Allocation<D> {
    pub physical_of: Vec<Option<usize>>,
    pub physical: Vec<D>,
}

/// Greedy interval assignment in order of first use: a shareable resource takes the first
/// free object with an equal descriptor, whose last user finished in an earlier stage.
pub fn allocate<D: PartialEq + Clone>(resources: &[LogicalResource<D>]) -> Allocation<D> {
    struct Slot {
        shareable: bool,
        busy_until: Stage,
    }
    let mut order: Vec<usize> = (0..resources.len())
        .filter(|&i| resources[i].lifetime.is_some())
        .collect();
    order.sort_by_key(|&i| (resources[i].lifetime.map(|l| l.first_stage), i));
    let mut physical_of = vec![None; resources.len()];
    let mut physical: Vec<D> = Vec::new();
    let mut slots: Vec<Slot> = Vec::new();
    for i in order {
        let r = &resources[i];
        let Some(life) = r.lifetime else { continue };
        let reuse = r.shareable.then(|| {
            (0..slots.len()).find(|&s| {
                slots[s].shareable
                    && slots[s].busy_until < life.first_stage
                    && physical[s] == r.descriptor
            })
        });
        let slot = match reuse.flatten() {
            Some(s) => s,
            None => {
                physical.push(r.descriptor.clone());
                slots.push(Slot {
                    shareable: r.shareable,
                    busy_until: Stage(0),
                });
                physical.len() - 1
            }
        };
        slots[slot].busy_until = life.last_stage;
        physical_of[i] = Some(slot);
    }
    Allocation {
        physical_of,
        physical,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn persistent_spans_the_frame_outputs_reach_the_end_and_unused_get_none() {
        let role = |persistent, output| Role { persistent, output };
        let roles = [
            role(false, false),
            role(true, false),
            role(false, true),
            role(false, false),
        ];
        let used_in = [
            (ResourceId(0), Stage(1)),
            (ResourceId(0), Stage(2)),
            (ResourceId(1), Stage(2)),
            (ResourceId(2), Stage(1)),
        ];
        let span = |first, last| {
            Some(Lifetime {
                first_stage: Stage(first),
                last_stage: Stage(last),
            })
        };
        assert_eq!(
            lifetimes(&roles, used_in, Stage(4)).into_vec(),
            vec![span(1, 2), span(0, 4), span(1, 4), None]
        );
    }

    fn r(desc: u32, first: usize, last: usize, shareable: bool) -> LogicalResource<u32> {
        LogicalResource {
            descriptor: desc,
            lifetime: Some(Lifetime {
                first_stage: Stage(first),
                last_stage: Stage(last),
            }),
            shareable,
        }
    }

    #[test]
    fn disjoint_equal_transients_share_one_object() {
        let a = allocate(&[r(7, 0, 1, true), r(7, 2, 3, true)]);
        assert_eq!(a.physical_of, vec![Some(0), Some(0)]);
        assert_eq!(a.physical.len(), 1);
    }

    #[test]
    fn overlapping_lifetimes_never_share() {
        let a = allocate(&[r(7, 0, 1, true), r(7, 1, 2, true)]);
        assert_eq!(a.physical.len(), 2);
    }

    #[test]
    fn different_descriptors_never_share() {
        let a = allocate(&[r(7, 0, 0, true), r(8, 1, 1, true)]);
        assert_eq!(a.physical.len(), 2);
    }

    #[test]
    fn persistent_resources_are_never_shared() {
        let a = allocate(&[r(7, 0, 0, false), r(7, 1, 1, true), r(7, 2, 2, false)]);
        assert_eq!(a.physical_of, vec![Some(0), Some(1), Some(2)]);
    }

    #[test]
    fn unused_resources_get_no_object() {
        let unused = LogicalResource {
            descriptor: 7,
            lifetime: None,
            shareable: true,
        };
        let a = allocate(&[unused]);
        assert_eq!(a.physical_of, vec![None]);
        assert!(a.physical.is_empty());
    }
}
