// Checkpoint files: round trip, truncation and corruption detection with fallback, and exact
// resumption of training.
#include "learner/checkpoint.h"

#include <cstdio>
#include <fstream>
#include <string>

#include "gmock/gmock.h"
#include "common/testing/temp_dir.h"
#include "gtest/gtest.h"
#include "learner/ppo_trainer.h"
#include "learner/testing/point_mass.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

class CheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir("juggle_ckpt_");
  }
  void TearDown() override { std::system(("rm -rf " + dir_).c_str()); }
  static std::string Slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  static void Spit(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  }
  std::string dir_;
};

TEST_F(CheckpointTest, RoundTripPreservesEverySection) {
  const Sections in = {{"a", "hello"}, {"b", std::string("\0\1\2", 3)}, {"empty", ""}};
  ASSERT_TRUE(WriteCheckpointFile(dir_ + "/x.jglc", in).ok());
  absl::StatusOr<Sections> out = ReadCheckpointFile(dir_ + "/x.jglc");
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(*out, in);
}

TEST_F(CheckpointTest, TruncatedFileIsDataLossNamingTheFile) {
  const std::string path = dir_ + "/x.jglc";
  ASSERT_TRUE(WriteCheckpointFile(path, {{"model", std::string(1000, 'm')}}).ok());
  const std::string bytes = Slurp(path);
  Spit(path, bytes.substr(0, bytes.size() - 10));
  const absl::StatusOr<Sections> out = ReadCheckpointFile(path);
  EXPECT_EQ(out.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(out.status().message(), HasSubstr(path));
  EXPECT_THAT(out.status().message(), HasSubstr("truncated"));
}

TEST_F(CheckpointTest, FlippedByteIsDetectedByTheChecksum) {
  const std::string path = dir_ + "/x.jglc";
  ASSERT_TRUE(WriteCheckpointFile(path, {{"model", std::string(1000, 'm')}}).ok());
  std::string bytes = Slurp(path);
  bytes[bytes.size() / 2] ^= 0x40;
  Spit(path, bytes);
  EXPECT_THAT(ReadCheckpointFile(path).status().message(), HasSubstr("checksum mismatch"));
}

TEST(CheckpointParseTest, ASectionLengthThatWouldWrapThePositionIsDataLoss) {
  // A valid header and checksum around a section claiming 2^64 - 1 bytes.
  std::string payload;
  auto put = [&](auto v) { payload.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
  put(uint32_t{2});
  put(uint32_t{1});
  payload += "a";
  put(~uint64_t{0});
  payload += "xyz";
  std::string file = "JGLCKPT1";
  const uint64_t size = payload.size(), checksum = Fnv1a64(payload);
  file.append(reinterpret_cast<const char*>(&size), 8);
  file.append(reinterpret_cast<const char*>(&checksum), 8);
  file += payload;
  const absl::StatusOr<Sections> s = ParseCheckpoint(file, "hostile.jglc");
  EXPECT_EQ(s.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(std::string(s.status().message()), ::testing::HasSubstr("hostile.jglc: bad section"));
}

TEST_F(CheckpointTest, LoadLatestFallsBackToThePreviousGoodCheckpoint) {
  CheckpointDir ckpts(dir_ + "/ckpts", /*keep=*/3);
  ASSERT_TRUE(ckpts.Save(10, {{"it", "10"}}).ok());
  absl::StatusOr<std::string> newest = ckpts.Save(20, {{"it", "20"}});
  ASSERT_TRUE(newest.ok());
  Spit(*newest, Slurp(*newest).substr(0, 20));  // a crash mid-write would look like this
  absl::StatusOr<CheckpointDir::Loaded> loaded = ckpts.LoadLatest();
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->sections.at("it"), "10");
  ASSERT_EQ(loaded->skipped.size(), 1u);
  EXPECT_THAT(loaded->skipped[0], HasSubstr("ckpt-0000000020"));
}

TEST_F(CheckpointTest, KeepsOnlyTheNewestFew) {
  CheckpointDir ckpts(dir_ + "/ckpts", /*keep=*/2);
  for (int it = 1; it <= 4; ++it) ASSERT_TRUE(ckpts.Save(it, {{"it", "x"}}).ok());
  const std::vector<std::string> files = ckpts.List();
  ASSERT_EQ(files.size(), 2u);
  EXPECT_THAT(files[0], HasSubstr("ckpt-0000000004"));
  EXPECT_THAT(files[1], HasSubstr("ckpt-0000000003"));
}

TEST_F(CheckpointTest, NoCheckpointIsNotFound) {
  EXPECT_EQ(CheckpointDir(dir_ + "/none").LoadLatest().status().code(),
            absl::StatusCode::kNotFound);
}

// The batch of iteration `it`: a deterministic function of the policy and the iteration.
UnrollBatch BatchFor(const PpoTrainer& trainer, int it) {
  std::vector<testing::PointMass> envs;
  for (int i = 0; i < 8; ++i) envs.emplace_back(1000 * it + i);
  Rng rng(it);
  UnrollBatch batch;
  testing::Collect(trainer, &envs, &rng, &batch);
  return batch;
}

TEST_F(CheckpointTest, ResumingHalfwayGivesTheSameParametersAsTrainingStraight) {
  config::PpoConfig ppo = testing::SmallPpo();
  ppo.set_reset_optimizer_each_iteration(false);  // exercise the optimizer state
  ppo.set_normalize_observations(true);           // and the normalizer
  const int kN = 6;
  PpoTrainer straight(testing::SmallModel(), ppo, 2, 2, 17);
  for (int it = 0; it < kN; ++it) ASSERT_TRUE(straight.Update(BatchFor(straight, it)).ok());

  const std::string path = dir_ + "/half.jglc";
  {
    PpoTrainer first(testing::SmallModel(), ppo, 2, 2, 17);
    for (int it = 0; it < kN / 2; ++it) ASSERT_TRUE(first.Update(BatchFor(first, it)).ok());
    ASSERT_TRUE(WriteCheckpointFile(path, first.SaveState()).ok());
  }
  // A fresh process would start from another seed; the checkpoint must override all of it.
  PpoTrainer resumed(testing::SmallModel(), ppo, 2, 2, 99);
  absl::StatusOr<Sections> sections = ReadCheckpointFile(path);
  ASSERT_TRUE(sections.ok());
  ASSERT_TRUE(resumed.RestoreState(*sections).ok());
  EXPECT_EQ(resumed.iteration(), kN / 2);
  for (int it = kN / 2; it < kN; ++it) ASSERT_TRUE(resumed.Update(BatchFor(resumed, it)).ok());

  EXPECT_EQ(resumed.version(), straight.version());
  EXPECT_EQ(resumed.actor_lr(), straight.actor_lr());
  EXPECT_EQ(resumed.ExportAll().values(), straight.ExportAll().values());
  EXPECT_EQ(resumed.ExportPolicy().values(), straight.ExportPolicy().values());
}

TEST_F(CheckpointTest, RestoreRejectsMissingSectionsAndLeavesTheTrainerUnchanged) {
  PpoTrainer trainer(testing::SmallModel(), testing::SmallPpo(), 2, 2, 1);
  const std::vector<float> before = trainer.ExportAll().values();
  Sections s = trainer.SaveState();
  s.erase("model");
  const absl::Status status = trainer.RestoreState(s);
  EXPECT_EQ(status.code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(status.message(), HasSubstr("'model'"));
  EXPECT_EQ(trainer.ExportAll().values(), before);
}

TEST_F(CheckpointTest, RestoreRejectsTheStateOfOtherNetworksAndLeavesTheTrainerUnchanged) {
  config::ModelConfig wider = testing::SmallModel();
  for (int i = 0; i < wider.hidden_size(); ++i) wider.set_hidden(i, 2 * wider.hidden(i));
  const Sections other = PpoTrainer(wider, testing::SmallPpo(), 2, 2, 1).SaveState();
  PpoTrainer trainer(testing::SmallModel(), testing::SmallPpo(), 2, 2, 1);
  const std::vector<float> before = trainer.ExportAll().values();
  const absl::Status status = trainer.RestoreState(other);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(status.message(), HasSubstr("trained under another model config"));
  EXPECT_EQ(trainer.ExportAll().values(), before);
}

}  // namespace
}  // namespace juggle
