#include "common/chunk_codec.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

constexpr int kU = 5, kT = 6, kD = 7, kA = 3;
constexpr int kNodes = 3, kEdges = 4;
constexpr int64_t kVersion = 3;
constexpr uint64_t kIncarnation = 0x1234'0000'0007ull;
// Bytes per unroll as EncodeContribution estimates them.
constexpr size_t kUnrollBytes = size_t(kT) * (kD + kA + 4) * 4 + size_t(kD) * 4;

// Random data (fixed seed); truncated steps in unrolls 0, 2 (twice) and 4, done steps in 1 and 3.
Contribution RandomContribution() {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> uni(-2.0f, 2.0f);
  auto fill = [&](std::vector<float>* v, size_t n) {
    v->resize(n);
    for (float& x : *v) x = uni(rng);
  };
  Contribution c;
  UnrollBatch& b = c.batch;
  b.num_unrolls = kU;
  b.unroll_length = kT;
  b.obs_dim = kD;
  b.act_dim = kA;
  const size_t n = size_t(kU) * kT;
  fill(&b.obs, n * kD);
  fill(&b.actions, n * kA);
  fill(&b.log_probs, n);
  fill(&b.rewards, n);
  b.done.assign(n, 0);
  b.truncated.assign(n, 0);
  for (auto [u, t] : {std::pair{0, 2}, {2, 1}, {2, 4}, {4, 5}}) b.truncated[u * kT + t] = 1;
  for (auto [u, t] : {std::pair{1, 3}, {3, 0}}) b.done[u * kT + t] = 1;
  fill(&b.truncated_obs, size_t(b.num_truncated()) * kD);
  fill(&b.bootstrap_obs, size_t(kU) * kD);
  b.policy_version.assign(kU, kVersion);
  c.node.resize(n);
  for (int32_t& x : c.node) x = static_cast<int32_t>(rng() % kNodes);
  c.events = {{0, EdgeEventType::kChosen}, {3, EdgeEventType::kCompleted},
              {1, EdgeEventType::kFailed}, {2, EdgeEventType::kChosen}};
  c.stats.episodes = 3;
  c.stats.return_sum = 12.25;
  c.stats.length_sum = 40;
  c.stats.completions_sum = 5;
  c.stats.outcomes = {1, 0, 2};
  return c;
}

void ExpectSameContribution(const Contribution& got, const Contribution& want) {
  const UnrollBatch& g = got.batch;
  const UnrollBatch& w = want.batch;
  EXPECT_EQ(g.num_unrolls, w.num_unrolls);
  EXPECT_EQ(g.unroll_length, w.unroll_length);
  EXPECT_EQ(g.obs_dim, w.obs_dim);
  EXPECT_EQ(g.act_dim, w.act_dim);
  EXPECT_EQ(g.obs, w.obs);
  EXPECT_EQ(g.actions, w.actions);
  EXPECT_EQ(g.log_probs, w.log_probs);
  EXPECT_EQ(g.rewards, w.rewards);
  EXPECT_EQ(g.done, w.done);
  EXPECT_EQ(g.truncated, w.truncated);
  EXPECT_EQ(g.truncated_obs, w.truncated_obs);
  EXPECT_EQ(g.bootstrap_obs, w.bootstrap_obs);
  EXPECT_EQ(g.policy_version, w.policy_version);
  EXPECT_EQ(got.node, want.node);
  EXPECT_EQ(got.events, want.events);
  EXPECT_EQ(got.stats.episodes, want.stats.episodes);
  EXPECT_EQ(got.stats.return_sum, want.stats.return_sum);
  EXPECT_EQ(got.stats.length_sum, want.stats.length_sum);
  EXPECT_EQ(got.stats.completions_sum, want.stats.completions_sum);
  EXPECT_EQ(got.stats.outcomes, want.stats.outcomes);
  EXPECT_EQ(g.labelled, w.labelled);
  EXPECT_EQ(g.labels, w.labels);
  EXPECT_EQ(g.expert_driven, w.expert_driven);
  EXPECT_EQ(got.expert_stats.episodes, want.expert_stats.episodes);
  EXPECT_EQ(got.expert_stats.juggles_sum, want.expert_stats.juggles_sum);
  EXPECT_EQ(got.expert_stats.length_sum, want.expert_stats.length_sum);
  EXPECT_EQ(got.expert_cost.labels, want.expert_cost.labels);
  EXPECT_EQ(got.expert_cost.replans, want.expert_cost.replans);
  EXPECT_EQ(got.expert_cost.rollout_steps, want.expert_cost.rollout_steps);
  EXPECT_EQ(got.expert_cost.rescues, want.expert_cost.rescues);
  EXPECT_EQ(got.expert_cost.proposal_tried, want.expert_cost.proposal_tried);
  EXPECT_EQ(got.expert_cost.proposal_chosen, want.expert_cost.proposal_chosen);
  EXPECT_EQ(got.expert_cost.proposal_weight_sum, want.expert_cost.proposal_weight_sum);
}

// RandomContribution with expert labels: unrolls 0 (expert-driven), 2 and 3 labelled.
Contribution LabelledContribution() {
  Contribution c = RandomContribution();
  UnrollBatch& b = c.batch;
  b.labelled = {1, 0, 1, 1, 0};
  b.expert_driven = {1, 0, 0, 0, 0};
  std::mt19937 rng(777);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  b.labels.resize(size_t(3) * kT * kA);
  for (float& x : b.labels) x = uni(rng);
  b.labels[5] = std::numeric_limits<float>::denorm_min();  // bit-exact, even the odd values
  b.labels[6] = -0.0f;
  c.expert_stats.episodes = 2;
  c.expert_stats.juggles_sum = 31;
  c.expert_stats.length_sum = 900;
  c.expert_cost = {.labels = 3 * kT, .replans = 40, .rollout_steps = 9000, .rescues = 3,
                   .proposal_tried = 39, .proposal_chosen = 7, .proposal_weight_sum = 12.5};
  return c;
}

Contribution DecodeAll(const std::vector<rpc::TrajectoryChunk>& chunks) {
  Contribution all;
  for (const rpc::TrajectoryChunk& ch : chunks) {
    absl::StatusOr<Contribution> part = DecodeChunk(ch, kD, kA, kNodes, kEdges);
    EXPECT_TRUE(part.ok()) << "part " << ch.part() << ": " << part.status();
    if (part.ok()) AppendContribution(&all, *part);
  }
  return all;
}

TEST(ChunkCodecTest, RoundTripInSeveralPartsReproducesTheContribution) {
  const Contribution c = RandomContribution();
  // Two unrolls per chunk: parts of 2, 2 and 1 unrolls, each holding a truncated unroll.
  const std::vector<rpc::TrajectoryChunk> chunks =
      EncodeContribution(c, kIncarnation, 9, 2 * kUnrollBytes);
  ASSERT_EQ(chunks.size(), 3u);
  const int unrolls[] = {2, 2, 1};
  const int truncated[] = {1, 2, 1};
  for (int p = 0; p < 3; ++p) {
    const rpc::TrajectoryChunk& ch = chunks[p];
    EXPECT_EQ(ch.incarnation(), kIncarnation);
    EXPECT_EQ(ch.sequence(), 9);
    EXPECT_EQ(ch.policy_version(), kVersion);
    EXPECT_EQ(ch.part(), p);
    EXPECT_EQ(ch.num_parts(), 3);
    EXPECT_EQ(ch.num_unrolls(), unrolls[p]);
    EXPECT_EQ(ch.truncated_obs_size(), truncated[p] * kD) << "part " << p;
  }
  // Events and statistics travel with the last part only.
  EXPECT_EQ(chunks[0].edge_events().edge_size(), 0);
  EXPECT_EQ(chunks[0].episodes(), 0);
  EXPECT_EQ(chunks[2].edge_events().edge_size(), 4);
  EXPECT_EQ(chunks[2].episodes(), 3);
  ExpectSameContribution(DecodeAll(chunks), c);
}

TEST(ChunkCodecTest, RoundTripInOnePartReproducesTheContribution) {
  const Contribution c = RandomContribution();
  const std::vector<rpc::TrajectoryChunk> chunks =
      EncodeContribution(c, kIncarnation, 0, size_t(1) << 20);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0].num_parts(), 1);
  EXPECT_EQ(chunks[0].num_unrolls(), kU);
  ExpectSameContribution(DecodeAll(chunks), c);
}

TEST(ChunkCodecTest, BudgetBelowOneUnrollStillSendsOneUnrollPerPart) {
  const Contribution c = RandomContribution();
  const std::vector<rpc::TrajectoryChunk> chunks = EncodeContribution(c, kIncarnation, 0, 1);
  ASSERT_EQ(chunks.size(), size_t(kU));
  for (const rpc::TrajectoryChunk& ch : chunks) EXPECT_EQ(ch.num_unrolls(), 1);
  ExpectSameContribution(DecodeAll(chunks), c);
}

TEST(ChunkCodecTest, LabelsSurviveTheWireBitExactInSeveralParts) {
  const Contribution c = LabelledContribution();
  ASSERT_TRUE(ValidateUnrollBatch(c.batch, kD, kA, kVersion, 0).ok());
  for (size_t budget : {size_t(1), 2 * kUnrollBytes, size_t(1) << 20}) {
    const std::vector<rpc::TrajectoryChunk> chunks = EncodeContribution(c, kIncarnation, 0, budget);
    const Contribution got = DecodeAll(chunks);
    ExpectSameContribution(got, c);
    // Bit for bit: -0.0 and denormals included.
    ASSERT_EQ(got.batch.labels.size(), c.batch.labels.size());
    EXPECT_EQ(std::memcmp(got.batch.labels.data(), c.batch.labels.data(),
                          c.batch.labels.size() * sizeof(float)), 0);
  }
}

TEST(ChunkCodecTest, PartsWithAndWithoutLabelsAppendToConsistentMasks) {
  Contribution unlabelled = RandomContribution();
  const Contribution labelled = LabelledContribution();
  Contribution all;
  AppendContribution(&all, unlabelled);
  AppendContribution(&all, labelled);
  ASSERT_EQ(all.batch.num_unrolls, 2 * kU);
  EXPECT_EQ(all.batch.labelled, (std::vector<uint8_t>{0, 0, 0, 0, 0, 1, 0, 1, 1, 0}));
  EXPECT_EQ(all.batch.expert_driven, (std::vector<uint8_t>{0, 0, 0, 0, 0, 1, 0, 0, 0, 0}));
  EXPECT_EQ(all.batch.labels, labelled.batch.labels);
  EXPECT_TRUE(ValidateUnrollBatch(all.batch, kD, kA, kVersion, 0).ok());
}

rpc::TrajectoryChunk GoodLabelledChunk() {
  return EncodeContribution(LabelledContribution(), kIncarnation, 0, size_t(1) << 20).at(0);
}

void ExpectInvalid(const rpc::TrajectoryChunk& ch, const std::string& message);

TEST(ChunkCodecTest, RejectsLabelsOfTheWrongSize) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.add_labels(0.5f);
  ExpectInvalid(ch, "'labels' has 55 entries, expected 54 (3 labelled unrolls)");
}

TEST(ChunkCodecTest, RejectsNonFiniteLabel) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.set_labels(7, std::numeric_limits<float>::infinity());
  ExpectInvalid(ch, "'labels' has a non-finite value at index 7");
}

TEST(ChunkCodecTest, RejectsLabelMaskOfTheWrongSize) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.set_labelled(std::string(kU + 1, '\0'));
  ExpectInvalid(ch, "'labelled' has 6 entries, expected 5");
}

TEST(ChunkCodecTest, RejectsLabelFlagOtherThanZeroOrOne) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  std::string mask = ch.labelled();
  mask[1] = 2;
  ch.set_labelled(mask);
  ExpectInvalid(ch, "'labelled' has a flag other than 0 or 1");
}

TEST(ChunkCodecTest, RejectsExpertDrivenUnrollWithoutLabels) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.set_expert_driven(std::string("\0\1\0\0\0", kU));
  ExpectInvalid(ch, "unroll 1 is expert-driven but carries no labels");
}

TEST(ChunkCodecTest, RejectsLabelsWithoutAMask) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.clear_labelled();
  ExpectInvalid(ch, "labels or expert_driven but no labelled mask");
}

TEST(ChunkCodecTest, RejectsNegativeExpertEpisodeCounts) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.set_expert_juggles_sum(-1);
  ExpectInvalid(ch, "episode statistics are invalid");
}

TEST(ChunkCodecTest, RejectsAnExpertCostWithMoreProposalChoicesThanTries) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.mutable_expert_cost()->set_proposal_chosen(ch.expert_cost().proposal_tried() + 1);
  ExpectInvalid(ch, "chunk field 'expert_cost' is invalid");
}

TEST(ChunkCodecTest, RejectsAProposalWeightAboveItsTriesOrNotFinite) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.mutable_expert_cost()->set_proposal_weight_sum(ch.expert_cost().proposal_tried() + 0.5);
  ExpectInvalid(ch, "chunk field 'expert_cost' is invalid");
  ch.mutable_expert_cost()->set_proposal_weight_sum(std::nan(""));
  ExpectInvalid(ch, "chunk field 'expert_cost' is invalid");
}

TEST(ChunkCodecTest, RejectsANegativeExpertCost) {
  rpc::TrajectoryChunk ch = GoodLabelledChunk();
  ch.mutable_expert_cost()->set_rollout_steps(-5);
  ExpectInvalid(ch, "chunk field 'expert_cost' is invalid");
}

TEST(ChunkCodecTest, BatchWithoutExpertUnrollsKeepsTheOthersAndTheirLabels) {
  const Contribution c = LabelledContribution();
  const UnrollBatch& b = c.batch;
  const UnrollBatch s = WithoutExpertUnrolls(b);
  ASSERT_TRUE(ValidateUnrollBatch(s, kD, kA, kVersion, 0).ok());
  ASSERT_EQ(s.num_unrolls, kU - 1);
  // Unrolls 1..4 in order; unroll 0 held one truncated step, so truncated_obs loses one row.
  const size_t T = kT;
  EXPECT_EQ(s.obs, std::vector<float>(b.obs.begin() + T * kD, b.obs.end()));
  EXPECT_EQ(s.rewards, std::vector<float>(b.rewards.begin() + T, b.rewards.end()));
  EXPECT_EQ(s.truncated_obs, std::vector<float>(b.truncated_obs.begin() + kD, b.truncated_obs.end()));
  EXPECT_EQ(s.bootstrap_obs, std::vector<float>(b.bootstrap_obs.begin() + kD, b.bootstrap_obs.end()));
  EXPECT_EQ(s.labelled, (std::vector<uint8_t>{0, 1, 1, 0}));
  // The labels of unrolls 2 and 3 (label rows 1 and 2).
  EXPECT_EQ(s.labels, std::vector<float>(b.labels.begin() + T * kA, b.labels.end()));
  EXPECT_EQ(s.num_labelled(), 2);
}

// One valid single-part chunk to corrupt.
rpc::TrajectoryChunk GoodChunk() {
  return EncodeContribution(RandomContribution(), kIncarnation, 0, size_t(1) << 20).at(0);
}

void ExpectInvalid(const rpc::TrajectoryChunk& ch, const std::string& message) {
  const absl::StatusOr<Contribution> c = DecodeChunk(ch, kD, kA, kNodes, kEdges);
  EXPECT_EQ(c.status().code(), absl::StatusCode::kInvalidArgument) << c.status();
  EXPECT_THAT(std::string(c.status().message()), HasSubstr(message));
}

TEST(ChunkCodecTest, GoodChunkDecodes) {
  EXPECT_TRUE(DecodeChunk(GoodChunk(), kD, kA, kNodes, kEdges).ok());
}

TEST(ChunkCodecTest, RejectsObsDimOtherThanTheLearners) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_obs_dim(kD + 1);
  ExpectInvalid(ch, "obs_dim 8 and act_dim 3; the policy expects 7 and 3");
}

TEST(ChunkCodecTest, RejectsObsOfTheWrongSize) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.mutable_obs()->RemoveLast();
  ExpectInvalid(ch, absl::StrCat("'obs' has ", kU * kT * kD - 1, " entries, expected ",
                                 kU * kT * kD));
}

TEST(ChunkCodecTest, RejectsNanReward) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_rewards(4, std::numeric_limits<float>::quiet_NaN());
  ExpectInvalid(ch, "'rewards' has a non-finite value at index 4");
}

TEST(ChunkCodecTest, RejectsDoneFlagOtherThanZeroOrOne) {
  rpc::TrajectoryChunk ch = GoodChunk();
  (*ch.mutable_done())[5] = 2;
  ExpectInvalid(ch, "flag at step 5 is not 0 or 1");
}

TEST(ChunkCodecTest, RejectsNodeIdBeyondTheGraph) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_node(7, kNodes);
  ExpectInvalid(ch, "unknown node id 3 at step 7 (the graph has 3 nodes)");
}

TEST(ChunkCodecTest, RejectsNegativeNodeId) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_node(2, -1);
  ExpectInvalid(ch, "unknown node id -1 at step 2");
}

TEST(ChunkCodecTest, RejectsNodeArrayOfTheWrongSize) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.mutable_node()->RemoveLast();
  ExpectInvalid(ch, absl::StrCat("'node' has ", kU * kT - 1, " entries, expected ", kU * kT));
}

TEST(ChunkCodecTest, RejectsEdgeEventForAnEdgeOutsideTheGraph) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.mutable_edge_events()->set_edge(1, kEdges);
  ExpectInvalid(ch, "edge event 1 (edge 4, type 1) is outside the graph's 4 edges");
}

TEST(ChunkCodecTest, RejectsEdgeEventOfUnknownType) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.mutable_edge_events()->set_type(2, 3);
  ExpectInvalid(ch, "edge event 2 (edge 1, type 3)");
}

TEST(ChunkCodecTest, RejectsEdgeEventsWithDifferentEdgeAndTypeCounts) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.mutable_edge_events()->add_edge(0);
  ExpectInvalid(ch, "edge_events: edge and type sizes differ");
}

TEST(ChunkCodecTest, RejectsPartNotBelowNumParts) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_num_parts(2);
  ch.set_part(2);
  ExpectInvalid(ch, "chunk part 2 of 2 is invalid");
}

TEST(ChunkCodecTest, RejectsZeroParts) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_num_parts(0);
  ch.set_part(0);
  ExpectInvalid(ch, "chunk part 0 of 0 is invalid");
}

TEST(ChunkCodecTest, RejectsStepBothDoneAndTruncated) {
  rpc::TrajectoryChunk ch = GoodChunk();
  // Step (0, 2) is truncated in RandomContribution.
  (*ch.mutable_done())[2] = 1;
  ExpectInvalid(ch, "step 2 is both done and truncated");
}

TEST(ChunkCodecTest, RejectsNonFiniteEpisodeReturn) {
  rpc::TrajectoryChunk ch = GoodChunk();
  ch.set_episode_return_sum(std::numeric_limits<double>::infinity());
  ExpectInvalid(ch, "chunk episode statistics are invalid");
}

TEST(ChunkCodecTest, AppendAddsEpisodeCountersAndWidensOutcomes) {
  Contribution a, b;
  a.stats.episodes = 1;
  a.stats.outcomes = {1};
  b.stats.episodes = 2;
  b.stats.return_sum = 0.5;
  b.stats.outcomes = {2, 3};
  AppendContribution(&a, b);
  EXPECT_EQ(a.stats.episodes, 3);
  EXPECT_EQ(a.stats.return_sum, 0.5);
  EXPECT_EQ(a.stats.outcomes, (std::vector<int64_t>{3, 3}));
}

}  // namespace
}  // namespace juggle
