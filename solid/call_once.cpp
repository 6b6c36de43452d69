// pthread_once for Cover's own code: std::call_once without a system call per first call.
//
// Why hand-written. CGAL's lazy exact kernel (Epeck, used by evaluation, clipping and caps)
// guards each node's exact evaluation with std::call_once, which libstdc++ implements with
// pthread_once. glibc 2.36's pthread_once ends every first call with an unconditional
// futex_wake system call, waiters or not. An exact evaluation visits about ten lazy nodes, so
// `cover evaluate` of cheese ∪ fandisk makes 62k such calls; on paravirtualized machines, where a
// system call costs microseconds, glibc's version spends about 30 % of evaluate()'s time in them
// (bench/evaluate_vs_manifold). This one wakes only when a thread waits.
//
// This definition has hidden visibility: it binds only the calls made from Cover's own objects
// (the inline std::call_once of CGAL's and our headers, linked statically into the CLI, the
// Python module and the tests); libc, libstdc++ and TBB keep glibc's. It is its own library,
// cover_call_once, linked into Cover's build tree only and never installed; the linker pulls it
// through `--undefined=pthread_once` (solid/CMakeLists.txt), since libstdc++ refers to
// pthread_once only weakly. A program built against the installed package keeps glibc's
// pthread_once everywhere.
//
// Semantics are pthread_once's: the routine runs once; concurrent callers wait until it has
// returned; if it exits by an exception (std::call_once's callable threw) the flag is reset,
// the waiters are woken to retry, and the exception propagates. States of the flag word (values
// compatible with glibc's reading of its own flags: 2 means done):
//   0 new, 1 running, 5 running with at least one waiter, 2 done.
// No header that declares pthread_once (<pthread.h>, or <atomic> and <mutex>, which include it):
// that declaration's default visibility would override the hidden one below. The flag word is
// accessed with the compiler's __atomic builtins instead of std::atomic_ref.
#include <climits>  // also defines __GLIBC__

#if defined(__linux__) && defined(__GLIBC__)

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace {

constexpr int kNew = 0, kRunning = 1, kDone = 2, kWaited = 5;

void futex_wait(int* word, int expected) {
  syscall(SYS_futex, word, FUTEX_WAIT_PRIVATE, expected, nullptr, nullptr, 0);
}

void futex_wake(int* word, int count) {
  syscall(SYS_futex, word, FUTEX_WAKE_PRIVATE, count, nullptr, nullptr, 0);
}

}  // namespace

// pthread_once_t is an int on glibc; the C linkage name is what matters, so <pthread.h> (which
// declares the function with default visibility) is not included here.
extern "C" __attribute__((visibility("hidden"))) int pthread_once(int* flag, void (*routine)()) {
  for (;;) {
    int s = __atomic_load_n(flag, __ATOMIC_ACQUIRE);
    if (s == kDone) return 0;
    if (s == kNew) {
      if (!__atomic_compare_exchange_n(flag, &s, kRunning, false, __ATOMIC_ACQUIRE,
                                       __ATOMIC_RELAXED))
        continue;
      try {
        routine();
      } catch (...) {
        // Every waiter retries (one wins); waking only one would strand the others asleep.
        if (__atomic_exchange_n(flag, kNew, __ATOMIC_RELEASE) == kWaited) futex_wake(flag, INT_MAX);
        throw;
      }
      if (__atomic_exchange_n(flag, kDone, __ATOMIC_RELEASE) == kWaited) futex_wake(flag, INT_MAX);
      return 0;
    }
    // Running elsewhere: announce a waiter, then sleep until the state changes.
    if (s == kRunning &&
        !__atomic_compare_exchange_n(flag, &s, kWaited, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
      continue;
    futex_wait(flag, kWaited);
  }
}

#endif
