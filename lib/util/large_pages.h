#pragma once
// An allocator for the few arrays of hundreds of megabytes (the nodes of the sweep and distance
// trees of an 832,000-face mesh: 200 bytes a node, two nodes a triangle): blocks of at least
// kLargeBlock bytes are aligned to 2 MiB and advised as transparent huge pages, so that touching
// them costs one page fault per 2 MiB instead of one per 4 KiB. Where the kernel's THP mode is
// "madvise" (Debian's cloud kernels), that fault cost was a sixth of `cdbench poses` on armadillo
// x16 (doc/performance.md). Only where memory comes from changes: contents and results do not.
// Smaller blocks, and systems without madvise, use operator new as std::allocator does.
// A large block's pages are touched on all threads when it is allocated: the kernel clears each
// page at its first touch, and the vector's constructing loop would otherwise do it on one thread
// (the sweep tree of 832,000 faces: 360 MB, 1.5 s of a serial resize; doc/performance.md).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cdbench {

inline constexpr std::size_t kLargeBlock = std::size_t(4) << 20;  // 4 MiB
inline constexpr std::size_t kHugePage = std::size_t(2) << 20;    // 2 MiB
inline constexpr std::size_t kSmallPage = 4096;                     // a touch per page without huge pages

template <class T>
struct LargePageAllocator {
  using value_type = T;
  LargePageAllocator() noexcept = default;
  template <class U>
  LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kLargeBlock || alignof(T) > kHugePage) return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: a refusal leaves ordinary pages
#endif
    char* const bytes_p = static_cast<char*>(p);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rounded / kHugePage), [bytes_p](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        for (std::size_t off = 0; off < kHugePage; off += kSmallPage) bytes_p[i * kHugePage + off] = 0;
    });
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kLargeBlock || alignof(T) > kHugePage) ::operator delete(p);
    else std::free(p);
  }
};

template <class T, class U>
bool operator==(const LargePageAllocator<T>&, const LargePageAllocator<U>&) noexcept {
  return true;
}
template <class T, class U>
bool operator!=(const LargePageAllocator<T>&, const LargePageAllocator<U>&) noexcept {
  return false;
}

}  // namespace cdbench
