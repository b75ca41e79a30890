//! # Where large arrays start: allocations staggered within the page
//!
//! A step is a few loops over struct-of-arrays data: loop 3 of the 1D step
//! reads and writes nine particle arrays at the same index k. glibc's
//! `malloc` serves every allocation of 128 KiB or more (its starting
//! threshold) by an `mmap` of its own, which starts 16 bytes into a page.
//! So the particle arrays of a large run all start at the same offset within
//! a page, element k of each has the same address modulo 4096, and the
//! processor, which compares a load with the stores before it by the low
//! twelve bits of their addresses first, makes the loads of one array wait
//! for the stores to another ("4K aliasing"; the arrays also share the
//! sets of the first-level cache).
//!
//! Measured on session 12's host (docs/conventions.md, "Session 13"), the
//! 1D P1 bar at 16384 cells × 4 (arrays of 512 KiB), CPU time per
//! particle-step: hompm's step with the stability monitor 72.8 → 34.2 ns
//! and the lean step of issue #39 62.0 → 24.6 ns when each large
//! allocation starts a different number of cache lines into its block; at
//! 1024 cells (32 KiB arrays, which `malloc` places one after another)
//! nothing changes.
//!
//! [`StaggeredAllocator`] is that placement as a global allocator: it
//! hands every allocation of at least [`STAGGERED_FROM`] bytes (and an
//! alignment of at most 16) out of a block of the system allocator that is
//! 1 to 61 cache lines longer, starting that many lines in, the count
//! rotating from one allocation to the next; it keeps the count in the
//! eight bytes just before the pointer it returns, where `dealloc` finds
//! it. Smaller allocations and larger alignments go to the system
//! allocator as they are. The binary `hompm`, the benches and the step-cost
//! examples register it (`#[global_allocator]`). It moves where arrays
//! start, never what is computed in them: every result has the same bits
//! with it and without it (the test suite runs without it).
//!
//! Items: [`StaggeredAllocator`], [`STAGGERED_FROM`].

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The smallest allocation that [`StaggeredAllocator`] staggers: 64 KiB,
/// below glibc's `mmap` threshold, so that every array it maps by itself
/// is staggered.
pub const STAGGERED_FROM: usize = 64 * 1024;

/// A cache line: the unit of the stagger.
const LINE: usize = 64;
/// The stagger runs through 1, 2, …, 61 lines (61 is prime, so a run of
/// arrays allocated in a fixed pattern still gets distinct offsets).
const OFFSETS: usize = 61;

/// The global allocator that starts large allocations at rotating offsets
/// within the page (module docs). Placement only: the same bits.
#[derive(Debug, Default)]
pub struct StaggeredAllocator {
    next: AtomicUsize,
}

/// Whether an allocation of this layout is staggered.
fn staggered(layout: Layout) -> bool {
    layout.size() >= STAGGERED_FROM && layout.align() <= 16
}

/// The system block of a staggered allocation `offset` bytes in: aligned
/// for the offset kept just before the data, at least.
fn block(layout: Layout, offset: usize) -> Option<Layout> {
    let align = layout.align().max(std::mem::align_of::<usize>());
    Layout::from_size_align(layout.size().checked_add(offset)?, align).ok()
}

impl StaggeredAllocator {
    /// The allocator, its rotation at the first offset.
    pub const fn new() -> Self {
        Self {
            next: AtomicUsize::new(0),
        }
    }

    /// A staggered allocation: the next offset, the block from the system
    /// allocator (`zeroed` or not), the offset written before the pointer.
    ///
    /// # Safety
    /// As [`GlobalAlloc::alloc`], for a layout that [`staggered`] accepts.
    unsafe fn allocate(&self, layout: Layout, zeroed: bool) -> *mut u8 {
        let offset = LINE * (1 + self.next.fetch_add(1, Ordering::Relaxed) % OFFSETS);
        let Some(block) = block(layout, offset) else {
            return std::ptr::null_mut();
        };
        // SAFETY: `block` has a non-zero size (at least STAGGERED_FROM).
        let start = unsafe {
            if zeroed {
                System.alloc_zeroed(block)
            } else {
                System.alloc(block)
            }
        };
        if start.is_null() {
            return start;
        }
        // SAFETY: the offset, at least 64 bytes, lies inside the block
        // before the pointer returned, which is aligned as the block (the
        // offset is a multiple of 64, the block's alignment 8 or 16), so the
        // eight bytes before it are inside the block and aligned for a usize.
        unsafe {
            let data = start.add(offset);
            data.cast::<usize>().sub(1).write(offset);
            data
        }
    }
}

// SAFETY: every staggered pointer is `offset` bytes into a live system
// block of `layout.size() + offset` bytes, aligned as `layout` asks;
// `dealloc` recognises a staggered layout by the same test as `alloc` and
// frees that block; everything else is the system allocator's.
unsafe impl GlobalAlloc for StaggeredAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if staggered(layout) {
            // SAFETY: the layout is staggered; the caller's contract holds.
            unsafe { self.allocate(layout, false) }
        } else {
            // SAFETY: the caller's contract, passed on.
            unsafe { System.alloc(layout) }
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if staggered(layout) {
            // SAFETY: as in `alloc`.
            unsafe { self.allocate(layout, true) }
        } else {
            // SAFETY: the caller's contract, passed on.
            unsafe { System.alloc_zeroed(layout) }
        }
    }

    unsafe fn dealloc(&self, data: *mut u8, layout: Layout) {
        if staggered(layout) {
            // SAFETY: `data` came from `allocate` with this layout, which
            // wrote its offset just before it; the block it allocated is
            // `offset` bytes before `data`, of `size + offset` bytes.
            unsafe {
                let offset = data.cast::<usize>().sub(1).read();
                let align = layout.align().max(std::mem::align_of::<usize>());
                let block = Layout::from_size_align_unchecked(layout.size() + offset, align);
                System.dealloc(data.sub(offset), block);
            }
        } else {
            // SAFETY: the caller's contract, passed on.
            unsafe { System.dealloc(data, layout) }
        }
    }

    unsafe fn realloc(&self, data: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller guarantees that new_size with the old alignment
        // is a valid layout.
        let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
        if !staggered(layout) && !staggered(new_layout) {
            // SAFETY: both are the system allocator's; the contract passed on.
            return unsafe { System.realloc(data, layout, new_size) };
        }
        // SAFETY: a new allocation, the common bytes copied, the old freed:
        // GlobalAlloc's own default, through this allocator's alloc and
        // dealloc so that each side is freed as it was allocated.
        unsafe {
            let moved = self.alloc(new_layout);
            if !moved.is_null() {
                std::ptr::copy_nonoverlapping(data, moved, layout.size().min(new_size));
                self.dealloc(data, layout);
            }
            moved
        }
    }
}
