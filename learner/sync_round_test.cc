#include "learner/sync_round.h"

#include <chrono>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;
using Clock = SyncRound::Clock;
using std::chrono::seconds;

const Clock::time_point kRoundT0 = Clock::time_point() + std::chrono::hours(1);

TEST(SyncRoundTest, WaitsForEverySlotUntilTheTimeout) {
  SyncRound r;
  EXPECT_THAT(r.Update(0, kRoundT0, 30, {0, 1, 2}, {1, 2}), IsEmpty());
  EXPECT_THAT(r.Update(0, kRoundT0 + seconds(29), 30, {0, 1, 2}, {1, 2}), IsEmpty());
  EXPECT_THAT(r.Required({0, 1, 2}), ElementsAre(0, 1, 2));
}

TEST(SyncRoundTest, BenchesTheSilentSlotsOnceAfterTheTimeout) {
  SyncRound r;
  r.Update(0, kRoundT0, 30, {0, 1, 2}, {1, 2});
  EXPECT_THAT(r.Update(0, kRoundT0 + seconds(31), 30, {0, 1, 2}, {1, 2}), ElementsAre(1, 2));
  EXPECT_THAT(r.Required({0, 1, 2}), ElementsAre(0));
  EXPECT_THAT(r.Update(0, kRoundT0 + seconds(32), 30, {0, 1, 2}, {1, 2}), IsEmpty())
      << "a slot is reported once";
}

TEST(SyncRoundTest, ABenchedSlotThatDeliversIsWaitedForAgain) {
  SyncRound r;
  r.Update(0, kRoundT0, 30, {0, 1}, {1});
  r.Update(0, kRoundT0 + seconds(31), 30, {0, 1}, {1});
  // Next round: slot 1 still silent, it is not waited for.
  r.Update(1, kRoundT0 + seconds(32), 30, {0, 1}, {0, 1});
  EXPECT_THAT(r.Required({0, 1}), ElementsAre(0));
  // Slot 1 delivers the current version: back in.
  r.Update(1, kRoundT0 + seconds(33), 30, {0, 1}, {0});
  EXPECT_THAT(r.Required({0, 1}), ElementsAre(0, 1));
}

// The livelock of the network-fault schedule (tests/netfaults/): after a partition a slot is
// benched, fetches each new version with the others but delivers it just after the round
// closed without it, so each of its chunks is refused as stale and it never delivers the
// current version. A chunk of the version it was benched in brings it back.
TEST(SyncRoundTest, ABenchedSlotThatSendsAStaleChunkOfItsBenchVersionIsWaitedForAgain) {
  SyncRound r;
  r.Update(5, kRoundT0, 3, {0, 1}, {1}, {{0, 5}, {1, 4}});
  EXPECT_THAT(r.Update(5, kRoundT0 + seconds(4), 3, {0, 1}, {1}, {{0, 5}, {1, 4}}), ElementsAre(1));
  // Round 6: slot 1's chunk of version 5 arrives late (refused as stale by the service).
  r.Update(6, kRoundT0 + seconds(5), 3, {0, 1}, {0, 1}, {{0, 5}, {1, 5}});
  EXPECT_THAT(r.Required({0, 1}), ElementsAre(0, 1));
  // A full timeout from the readmission, even when the round began earlier.
  EXPECT_THAT(r.Update(6, kRoundT0 + seconds(7), 3, {0, 1}, {1}, {{0, 6}, {1, 5}}), IsEmpty());
  EXPECT_THAT(r.Update(6, kRoundT0 + seconds(8) + std::chrono::milliseconds(100), 3, {0, 1}, {1},
                       {{0, 6}, {1, 5}}),
              ElementsAre(1))
      << "silent again for a full timeout: benched again";
}

TEST(SyncRoundTest, ABenchedSlotWhoseChunksAreOlderThanItsBenchVersionStaysBenched) {
  SyncRound r;
  r.Update(5, kRoundT0, 3, {0, 1}, {1}, {{0, 5}, {1, 4}});
  r.Update(5, kRoundT0 + seconds(4), 3, {0, 1}, {1}, {{0, 5}, {1, 4}});
  r.Update(6, kRoundT0 + seconds(5), 3, {0, 1}, {1}, {{0, 5}, {1, 4}});
  EXPECT_THAT(r.Required({0, 1}), ElementsAre(0));
  r.Update(7, kRoundT0 + seconds(6), 3, {0, 1}, {1}, {{0, 6}});
  EXPECT_THAT(r.Required({0, 1}), ElementsAre(0)) << "no chunk at all from slot 1";
}

TEST(SyncRoundTest, NeverBenchesWhenNobodyDeliveredOrWithoutATimeout) {
  SyncRound r;
  r.Update(0, kRoundT0, 30, {0, 1}, {0, 1});
  EXPECT_THAT(r.Update(0, kRoundT0 + seconds(100), 30, {0, 1}, {0, 1}), IsEmpty())
      << "all silent: nothing to train on anyway";
  SyncRound no_timeout;
  no_timeout.Update(0, kRoundT0, 0, {0, 1}, {1});
  EXPECT_THAT(no_timeout.Update(0, kRoundT0 + seconds(1000), 0, {0, 1}, {1}), IsEmpty());
}

TEST(SyncRoundTest, TheTimeoutRestartsWithEveryVersion) {
  SyncRound r;
  r.Update(0, kRoundT0, 30, {0, 1}, {1});
  r.Update(1, kRoundT0 + seconds(25), 30, {0, 1}, {1});
  EXPECT_THAT(r.Update(1, kRoundT0 + seconds(40), 30, {0, 1}, {1}), IsEmpty())
      << "15 s into round 1";
  EXPECT_THAT(r.Update(1, kRoundT0 + seconds(56), 30, {0, 1}, {1}), ElementsAre(1));
}

TEST(SyncRoundTest, ASlotThatLeftIsForgotten) {
  SyncRound r;
  r.Update(0, kRoundT0, 1, {0, 1}, {1});
  r.Update(0, kRoundT0 + seconds(2), 1, {0, 1}, {1});
  r.Update(0, kRoundT0 + seconds(3), 1, {0}, {});
  EXPECT_TRUE(r.benched().empty());
}

}  // namespace
}  // namespace juggle
