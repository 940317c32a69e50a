// Run configs composed with base_config (common/config_merge.h): a derived config is its base
// plus its differences, errors name the file that set the field, cycles are refused, and the
// base's file names keep naming its files.
#include <string>

#include "common/config_merge.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::testing::HasSubstr;
using ::testing::StartsWith;
using testing::Loc;
using testing::RepoPath;
using testing::WriteTemp;

TEST(BaseConfigTest, ADerivedConfigIsItsBasePlusItsDifferences) {
  const std::string base = RepoPath("tests/data/tiny_right_foot.textproto");
  const std::string derived = WriteTemp("derived.textproto", absl::StrCat(
      "base_config: \"", base, "\"\n"
      "name: \"derived\"\n"
      "model { hidden: 64 }\n"                      // a repeated field: replaces [32, 32]
      "ppo { epochs: 3 }\n"                         // one field of a message
      "soccer_juggle { env { carry_phase: true } }\n"));
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(derived);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  absl::StatusOr<LoadedConfig> expected = LoadRunConfig(base);
  ASSERT_TRUE(expected.ok()) << expected.status();
  expected->run.set_name("derived");
  expected->run.mutable_model()->clear_hidden();
  expected->run.mutable_model()->add_hidden(64);
  expected->run.mutable_ppo()->set_epochs(3);
  expected->run.mutable_soccer_juggle()->mutable_env()->set_carry_phase(true);
  // Everything else — seed, sampling, service, the graph, the model file — is the base's.
  config::RunConfig got = loaded->run, want = expected->run;
  RebaseFileNames(loaded->config_dir, expected->config_dir, &got);
  EXPECT_TRUE(MessageDifferencer::Equals(got, want))
      << got.ShortDebugString() << "\nvs\n" << want.ShortDebugString();
  EXPECT_FALSE(loaded->run.has_base_config());
  EXPECT_EQ(loaded->graph->num_nodes(), expected->graph->num_nodes());
}

TEST(BaseConfigTest, AnErrorInAFieldTheBaseSetNamesTheBaseFile) {
  const std::string base_text =
      "name: \"base\"\n"
      "soccer_juggle {\n"
      "  graph_file: \"no_such_graph.textproto\"\n"
      "}\n";
  const std::string base = WriteTemp("broken_base.textproto", base_text);
  const std::string derived = WriteTemp(
      "on_broken_base.textproto",
      "base_config: \"broken_base.textproto\"\nsoccer_juggle { env { carry_phase: true } }\n");
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(derived);
  ASSERT_FALSE(loaded.ok());
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(Loc(base, base_text, "graph_file") + ": graph_file"));

  // The same field set by the derived file: the derived file is named.
  const std::string fix_text =
      "base_config: \"broken_base.textproto\"\n"
      "soccer_juggle { graph_file: \"also_missing.textproto\" }\n";
  const std::string fix = WriteTemp("overrides_base.textproto", fix_text);
  loaded = LoadRunConfig(fix);
  ASSERT_FALSE(loaded.ok());
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(Loc(fix, fix_text, "graph_file") + ": graph_file"));
}

TEST(BaseConfigTest, ARangeErrorInTheBaseNamesTheBaseFile) {
  const std::string base_text = "name: \"b\"\nsampling { num_envs: 0 }\n";
  const std::string base = WriteTemp("range_base.textproto", base_text);
  const std::string derived =
      WriteTemp("range_derived.textproto", "base_config: \"range_base.textproto\"\nseed: 2\n");
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(derived);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), StartsWith(Loc(base, base_text, "num_envs")));
}

TEST(BaseConfigTest, ACycleOfBasesIsRefusedNamingTheChain) {
  const std::string a = WriteTemp("cycle_a.textproto", "base_config: \"cycle_b.textproto\"\n");
  const std::string b_text = "name: \"b\"\nbase_config: \"cycle_a.textproto\"\n";
  const std::string b = WriteTemp("cycle_b.textproto", b_text);
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(a);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            absl::StrCat(Loc(b, b_text, "base_config"), ": base_config: a cycle of bases: ", a,
                         " -> ", b, " -> ", a));
}

TEST(BaseConfigTest, AMissingBaseIsNotFoundAtTheLineThatNamesIt) {
  const std::string text = "name: \"x\"\nbase_config: \"nowhere.textproto\"\n";
  const std::string derived = WriteTemp("missing_base.textproto", text);
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(derived);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(Loc(derived, text, "base_config") + ": base_config: "));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("nowhere.textproto: cannot open file"));
}

}  // namespace
}  // namespace juggle
