// app/learner_flags: a resumed run continues under the config stored in its newest checkpoint,
// whatever has happened to the config file since, unless --config names another (today's
// behaviour, now with a note when it differs).
#include "app/learner_flags.h"

#include <filesystem>
#include <string>

#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "learner/testing/untrained_checkpoint.h"

namespace juggle {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class ResumeConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = MakeTempDir("juggle_resume_config_");
    config_path_ = dir_ + "/cfg.textproto";
    testing::WriteSmallConfig(config_path_, /*seed=*/4242, /*hidden=*/32);
    ASSERT_FALSE(testing::WriteUntrainedCheckpoint(config_path_, dir_).empty());
    flags_.run_dir = dir_;
    flags_.resume = true;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string dir_, config_path_;
  LearnerFlags flags_;
};

TEST_F(ResumeConfigTest, WithoutConfigTheStoredCopyIsUsedAfterTheFileIsEditedOrDeleted) {
  testing::WriteSmallConfig(config_path_, /*seed=*/1, /*hidden=*/64);
  absl::StatusOr<LearnerOptions> edited = MakeLearnerOptions(flags_);
  ASSERT_TRUE(edited.ok()) << edited.status();
  EXPECT_EQ(edited->config.run.seed(), 4242u);
  EXPECT_EQ(edited->config.run.model().hidden(0), 32);
  EXPECT_FALSE(edited->config.model_mjb.empty());
  EXPECT_EQ(edited->config.config_path, config_path_);
  EXPECT_TRUE(edited->resume);

  fs::remove(config_path_);
  absl::StatusOr<LearnerOptions> deleted = MakeLearnerOptions(flags_);
  ASSERT_TRUE(deleted.ok()) << deleted.status();
  EXPECT_EQ(deleted->config.run.seed(), 4242u);
}

TEST_F(ResumeConfigTest, AnExplicitDifferentConfigIsUsedWithANote) {
  testing::WriteSmallConfig(config_path_, /*seed=*/5, /*hidden=*/32);
  flags_.config = config_path_;
  ::testing::internal::CaptureStderr();
  absl::StatusOr<LearnerOptions> o = MakeLearnerOptions(flags_);
  const std::string err = ::testing::internal::GetCapturedStderr();
  ASSERT_TRUE(o.ok()) << o.status();
  EXPECT_EQ(o->config.run.seed(), 5u);
  EXPECT_TRUE(o->config.model_mjb.empty()) << "compiled from the MJCF, as before";
  EXPECT_THAT(err, HasSubstr("note: --config=" + config_path_ +
                             " differs from the run config stored in " + dir_ +
                             "/checkpoints/ckpt-0000000001.jglc (its settings)"));
}

TEST_F(ResumeConfigTest, AnExplicitUnchangedConfigGivesNoNote) {
  flags_.config = config_path_;
  ::testing::internal::CaptureStderr();
  absl::StatusOr<LearnerOptions> o = MakeLearnerOptions(flags_);
  const std::string err = ::testing::internal::GetCapturedStderr();
  ASSERT_TRUE(o.ok()) << o.status();
  EXPECT_EQ(o->config.run.seed(), 4242u);
  EXPECT_EQ(err, "");
}

}  // namespace
}  // namespace juggle
