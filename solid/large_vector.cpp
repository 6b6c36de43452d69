#include "cover/solid/large_vector.h"

#include <cstdint>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace cover::detail {
namespace {
constexpr size_t kHugePage = size_t{2} << 20;
size_t round_up(size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
}  // namespace

#if defined(__linux__)
void* map_large(size_t bytes) {
  if (bytes > SIZE_MAX - 2 * kHugePage) throw std::bad_alloc();
  const size_t size = round_up(bytes);
  // Over-map by one huge page, then trim the head and tail so the block starts on a 2 MiB
  // boundary (mmap only guarantees 4 KiB alignment; THP needs aligned 2 MiB ranges).
  void* raw =
      mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto begin = reinterpret_cast<uintptr_t>(raw);
  const uintptr_t aligned = (begin + kHugePage - 1) / kHugePage * kHugePage;
  if (aligned > begin) munmap(raw, aligned - begin);
  const uintptr_t tail = begin + size + kHugePage - (aligned + size);
  if (tail > 0) munmap(reinterpret_cast<void*>(aligned + size), tail);
  void* p = reinterpret_cast<void*>(aligned);
  madvise(p, size, MADV_HUGEPAGE);  // advice only: on failure the block keeps 4 KiB pages
  return p;
}
void unmap_large(void* p, size_t bytes) noexcept { munmap(p, round_up(bytes)); }
void advise_huge(void* p, size_t bytes) noexcept {
  if (bytes < kLargeBytes) return;
  const auto begin = reinterpret_cast<uintptr_t>(p);
  const uintptr_t first = (begin + kHugePage - 1) / kHugePage * kHugePage;
  const uintptr_t last = (begin + bytes) / kHugePage * kHugePage;
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}
#else
void* map_large(size_t bytes) {
  void* p = std::aligned_alloc(kHugePage, round_up(bytes));
  if (!p) throw std::bad_alloc();
  return p;
}
void unmap_large(void* p, size_t) noexcept { std::free(p); }
void advise_huge(void*, size_t) noexcept {}
#endif

}  // namespace cover::detail
