// Crew (src/crew.hpp): the threads that drive the other devices of a split OpenCL backend.
#include "core/crew.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace freespace {
namespace {

// Many rounds of every size, helpers awake, asleep and in between: each part runs exactly once
// per round, on a thread of the crew, and Run returns only when all of its round's are done.
TEST(Crew, EveryPartRunsOnceOnACrewThread) {
  for (const int helpers : {0, 1, 3}) {
    Crew crew(helpers, std::chrono::microseconds(50));
    for (int round = 0; round < 3000; ++round) {
      if (round % 7 == 0) crew.Wake();
      if (round % 11 == 0) crew.Rest();
      const int parts = 1 + round % 9;
      std::array<std::atomic<int>, 9> runs{};
      std::atomic<int> bad_thread{0};
      crew.Run(parts, [&](int part, int thread) {
        runs[std::size_t(part)].fetch_add(1);
        if (thread < 0 || thread > helpers) bad_thread.fetch_add(1);
      });
      for (int p = 0; p < 9; ++p) {
        ASSERT_EQ(runs[std::size_t(p)].load(), p < parts ? 1 : 0)
            << "part " << p << " of " << parts << ", round " << round << ", " << helpers
            << " helpers";
      }
      ASSERT_EQ(bad_thread.load(), 0);
    }
  }
}

// An awake helper takes a part while the caller runs another: two parts that each wait for the
// other to start finish only if they run at the same time on two threads.
TEST(Crew, AnAwakeHelperRunsAPartBesideTheCaller) {
  Crew crew(1);
  crew.Wake();
  std::atomic<int> started{0};
  std::array<int, 2> thread_of{-1, -1};
  bool both = true;
  crew.Run(2, [&](int part, int thread) {
    thread_of[std::size_t(part)] = thread;
    started.fetch_add(1);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (started.load() < 2) {
      if (std::chrono::steady_clock::now() > give_up) {
        both = false;
        return;
      }
      std::this_thread::yield();
    }
  });
  crew.Rest();
  EXPECT_TRUE(both) << "the two parts never ran at the same time";
  EXPECT_NE(thread_of[0], thread_of[1]);
}

// A part that throws: Run rethrows it once every other part has run, and the crew goes on.
TEST(Crew, APartsExceptionReachesTheCaller) {
  Crew crew(2, std::chrono::microseconds(100));
  crew.Wake();
  std::atomic<int> runs{0};
  EXPECT_THROW(crew.Run(6,
                        [&](int part, int) {
                          runs.fetch_add(1);
                          if (part == 3) throw std::runtime_error("part 3");
                        }),
               std::runtime_error);
  EXPECT_EQ(runs.load(), 6);
  runs = 0;
  EXPECT_NO_THROW(crew.Run(4, [&](int, int) { runs.fetch_add(1); }));
  EXPECT_EQ(runs.load(), 4);
}

// Woken and never told to rest, helpers stop polling once the window has passed.
TEST(Crew, HelpersSleepOnceTheWakeWindowHasPassed) {
  Crew crew(2, std::chrono::microseconds(0), std::chrono::microseconds(1000));
  crew.Run(2, [](int, int) {});
  crew.Wake();
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (crew.sleeping() < 2 && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(crew.sleeping(), 2) << "helpers still polling 10 s after a 1 ms window";
  // And a round after that still runs every part.
  std::atomic<int> runs{0};
  crew.Run(5, [&](int, int) { runs.fetch_add(1); });
  EXPECT_EQ(runs.load(), 5);
}

// Destroying a crew whose helpers poll, sleep or were never used joins them.
TEST(Crew, DestructionJoinsPollingAndSleepingHelpers) {
  for (int k = 0; k < 50; ++k) {
    Crew polling(2);
    polling.Wake();
    Crew sleeping(2);
    Crew used(1, std::chrono::microseconds(1000));
    used.Run(3, [](int, int) {});
    used.Rest();
  }
  SUCCEED();
}

}  // namespace
}  // namespace freespace
