// Deterministic random numbers: reproducible streams, distinct streams per (seed, worker, env),
// and the distributions' ranges and moments.
#include "common/rng.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "gtest/gtest.h"

namespace juggle {
namespace {

std::vector<uint64_t> Draw(Rng rng, int n) {
  std::vector<uint64_t> out;
  for (int i = 0; i < n; ++i) out.push_back(rng.NextU64());
  return out;
}

TEST(RngTest, SplitMix64MatchesTheReferenceOutputs) {
  // Vigna's splitmix64.c seeded with 0: the first outputs are fixed by the algorithm.
  uint64_t state = 0;
  EXPECT_EQ(SplitMix64(&state), 0xE220A8397B1DCDAFULL);
  EXPECT_EQ(SplitMix64(&state), 0x6E789E6AA1B965F4ULL);
  EXPECT_EQ(SplitMix64(&state), 0x06C45D188009454FULL);
  EXPECT_EQ(state, 3 * 0x9E3779B97F4A7C15ULL);
}

TEST(RngTest, SameSeedGivesTheSameStream) {
  EXPECT_EQ(Draw(Rng(42), 1000), Draw(Rng(42), 1000));
  EXPECT_EQ(Draw(Rng::ForStream(7, 3, 11), 1000), Draw(Rng::ForStream(7, 3, 11), 1000));
}

TEST(RngTest, DifferentSeedsGiveDifferentStreams) {
  EXPECT_NE(Draw(Rng(1), 4), Draw(Rng(2), 4));
  EXPECT_NE(Draw(Rng(0), 4), Draw(Rng(1), 4));
}

TEST(RngTest, EverySeedWorkerEnvTripleGetsItsOwnStream) {
  std::set<std::vector<uint64_t>> streams;
  int triples = 0;
  for (uint64_t seed : {0, 1, 2}) {
    for (uint64_t worker = 0; worker < 4; ++worker) {
      for (uint64_t env = 0; env < 16; ++env) {
        streams.insert(Draw(Rng::ForStream(seed, worker, env), 2));
        ++triples;
      }
    }
  }
  EXPECT_EQ(static_cast<int>(streams.size()), triples);
}

TEST(RngTest, SwappingWorkerAndEnvGivesADifferentStream) {
  EXPECT_NE(Draw(Rng::ForStream(1, 2, 5), 4), Draw(Rng::ForStream(1, 5, 2), 4));
  EXPECT_NE(Draw(Rng::ForStream(1, 0, 1), 4), Draw(Rng::ForStream(1, 1, 0), 4));
}

TEST(RngTest, StreamIsAPureFunctionOfTheNumberOfDraws) {
  // Mixing calls of different kinds consumes one 64-bit draw each (Normal two).
  Rng a(9), b(9);
  a.Uniform();
  a.UniformInt(10);
  a.Normal();
  for (int i = 0; i < 4; ++i) b.NextU64();
  EXPECT_EQ(a.NextU64(), b.NextU64());
}

TEST(RngTest, UniformLiesInTheHalfOpenUnitInterval) {
  Rng rng(3);
  double sum = 0, lo = 1, hi = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double u = rng.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  EXPECT_NEAR(sum / n, 0.5, 0.005);
  EXPECT_LT(lo, 1e-3);
  EXPECT_GT(hi, 1 - 1e-3);
}

TEST(RngTest, UniformWithBoundsStaysInThem) {
  Rng rng(4);
  for (int i = 0; i < 10000; ++i) {
    const double u = rng.Uniform(1.0, 2.0);
    ASSERT_GE(u, 1.0);
    ASSERT_LT(u, 2.0);
    const double v = rng.Uniform(-3.0, -2.5);
    ASSERT_GE(v, -3.0);
    ASSERT_LT(v, -2.5);
  }
}

TEST(RngTest, UniformIntOfOneIsAlwaysZero) {
  Rng rng(5);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(rng.UniformInt(1), 0u);
}

TEST(RngTest, UniformIntStaysBelowNAndHitsEveryValueEvenly) {
  Rng rng(6);
  const uint64_t n = 7;
  const int draws = 70000;
  std::vector<int> hits(n, 0);
  for (int i = 0; i < draws; ++i) {
    const uint64_t k = rng.UniformInt(n);
    ASSERT_LT(k, n);
    ++hits[k];
  }
  for (uint64_t k = 0; k < n; ++k) EXPECT_NEAR(hits[k], draws / n, 0.05 * draws / n) << k;
}

TEST(RngTest, UniformIntWithAHugeBoundStaysBelowIt) {
  // Just above 2^63: half of all 64-bit values are rejected, the rest must land below n.
  Rng rng(8);
  const uint64_t n = (uint64_t{1} << 63) + 12345;
  int upper_half = 0;
  for (int i = 0; i < 10000; ++i) {
    const uint64_t k = rng.UniformInt(n);
    ASSERT_LT(k, n);
    upper_half += k >= n / 2;
  }
  EXPECT_NEAR(upper_half / 10000.0, 0.5, 0.03);
}

TEST(RngTest, NormalHasMeanZeroAndVarianceOne) {
  Rng rng(10);
  const int n = 100000;
  double sum = 0, sum2 = 0;
  int within_one = 0;
  for (int i = 0; i < n; ++i) {
    const double x = rng.Normal();
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
    sum2 += x * x;
    within_one += std::abs(x) < 1.0;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 0.015);
  EXPECT_NEAR(sum2 / n - mean * mean, 1.0, 0.02);
  EXPECT_NEAR(static_cast<double>(within_one) / n, 0.6827, 0.01);
}

}  // namespace
}  // namespace juggle
