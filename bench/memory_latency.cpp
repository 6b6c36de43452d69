// This machine's memory, as the BVH sees it: the time of a dependent load (pointer chasing over
// one random cycle of 64-byte lines) against the working set, on the BVH's own allocator
// (LargeVector: transparent huge pages), and the time per line when C chains are walked
// interleaved (how far independent misses overlap: what walk_batch relies on).
// Why: at 1M triangles the BVH is 80 MB; whether a query's loads hit the cache or DRAM, and
// what a miss costs, decides how far its time departs from its node count (docs/benchmarks.md).
// Usage: memory_latency [--chains C (24)] [--max-mb M (128)]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>
#include <vector>

#include "bench_cli.h"
#include "cover/solid/large_vector.h"

namespace {

using bench::arg;

struct Line {     // 64 bytes; LargeVector blocks start on a 2 MiB boundary, so each is one line
  uint32_t next;  ///< index of the next line of the cycle
  char pad[60];
};
static_assert(sizeof(Line) == 64);

/// Nanoseconds per load walking `chains` interleaved chains through one random cycle of `lines`.
double chase(cover::LargeVector<Line>& mem, size_t lines, int chains, uint64_t seed) {
  std::vector<uint32_t> order(lines);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937_64(seed));
  for (size_t i = 0; i < lines; ++i) mem[order[i]].next = order[(i + 1) % lines];
  std::vector<uint32_t> at(static_cast<size_t>(chains));
  for (int c = 0; c < chains; ++c) at[c] = order[static_cast<size_t>(c) * lines / chains];
  for (size_t i = 0; i < lines / chains + 1; ++i)  // one lap: warm the caches and the TLB
    for (int c = 0; c < chains; ++c) at[c] = mem[at[c]].next;
  const size_t steps = std::max<size_t>(2000000 / chains, lines / chains);
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t i = 0; i < steps; ++i)
    for (int c = 0; c < chains; ++c) at[c] = mem[at[c]].next;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  uint32_t sink = 0;
  for (uint32_t a : at) sink ^= a;
  if (sink == UINT32_MAX) std::puts("");  // keeps the loads
  return s * 1e9 / static_cast<double>(steps * chains);
}

}  // namespace

int main(int argc, char** argv) {
  const int chains = static_cast<int>(std::clamp(arg(argc, argv, "--chains", 24), 1L, 256L));
  const long max_mb = std::clamp(arg(argc, argv, "--max-mb", 128), 1L, 4096L);
  std::printf("working set   dependent load   %d chains interleaved (per line)\n", chains);
  for (long mb : {1, 2, 4, 8, 12, 16, 24, 32, 48, 64, 128, 256, 512, 1024, 2048, 4096}) {
    if (mb > max_mb) break;
    const size_t lines = static_cast<size_t>(mb) << 14;  // 2^20 / 64
    cover::LargeVector<Line> mem(lines);
    const double one = chase(mem, lines, 1, 1), many = chase(mem, lines, chains, 2);
    std::printf("%6ld MB %13.1f ns %20.1f ns\n", mb, one, many);
  }
  return 0;
}
