//! Large buffers of the build in huge pages.
//!
//! A ten-million-triangle mesh's index is written into about a gigabyte of fresh memory
//! (primitive records, nodes, the primitive order, triangle packets). In ordinary 4 KiB pages
//! the operating system stops the writer at every page to clear it and map it, a quarter of a
//! million stops per gigabyte: a fifth of the build's time went there. Linux can back memory with 2 MiB
//! pages instead, but where it is set to do so only on request (`madvise`, Debian's default)
//! nobody asks for it. These helpers ask, for the buffers large enough to gain: each fault
//! then maps 512 times as much, and walks through the finished index miss the address
//! translation caches less. Elsewhere (other systems, huge pages turned off) the advice is
//! ignored and the buffers are ordinary vectors.

use rayon::prelude::*;

/// Buffers smaller than this stay in ordinary pages (no whole huge page would lie inside).
const LARGE: usize = 4 << 20;

/// An empty vector with room for `capacity` items, backed by huge pages where it is large.
pub(crate) fn with_capacity<T>(capacity: usize) -> Vec<T> {
    let buffer = Vec::with_capacity(capacity);
    advise_huge_pages(&buffer);
    buffer
}

/// Collects `items` in order into a vector backed by huge pages where it is large (written in
/// place by the pool's threads, like `collect`).
pub(crate) fn collect<T: Send>(items: impl IndexedParallelIterator<Item = T>) -> Vec<T> {
    let mut buffer = with_capacity(items.len());
    buffer.par_extend(items);
    buffer
}

/// Asks the operating system to back the whole huge pages inside `buffer`'s allocation with huge pages
/// (done before the memory is first written, so the first write to each maps a huge page).
fn advise_huge_pages<T>(buffer: &Vec<T>) {
    let bytes = buffer.capacity() * std::mem::size_of::<T>();
    if bytes < LARGE {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        const HUGE_PAGE: usize = 2 << 20;
        let start = buffer.as_ptr() as usize;
        let first = start.next_multiple_of(HUGE_PAGE);
        let end = (start + bytes) / HUGE_PAGE * HUGE_PAGE;
        if end > first {
            // SAFETY: the range lies inside the vector's own allocation, and MADV_HUGEPAGE
            // changes only how the system backs it, never its contents or its mapping, so no
            // memory this process uses is affected. A refusal (no huge page support) is fine:
            // the memory stays in ordinary pages.
            unsafe {
                libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_and_small_buffers_collect_every_item_in_order() {
        for n in [0usize, 10, 3 << 20] {
            let collected = collect((0..n as u32).into_par_iter().map(|i| i * 3));
            assert_eq!(collected.len(), n);
            assert!(collected
                .iter()
                .enumerate()
                .all(|(i, &x)| x == i as u32 * 3));
        }
        let mut buffer: Vec<u64> = with_capacity(1 << 20);
        assert!(buffer.capacity() >= 1 << 20);
        buffer.extend(0..1 << 20);
        assert_eq!(buffer[12345], 12345);
    }
}
