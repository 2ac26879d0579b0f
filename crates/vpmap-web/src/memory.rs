//! Giving freed memory back to the system after a burst of requests.
//!
//! glibc's allocator serves a block of 128 KiB or more with its own `mmap` and unmaps it when
//! it is freed. But the first time such a block is freed it raises that threshold to the
//! block's size (up to 32 MiB) and its trim threshold to twice that, so from then on the
//! multi-megabyte buffers of a request (a grid, its PGM and base64 text, the JSON answer)
//! come from the worker threads' arenas and stay resident after the request: up to 64 MiB
//! per arena, one arena per worker thread. In the load test (`tests/it/load.rs`) the server
//! kept 23 MiB more after the bursts than before them, and more after each heavier burst.
//! Fixing the threshold turns the dynamic adjustment off: large blocks are unmapped when freed
//! and the server's memory returns to within a few MiB of its baseline.

/// Blocks of this size or more are mapped on their own and returned when freed, bytes
/// (glibc's initial threshold).
pub const MMAP_THRESHOLD_BYTES: i32 = 128 * 1024;

/// Make the process's allocator return large freed blocks to the system at once (see the
/// module's notes): fixes glibc's mmap threshold at [`MMAP_THRESHOLD_BYTES`]. Affects the
/// whole process; [`crate::serve_until_ctrl_c`] calls it, and a program embedding the server
/// may call it at start. Returns whether the allocator took the setting (false on other C
/// libraries, where it does nothing).
#[must_use]
pub fn return_freed_memory_promptly() -> bool {
    set_mmap_threshold(MMAP_THRESHOLD_BYTES)
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
fn set_mmap_threshold(bytes: i32) -> bool {
    // SAFETY: mallopt only changes an allocator parameter; glibc takes its own lock, so it
    // may be called at any time from any thread, and it has no pointer arguments.
    unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, bytes) == 1 }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn set_mmap_threshold(_bytes: i32) -> bool {
    false
}
