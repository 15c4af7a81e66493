//! Allocator settings for commands whose memory is a few very large arrays (the libraries leave
//! the allocator alone).
//!
//! glibc's malloc gives a block above its mmap threshold a mapping of its own, returned to the
//! system when the block is freed; a block below it is kept by the process for reuse once
//! freed. The threshold starts at 128 KiB but rises, up to 32 MiB, each time a larger mapped
//! block is freed: after a stock's rays are dropped every array up to 32 MiB (a contour's line
//! store, an edge report's lists) stays with the process when freed, and `swarf envelope` at
//! h = 0.05 mm held ≈ 50 MB it no longer used at its peak. A fixed threshold of 1 MiB keeps
//! such arrays returnable. Not for every command: where arrays of a few MiB are made and freed
//! over and over, fresh mappings cost page faults (the demo job ran ≈ 5 % slower with it).

/// Fixes glibc's mmap threshold at 1 MiB for the rest of the process (see the module docs).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
pub(crate) fn return_large_blocks() {
    // SAFETY: `mallopt` only sets a parameter of the allocator, which it applies under its own
    // lock; a refused setting (a zero return) leaves the allocator as it was.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 1 << 20);
    }
}

/// Other allocators: nothing to set.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
pub(crate) fn return_large_blocks() {}
