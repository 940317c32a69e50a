// Loading toss-juggling configs: recorded start states and partner policies are inlined for the
// workers; bad ones fail naming the file, line and field.
#include <string>

#include "common/policy_file.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::toss {
namespace {

using ::juggle::testing::WriteTemp;
using ::testing::HasSubstr;

TEST(TossConfigTest, StartStatesFileIsInlinedIntoTheTossConfig) {
  WriteTemp("arm_states.textproto",
            "state { angle: [0, 1, -2, 0.5] speed: [0, 3, -4, 1] }\n"
            "state { angle: [0, 0.9, -1.5, 0] speed: [0, 0, 0, 0] }\n");
  const std::string config_path = WriteTemp(
      "uses_arm_states.textproto",
      "toss {\n  task: CATCH\n  start_states_file: \"arm_states.textproto\"\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  const config::TossConfig& toss = loaded->run.toss();
  EXPECT_FALSE(toss.has_start_states_file()) << "workers receive the states inline";
  ASSERT_EQ(toss.start_state_size(), 2);
  EXPECT_EQ(toss.start_state(0).angle(2), -2);
  EXPECT_EQ(toss.start_state(0).speed(1), 3);
  EXPECT_EQ(toss.start_state(1).angle(1), 0.9);
}

TEST(TossConfigTest, StartStateWithoutFourJointsIsAnErrorNamingTheState) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: THROW\n  start_state { angle: [0, 1, -2, 0] speed: [0, 0, 0, 0] }\n"
      "  start_state { angle: [1, -2, 0] speed: [0, 0, 0] }\n}\n",
      "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:3"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("start state 1 has 3 angles"));
}

TEST(TossConfigTest, MissingStartStatesFileIsNotFoundNamingTheField) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: CATCH\n  start_states_file: \"no_such_states.textproto\"\n}\n",
      "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:3"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("no_such_states.textproto"));
}

TEST(TossConfigTest, KeepingNoCheckpointsIsAnErrorNamingTheField) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: CATCH\n}\nservice {\n  keep_checkpoints: 0\n}\n", "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:5"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("keep_checkpoints"));
}

TEST(TossConfigTest, LoopPolicyFilesAreInlinedForTheWorkers) {
  config::ExportedPolicy policy;
  policy.set_obs_dim(12);
  policy.set_act_dim(4);
  policy.set_parameters("JGLP-bytes");
  WriteTemp("partner.jglpolicy", policy.SerializeAsString());
  const std::string config_path = WriteTemp(
      "uses_partners.textproto",
      "toss {\n  task: THROW\n  loop {\n    pattern: \"3\"\n"
      "    catch_policy_file: \"partner.jglpolicy\"\n"
      "    throw_policy_file: \"partner.jglpolicy\"\n  }\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  const config::TossLoopConfig& loop = loaded->run.toss().loop();
  EXPECT_FALSE(loop.has_catch_policy_file());
  EXPECT_FALSE(loop.has_throw_policy_file());
  EXPECT_EQ(loop.catch_policy().parameters(), "JGLP-bytes");
  EXPECT_EQ(loop.throw_policy().obs_dim(), 12);
}

TEST(TossConfigTest, SelfContainedPartnerFilesAreInlinedWithoutTheirModel) {
  config::ExportedPolicy policy;
  policy.set_obs_dim(12);
  policy.set_act_dim(4);
  policy.set_parameters("JGLP-bytes");
  policy.set_run_config("toss { task: CATCH }\n");
  policy.set_model_mjb("compiled model bytes");
  policy.set_mujoco_version(222);
  WriteTemp("partner2.jglpolicy", SerializePolicyFile(policy));
  const std::string config_path = WriteTemp(
      "uses_format2_partners.textproto",
      "toss {\n  task: THROW\n  loop {\n    pattern: \"3\"\n"
      "    catch_policy_file: \"partner2.jglpolicy\"\n"
      "    throw_policy_file: \"partner2.jglpolicy\"\n  }\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  const config::ExportedPolicy& inlined = loaded->run.toss().loop().catch_policy();
  EXPECT_EQ(inlined.parameters(), "JGLP-bytes");
  EXPECT_EQ(inlined.run_config(), "toss { task: CATCH }\n");
  EXPECT_FALSE(inlined.has_model_mjb()) << "the loop runs partners in its own model";
  EXPECT_FALSE(inlined.has_mujoco_version());
}

TEST(TossConfigTest, MissingLoopPolicyFileIsNotFoundNamingTheLineAndTheExportCommand) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: THROW\n  loop {\n    pattern: \"3\"\n"
      "    catch_policy_file: \"no_such.jglpolicy\"\n  }\n}\n",
      "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:5"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("juggle export-policy"));
}

TEST(TossConfigTest, LoopWithoutAThrowPartnerIsAnErrorNamingTheField) {
  config::ExportedPolicy policy;
  policy.set_parameters("x");
  WriteTemp("catch_only.jglpolicy", policy.SerializeAsString());
  const std::string config_path = WriteTemp(
      "one_partner.textproto",
      "toss {\n  task: THROW\n  loop {\n    pattern: \"3\"\n"
      "    catch_policy_file: \"catch_only.jglpolicy\"\n  }\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("throw_policy_file"));
}

TEST(TossConfigTest, LoopWithoutPartnersNeedsTheBaseControllersAndNamesThem) {
  const std::string bare = WriteTemp(
      "no_partners.textproto", "toss {\n  task: CATCH\n  loop {\n    pattern: \"3\"\n  }\n}\n");
  const absl::StatusOr<LoadedConfig> refused = LoadRunConfig(bare);
  ASSERT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("toss.base"));
  const std::string with_base = WriteTemp(
      "base_partners.textproto",
      "toss {\n  task: CATCH\n  base {}\n  loop {\n    pattern: \"3\"\n  }\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(with_base);
  // The base controllers stand in (envs/toss/residual_loop_test.cc runs such a loop).
  EXPECT_TRUE(loaded.ok()) << loaded.status();
}

TEST(TossConfigTest, LoopPolicyFileThatIsNotAnExportIsAnErrorNamingFileAndLine) {
  WriteTemp("not_a_policy.jglpolicy", "state { angle: [0, 1, -2, 0.5] }\n");
  const std::string config_path = WriteTemp(
      "bad_partner.textproto",
      "toss {\n  task: CATCH\n  loop {\n    pattern: \"3\"\n"
      "    catch_policy_file: \"not_a_policy.jglpolicy\"\n"
      "    throw_policy_file: \"not_a_policy.jglpolicy\"\n  }\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("bad_partner.textproto:5"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("juggle export-policy"));
}

TEST(TossConfigTest, TossConfigWithAGraphOrWithoutATaskIsRejected) {
  absl::StatusOr<LoadedConfig> with_graph =
      ParseRunConfig("toss { task: THROW }\ngraph_file: \"g.textproto\"\n", "c.textproto");
  ASSERT_FALSE(with_graph.ok());
  EXPECT_NE(with_graph.status().message().find("c.textproto:2:1"), std::string::npos)
      << with_graph.status();
  absl::StatusOr<LoadedConfig> no_task = ParseRunConfig("toss { kp: 1000 }\n", "c.textproto");
  ASSERT_FALSE(no_task.ok());
  EXPECT_NE(no_task.status().message().find("task"), std::string::npos) << no_task.status();
}

TEST(TossConfigTest, NegativeStartSpeedNoiseIsAnErrorNamingFileLineAndField) {
  absl::StatusOr<LoadedConfig> config =
      ParseRunConfig("toss {\n  task: CATCH\n  start_speed_noise: -1\n}\n", "c.textproto");
  ASSERT_FALSE(config.ok());
  EXPECT_NE(config.status().message().find("c.textproto:3"), std::string::npos) << config.status();
  EXPECT_NE(config.status().message().find("start_speed_noise"), std::string::npos);
}

}  // namespace
}  // namespace juggle::toss
