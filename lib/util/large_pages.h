#pragma once
// An allocator for the few arrays of hundreds of megabytes (the nodes of the sweep and distance
// trees of an 832,000-face mesh: 200 bytes a node, two nodes a triangle): blocks of at least
// kLargeBlock bytes are aligned to 2 MiB and advised as transparent huge pages, so that touching
// them costs one page fault per 2 MiB instead of one per 4 KiB. Where the kernel's THP mode is
// "madvise" (Debian's cloud kernels), that fault cost was a sixth of `cdbench poses` on armadillo
// x16 (doc/performance.md). Only where memory comes from changes: contents and results do not.
// Smaller blocks, and systems without madvise, use operator new as std::allocator does.
#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cdbench {

inline constexpr std::size_t kLargeBlock = std::size_t(4) << 20;  // 4 MiB
inline constexpr std::size_t kHugePage = std::size_t(2) << 20;    // 2 MiB

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
