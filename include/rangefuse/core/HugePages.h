// Large arrays on 2 MiB pages: the voxel sums of a field run to hundreds of MiB, and on 4 KiB
// pages their first touch alone costs ~10^5 page faults.
#pragma once

#include <sys/mman.h>

#include <cstdlib>
#include <new>

namespace rangefuse {

/// A std::allocator that gives arrays of 4 MiB or more 2 MiB-aligned memory and asks the
/// kernel for transparent huge pages there (Linux "madvise" mode); smaller ones as usual.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr size_t kPage = size_t{2} << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
    if (bytes < 2 * kPage) return static_cast<T*>(::operator new(bytes));
    void* p = std::aligned_alloc(kPage, (bytes + kPage - 1) / kPage * kPage);
    if (!p) throw std::bad_alloc();
    madvise(p, bytes, MADV_HUGEPAGE);  // advice only: without it, ordinary pages
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    if (n * sizeof(T) < 2 * kPage)
      ::operator delete(p);
    else
      std::free(p);
  }
};

template <class T, class U>
bool operator==(const HugePageAllocator<T>&, const HugePageAllocator<U>&) {
  return true;
}
template <class T, class U>
bool operator!=(const HugePageAllocator<T>&, const HugePageAllocator<U>&) {
  return false;
}

}  // namespace rangefuse
