#include "learner/broadcast_tracker.h"

#include <set>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using Clock = BroadcastTracker::Clock;

Clock::time_point At(double seconds) {
  return Clock::time_point() + std::chrono::microseconds(static_cast<int64_t>(seconds * 1e6));
}

TEST(BroadcastTrackerTest, AVersionIsBroadcastWhenItsLastWorkerReceivesIt) {
  BroadcastTracker t;
  const auto all_live = [](uint64_t) { return true; };
  t.Published(5, At(10), {1, 2, 3});
  EXPECT_THAT(t.Delivered(1, 5, At(10.1), all_live), IsEmpty());
  EXPECT_THAT(t.Delivered(3, 5, At(10.2), all_live), IsEmpty());
  EXPECT_THAT(t.Delivered(2, 5, At(10.25), all_live), ElementsAre(::testing::DoubleNear(0.25, 1e-9)));
  EXPECT_THAT(t.Delivered(2, 5, At(11), all_live), IsEmpty()) << "measured once";
}

TEST(BroadcastTrackerTest, ANewerVersionDeliversEveryOlderOneItsWorkerWaitedFor) {
  BroadcastTracker t;
  const auto all_live = [](uint64_t) { return true; };
  t.Published(1, At(0), {7, 8});
  t.Published(2, At(1), {7, 8});
  EXPECT_THAT(t.Delivered(7, 2, At(1.5), all_live), IsEmpty());
  // Worker 8 skips version 1 (async long-polls fetch the newest): both complete, oldest first.
  EXPECT_THAT(t.Delivered(8, 2, At(2), all_live),
              ElementsAre(::testing::DoubleNear(2.0, 1e-9), ::testing::DoubleNear(1.0, 1e-9)));
  // An older version does not count for a newer one.
  t.Published(3, At(3), {7});
  EXPECT_THAT(t.Delivered(7, 2, At(3.5), all_live), IsEmpty());
  EXPECT_THAT(t.Delivered(7, 3, At(4), all_live), ElementsAre(::testing::DoubleNear(1.0, 1e-9)));
}

TEST(BroadcastTrackerTest, AWorkerThatLeftNoLongerHoldsAVersionBack) {
  BroadcastTracker t;
  std::set<uint64_t> live = {1, 2};
  const auto is_live = [&](uint64_t w) { return live.count(w) > 0; };
  t.Published(4, At(0), {1, 2});
  live.erase(2);  // worker 2 died before it fetched version 4
  EXPECT_THAT(t.Delivered(1, 4, At(0.5), is_live), ElementsAre(::testing::DoubleNear(0.5, 1e-9)));
}

TEST(BroadcastTrackerTest, VersionsWithoutWorkersOrBeyondThePendingCapAreNotMeasured) {
  BroadcastTracker t;
  const auto all_live = [](uint64_t) { return true; };
  t.Published(1, At(0), {});
  EXPECT_THAT(t.Delivered(1, 1, At(1), all_live), IsEmpty());
  for (int v = 0; v < static_cast<int>(BroadcastTracker::kMaxPending) + 10; ++v) {
    t.Published(v, At(v), {9});
  }
  const std::vector<double> done = t.Delivered(9, 1000, At(1000), all_live);
  EXPECT_EQ(done.size(), BroadcastTracker::kMaxPending) << "the 10 oldest were given up";
}

}  // namespace
}  // namespace juggle
