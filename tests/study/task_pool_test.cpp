#include "study/task_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace clothsim::analysis {
namespace {

TEST(ParallelFor, RunsEveryIndexExactlyOnce) {
  std::vector<std::atomic<int>> hits(200);
  parallel_for(hits.size(), 3, [&](std::size_t i) { hits[i]++; });
  for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
}

TEST(ParallelFor, RethrowsATasksExceptionAfterJoining) {
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_for(50, 2,
                            [&](std::size_t i) {
                              ++ran;
                              if (i == 3) throw std::runtime_error("task 3");
                              std::this_thread::sleep_for(std::chrono::milliseconds(2));
                            }),
               std::runtime_error);
  EXPECT_LT(ran.load(), 50);  // the failure stopped further tasks from starting
}

TEST(ParallelFor, StartsNoTaskOnceStopReturnsTrue) {
  std::atomic<int> ran{0};
  parallel_for(100, 2, [&](std::size_t) { ++ran; }, [&] { return ran.load() >= 10; });
  EXPECT_GE(ran.load(), 10);
  EXPECT_LE(ran.load(), 11);  // at most one task per thread was already past the check
}

TEST(ResolveJobs, ZeroMeansOnePerCore) {
  EXPECT_GE(resolve_jobs(0), 1);
  EXPECT_EQ(resolve_jobs(3), 3);
}

}  // namespace
}  // namespace clothsim::analysis
