//! `hompm::placement`: the allocator that starts large arrays at staggered
//! offsets within the page hands out usable, aligned memory, at a
//! different offset each time, keeps contents across `realloc`, and
//! changes no result: the `hompm` binary, which registers it, prints what
//! the library prints in this test process, which does not.

use hompm::placement::{StaggeredAllocator, STAGGERED_FROM};
use std::alloc::{GlobalAlloc, Layout};

/// Fills `len` bytes at `p` with a pattern of `seed` and checks it back.
fn fill_and_check(p: *mut u8, len: usize, seed: u8) {
    let bytes = unsafe { std::slice::from_raw_parts_mut(p, len) };
    for (k, b) in bytes.iter_mut().enumerate() {
        *b = (k as u8).wrapping_mul(31).wrapping_add(seed);
    }
    assert!(bytes
        .iter()
        .enumerate()
        .all(|(k, &b)| b == (k as u8).wrapping_mul(31).wrapping_add(seed)));
}

#[test]
fn large_allocations_start_at_different_offsets_within_a_page() {
    let allocator = StaggeredAllocator::new();
    // Eight arrays of 512 KiB, as the 1D particle arrays at 16384 cells.
    let layout = Layout::array::<f64>(65536).unwrap();
    let blocks: Vec<*mut u8> = (0..8).map(|_| unsafe { allocator.alloc(layout) }).collect();
    let mut offsets: Vec<usize> = blocks.iter().map(|&p| p as usize % 4096).collect();
    for (k, &p) in blocks.iter().enumerate() {
        assert!(!p.is_null());
        assert_eq!(p as usize % layout.align(), 0);
        fill_and_check(p, layout.size(), k as u8);
    }
    offsets.sort_unstable();
    offsets.dedup();
    assert_eq!(offsets.len(), 8, "offsets within the page: {offsets:?}");
    for p in blocks {
        unsafe { allocator.dealloc(p, layout) };
    }
}

#[test]
fn small_and_over_aligned_allocations_are_the_system_s() {
    let allocator = StaggeredAllocator::new();
    for layout in [
        Layout::from_size_align(STAGGERED_FROM - 1, 8).unwrap(),
        Layout::from_size_align(STAGGERED_FROM, 4096).unwrap(),
        Layout::from_size_align(1, 1).unwrap(),
    ] {
        let p = unsafe { allocator.alloc(layout) };
        assert!(!p.is_null());
        assert_eq!(p as usize % layout.align(), 0);
        fill_and_check(p, layout.size(), 7);
        unsafe { allocator.dealloc(p, layout) };
    }
}

/// Zeroed also where the block reuses memory just written and freed
/// (glibc serves a size again from its heap once such a block was freed).
#[test]
fn zeroed_large_allocations_are_zero() {
    let allocator = StaggeredAllocator::new();
    let layout = Layout::array::<f64>(40_000).unwrap();
    for _ in 0..3 {
        let dirty = unsafe { allocator.alloc(layout) };
        unsafe { std::ptr::write_bytes(dirty, 0xa5, layout.size()) };
        unsafe { allocator.dealloc(dirty, layout) };
        let p = unsafe { allocator.alloc_zeroed(layout) };
        assert!(!p.is_null());
        let bytes = unsafe { std::slice::from_raw_parts(p, layout.size()) };
        assert!(bytes.iter().all(|&b| b == 0));
        unsafe { allocator.dealloc(p, layout) };
    }
}

#[test]
fn realloc_keeps_the_contents_across_the_threshold() {
    let allocator = StaggeredAllocator::new();
    // Small → large (staggered) → larger → smaller but large → small.
    let sizes = [1000, 300_000, 500_000, 100_000, 2000];
    let mut layout = Layout::from_size_align(sizes[0], 8).unwrap();
    let mut p = unsafe { allocator.alloc(layout) };
    fill_and_check(p, layout.size(), 3);
    for &size in &sizes[1..] {
        let kept = layout.size().min(size);
        let before: Vec<u8> = unsafe { std::slice::from_raw_parts(p, kept) }.to_vec();
        p = unsafe { allocator.realloc(p, layout, size) };
        assert!(!p.is_null());
        assert_eq!(p as usize % 8, 0);
        layout = Layout::from_size_align(size, 8).unwrap();
        assert_eq!(unsafe { std::slice::from_raw_parts(p, kept) }, &before[..]);
        fill_and_check(p, size, size as u8);
    }
    unsafe { allocator.dealloc(p, layout) };
}

/// What `hompm ARGS` prints from the binary (staggered) against what
/// `hompm::cli::run` returns here (the system allocator).
fn assert_binary_prints_the_library_s(args: &[&str]) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_hompm"))
        .args(args)
        .output()
        .expect("the binary runs");
    assert!(out.status.success(), "{args:?}");
    let here = hompm::cli::run(args.iter().copied()).unwrap();
    assert!(here.failure.is_none());
    assert!(
        String::from_utf8_lossy(&out.stdout) == here.stdout,
        "{args:?}: the binary's output differs from the library's"
    );
}

#[test]
fn the_staggered_binary_computes_the_bits_of_the_library() {
    // 16384 particles: arrays of 128 KiB, each staggered in the binary.
    assert_binary_prints_the_library_s(&[
        "run",
        "vibrating-bar",
        "--method",
        "mpm",
        "--cells",
        "4096",
        "--ppc",
        "4",
        "--steps",
        "100",
        "--json",
    ]);
    // 9216 particles of 2D BSMPM: [f64; 2] arrays of 144 KiB.
    assert_binary_prints_the_library_s(&[
        "run",
        "aligned-vibration",
        "--method",
        "bsmpm",
        "--cells",
        "32",
        "--ppc",
        "9",
        "--steps",
        "20",
        "--json",
    ]);
}
