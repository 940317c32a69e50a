// Loading run configs through the family registry: the shared checks and the choice of family.
#include <string>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

TEST(LoadConfigTest, MissingConfigFileIsNotFound) {
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig("no/such/config.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(loaded.status().message(),
            "no/such/config.textproto: cannot open file (No such file or directory)");
}

TEST(LoadConfigTest, ConfigWithoutAFamilyNamesEveryFamily) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig("name: \"t\"\nseed: 3\n", "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            "c.textproto: the config sets no environment family; set exactly one of: "
            "soccer_juggle, toss, football");
}

TEST(LoadConfigTest, TwoFamiliesAreATextFormatErrorAtTheSecond) {
  const std::string text = "soccer_juggle {\n}\ntoss {\n  task: CATCH\n}\n";
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:3:"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("oneof"));
}

TEST(LoadConfigTest, ADirectoryGivenAsTheConfigSaysSo) {
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(::testing::TempDir());
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("is a directory, not a config file"));
}

TEST(LoadConfigTest, EveryFamilyIsListedOnceWithItsOwnConfigCase) {
  std::vector<int> cases;
  for (const EnvFamily* family : AllFamilies()) {
    EXPECT_EQ(std::count(cases.begin(), cases.end(), family->config_case()), 0) << family->name();
    cases.push_back(family->config_case());
    // The name is the oneof field's name.
    const auto* field = config::RunConfig::descriptor()->FindFieldByNumber(family->config_case());
    ASSERT_NE(field, nullptr) << family->name();
    EXPECT_EQ(field->name(), family->name());
  }
  EXPECT_EQ(static_cast<int>(cases.size()),
            config::RunConfig::descriptor()->FindOneofByName("family")->field_count());
}

}  // namespace
}  // namespace juggle
