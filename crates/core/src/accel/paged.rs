//! The tree's large arrays (nodes, triangle blocks, and the build's primitives) on 2 MiB
//! pages where the OS offers them. A large tree's queries wander over tens of megabytes;
//! with 4 KiB pages nearly every node or block they load is also a TLB miss, a page walk
//! before the cache miss (`perf annotate` of shadow rays on a 1M-triangle mesh put 10% of
//! the samples on the prefetch hints alone, which wait for the walk). A build touches each
//! of its pages first, one fault per page: 512 times fewer with huge pages. An array of [`PAGED_FROM_BYTES`] or more is
//! placed in an anonymous memory map advised to use transparent huge pages (Linux's
//! `madvise(MADV_HUGEPAGE)`, through `memmap2`'s safe API; a no-op where the kernel has them
//! off); smaller ones, and any the map cannot be made for, stay in a `Vec`. The element
//! types are plain data (`bytemuck::Pod`), so viewing the map's bytes as them is checked by
//! `bytemuck`, without `unsafe`.

use std::ops::{Deref, DerefMut};

use bytemuck::Pod;
use rayon::prelude::*;

/// Arrays from this size are mapped (a huge page is 2 MiB; below a few of them the TLB
/// holds a tree's pages anyway).
pub(super) const PAGED_FROM_BYTES: usize = 4 << 20;

/// A fixed-length array of `T`, in a `Vec` or a memory map.
pub(super) enum Paged<T: Pod> {
    Heap(Vec<T>),
    Mapped { map: memmap2::MmapMut, len: usize },
}

impl<T: Pod + Send + Sync> Paged<T> {
    /// `len` elements, element `i` being `make(i)`, made in parallel.
    pub fn from_fn(len: usize, make: impl Fn(usize) -> T + Sync) -> Self {
        match Self::mapped_zeroed(len) {
            Some(mut paged) => {
                paged.par_iter_mut().enumerate().for_each(|(i, x)| *x = make(i));
                paged
            }
            None => Self::Heap((0..len).into_par_iter().map(&make).collect()),
        }
    }

    /// An empty array with room for `capacity` elements before [`Self::push`] moves them:
    /// in a map when that many are many (its untouched pages cost nothing, so a generous
    /// capacity is cheap), else in a `Vec`.
    pub fn with_capacity(capacity: usize) -> Self {
        match Self::mapped_zeroed(capacity) {
            Some(Self::Mapped { map, .. }) => Self::Mapped { map, len: 0 },
            _ => Self::Heap(Vec::with_capacity(capacity)),
        }
    }

    /// Append `x`. A full map moves its elements to one twice as large.
    pub fn push(&mut self, x: T) {
        match self {
            Self::Heap(v) => v.push(x),
            Self::Mapped { map, len } => {
                if *len == map.len() / size_of::<T>().max(1) {
                    let mut larger = Self::with_capacity(2 * *len + 1);
                    for &y in &bytemuck::cast_slice::<u8, T>(map)[..*len] {
                        larger.push(y);
                    }
                    larger.push(x);
                    *self = larger;
                    return;
                }
                bytemuck::cast_slice_mut::<u8, T>(map)[*len] = x;
                *len += 1;
            }
        }
    }

    /// A zeroed map for `len` elements, or `None` when they are too few or the map fails.
    fn mapped_zeroed(len: usize) -> Option<Self> {
        let bytes = len.checked_mul(size_of::<T>())?;
        if bytes < PAGED_FROM_BYTES {
            return None;
        }
        let map = memmap2::MmapMut::map_anon(bytes).ok()?;
        // Only a hint: without transparent huge pages the map is ordinary memory.
        #[cfg(target_os = "linux")]
        let _ = map.advise(memmap2::Advice::HugePage);
        // A map starts on a page boundary, so any `T` is aligned there.
        bytemuck::try_cast_slice::<u8, T>(&map).ok()?;
        Some(Self::Mapped { map, len })
    }

    /// Keep the first `len` elements (no more than there are); a map keeps its pages.
    pub fn truncate(&mut self, len: usize) {
        match self {
            Self::Heap(v) => v.truncate(len),
            Self::Mapped { len: n, .. } => *n = len.min(*n),
        }
    }

    /// True when the elements are in a memory map.
    #[cfg(test)]
    pub fn is_mapped(&self) -> bool {
        matches!(self, Self::Mapped { .. })
    }
}

impl<T: Pod> Deref for Paged<T> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        match self {
            Self::Heap(v) => v,
            Self::Mapped { map, len } => &bytemuck::cast_slice(map)[..*len],
        }
    }
}

impl<T: Pod> DerefMut for Paged<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        match self {
            Self::Heap(v) => v,
            Self::Mapped { map, len } => &mut bytemuck::cast_slice_mut(map)[..*len],
        }
    }
}

impl<T: Pod> Default for Paged<T> {
    fn default() -> Self {
        Self::Heap(Vec::new())
    }
}

impl<T: Pod + Send + Sync> Clone for Paged<T> {
    fn clone(&self) -> Self {
        Self::from_fn(self.len(), |i| self[i])
    }
}

impl<T: Pod + std::fmt::Debug> std::fmt::Debug for Paged<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small arrays stay on the heap, large ones are mapped; both hold what was put in, and
    /// joining and cloning keep every element.
    #[test]
    fn small_arrays_stay_on_the_heap_and_large_ones_are_mapped_intact() {
        let small = Paged::from_fn(1000, |i| i as u32 * 3);
        assert!(!small.is_mapped());
        assert!(small.iter().enumerate().all(|(i, &x)| x == i as u32 * 3));
        let n = PAGED_FROM_BYTES / 4 + 7;
        let large = Paged::from_fn(n, |i| i as u32 ^ 0x5a5a);
        assert!(large.is_mapped());
        assert_eq!(large.len(), n);
        assert!(large.iter().enumerate().all(|(i, &x)| x == i as u32 ^ 0x5a5a));
        let mut moved = Paged::with_capacity(n);
        assert!(moved.is_mapped() && moved.is_empty());
        for i in 0..n as u32 {
            moved.push(i);
        }
        assert!(moved.is_mapped());
        assert!(moved.iter().enumerate().all(|(i, &x)| x == i as u32));
        // As `WideBvh::attach_triangles` appends blocks to those of an earlier call.
        let joined = Paged::from_fn(1000 + n, |i| small.get(i).copied().unwrap_or_else(|| moved[i - 1000]));
        assert!(joined.is_mapped());
        assert_eq!(joined.len(), 1000 + n);
        assert_eq!(
            (joined[999], joined[1000], joined[1000 + n - 1]),
            (2997, 0, n as u32 - 1)
        );
        let mut copy = joined.clone();
        assert_eq!(&copy[..], &joined[..]);
        copy[5] = 1;
        assert_eq!((copy[5], joined[5]), (1, 15));
        assert_eq!(Paged::<u32>::default().len(), 0);
    }

    /// Pushing past the capacity keeps every element, in a map or a `Vec`.
    #[test]
    fn pushing_past_the_capacity_keeps_the_elements() {
        for capacity in [10, PAGED_FROM_BYTES / 8] {
            let mut v = Paged::with_capacity(capacity);
            assert_eq!(v.is_mapped(), capacity > 10);
            let n = 2 * capacity + 3;
            for i in 0..n as u64 {
                v.push(i * 7);
            }
            assert_eq!(v.len(), n);
            assert!(v.iter().enumerate().all(|(i, &x)| x == i as u64 * 7));
        }
    }
}
