#include "common/bounded_queue.h"

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <thread>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using Clock = BoundedQueue<int>::Clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

// Long enough that a test never reaches it unless the queue fails to wake a waiter.
Clock::time_point Far() { return Clock::now() + seconds(10); }

TEST(BoundedQueueTest, PopsItemsInTheOrderTheyWerePushed) {
  BoundedQueue<int> q(4);
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(q.Push(i, Far()));
  EXPECT_EQ(q.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(q.Pop(Far()), std::optional<int>(i));
  EXPECT_EQ(q.size(), 0u);
}

TEST(BoundedQueueTest, PushBlocksWhileFullAndSucceedsOnceAConsumerPops) {
  BoundedQueue<int> q(1);
  ASSERT_TRUE(q.Push(1, Far()));
  std::atomic<bool> done{false};
  bool pushed = false;
  std::thread producer([&] {
    pushed = q.Push(2, Far());
    done = true;
  });
  std::this_thread::sleep_for(milliseconds(100));
  EXPECT_FALSE(done.load()) << "Push returned although the queue was full";
  EXPECT_EQ(q.Pop(Far()), std::optional<int>(1));
  producer.join();
  EXPECT_TRUE(pushed);
  EXPECT_EQ(q.Pop(Far()), std::optional<int>(2));
}

TEST(BoundedQueueTest, PushReturnsFalseAtTheDeadlineWhenFull) {
  BoundedQueue<int> q(1);
  ASSERT_TRUE(q.Push(1, Far()));
  const auto start = Clock::now();
  EXPECT_FALSE(q.Push(2, start + milliseconds(50)));
  EXPECT_GE(Clock::now() - start, milliseconds(50));
  EXPECT_EQ(q.size(), 1u);
  EXPECT_EQ(q.Pop(Far()), std::optional<int>(1));
}

TEST(BoundedQueueTest, PopReturnsNulloptAtTheDeadlineWhenEmpty) {
  BoundedQueue<int> q(1);
  const auto start = Clock::now();
  EXPECT_EQ(q.Pop(start + milliseconds(50)), std::nullopt);
  EXPECT_GE(Clock::now() - start, milliseconds(50));
}

TEST(BoundedQueueTest, CloseWakesABlockedPushWhichReturnsFalse) {
  BoundedQueue<int> q(1);
  ASSERT_TRUE(q.Push(1, Far()));
  std::atomic<bool> done{false};
  bool pushed = true;
  std::thread producer([&] {
    pushed = q.Push(2, Far());
    done = true;
  });
  std::this_thread::sleep_for(milliseconds(50));
  EXPECT_FALSE(done.load());
  const auto closed_at = Clock::now();
  q.Close();
  producer.join();
  EXPECT_LT(Clock::now() - closed_at, seconds(5)) << "Close did not wake the producer";
  EXPECT_FALSE(pushed);
  EXPECT_EQ(q.size(), 1u);
}

TEST(BoundedQueueTest, CloseWakesABlockedPopWhichReturnsNullopt) {
  BoundedQueue<int> q(1);
  std::atomic<bool> done{false};
  std::optional<int> popped = 42;
  std::thread consumer([&] {
    popped = q.Pop(Far());
    done = true;
  });
  std::this_thread::sleep_for(milliseconds(50));
  EXPECT_FALSE(done.load());
  const auto closed_at = Clock::now();
  q.Close();
  consumer.join();
  EXPECT_LT(Clock::now() - closed_at, seconds(5)) << "Close did not wake the consumer";
  EXPECT_EQ(popped, std::nullopt);
}

TEST(BoundedQueueTest, PushAfterCloseFailsAtOnceEvenWithRoom) {
  BoundedQueue<int> q(4);
  q.Close();
  const auto start = Clock::now();
  EXPECT_FALSE(q.Push(1, Far()));
  EXPECT_LT(Clock::now() - start, seconds(5));
  EXPECT_EQ(q.size(), 0u);
}

TEST(BoundedQueueTest, PopDrainsRemainingItemsAfterCloseThenReturnsNulloptAtOnce) {
  BoundedQueue<std::string> q(3);
  ASSERT_TRUE(q.Push("a", Far()));
  ASSERT_TRUE(q.Push("b", Far()));
  q.Close();
  EXPECT_EQ(q.Pop(Far()), std::optional<std::string>("a"));
  EXPECT_EQ(q.Pop(Far()), std::optional<std::string>("b"));
  const auto start = Clock::now();
  EXPECT_EQ(q.Pop(Far()), std::nullopt);
  EXPECT_LT(Clock::now() - start, seconds(5)) << "Pop waited on a closed, drained queue";
}

}  // namespace
}  // namespace juggle
