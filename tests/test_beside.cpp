// The threads qsp's steps run beside the caller (src/beside.h): where they run, that a wait ends, what
// the thread limit and a one-thread scope switch off, and that a started thread keeps no narrowed mask.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "beside.h"
#include "qsp/mesh.h"

#if defined(__linux__)
#include <sched.h>
#endif

namespace qsp {
namespace {

const bool kMoreThanOneCore = std::thread::hardware_concurrency() > 1;

// Restores the process-wide limit however a test ends.
struct LimitGuard {
  ~LimitGuard() { set_thread_limit(0); }
};

TEST(Beside, RunsOnAnotherThreadWhenWantedAndHereWhenNot) {
  const std::thread::id here = std::this_thread::get_id();
  auto away = beside(true, [] { return std::this_thread::get_id(); });
  auto deferred = beside(false, [] { return std::this_thread::get_id(); });
  if (kMoreThanOneCore) {
    EXPECT_NE(away.get(), here);
  } else {
    EXPECT_EQ(away.get(), here);
  }
  EXPECT_EQ(deferred.get(), here);
}

TEST(Beside, GetRethrowsWhatTheTaskThrew) {
  for (const bool wanted : {true, false}) {
    auto b = beside(wanted, []() -> int { throw std::runtime_error("task failed"); });
    EXPECT_THROW(b.get(), std::runtime_error) << "wanted " << wanted;
  }
}

TEST(Beside, DestructorWaitsForARunningTask) {
  std::atomic<bool> finished{false};
  {
    auto b = beside(true, [&finished] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      finished = true;
    });
  }  // destroyed without get()
  if (kMoreThanOneCore) {
    EXPECT_TRUE(finished.load());
  }
}

TEST(Beside, MovedAndAssignedKeepsItsTask) {
  Beside<int> later;
  EXPECT_FALSE(later.valid());
  later = beside(true, [] { return 7; });
  Beside<int> moved = std::move(later);
  ASSERT_TRUE(moved.valid());
  EXPECT_EQ(moved.get(), 7);
}

TEST(Beside, ThreadLimitOneKeepsEveryStepOnTheCallersThread) {
  const LimitGuard guard;
  const std::thread::id here = std::this_thread::get_id();
  set_thread_limit(1);
  EXPECT_FALSE(threads_allowed());
  EXPECT_EQ(beside(true, [] { return std::this_thread::get_id(); }).get(), here);
  EXPECT_THROW(start_beside([] {}), std::system_error);
  set_thread_limit(0);
  EXPECT_EQ(threads_allowed(), kMoreThanOneCore);
}

TEST(Beside, OneThreadScopeEndsWithItsScope) {
  const std::thread::id here = std::this_thread::get_id();
  {
    const OneThread one(true);
    EXPECT_FALSE(threads_allowed());
    EXPECT_EQ(beside(true, [] { return std::this_thread::get_id(); }).get(), here);
    {
      const OneThread inner(false);  // does not lift the outer scope
      EXPECT_FALSE(threads_allowed());
    }
    EXPECT_FALSE(threads_allowed());
  }
  EXPECT_EQ(threads_allowed(), kMoreThanOneCore);
}

TEST(Beside, StartedThreadEndsWithTheCreatorsMask) {
  if (!kMoreThanOneCore) GTEST_SKIP() << "one core: no thread is started";
#if defined(__linux__)
  cpu_set_t creator;
  ASSERT_EQ(sched_getaffinity(0, sizeof creator, &creator), 0);
  for (int i = 0; i < 20; ++i) {  // either side may come second; both orders happen over a few tries
    cpu_set_t seen;
    bool got = false;
    std::atomic<bool> returned{false};
    Helper h = start_beside([&] {
      while (!returned) std::this_thread::yield();  // start_beside's part is done once it returns
      got = sched_getaffinity(0, sizeof seen, &seen) == 0;
    });
    returned = true;
    h.join();
    ASSERT_TRUE(got);
    EXPECT_TRUE(CPU_EQUAL(&seen, &creator)) << "try " << i << ": the thread kept a narrowed mask";
  }
#else
  GTEST_SKIP() << "placement is Linux-only";
#endif
}

TEST(Beside, SpinUntilStopsAtTheLimit) {
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(spin_until([] { return false; }, std::chrono::microseconds(200)));
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::microseconds(200));
  int tries = 0;
  // A limit no preemption reaches (under a sanitizer on a busy machine, 500 us passed before a third try).
  EXPECT_TRUE(spin_until([&tries] { return ++tries == 3; }, std::chrono::seconds(10)));
  EXPECT_EQ(tries, 3);
}

}  // namespace
}  // namespace qsp
