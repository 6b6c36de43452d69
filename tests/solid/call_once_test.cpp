// solid/call_once.cpp: Cover's programs use its own pthread_once (std::call_once without a
// system call per first call), and it keeps std::call_once's semantics.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

TEST(CallOnce, ProgramsBindCoversOwnPthreadOnce) {
#if defined(__linux__) && defined(__GLIBC__)
  Dl_info fn{}, libc{};
  ASSERT_NE(dladdr(reinterpret_cast<void*>(&pthread_once), &fn), 0);
  ASSERT_NE(dladdr(reinterpret_cast<void*>(&pthread_create), &libc), 0);
  // The definition lies in this program (linked from libcover_solid.a), not in libc.
  EXPECT_NE(fn.dli_fbase, libc.dli_fbase) << fn.dli_fname;
#else
  GTEST_SKIP() << "glibc only";
#endif
}

TEST(CallOnce, ConcurrentCallersRunTheRoutineOnceAndSeeItsEffect) {
  for (int round = 0; round < 50; ++round) {
    std::once_flag flag;
    std::atomic<int> runs{0};
    int value = 0;  // written by the routine only, read by every caller after call_once
    std::vector<std::thread> threads;
    std::atomic<int> wrong{0};
    for (int t = 0; t < 8; ++t)
      threads.emplace_back([&] {
        std::call_once(flag, [&] {
          std::this_thread::sleep_for(std::chrono::microseconds(round % 5 * 100));
          value = 42;
          ++runs;
        });
        if (value != 42) ++wrong;
      });
    for (auto& t : threads) t.join();
    EXPECT_EQ(runs.load(), 1);
    EXPECT_EQ(wrong.load(), 0);
  }
}

TEST(CallOnce, AThrowingRoutineLetsTheNextCallerRetry) {
  std::once_flag flag;
  int calls = 0;
  EXPECT_THROW(std::call_once(flag,
                              [&] {
                                ++calls;
                                throw std::runtime_error("first");
                              }),
               std::runtime_error);
  std::call_once(flag, [&] { ++calls; });
  std::call_once(flag, [&] { ++calls; });
  EXPECT_EQ(calls, 2);
}

TEST(CallOnce, WaitersOfAThrowingRoutineAllRetryAndOneSucceeds) {
  for (int round = 0; round < 20; ++round) {
    std::once_flag flag;
    std::atomic<int> attempts{0}, successes{0}, done{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 6; ++t)
      threads.emplace_back([&] {
        for (;;) {
          try {
            std::call_once(flag, [&] {
              // The first attempt throws after the others have started waiting.
              if (attempts++ == 0) {
                std::this_thread::sleep_for(std::chrono::milliseconds(2));
                throw std::runtime_error("first attempt");
              }
              ++successes;
            });
            ++done;
            return;
          } catch (const std::runtime_error&) {
          }
        }
      });
    for (auto& t : threads) t.join();
    EXPECT_EQ(successes.load(), 1);
    EXPECT_EQ(attempts.load(), 2);
    EXPECT_EQ(done.load(), 6);
  }
}

}  // namespace
