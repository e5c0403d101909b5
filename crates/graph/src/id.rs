//! Typed indices, one per index space: a pass's position in program order, its position among
//! the kept passes, and a resource's position in the plan. Each indexes only an [`IdVec`] of
//! its own space, so the compiler cannot use one where another is meant: indexing the plan's
//! passes with a `ResourceId` does not compile (the `compile_fail` example below).

use std::fmt;
use std::hash::Hash;
use std::marker::PhantomData;
use std::ops::{Deref, DerefMut, Index, IndexMut};

/// An index into one index space.
pub trait Id: Copy + Eq + Ord + Hash + fmt::Debug {
    fn new(index: usize) -> Self;
    fn index(self) -> usize;

    /// Every id below `count`.
    fn all(count: usize) -> impl Iterator<Item = Self> {
        (0..count).map(Self::new)
    }
}

macro_rules! id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub usize);

        impl Id for $name {
            fn new(index: usize) -> Self {
                $name(index)
            }

            fn index(self) -> usize {
                self.0
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.fmt(f)
            }
        }
    };
}

id!(
    /// A pass instance's position in the graph's `passes`, culled or not (program order).
    PassIndex
);
id!(
    /// A kept pass's position in `Plan::passes` (program order among the kept passes).
    KeptPass
);
id!(
    /// A resource's position in `Plan::resources`.
    ResourceId
);
id!(
    /// A stage's position in `Plan::stages`: the passes of one stage run without barriers
    /// between them, after every pass of the stages before.
    Stage
);

/// A vector indexed by one kind of id. It reads as a `Vec` (`iter`, `len`, `push`), but `v[i]`
/// takes only its own id type (`as_slice()[n]` for a plain position):
///
/// ```
/// use passgraph_graph::id::{IdVec, ResourceId};
/// let sizes: IdVec<ResourceId, u64> = IdVec::from(vec![16, 32]);
/// assert_eq!(sizes[ResourceId(1)], 32);
/// ```
///
/// ```compile_fail
/// use passgraph_graph::id::{IdVec, KeptPass, ResourceId};
/// let sizes: IdVec<ResourceId, u64> = IdVec::from(vec![16, 32]);
/// let _ = sizes[KeptPass(1)]; // a pass's position is not a resource's
/// ```
#[derive(Clone, PartialEq)]
pub struct IdVec<I, T> {
    items: Vec<T>,
    id: PhantomData<I>,
}

impl<I: Id, T> IdVec<I, T> {
    pub fn new() -> Self {
        IdVec::from(Vec::new())
    }

    /// Every (id, element) pair in order.
    pub fn iter_ids(&self) -> impl Iterator<Item = (I, &T)> {
        self.items.iter().enumerate().map(|(i, t)| (I::new(i), t))
    }

    /// The id of the first element matching `f`.
    pub fn position(&self, f: impl FnMut(&T) -> bool) -> Option<I> {
        self.items.iter().position(f).map(I::new)
    }

    pub fn into_vec(self) -> Vec<T> {
        self.items
    }
}

impl<I: Id, T> Default for IdVec<I, T> {
    fn default() -> Self {
        IdVec::new()
    }
}

impl<I, T: fmt::Debug> fmt::Debug for IdVec<I, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.items.fmt(f)
    }
}

impl<I, T> From<Vec<T>> for IdVec<I, T> {
    fn from(items: Vec<T>) -> Self {
        IdVec {
            items,
            id: PhantomData,
        }
    }
}

impl<I, T> FromIterator<T> for IdVec<I, T> {
    fn from_iter<It: IntoIterator<Item = T>>(iter: It) -> Self {
        IdVec::from(iter.into_iter().collect::<Vec<T>>())
    }
}

impl<I, T> IntoIterator for IdVec<I, T> {
    type Item = T;
    type IntoIter = std::vec::IntoIter<T>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.into_iter()
    }
}

impl<'a, I, T> IntoIterator for &'a IdVec<I, T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter()
    }
}

// A Vec in all but indexing: its methods (push, splice, retain, iter) reach through.
impl<'a, I, T> IntoIterator for &'a mut IdVec<I, T> {
    type Item = &'a mut T;
    type IntoIter = std::slice::IterMut<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter_mut()
    }
}

impl<I, T> Deref for IdVec<I, T> {
    type Target = Vec<T>;
    fn deref(&self) -> &Vec<T> {
        &self.items
    }
}

impl<I, T> DerefMut for IdVec<I, T> {
    fn deref_mut(&mut self) -> &mut Vec<T> {
        &mut self.items
    }
}

impl<'de, I, T: serde::Deserialize<'de>> serde::Deserialize<'de> for IdVec<I, T> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Vec::deserialize(deserializer).map(IdVec::from)
    }
}

impl<I: Id, T> Index<I> for IdVec<I, T> {
    type Output = T;
    fn index(&self, id: I) -> &T {
        &self.items[id.index()]
    }
}

impl<I: Id, T> IndexMut<I> for IdVec<I, T> {
    fn index_mut(&mut self, id: I) -> &mut T {
        &mut self.items[id.index()]
    }
}
