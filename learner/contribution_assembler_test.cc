#include "learner/contribution_assembler.h"

#include <cstdint>
#include <optional>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::ElementsAre;
using ::testing::Each;

constexpr int kT = 2;  // steps per unroll; obs_dim = act_dim = 1

// A part of `unrolls` unrolls whose observations all equal `mark` (to tell parts apart).
ChunkPart Part(int slot, uint64_t incarnation, int64_t sequence, int part, int num_parts,
               int64_t version, float mark, int unrolls = 1) {
  ChunkPart p;
  p.slot = slot;
  p.incarnation = incarnation;
  p.sequence = sequence;
  p.part = part;
  p.num_parts = num_parts;
  p.version = version;
  UnrollBatch& b = p.data.batch;
  b.num_unrolls = unrolls;
  b.unroll_length = kT;
  b.obs_dim = 1;
  b.act_dim = 1;
  const size_t n = size_t(unrolls) * kT;
  b.obs.assign(n, mark);
  b.actions.assign(n, 0.0f);
  b.log_probs.assign(n, -1.0f);
  b.rewards.assign(n, 0.5f);
  b.done.assign(n, 0);
  b.truncated.assign(n, 0);
  b.bootstrap_obs.assign(unrolls, mark);
  b.policy_version.assign(unrolls, version);
  p.data.node.assign(n, 0);
  return p;
}

// A complete single-part contribution.
ChunkPart Whole(int slot, uint64_t incarnation, int64_t sequence, int64_t version, float mark,
                int unrolls = 1) {
  return Part(slot, incarnation, sequence, 0, 1, version, mark, unrolls);
}

// One mark per unroll (the first observation of each).
std::vector<float> Marks(const Contribution& c) {
  std::vector<float> marks;
  for (int u = 0; u < c.batch.num_unrolls; ++u) marks.push_back(c.batch.obs[size_t(u) * kT]);
  return marks;
}

TEST(ContributionAssemblerTest, PartThatDisagreesWithItsSiblingsIsRejected) {
  ContributionAssembler a;
  ASSERT_TRUE(a.Add(Part(0, 7, 0, 0, 2, 0, 0.0f)).ok());
  ChunkPart odd = Part(0, 7, 0, 1, 2, 0, 1.0f);
  odd.data.batch.unroll_length = kT + 1;
  const absl::Status s = a.Add(odd);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), ::testing::HasSubstr("disagrees with its other parts"));
  ChunkPart other_count = Part(0, 7, 0, 1, 3, 0, 1.0f);
  EXPECT_EQ(a.Add(other_count).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(a.pending_parts(), 1);
}

TEST(ContributionAssemblerTest, PartsResentAfterTheirContributionCompletedAreIgnored) {
  ContributionAssembler a;
  int64_t dropped = 0;
  ASSERT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f)).ok());
  ASSERT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f)).ok());  // a resend of the same contribution
  const std::optional<Contribution> c = a.TakeAsync(0, 0, 1, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->batch.num_unrolls, 1) << "the resend was trained on twice";
  EXPECT_FALSE(a.TakeAsync(0, 0, 1, &dropped).has_value());
}

TEST(ContributionAssemblerTest, CompletesAContributionOnlyWhenEveryPartArrivedInAnyOrder) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 2, 3, 0, 2.0f)).ok());
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 0, 3, 0, 0.0f)).ok());
  EXPECT_EQ(a.pending_parts(), 2);
  EXPECT_FALSE(a.TakeAsync(0, 0, 1, &dropped).has_value());
  EXPECT_FALSE(a.TakeSync(0, {0}, &dropped).has_value());
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 1, 3, 0, 1.0f)).ok());
  EXPECT_EQ(a.pending_parts(), 0);
  const std::optional<Contribution> c = a.TakeSync(0, {0}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->batch.num_unrolls, 3);
  EXPECT_THAT(Marks(*c), ElementsAre(0.0f, 1.0f, 2.0f)) << "parts are joined in part order";
  EXPECT_EQ(c->batch.obs.size(), 3u * kT);
  EXPECT_EQ(dropped, 0);
}

TEST(ContributionAssemblerTest, IgnoresADuplicatePart) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 0, 2, 0, 10.0f)).ok());
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 0, 2, 0, 99.0f)).ok());  // a resend of part 0
  EXPECT_EQ(a.pending_parts(), 1);
  EXPECT_FALSE(a.TakeAsync(0, 0, 1, &dropped).has_value()) << "a duplicate completed it";
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 1, 2, 0, 11.0f)).ok());
  const std::optional<Contribution> c = a.TakeAsync(0, 0, 1, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(10.0f, 11.0f));
}

TEST(ContributionAssemblerTest, KeepsContributionsOfDifferentSequencesApart) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Part(0, 7, 0, 0, 2, 0, 1.0f)).ok());
  EXPECT_TRUE(a.Add(Part(0, 7, 1, 1, 2, 0, 2.0f)).ok());
  EXPECT_EQ(a.pending_parts(), 2);
  EXPECT_FALSE(a.TakeAsync(0, 0, 1, &dropped).has_value());
}

TEST(ContributionAssemblerTest, DropIncarnationDiscardsPartialPartsButKeepsCompleteOnes) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f)).ok());               // complete
  EXPECT_TRUE(a.Add(Part(0, 7, 1, 0, 2, 0, 2.0f)).ok());          // partial of the same incarnation
  EXPECT_TRUE(a.Add(Part(1, 8, 0, 0, 2, 0, 3.0f)).ok());          // partial of another
  EXPECT_EQ(a.DropIncarnation(7), 1);
  EXPECT_EQ(a.pending_parts(), 1);
  // The dropped part is gone: its other half no longer completes anything.
  EXPECT_TRUE(a.Add(Part(0, 7, 1, 1, 2, 0, 2.5f)).ok());
  EXPECT_EQ(a.pending_parts(), 2);
  const std::optional<Contribution> c = a.TakeSync(0, {0}, &dropped);
  ASSERT_TRUE(c.has_value()) << "the complete contribution of the dropped incarnation was lost";
  EXPECT_THAT(Marks(*c), ElementsAre(1.0f));
  EXPECT_EQ(a.DropIncarnation(12345), 0);
}

TEST(ContributionAssemblerTest, DropAllButDiscardsPartialPartsOfDeadIncarnationsOnly) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f)).ok());
  EXPECT_TRUE(a.Add(Part(0, 7, 1, 0, 3, 0, 0.0f)).ok());
  EXPECT_TRUE(a.Add(Part(0, 7, 1, 1, 3, 0, 0.0f)).ok());
  EXPECT_TRUE(a.Add(Part(1, 8, 0, 0, 2, 0, 0.0f)).ok());
  EXPECT_TRUE(a.Add(Part(2, 9, 0, 0, 2, 0, 0.0f)).ok());
  EXPECT_EQ(a.DropAllBut({8}), 3);
  EXPECT_EQ(a.pending_parts(), 1);
  EXPECT_TRUE(a.Add(Part(1, 8, 0, 1, 2, 0, 5.0f)).ok());  // the live one still completes
  EXPECT_EQ(a.pending_parts(), 0);
  const std::optional<Contribution> c = a.TakeSync(0, {0, 1}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(1.0f, 0.0f, 5.0f));
}

TEST(ContributionAssemblerTest, TakeSyncWaitsForEveryLiveSlotAndReturnsSlotOrder) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(2, 9, 0, 4, 2.0f)).ok());
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 4, 0.0f, 2)).ok());
  EXPECT_FALSE(a.TakeSync(4, {0, 1, 2}, &dropped).has_value());
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 4, 1.0f)).ok());
  const std::optional<Contribution> c = a.TakeSync(4, {0, 1, 2}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(0.0f, 0.0f, 1.0f, 2.0f));
  EXPECT_THAT(c->batch.policy_version, Each(4));
  EXPECT_EQ(dropped, 0);
  EXPECT_FALSE(a.TakeSync(4, {0, 1, 2}, &dropped).has_value()) << "contributions were reused";
}

TEST(ContributionAssemblerTest, TakeSyncDiscardsOlderVersionsAndCountsTheirUnrolls) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 9.0f, 3)).ok());
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 0, 9.0f, 2)).ok());
  EXPECT_TRUE(a.Add(Whole(0, 7, 1, 1, 1.0f)).ok());
  // Not ready (slot 1 has no version-1 contribution), but the stale ones go anyway.
  EXPECT_FALSE(a.TakeSync(1, {0, 1}, &dropped).has_value());
  EXPECT_EQ(dropped, 5);
  EXPECT_TRUE(a.Add(Whole(1, 8, 1, 1, 2.0f)).ok());
  const std::optional<Contribution> c = a.TakeSync(1, {0, 1}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(1.0f, 2.0f));
  EXPECT_THAT(c->batch.policy_version, Each(1));
  EXPECT_EQ(dropped, 5);
}

TEST(ContributionAssemblerTest, TakeSyncIncludesADeadWorkersCompleteContribution) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 2, 1.0f)).ok());  // slot 1's worker then dies
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 2, 0.0f)).ok());
  const std::optional<Contribution> c = a.TakeSync(2, {0}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(0.0f, 1.0f));
}

TEST(ContributionAssemblerTest, TakeSyncTakesOneContributionPerSlotTheFirstThatArrived) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f)).ok());
  EXPECT_TRUE(a.Add(Whole(0, 17, 0, 0, 2.0f)).ok());  // a restarted worker in the same slot
  const std::optional<Contribution> c = a.TakeSync(0, {0}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(1.0f));
  // The leftover is stale once the version moves on.
  EXPECT_FALSE(a.TakeSync(1, {0}, &dropped).has_value());
  EXPECT_EQ(dropped, 1);
}

TEST(ContributionAssemblerTest, TakeSyncWithNoLiveSlotReturnsNothing) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f)).ok());
  EXPECT_FALSE(a.TakeSync(0, {}, &dropped).has_value());
  EXPECT_TRUE(a.TakeSync(0, {0}, &dropped).has_value()) << "the contribution was discarded";
}

TEST(ContributionAssemblerTest, TakeAsyncReturnsNothingUntilEnoughUnrolls) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_FALSE(a.TakeAsync(0, 2, 4, &dropped).has_value());
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f, 2)).ok());
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 0, 2.0f, 1)).ok());
  EXPECT_FALSE(a.TakeAsync(0, 2, 4, &dropped).has_value());
  EXPECT_TRUE(a.Add(Whole(0, 7, 1, 0, 3.0f, 1)).ok());
  const std::optional<Contribution> c = a.TakeAsync(0, 2, 4, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(1.0f, 1.0f, 2.0f, 3.0f));
  EXPECT_EQ(dropped, 0);
}

TEST(ContributionAssemblerTest, TakeAsyncDropsVersionsOlderThanTheLagAndCountsThem) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 2, 1.0f, 2)).ok());  // 5 − 2 = 3 is the oldest allowed
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 3, 2.0f, 1)).ok());
  EXPECT_TRUE(a.Add(Whole(0, 7, 1, 5, 3.0f, 1)).ok());
  const std::optional<Contribution> c = a.TakeAsync(5, 2, 2, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(dropped, 2);
  EXPECT_THAT(Marks(*c), ElementsAre(2.0f, 3.0f));
  EXPECT_THAT(c->batch.policy_version, ElementsAre(3, 5));
}

TEST(ContributionAssemblerTest, TakeAsyncCountsStaleUnrollsEvenWhenNotReady) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f, 3)).ok());
  EXPECT_FALSE(a.TakeAsync(4, 2, 1, &dropped).has_value());
  EXPECT_EQ(dropped, 3);
}

TEST(ContributionAssemblerTest, TakeAsyncTakesTheOldestFirstAndLeavesTheRest) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 3, 1.0f)).ok());
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 4, 2.0f)).ok());
  EXPECT_TRUE(a.Add(Whole(0, 7, 1, 4, 3.0f)).ok());
  const std::optional<Contribution> first = a.TakeAsync(4, 2, 2, &dropped);
  ASSERT_TRUE(first.has_value());
  EXPECT_THAT(Marks(*first), ElementsAre(1.0f, 2.0f));
  const std::optional<Contribution> second = a.TakeAsync(4, 2, 1, &dropped);
  ASSERT_TRUE(second.has_value());
  EXPECT_THAT(Marks(*second), ElementsAre(3.0f));
  EXPECT_EQ(dropped, 0);
}

TEST(ContributionAssemblerTest, TakeAsyncTakesWholeContributionsEvenPastTheWantedCount) {
  ContributionAssembler a;
  int64_t dropped = 0;
  EXPECT_TRUE(a.Add(Whole(0, 7, 0, 0, 1.0f, 2)).ok());
  EXPECT_TRUE(a.Add(Whole(1, 8, 0, 0, 2.0f, 2)).ok());
  const std::optional<Contribution> c = a.TakeAsync(0, 0, 3, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->batch.num_unrolls, 4);
  EXPECT_EQ(c->batch.obs.size(), 4u * kT);
}

TEST(ContributionAssemblerTest, APartialFloodKeepsTwoContributionsInAssemblyPerIncarnation) {
  ContributionAssembler a;
  for (int64_t seq = 0; seq < 100; ++seq) ASSERT_TRUE(a.Add(Part(0, 7, seq, 0, 2, 0, 1.0f)).ok());
  ASSERT_TRUE(a.Add(Part(1, 8, 0, 0, 2, 0, 2.0f)).ok());
  EXPECT_EQ(a.pending_parts(), ContributionAssembler::kMaxPartialPerIncarnation + 1);
  EXPECT_EQ(a.evicted_unrolls(), 98);
  // The newest contribution of the flooding incarnation can still complete.
  ASSERT_TRUE(a.Add(Part(0, 7, 99, 1, 2, 0, 1.0f)).ok());
  EXPECT_EQ(a.held_unrolls(), 2);
}

TEST(ContributionAssemblerTest, PartsCarryingMoreUnrollsThanTheWorkersEnvsAreRejected) {
  ContributionAssembler a;
  ChunkPart first = Part(0, 7, 0, 0, 2, 0, 1.0f, 2);
  first.max_unrolls = 2;
  ASSERT_TRUE(a.Add(first).ok());
  ChunkPart second = Part(0, 7, 0, 1, 2, 0, 1.0f, 1);
  second.max_unrolls = 2;
  const absl::Status s = a.Add(second);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), ::testing::HasSubstr("carry 3 unrolls; the worker has 2 envs"));
  EXPECT_EQ(a.pending_parts(), 0) << "the contribution is dropped";
  EXPECT_EQ(a.held_unrolls(), 0);
}

TEST(ContributionAssemblerTest, CompleteContributionsOfOneSlotAreBoundedOldestFirst) {
  ContributionAssembler a(/*versions_kept=*/2);
  ASSERT_TRUE(a.Add(Whole(1, 8, 0, 0, 50.0f)).ok());
  for (int64_t seq = 0; seq < 10; ++seq) {
    ASSERT_TRUE(a.Add(Whole(0, 7, seq, 0, float(seq))).ok());
  }
  EXPECT_EQ(a.held_unrolls(), 3) << "two of slot 0, one of slot 1";
  EXPECT_EQ(a.evicted_unrolls(), 8);
  int64_t dropped = 0;
  const std::optional<Contribution> c = a.TakeSync(0, {0, 1}, &dropped);
  ASSERT_TRUE(c.has_value());
  EXPECT_THAT(Marks(*c), ElementsAre(8.0f, 50.0f)) << "slot 0's oldest were evicted";
}

TEST(ContributionAssemblerTest, AsyncBoundLeavesRoomForABatchFromOneSmallWorker) {
  // A worker of 2 envs and batches of 8 unrolls: 4 contributions make one batch.
  ContributionAssembler a(/*versions_kept=*/3, /*wanted_unrolls=*/8);
  for (int64_t seq = 0; seq < 7; ++seq) {
    ChunkPart p = Whole(0, 7, seq, 0, float(seq), 2);
    p.max_unrolls = 2;
    ASSERT_TRUE(a.Add(p).ok());
  }
  EXPECT_EQ(a.evicted_unrolls(), 0) << "3 + 8/2 = 7 contributions fit";
  ChunkPart eighth = Whole(0, 7, 7, 0, 7.0f, 2);
  eighth.max_unrolls = 2;
  ASSERT_TRUE(a.Add(eighth).ok());
  EXPECT_EQ(a.evicted_unrolls(), 2);
  int64_t dropped = 0;
  EXPECT_TRUE(a.TakeAsync(0, 2, 8, &dropped).has_value());
}

TEST(ContributionAssemblerTest, PartialContributionsOfUnusableVersionsAreDropped) {
  ContributionAssembler a;
  ASSERT_TRUE(a.Add(Part(0, 7, 0, 0, 2, /*version=*/3, 1.0f, 2)).ok());
  ASSERT_TRUE(a.Add(Part(1, 8, 0, 0, 2, /*version=*/5, 1.0f, 1)).ok());
  EXPECT_EQ(a.DropPartialsOlderThan(4), 2) << "version 3's part";
  EXPECT_EQ(a.partial_unrolls(), 1);
  EXPECT_EQ(a.DropPartialsOlderThan(4), 0);
}

}  // namespace
}  // namespace juggle
