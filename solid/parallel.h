#pragma once
// The one parallelism wrapper; results are identical for any thread count. TBB stays behind
// this header.
// parallel_for splits [0, n) into fixed chunks of `grain` items (the chunking does not depend on
// the thread count), so any per-chunk reduction combined in chunk order is deterministic.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace cover {

/// Calls body(begin, end) over consecutive chunks of [0, n); serial when n <= grain.
void parallel_for(size_t n, size_t grain, const std::function<void(size_t, size_t)>& body);

/// Runs f() and g(), possibly in parallel; returns when both are done.
void parallel_invoke(const std::function<void()>& f, const std::function<void()>& g);

/// Sorts ascending (parallel; the result is unique, so it does not depend on the threads).
void parallel_sort(std::vector<uint64_t>& keys);

/// Number of threads a parallel_for may use now (ThreadLimit and the machine's cores).
int max_threads();

/// Limits the worker threads of every parallel_for while alive (n <= 0: all cores).
class ThreadLimit {
 public:
  explicit ThreadLimit(int n);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cover
