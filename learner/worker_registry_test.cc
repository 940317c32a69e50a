#include "learner/worker_registry.h"

#include <chrono>
#include <optional>
#include <set>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::ElementsAre;
using Clock = WorkerRegistry::Clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

// A fixed time origin: tests pass explicit time points, never the wall clock.
const Clock::time_point kT0 = Clock::time_point() + std::chrono::hours(1);

WorkerInfo Reg(WorkerRegistry* r, int requested_slot, Clock::time_point now = kT0,
               std::optional<uint64_t>* replaced = nullptr) {
  std::optional<uint64_t> ignored;
  absl::StatusOr<WorkerInfo> w =
      r->Register(requested_slot, 4, "host", now, replaced ? replaced : &ignored);
  EXPECT_TRUE(w.ok()) << w.status();
  return w.value_or(WorkerInfo());
}

std::vector<int> LiveSlots(const WorkerRegistry& r) {
  std::vector<int> slots;
  for (const WorkerInfo& w : r.Live()) slots.push_back(w.slot);
  return slots;
}

TEST(WorkerRegistryTest, AssignsTheLowestFreeSlot) {
  WorkerRegistry r(1);
  EXPECT_EQ(Reg(&r, -1).slot, 0);
  const WorkerInfo second = Reg(&r, -1);
  EXPECT_EQ(second.slot, 1);
  EXPECT_EQ(Reg(&r, -1).slot, 2);
  r.Remove(second.incarnation);
  EXPECT_EQ(Reg(&r, -1).slot, 1);
  EXPECT_EQ(Reg(&r, -1).slot, 3);
}

TEST(WorkerRegistryTest, CountChunkKeepsTheNewestVersionOfAcceptedAndRefusedChunks) {
  WorkerRegistry r(1);
  const WorkerInfo w = Reg(&r, -1);
  EXPECT_EQ(r.Find(w.incarnation)->newest_chunk_version, -1);
  r.CountChunk(w.incarnation, true, 7);
  r.CountChunk(w.incarnation, false, 9);
  r.CountChunk(w.incarnation, true, 8);
  r.CountChunk(w.incarnation, false);
  const WorkerInfo after = *r.Find(w.incarnation);
  EXPECT_EQ(after.newest_chunk_version, 9);
  EXPECT_EQ(after.chunks_accepted, 2);
  EXPECT_EQ(after.chunks_rejected, 2);
}

TEST(WorkerRegistryTest, RegisterKeepsTheWorkersSessionCountClamped) {
  WorkerRegistry r(1);
  std::optional<uint64_t> replaced;
  EXPECT_EQ(r.Register(-1, 4, "h", kT0, &replaced)->sessions, 1);
  EXPECT_EQ(r.Register(-1, 4, "h", kT0, &replaced, 6)->sessions, 7);
  EXPECT_EQ(r.Register(-1, 4, "h", kT0, &replaced, -5)->sessions, 1) << "a negative claim";
  EXPECT_EQ(r.Register(-1, 4, "h", kT0, &replaced, int64_t{1} << 62)->sessions,
            (int64_t{1} << 40) + 1);
}

TEST(WorkerRegistryTest, LowestFreeSlotSkipsRequestedSlots) {
  WorkerRegistry r(1);
  Reg(&r, 0);
  Reg(&r, 2);
  EXPECT_EQ(Reg(&r, -1).slot, 1);
  EXPECT_EQ(Reg(&r, -1).slot, 3);
}

TEST(WorkerRegistryTest, RegisterRecordsTheWorkersDetails) {
  WorkerRegistry r(1);
  std::optional<uint64_t> replaced = 99;
  const WorkerInfo w = *r.Register(-1, 16, "box7", kT0, &replaced);
  EXPECT_FALSE(replaced.has_value()) << "a first registration replaces nothing";
  const std::optional<WorkerInfo> found = r.Find(w.incarnation);
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->slot, 0);
  EXPECT_EQ(found->num_envs, 16);
  EXPECT_EQ(found->host, "box7");
  EXPECT_EQ(found->last_seen, kT0);
  EXPECT_EQ(found->policy_version, -1);
}

TEST(WorkerRegistryTest, RequestedSlotReplacesTheOldIncarnation) {
  WorkerRegistry r(1);
  const WorkerInfo old = Reg(&r, 0);
  Reg(&r, 1);
  std::optional<uint64_t> replaced;
  const WorkerInfo fresh = Reg(&r, 0, kT0 + seconds(1), &replaced);
  EXPECT_EQ(fresh.slot, 0);
  ASSERT_TRUE(replaced.has_value());
  EXPECT_EQ(*replaced, old.incarnation);
  EXPECT_NE(fresh.incarnation, old.incarnation);
  EXPECT_FALSE(r.Find(old.incarnation).has_value());
  EXPECT_FALSE(r.Touch(old.incarnation, kT0 + seconds(2)));
  ASSERT_TRUE(r.Find(fresh.incarnation).has_value());
  EXPECT_EQ(r.Find(fresh.incarnation)->slot, 0);
  EXPECT_THAT(LiveSlots(r), ElementsAre(0, 1));
}

TEST(WorkerRegistryTest, RequestedFreeSlotReplacesNothing) {
  WorkerRegistry r(1);
  Reg(&r, 0);
  std::optional<uint64_t> replaced;
  EXPECT_EQ(Reg(&r, 5, kT0, &replaced).slot, 5);
  EXPECT_FALSE(replaced.has_value());
  EXPECT_THAT(LiveSlots(r), ElementsAre(0, 5));
}

TEST(WorkerRegistryTest, IncarnationsAreUniqueAndCarryTheEpochInTheHigh32Bits) {
  constexpr uint32_t kEpoch = 0xDEADBEEF;
  WorkerRegistry r(kEpoch);
  std::set<uint64_t> seen;
  for (int i = 0; i < 5; ++i) seen.insert(Reg(&r, -1).incarnation);
  for (int i = 0; i < 5; ++i) seen.insert(Reg(&r, 2).incarnation);  // replacements too
  EXPECT_EQ(seen.size(), 10u);
  for (uint64_t inc : seen) {
    EXPECT_EQ(inc >> 32, kEpoch) << std::hex << inc;
    EXPECT_NE(inc & 0xFFFFFFFFu, 0u) << "incarnation 0 of an epoch would look unset";
  }
  WorkerRegistry other(kEpoch + 1);
  EXPECT_EQ(Reg(&other, -1).incarnation >> 32, uint64_t(kEpoch) + 1);
}

TEST(WorkerRegistryTest, TouchOfAnUnknownIncarnationReturnsFalse) {
  WorkerRegistry r(1);
  EXPECT_FALSE(r.Touch(12345, kT0));
  const WorkerInfo w = Reg(&r, -1);
  EXPECT_FALSE(r.Touch(w.incarnation + 1, kT0));
  r.Remove(w.incarnation);
  EXPECT_FALSE(r.Touch(w.incarnation, kT0));
}

TEST(WorkerRegistryTest, TouchUpdatesLastSeenAndOnlyTheReportedFields) {
  WorkerRegistry r(1);
  const WorkerInfo w = Reg(&r, -1);
  ASSERT_TRUE(r.Touch(w.incarnation, kT0 + seconds(3), 7, 250.0));
  EXPECT_EQ(r.Find(w.incarnation)->last_seen, kT0 + seconds(3));
  EXPECT_EQ(r.Find(w.incarnation)->policy_version, 7);
  EXPECT_EQ(r.Find(w.incarnation)->env_steps_per_s, 250.0);
  // The defaults (-1) leave version and speed alone.
  ASSERT_TRUE(r.Touch(w.incarnation, kT0 + seconds(4)));
  EXPECT_EQ(r.Find(w.incarnation)->last_seen, kT0 + seconds(4));
  EXPECT_EQ(r.Find(w.incarnation)->policy_version, 7);
  EXPECT_EQ(r.Find(w.incarnation)->env_steps_per_s, 250.0);
}

TEST(WorkerRegistryTest, ExpireRemovesOnlyWorkersSilentLongerThanTheTimeout) {
  WorkerRegistry r(1);
  const WorkerInfo silent = Reg(&r, -1, kT0);
  const WorkerInfo touched = Reg(&r, -1, kT0);
  const WorkerInfo late = Reg(&r, -1, kT0 + seconds(5));
  ASSERT_TRUE(r.Touch(touched.incarnation, kT0 + seconds(8)));
  const std::vector<uint64_t> expired = r.Expire(kT0 + milliseconds(10500), seconds(10));
  EXPECT_THAT(expired, ElementsAre(silent.incarnation));
  EXPECT_FALSE(r.Find(silent.incarnation).has_value());
  EXPECT_TRUE(r.Find(touched.incarnation).has_value());
  EXPECT_TRUE(r.Find(late.incarnation).has_value());
  EXPECT_THAT(LiveSlots(r), ElementsAre(1, 2));
}

TEST(WorkerRegistryTest, ExpireKeepsAWorkerSilentExactlyTheTimeout) {
  WorkerRegistry r(1);
  const WorkerInfo w = Reg(&r, -1, kT0);
  EXPECT_TRUE(r.Expire(kT0 + seconds(10), seconds(10)).empty());
  EXPECT_THAT(r.Expire(kT0 + seconds(10) + milliseconds(1), seconds(10)),
              ElementsAre(w.incarnation));
}

TEST(WorkerRegistryTest, ExpiredSlotIsReusedByTheNextRegistration) {
  WorkerRegistry r(1);
  Reg(&r, -1, kT0);
  Reg(&r, -1, kT0 + seconds(9));
  ASSERT_EQ(r.Expire(kT0 + seconds(11), seconds(10)).size(), 1u);
  EXPECT_EQ(Reg(&r, -1, kT0 + seconds(11)).slot, 0);
}

TEST(WorkerRegistryTest, LiveIsSortedBySlotNotByRegistrationOrder) {
  WorkerRegistry r(1);
  Reg(&r, 3);
  Reg(&r, 1);
  Reg(&r, -1);  // slot 0
  Reg(&r, 2);
  EXPECT_THAT(LiveSlots(r), ElementsAre(0, 1, 2, 3));
}

TEST(WorkerRegistryTest, RejectsSlotsEnvCountsAndHostNamesOutsideTheLimits) {
  RegistryLimits limits;
  limits.max_workers = 8;
  limits.max_envs_per_worker = 64;
  WorkerRegistry r(1, limits);
  std::optional<uint64_t> replaced;
  auto code = [&](int slot, int envs, const std::string& host) {
    return r.Register(slot, envs, host, kT0, &replaced).status().code();
  };
  EXPECT_EQ(code(8, 4, "h"), absl::StatusCode::kInvalidArgument) << "slot == max_workers";
  EXPECT_EQ(code(2147483647, 4, "h"), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(code(-2, 4, "h"), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(code(0, 0, "h"), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(code(0, 65, "h"), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(code(0, 4, ""), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(code(0, 4, std::string(4 << 20, 'x')), absl::StatusCode::kInvalidArgument)
      << "a 4 MiB host name";
  EXPECT_EQ(code(0, 4, std::string("a\nb")), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(r.Live().empty()) << "a rejected registration leaves nothing behind";
  EXPECT_EQ(code(7, 64, std::string(253, 'x')), absl::StatusCode::kOk) << "the limits themselves";
}

TEST(WorkerRegistryTest, TotalAndPerHostLimitsRefuseNewWorkersButNotReplacements) {
  RegistryLimits limits;
  limits.max_workers = 4;
  limits.max_workers_per_host = 2;
  WorkerRegistry r(1, limits);
  std::optional<uint64_t> replaced;
  ASSERT_TRUE(r.Register(-1, 1, "a", kT0, &replaced).ok());
  ASSERT_TRUE(r.Register(-1, 1, "a", kT0, &replaced).ok());
  const absl::StatusOr<WorkerInfo> third_on_a = r.Register(-1, 1, "a", kT0, &replaced);
  EXPECT_EQ(third_on_a.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(third_on_a.status().message()), ::testing::HasSubstr("max_workers_per_host"));
  // A restarted worker of host a takes its slot back although a is full.
  const absl::StatusOr<WorkerInfo> restarted = r.Register(1, 1, "a", kT0, &replaced);
  ASSERT_TRUE(restarted.ok()) << restarted.status();
  EXPECT_TRUE(replaced.has_value());
  ASSERT_TRUE(r.Register(-1, 1, "b", kT0, &replaced).ok());
  ASSERT_TRUE(r.Register(-1, 1, "c", kT0, &replaced).ok());
  const absl::StatusOr<WorkerInfo> fifth = r.Register(-1, 1, "d", kT0, &replaced);
  EXPECT_EQ(fifth.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(fifth.status().message()), ::testing::HasSubstr("service.max_workers"));
  EXPECT_EQ(r.Live().size(), 4u);
  // Room again once a worker is forgotten.
  r.Expire(kT0 + seconds(100), seconds(10));
  EXPECT_TRUE(r.Register(-1, 1, "d", kT0 + seconds(100), &replaced).ok());
}

}  // namespace
}  // namespace juggle
