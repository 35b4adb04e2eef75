// ThreadArena (core/thread_arena.hpp): where the host stages and the clutter filter run their
// TBB loops. With 0 threads, in the caller's arena, so that an application's own arena holds
// the engine; with N, in an arena of N whoever calls.
#include "core/thread_arena.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>

namespace freespace {
namespace {

// The concurrency a loop run through `arena` from inside an arena of `outer` threads sees, and
// whether any of its iterations ran on a thread other than the caller's slot 0.
struct Seen {
  int concurrency = 0;
  bool other_slot = false;
};

Seen RunFrom(int outer, ThreadArena* arena) {
  Seen seen;
  std::atomic<bool> other{false};
  tbb::task_arena caller(outer);
  caller.execute([&] {
    arena->execute([&] {
      seen.concurrency = tbb::this_task_arena::max_concurrency();
      tbb::parallel_for(0, 256, [&](int) {
        if (tbb::this_task_arena::current_thread_index() != 0) other = true;
      });
    });
  });
  seen.other_slot = other.load();
  return seen;
}

TEST(ThreadArena, ZeroThreadsRunInTheCallersArena) {
  ThreadArena arena(0);
  const Seen one = RunFrom(1, &arena);
  EXPECT_EQ(one.concurrency, 1);
  EXPECT_FALSE(one.other_slot) << "a loop left the caller's one-thread arena";
  EXPECT_EQ(RunFrom(3, &arena).concurrency, 3);
}

TEST(ThreadArena, AThreadCountGetsAnArenaOfItsOwn) {
  ThreadArena arena(3);
  EXPECT_EQ(RunFrom(1, &arena).concurrency, 3);
  ThreadArena single(1);
  const Seen seen = RunFrom(4, &single);
  EXPECT_EQ(seen.concurrency, 1);
  EXPECT_FALSE(seen.other_slot);
}

}  // namespace
}  // namespace freespace
