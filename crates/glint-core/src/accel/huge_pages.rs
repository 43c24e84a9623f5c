//! Big traversal arrays on 2 MiB pages. An incoherent ray touches nodes and triangle
//! packets scattered over tens of megabytes; on 4 KiB pages nearly every access also
//! misses the TLB and walks the page table, which costs as much as the cache miss
//! itself. Linux backs memory with transparent huge pages where asked
//! (`madvise(MADV_HUGEPAGE)`, the default policy of most distributions), as Embree asks
//! for its BVH; measured on the 1M-triangle benchmark, incoherent rays got
//! about 1.3× faster (docs/performance.md).

/// Arrays smaller than this stay where they are: they span few pages anyway.
const WORTH_IT: usize = 4 << 20;

/// `values`, moved (when big enough, on Linux) into memory the kernel is asked to back
/// with huge pages before anything is written to it. The advice is a hint: where the
/// kernel declines, this is an ordinary copy.
pub fn on_huge_pages<T: Copy>(values: Vec<T>) -> Vec<T> {
    if std::mem::size_of_val(values.as_slice()) < WORTH_IT || !cfg!(target_os = "linux") {
        return values;
    }
    let mut out = with_capacity_on_huge_pages(values.len());
    out.extend_from_slice(&values);
    out
}

/// An empty vector with room for `len` values, its memory (when big enough, on Linux)
/// advised onto huge pages: a builder that knows its size fills it in place, without
/// the copy [`on_huge_pages`] makes.
pub fn with_capacity_on_huge_pages<T: Copy>(len: usize) -> Vec<T> {
    let size = std::mem::size_of::<T>().max(1);
    if len * size < WORTH_IT || !cfg!(target_os = "linux") {
        return Vec::with_capacity(len);
    }
    const HUGE: usize = 2 << 20;
    // Room for a whole number of huge pages inside, wherever the allocation starts.
    let out: Vec<T> = Vec::with_capacity(len + HUGE / size + 1);
    let start = out.as_ptr() as usize;
    let first = start.next_multiple_of(HUGE);
    let end = (start + out.capacity() * size) / HUGE * HUGE;
    if end > first {
        advise_huge(first, end - first);
    }
    out
}

#[cfg(target_os = "linux")]
fn advise_huge(address: usize, len: usize) {
    // SAFETY: the range lies inside an allocation this function's caller owns and has
    // not written yet; MADV_HUGEPAGE changes how it is backed, never its contents. A
    // failure (a kernel without THP) leaves ordinary pages, which is fine.
    unsafe { libc::madvise(address as *mut libc::c_void, len, libc::MADV_HUGEPAGE) };
    // SAFETY: as above, and nothing in the range has been written: dropping its pages
    // loses nothing. Memory the allocator reuses (a freed array of an earlier build)
    // is already backed by small pages, which the advice alone leaves as they are; the
    // next write faults in fresh ones, huge where the kernel can.
    unsafe { libc::madvise(address as *mut libc::c_void, len, libc::MADV_DONTNEED) };
}

#[cfg(not(target_os = "linux"))]
fn advise_huge(_address: usize, _len: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contents_survive_the_move() {
        let small: Vec<u32> = (0..1000).collect();
        assert_eq!(on_huge_pages(small.clone()), small);
        let big: Vec<u64> = (0..(WORTH_IT as u64 / 4)).collect();
        assert_eq!(on_huge_pages(big.clone()), big);
        let room: Vec<u64> = with_capacity_on_huge_pages(big.len());
        assert!(room.is_empty() && room.capacity() >= big.len());
    }
}
