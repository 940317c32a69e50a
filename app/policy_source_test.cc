// app/policy_source: policies and checkpoints carry their run config, so what they load does not
// depend on the working folder or on later edits of the config files; older files still load,
// with a note; damaged files are clear errors.
#include "app/policy_source.h"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "common/file_io.h"
#include "common/policy_file.h"
#include "common/testing/temp_dir.h"
#include "common/testing/working_dir.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "learner/testing/untrained_checkpoint.h"

namespace juggle {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

// The shipped right-foot policy (format 2).
constexpr char kShippedPolicy[] = "policies/right_foot/kick_fb_30min.jglpolicy";

// The shipped policy as it was before format 2: the bare protobuf without the model, its config
// naming the model relative to configs/learning/kick_fb.textproto (so it loads from the
// repository root, ctest's folder). Written to <dir>/old.jglpolicy.
std::string WriteOldFormatPolicy(const std::string& dir) {
  absl::StatusOr<PolicyFile> shipped = ReadPolicyFile(kShippedPolicy);
  EXPECT_TRUE(shipped.ok()) << shipped.status();
  config::ExportedPolicy old = shipped.ok() ? shipped->policy : config::ExportedPolicy();
  old.clear_model_mjb();
  old.clear_mujoco_version();
  const std::string path = dir + "/old.jglpolicy";
  EXPECT_TRUE(WriteFile(path, old.SerializeAsString()).ok());
  return path;
}

// The policy's mean actions, every one of them kept.
class RecordingController final : public Controller {
 public:
  RecordingController(std::shared_ptr<const EigenPolicy> policy, int act_dim)
      : policy_(std::move(policy)), act_dim_(act_dim) {}
  void Act(const Env* const* envs, const float* obs, int n, float* actions) override {
    policy_.Act(envs, obs, n, actions);
    actions_.insert(actions_.end(), actions, actions + static_cast<size_t>(n) * act_dim_);
  }
  std::string name() const override { return "recording"; }
  const std::vector<float>& actions() const { return actions_; }

 private:
  PolicyController policy_;
  int act_dim_;
  std::vector<float> actions_;
};

struct Rollout {
  std::vector<float> actions;
  std::vector<double> qpos;
};

// Two seconds of `source`'s policy in its own env from a fixed stream.
Rollout RollOut(const PolicySource& source) {
  RecordingController controller(source.policy, source.spec->act_dim());
  absl::StatusOr<Trajectory> t =
      RecordRollout(source.spec, &controller, 2.0, /*seed=*/1000003, -1, "rollout");
  EXPECT_TRUE(t.ok()) << t.status();
  return {controller.actions(), t.ok() ? t->qpos : std::vector<double>{}};
}

TEST(PolicySourceTest, AnOldFormatPolicyLoadsWithANoteSayingHowToUpgradeIt) {
  const std::string dir = MakeTempDir("juggle_policy_old_");
  const std::string path = WriteOldFormatPolicy(dir);
  absl::StatusOr<PolicySource> source = LoadPolicySource(path, "");
  ASSERT_TRUE(source.ok()) << source.status();
  EXPECT_EQ(source->note,
            "note: " + path +
                " is an old-format policy that names its model relative to "
                "configs/learning/kick_fb.textproto (so it loads only from the folder it was "
                "exported in); re-export it to make it self-contained: juggle export-policy "
                "--checkpoint=" + path + " --out=NEW");
  EXPECT_TRUE(source->config.model_mjb.empty());
  fs::remove_all(dir);
}

TEST(PolicySourceTest, TheShippedPolicyIsSelfContained) {
  absl::StatusOr<PolicySource> source = LoadPolicySource(kShippedPolicy, "");
  ASSERT_TRUE(source.ok()) << source.status();
  EXPECT_EQ(source->note, "");
  EXPECT_FALSE(source->config.model_mjb.empty());
}

TEST(PolicySourceTest, AnExportedPolicyMovedElsewhereActsBitIdentically) {
  const std::string old_dir = MakeTempDir("juggle_policy_old_");
  absl::StatusOr<PolicySource> old = LoadPolicySource(WriteOldFormatPolicy(old_dir), "");
  ASSERT_TRUE(old.ok()) << old.status();
  const Rollout before_export = RollOut(*old);
  ASSERT_GT(before_export.actions.size(), 1000u);

  const std::string first = MakeTempDir("juggle_policy_first_");
  ASSERT_TRUE(WritePolicyFile(first + "/p.jglpolicy", ExportPolicySource(*old)).ok());
  absl::StatusOr<PolicySource> exported = LoadPolicySource(first + "/p.jglpolicy", "");
  ASSERT_TRUE(exported.ok()) << exported.status();
  EXPECT_EQ(exported->note, "");
  EXPECT_FALSE(exported->config.model_mjb.empty());
  EXPECT_EQ(exported->config.config_path, "configs/learning/kick_fb.textproto");
  const Rollout before_move = RollOut(*exported);

  // Moved, and loaded with the working folder somewhere without configs or models.
  const std::string second = MakeTempDir("juggle_policy_second_");
  const std::string empty = MakeTempDir("juggle_policy_cwd_");
  fs::copy(first + "/p.jglpolicy", second + "/moved.jglpolicy");
  fs::remove_all(first);
  ScopedWorkingDir cd(empty);
  absl::StatusOr<PolicySource> moved = LoadPolicySource(second + "/moved.jglpolicy", "");
  ASSERT_TRUE(moved.ok()) << moved.status();
  const Rollout after_move = RollOut(*moved);

  EXPECT_TRUE(after_move.actions == before_move.actions);
  EXPECT_TRUE(after_move.qpos == before_move.qpos);
  // The upgrade itself changed nothing either.
  EXPECT_TRUE(before_move.actions == before_export.actions);
  EXPECT_TRUE(before_move.qpos == before_export.qpos);
  fs::remove_all(second);
  fs::remove_all(empty);
  fs::remove_all(old_dir);
}

TEST(PolicySourceTest, ADamagedPolicyFileIsAnErrorNamingIt) {
  absl::StatusOr<PolicySource> old = LoadPolicySource(kShippedPolicy, "");
  ASSERT_TRUE(old.ok()) << old.status();
  const std::string dir = MakeTempDir("juggle_policy_damaged_");
  const std::string path = dir + "/p.jglpolicy";
  const config::ExportedPolicy policy = ExportPolicySource(*old);
  const std::string bytes = SerializePolicyFile(policy);

  ASSERT_TRUE(WriteFile(path, bytes.substr(0, bytes.size() / 2)).ok());
  absl::StatusOr<PolicySource> truncated = LoadPolicySource(path, "");
  EXPECT_EQ(truncated.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(std::string(truncated.status().message()),
              StartsWith(path + ": exported policy truncated"));

  std::string flipped = bytes;
  flipped[flipped.size() / 3] ^= 0x01;
  ASSERT_TRUE(WriteFile(path, flipped).ok());
  EXPECT_EQ(LoadPolicySource(path, "").status().message(),
            path + ": exported policy corrupted: checksum mismatch");

  // A well-formed file whose model MuJoCo cannot read.
  config::ExportedPolicy garbage_model = policy;
  garbage_model.set_model_mjb(std::string(4096, '\x7f'));
  ASSERT_TRUE(WritePolicyFile(path, garbage_model).ok());
  absl::StatusOr<PolicySource> unreadable = LoadPolicySource(path, "");
  EXPECT_EQ(unreadable.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(unreadable.status().message(), path + ": cannot load the compiled model");
  fs::remove_all(dir);
}

// A run folder with one checkpoint of an untrained policy under <dir>/cfg.textproto (seed
// 4242, 32-unit layers).
class CheckpointConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir("juggle_ckpt_config_");
    config_path_ = dir_ + "/cfg.textproto";
    WriteConfig(4242, 32);
    sections_ = testing::WriteUntrainedCheckpoint(config_path_, dir_);
    ASSERT_FALSE(sections_.empty());
    checkpoint_ = dir_ + "/checkpoints/ckpt-0000000001.jglc";
  }
  void TearDown() override { fs::remove_all(dir_); }
  void WriteConfig(int seed, int hidden) { testing::WriteSmallConfig(config_path_, seed, hidden); }

  std::string dir_, config_path_, checkpoint_;
  Sections sections_;
};

TEST_F(CheckpointConfigTest, ACheckpointLoadsItsStoredConfigAfterTheFileIsEdited) {
  WriteConfig(/*seed=*/1, /*hidden=*/64);  // other networks: the policy would not fit
  absl::StatusOr<PolicySource> source = LoadPolicySource(checkpoint_, "");
  ASSERT_TRUE(source.ok()) << source.status();
  EXPECT_EQ(source->config.run.seed(), 4242u);
  EXPECT_EQ(source->config.run.model().hidden(0), 32);
  EXPECT_EQ(source->config.config_path, config_path_);
  EXPECT_EQ(source->note, "");
  // And from the run folder, after the config is gone.
  fs::remove(config_path_);
  absl::StatusOr<PolicySource> from_run = LoadPolicySource(dir_, "");
  ASSERT_TRUE(from_run.ok()) << from_run.status();
  EXPECT_EQ(from_run->config.run.seed(), 4242u);
}

TEST_F(CheckpointConfigTest, AnOldFormatCheckpointReadsItsConfigFileWithANote) {
  Sections old = sections_;
  old.erase("model_mjb");
  ASSERT_TRUE(WriteCheckpointFile(checkpoint_, old).ok());
  WriteConfig(/*seed=*/1, /*hidden=*/32);
  absl::StatusOr<PolicySource> source = LoadPolicySource(checkpoint_, "");
  ASSERT_TRUE(source.ok()) << source.status();
  EXPECT_EQ(source->config.run.seed(), 1u) << "as before stored models: the file as it is now";
  EXPECT_THAT(source->note, HasSubstr(checkpoint_ + " is an old-format checkpoint that names " +
                                      config_path_ + " by path"));
}

TEST_F(CheckpointConfigTest, AnExplicitConfigStillReplacesTheStoredOne) {
  WriteConfig(/*seed=*/99, /*hidden=*/32);
  absl::StatusOr<PolicySource> source = LoadPolicySource(checkpoint_, config_path_);
  ASSERT_TRUE(source.ok()) << source.status();
  EXPECT_EQ(source->config.run.seed(), 99u);
}

}  // namespace
}  // namespace juggle
