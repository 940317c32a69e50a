#include "learner/policy_store.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

std::shared_ptr<const PolicySnapshot> Snapshot(int64_t version) {
  auto s = std::make_shared<PolicySnapshot>();
  s->version = version;
  s->params = "params-" + std::to_string(version);
  s->edge_counts = {1.0, 2.0};
  return s;
}

// Long enough that a test never reaches it unless the store fails to wake a waiter.
Clock::time_point Far() { return Clock::now() + seconds(10); }

TEST(PolicyStoreTest, CurrentIsNullBeforeTheFirstPublishThenTheLatest) {
  PolicyStore store;
  EXPECT_EQ(store.Current(), nullptr);
  store.Publish(Snapshot(0));
  store.Publish(Snapshot(1));
  ASSERT_NE(store.Current(), nullptr);
  EXPECT_EQ(store.Current()->version, 1);
  EXPECT_EQ(store.Current()->params, "params-1");
}

TEST(PolicyStoreTest, WaitNewerReturnsAtOnceWhenANewerSnapshotExists) {
  PolicyStore store;
  store.Publish(Snapshot(3));
  const auto start = Clock::now();
  std::shared_ptr<const PolicySnapshot> s = store.WaitNewer(2, Far());
  EXPECT_LT(Clock::now() - start, seconds(5));
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->version, 3);
  // min_version −1 (any snapshot) too.
  EXPECT_EQ(store.WaitNewer(-1, Far())->version, 3);
}

TEST(PolicyStoreTest, WaitNewerBlocksUntilAnotherThreadPublishes) {
  PolicyStore store;
  store.Publish(Snapshot(0));
  std::atomic<bool> returned{false};
  std::shared_ptr<const PolicySnapshot> got;
  std::thread waiter([&] {
    got = store.WaitNewer(0, Far());
    returned = true;
  });
  std::this_thread::sleep_for(milliseconds(100));
  EXPECT_FALSE(returned.load()) << "WaitNewer returned without a newer snapshot";
  const auto published_at = Clock::now();
  store.Publish(Snapshot(1));
  waiter.join();
  EXPECT_LT(Clock::now() - published_at, seconds(5));
  ASSERT_NE(got, nullptr);
  EXPECT_EQ(got->version, 1);
}

TEST(PolicyStoreTest, WaitNewerReturnsTheCurrentSnapshotAtTheDeadline) {
  PolicyStore store;
  store.Publish(Snapshot(4));
  const auto start = Clock::now();
  std::shared_ptr<const PolicySnapshot> s = store.WaitNewer(4, start + milliseconds(50));
  EXPECT_GE(Clock::now() - start, milliseconds(50));
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->version, 4);
}

TEST(PolicyStoreTest, CloseWakesWaitersWhichReturnTheCurrentSnapshot) {
  PolicyStore store;
  store.Publish(Snapshot(2));
  std::shared_ptr<const PolicySnapshot> got[2];
  std::atomic<int> returned{0};
  std::thread waiters[2];
  for (int i = 0; i < 2; ++i) {
    waiters[i] = std::thread([&, i] {
      got[i] = store.WaitNewer(2, Far());
      ++returned;
    });
  }
  std::this_thread::sleep_for(milliseconds(50));
  EXPECT_EQ(returned.load(), 0);
  const auto closed_at = Clock::now();
  store.Close();
  for (std::thread& t : waiters) t.join();
  EXPECT_LT(Clock::now() - closed_at, seconds(5)) << "Close did not wake the waiters";
  for (const auto& s : got) {
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->version, 2);
  }
}

TEST(PolicyStoreTest, WaitNewerAfterCloseReturnsAtOnce) {
  PolicyStore store;
  store.Publish(Snapshot(1));
  store.Close();
  const auto start = Clock::now();
  EXPECT_EQ(store.WaitNewer(1, Far())->version, 1);
  EXPECT_LT(Clock::now() - start, seconds(5));
}

}  // namespace
}  // namespace juggle
