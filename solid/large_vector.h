#pragma once
// Large arrays on transparent huge pages.
//
// Why: on the 2-core VMs this project is built and benchmarked on, the first touch of a 4 KiB page
// costs ~11 µs (2.8 ms per MiB; 256 MiB malloc + memset: 720 ms), so on 4 KiB pages page faults,
// not arithmetic, dominate every step that fills a fresh array (about three quarters of a
// 606k-triangle BVH build). A 2 MiB page faults once for 512 small ones (same test: 0.08 ms per
// MiB once the host has backed the memory) and needs one TLB entry instead of 512, which also
// shortens random queries on structures larger than the TLB reach.
//
// LargeAllocator maps blocks of at least kLargeBytes with mmap, aligned to 2 MiB, and advises
// MADV_HUGEPAGE (effective when /sys/kernel/mm/transparent_hugepage/enabled is "madvise" or
// "always"; otherwise they are ordinary pages). Smaller blocks, and every block off Linux, use
// operator new. Stateless: all instances are equal.

#include <algorithm>
#include <cstddef>
#include <new>
#include <type_traits>
#include <vector>

namespace cover {

namespace detail {
/// Blocks of at least this many bytes are mapped on huge pages (a smaller array would round up
/// to a whole 2 MiB page).
inline constexpr size_t kLargeBytes = size_t{1} << 20;
/// mmap'd, 2 MiB-aligned, MADV_HUGEPAGE block of at least `bytes`; throws std::bad_alloc.
void* map_large(size_t bytes);
/// Releases a block of map_large(bytes) (the same `bytes`).
void unmap_large(void* p, size_t bytes) noexcept;
}  // namespace detail

template <typename T>
struct LargeAllocator {
  static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__,
                "over-aligned types: not supported");
  using value_type = T;
  LargeAllocator() = default;
  template <typename U>
  LargeAllocator(const LargeAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    if (n > static_cast<size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
    if (bytes >= detail::kLargeBytes) return static_cast<T*>(detail::map_large(bytes));
    return static_cast<T*>(::operator new(bytes));
  }
  void deallocate(T* p, size_t n) noexcept {
    const size_t bytes = n * sizeof(T);
    if (bytes >= detail::kLargeBytes)
      detail::unmap_large(p, bytes);
    else
      ::operator delete(p);
  }
  template <typename U>
  bool operator==(const LargeAllocator<U>&) const noexcept {
    return true;
  }
};

/// A std::vector whose large buffers live on huge pages (see above).
template <typename T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

/// LargeAllocator that default-initializes: `resize(n)` and `LargeBuffer<T>(n)` of a trivial T
/// write nothing, so the first write to a fresh page can come from a parallel loop instead of
/// one thread's zero fill. Only for arrays a parallel loop then writes in full (elements are
/// indeterminate until written). Why: a fresh page's first touch is what costs here (above),
/// and two threads touching halves of an array fault in parallel.
template <typename T>
struct LargeUninitAllocator : LargeAllocator<T> {
  LargeUninitAllocator() = default;
  template <typename U>
  LargeUninitAllocator(const LargeUninitAllocator<U>&) noexcept {}
  /// Default-initializes; construction with arguments falls back to allocator_traits'
  /// construct_at (this overload does not take them).
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
};

/// A LargeVector whose new elements are default-initialized (see LargeUninitAllocator).
template <typename T>
using LargeBuffer = std::vector<T, LargeUninitAllocator<T>>;

namespace detail {
/// Advises MADV_HUGEPAGE on the 2 MiB-aligned part of [p, p + bytes) (nothing below
/// kLargeBytes, or off Linux). Only pages not yet touched change.
void advise_huge(void* p, size_t bytes) noexcept;
}  // namespace detail

/// Reserves room for n elements in a plain std::vector and advises huge pages on the part not yet
/// written. The public value types (Solid, PolygonMesh, Image, VoxelGrid, Octree) hold
/// std::vector so that users can assign their own; the kernels that fill a large one reserve it
/// here first, which keeps the page-fault saving above (a fresh block of 1 MiB or more comes
/// from the C library's own mmap, untouched until written).
template <typename T>
void reserve_huge(std::vector<T>& v, size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
  detail::advise_huge(v.data() + v.size(), (n - v.size()) * sizeof(T));
}

/// reserve_huge, then resize to n (new elements value-initialized).
template <typename T>
void resize_huge(std::vector<T>& v, size_t n) {
  reserve_huge(v, n);
  v.resize(n);
}

/// Element-wise equality with a plain std::vector (found by argument-dependent lookup through
/// the allocator; C++20 also provides the reversed form).
template <typename T>
bool operator==(const LargeVector<T>& a, const std::vector<T>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end());
}

}  // namespace cover
