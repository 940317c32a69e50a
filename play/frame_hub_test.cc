// The viewers' frame queues: every viewer gets every message in order; a full queue drops its
// oldest (counted) without blocking the publisher; the viewer limit, leaving, and Close waking a
// waiting Take.
#include "play/frame_hub.h"

#include <chrono>
#include <thread>

#include "gtest/gtest.h"

namespace juggle::play {
namespace {

using std::chrono::milliseconds;

TEST(FrameHubTest, EveryViewerGetsEveryMessageInOrder) {
  FrameHub hub(4, 8);
  const int64_t a = *hub.Join(), b = *hub.Join();
  hub.Publish("1");
  hub.Publish("2");
  hub.SendTo(b, "only b");
  EXPECT_EQ(*hub.Take(a, milliseconds(10)), "1");
  EXPECT_EQ(*hub.Take(a, milliseconds(10)), "2");
  EXPECT_FALSE(hub.Take(a, milliseconds(10)).has_value());
  EXPECT_EQ(*hub.Take(b, milliseconds(10)), "1");
  EXPECT_EQ(*hub.Take(b, milliseconds(10)), "2");
  EXPECT_EQ(*hub.Take(b, milliseconds(10)), "only b");
  EXPECT_EQ(hub.published(), 2);
}

TEST(FrameHubTest, ASlowViewerLosesItsOldestMessagesAndThePublisherNeverWaits) {
  FrameHub hub(2, 3);
  const int64_t slow = *hub.Join();
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 1000; ++i) hub.Publish(std::to_string(i));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_EQ(hub.dropped(), 997);
  EXPECT_EQ(*hub.Take(slow, milliseconds(10)), "997");
  EXPECT_EQ(*hub.Take(slow, milliseconds(10)), "998");
  EXPECT_EQ(*hub.Take(slow, milliseconds(10)), "999");
}

TEST(FrameHubTest, RefusesViewersBeyondTheLimitUntilOneLeaves) {
  FrameHub hub(2, 4);
  const int64_t a = *hub.Join();
  ASSERT_TRUE(hub.Join().has_value());
  EXPECT_FALSE(hub.Join().has_value());
  hub.Leave(a);
  EXPECT_FALSE(hub.has_viewer(a));
  EXPECT_FALSE(hub.Take(a, milliseconds(1)).has_value());
  EXPECT_TRUE(hub.Join().has_value());
  EXPECT_EQ(hub.viewers(), 2);
}

TEST(FrameHubTest, TakeWaitsForAMessageAndCloseWakesIt) {
  FrameHub hub(2, 4);
  const int64_t a = *hub.Join();
  std::thread publisher([&] {
    std::this_thread::sleep_for(milliseconds(50));
    hub.Publish("late");
  });
  EXPECT_EQ(*hub.Take(a, milliseconds(5000)), "late");
  publisher.join();
  std::thread closer([&] {
    std::this_thread::sleep_for(milliseconds(50));
    hub.Close();
  });
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(hub.Take(a, milliseconds(10000)).has_value());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  closer.join();
  EXPECT_TRUE(hub.closed());
  EXPECT_FALSE(hub.Join().has_value());
}

}  // namespace
}  // namespace juggle::play
