#include "learner/demo_buffer.h"

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "gtest/gtest.h"

namespace juggle {
namespace {

constexpr int kD = 3, kA = 2, kSteps = 4;

// `unrolls` unrolls of kSteps steps; unroll u is labelled when u is odd. Observation row i (over
// the whole batch) starts with `first + i`, and its label (if any) with -(first + i).
UnrollBatch Batch(int unrolls, float first) {
  UnrollBatch b;
  b.num_unrolls = unrolls;
  b.unroll_length = kSteps;
  b.obs_dim = kD;
  b.act_dim = kA;
  b.obs.assign(size_t(unrolls) * kSteps * kD, 0);
  for (int i = 0; i < unrolls * kSteps; ++i) b.obs[size_t(i) * kD] = first + i;
  b.labelled.assign(unrolls, 0);
  for (int u = 1; u < unrolls; u += 2) {
    b.labelled[u] = 1;
    for (int t = 0; t < kSteps; ++t) {
      b.labels.push_back(-(first + u * kSteps + t));
      b.labels.push_back(0.5f);
    }
  }
  return b;
}

// The observation keys (first entries) the buffer holds, checking that each row's label
// belongs to its observation.
std::set<float> Keys(const DemoBuffer& d) {
  std::set<float> keys;
  for (int64_t i = 0; i < d.size(); ++i) {
    const float key = d.obs()[i * kD];
    EXPECT_EQ(d.labels()[i * kA], -key) << "row " << i;
    keys.insert(key);
  }
  return keys;
}

TEST(DemoBufferTest, AddsOnlyTheLabelledUnrollsWithTheirOwnLabels) {
  DemoBuffer d(100, kD, kA);
  EXPECT_EQ(d.AddLabelled(Batch(4, 0)), 2 * kSteps);  // unrolls 1 and 3
  EXPECT_EQ(Keys(d), (std::set<float>{4, 5, 6, 7, 12, 13, 14, 15}));
}

TEST(DemoBufferTest, BatchWithoutLabelsAddsNothing) {
  DemoBuffer d(100, kD, kA);
  UnrollBatch b = Batch(2, 0);
  b.labelled.clear();
  b.labels.clear();
  EXPECT_EQ(d.AddLabelled(b), 0);
  EXPECT_EQ(d.size(), 0);
}

TEST(DemoBufferTest, StaysWithinItsBoundKeepingTheNewestAndReconciles) {
  DemoBuffer d(10, kD, kA);
  float first = 0;
  const float* storage = nullptr;
  for (int round = 0; round < 20; ++round, first += 1000) {
    d.AddLabelled(Batch(4, first));  // 8 labelled states per batch
    EXPECT_LE(d.size(), 10);
    EXPECT_EQ(d.added(), d.size() + d.evicted());
    if (round == 1) storage = d.obs();
    // Memory stays flat: the storage never moves once the bound is reached.
    if (round > 1) {
      EXPECT_EQ(d.obs(), storage);
    }
  }
  EXPECT_EQ(d.size(), 10);
  EXPECT_EQ(d.added(), 160);
  EXPECT_EQ(d.evicted(), 150);
  // The newest 10: the last batch's 8 and the previous batch's last 2.
  const float last = 19000, previous = 18000;
  EXPECT_EQ(Keys(d), (std::set<float>{previous + 14, previous + 15, last + 4, last + 5, last + 6,
                                      last + 7, last + 12, last + 13, last + 14, last + 15}));
}

// imitation.initial_demos_file: a saved buffer seeds a new run's, in the order its pairs were added.
TEST(DemoBufferTest, AddPairsTakesRowsInOrderAndKeepsTheNewest) {
  std::vector<float> obs, labels;
  for (int i = 0; i < 6; ++i) {
    obs.insert(obs.end(), {float(10 + i), 0, 0});
    labels.insert(labels.end(), {-float(10 + i), 0.5f});
  }
  DemoBuffer d(4, kD, kA);
  EXPECT_EQ(d.AddPairs(obs.data(), labels.data(), 6), 6);
  EXPECT_EQ(Keys(d), (std::set<float>{12, 13, 14, 15}));
  EXPECT_EQ(d.obs()[d.oldest() * kD], 12);
  EXPECT_EQ(d.evicted(), 2);
}

TEST(DemoBufferTest, AddAllTakesAnotherBuffersPairsOldestFirstAndKeepsTheNewest) {
  DemoBuffer source(5, kD, kA);
  source.AddLabelled(Batch(4, 0));  // keys 4..7, 12..15 into 5: 7, 12..15 held, ring wrapped
  DemoBuffer into(4, kD, kA);
  into.AddLabelled(Batch(2, 500));  // keys 504..507
  absl::StatusOr<int64_t> added = into.AddAll(source);
  ASSERT_TRUE(added.ok()) << added.status();
  EXPECT_EQ(*added, 5);
  EXPECT_EQ(into.added(), 9);
  // Added one by one in the source's order, the last four are the source's newest four.
  EXPECT_EQ(Keys(into), (std::set<float>{12, 13, 14, 15}));
  DemoBuffer wide(10, kD, kA);
  ASSERT_TRUE(wide.AddAll(source).ok());
  EXPECT_EQ(Keys(wide), (std::set<float>{7, 12, 13, 14, 15}));
  EXPECT_EQ(wide.oldest(), 0);
  EXPECT_EQ(wide.obs()[0], 7);  // the source's oldest pair came first
  DemoBuffer other_dims(10, kD + 1, kA);
  EXPECT_EQ(other_dims.AddAll(source).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(DemoBufferTest, LabelVarianceMatchesADirectComputationOverTheRowsHeld) {
  DemoBuffer d(10, kD, kA);
  for (int round = 0; round < 7; ++round) d.AddLabelled(Batch(4, 100.0f * round));
  ASSERT_EQ(d.size(), 10);
  for (int a = 0; a < kA; ++a) {
    double sum = 0, sum_sq = 0;
    for (int64_t i = 0; i < d.size(); ++i) sum += d.labels()[i * kA + a];
    const double mean = sum / d.size();
    for (int64_t i = 0; i < d.size(); ++i) sum_sq += std::pow(d.labels()[i * kA + a] - mean, 2);
    EXPECT_NEAR(d.LabelVariance()[a], sum_sq / d.size(), 1e-6 * (1 + sum_sq / d.size())) << a;
  }
  EXPECT_EQ(d.LabelVariance()[1], 0);  // the second label is always 0.5
}

}  // namespace
}  // namespace juggle

namespace juggle {
namespace {

// The buffer saved beside the checkpoints (learner/learner_server.cc) comes back whole: the
// same rows, accounts and label variance, and it goes on as the original would; bytes that are
// not a buffer, are cut short or come from another config are refused.
TEST(DemoBufferPersistenceTest, SerializedBufferParsesBackWithItsRowsAccountsAndVariance) {
  DemoBuffer buffer(5, kD, kA);
  buffer.AddLabelled(Batch(4, 0));  // unrolls 1 and 3: 8 pairs into 5, 3 evicted, ring wrapped
  ASSERT_EQ(buffer.size(), 5);
  const std::string bytes = buffer.Serialize();
  absl::StatusOr<DemoBuffer> back = DemoBuffer::Parse(bytes, 5, kD, kA);
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_EQ(back->size(), 5);
  EXPECT_EQ(back->added(), 8);
  EXPECT_EQ(back->evicted(), 3);
  EXPECT_EQ(std::vector<float>(back->obs(), back->obs() + 5 * kD),
            std::vector<float>(buffer.obs(), buffer.obs() + 5 * kD));
  EXPECT_EQ(std::vector<float>(back->labels(), back->labels() + 5 * kA),
            std::vector<float>(buffer.labels(), buffer.labels() + 5 * kA));
  for (int a = 0; a < kA; ++a) {
    EXPECT_NEAR(back->LabelVariance()[a], buffer.LabelVariance()[a], 1e-9);
  }
  DemoBuffer original = buffer;
  const UnrollBatch more = Batch(2, 100);
  original.AddLabelled(more);
  back->AddLabelled(more);
  EXPECT_EQ(Keys(*back), Keys(original));

  EXPECT_FALSE(DemoBuffer::Parse("not a buffer", 5, kD, kA).ok());
  EXPECT_FALSE(DemoBuffer::Parse(bytes.substr(0, bytes.size() - 4), 5, kD, kA).ok());
  EXPECT_FALSE(DemoBuffer::Parse(bytes, 6, kD, kA).ok());      // another buffer_size
  EXPECT_FALSE(DemoBuffer::Parse(bytes, 5, kD + 1, kA).ok());  // another observation size
}

}  // namespace
}  // namespace juggle
