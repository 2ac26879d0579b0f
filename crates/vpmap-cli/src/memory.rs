//! The program's allocator, which counts the bytes in use and their peak, lent to
//! `vpmap bench` as its memory probe (the results' peak-heap column).

use peak_alloc::PeakAlloc;
use vpmap_eval::bench::MemoryProbe;

/// The allocator, counting bytes in use and their peak (for `vpmap bench`'s memory column).
#[global_allocator]
static ALLOCATOR: PeakAlloc = PeakAlloc;

/// The global allocator's counters, lent to the benchmark.
pub struct PeakAllocProbe;

impl MemoryProbe for PeakAllocProbe {
    fn current_bytes(&self) -> usize {
        ALLOCATOR.current_usage()
    }
    fn reset_peak(&self) {
        ALLOCATOR.reset_peak_usage();
    }
    fn peak_bytes(&self) -> usize {
        ALLOCATOR.peak_usage()
    }
}
