//! Typed indices, one per index space: a pass's position in program order, its position among
//! the kept passes, and a resource's position in the plan. Each indexes only its own vectors'
//! elements by meaning, so the compiler cannot use one where another is meant.

use std::fmt;
use std::hash::Hash;
use std::ops::{Index, IndexMut};

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

        impl<T> Index<$name> for [T] {
            type Output = T;
            fn index(&self, id: $name) -> &T {
                &self[id.0]
            }
        }

        impl<T> IndexMut<$name> for [T] {
            fn index_mut(&mut self, id: $name) -> &mut T {
                &mut self[id.0]
            }
        }

        impl<T> Index<$name> for Vec<T> {
            type Output = T;
            fn index(&self, id: $name) -> &T {
                &self[id.0]
            }
        }

        impl<T> IndexMut<$name> for Vec<T> {
            fn index_mut(&mut self, id: $name) -> &mut T {
                &mut self[id.0]
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
