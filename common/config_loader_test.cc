// Config loading: every bad config fails with a message that names the file, the line (and
// column) and the offending field; the shipped configs load.
#include "common/config_loader.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kFile[] = "test.textproto";

// "test.textproto:<line>:<column>" of the `occurrence`-th (0-based) appearance of `needle` in
// `text`, 1-based like the loader's messages. Fails the test if there is no such appearance.
std::string Loc(const std::string& text, const std::string& needle, int occurrence = 0) {
  size_t pos = std::string::npos;
  size_t from = 0;
  for (int i = 0; i <= occurrence; ++i) {
    pos = text.find(needle, from);
    if (pos == std::string::npos) {
      ADD_FAILURE() << "'" << needle << "' occurs fewer than " << occurrence + 1 << " times";
      return "<missing>";
    }
    from = pos + 1;
  }
  int line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < pos; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return absl::StrCat(kFile, ":", line, ":", pos - line_start + 1);
}

// "test.textproto:<line>:" of `needle` (for errors whose column is not the field's start).
std::string LineOf(const std::string& text, const std::string& needle) {
  const std::string loc = Loc(text, needle);
  return loc.substr(0, loc.rfind(':') + 1);
}

// A node with the fields every stage needs. `fields` is appended inside the node; `heights`
// replaces the contact/apex line. An empty `stage` leaves the stage out.
std::string Node(const std::string& name, const std::string& stage, const std::string& fields = "",
                 const std::string& heights = "contact_height: 0.5 apex_height: 1.4") {
  return absl::StrCat("  node {\n",
                      "    name: \"", name, "\"\n",
                      stage.empty() ? "" : absl::StrCat("    stage: ", stage, "\n"),
                      "    contact_body: \"right_ankle\"\n",
                      "    ", heights, "\n",
                      "    pose { leg_swing { side: RIGHT } }\n",
                      fields.empty() ? "" : absl::StrCat("    ", fields, "\n"),
                      "  }\n");
}

std::string Edge(const std::string& from, const std::string& to, const std::string& extra = "") {
  return absl::StrCat("  edge { from: \"", from, "\" to: \"", to, "\"",
                      extra.empty() ? "" : absl::StrCat(" ", extra), " }\n");
}

// A RunConfig with the given inline graph body.
std::string WithGraph(const std::string& body) {
  return absl::StrCat("name: \"t\"\n", "graph {\n", body, "}\n");
}

// The smallest valid graph: down <-> up.
std::string ValidBody() {
  return Node("down", "DOWN", "initial: true") + Node("up", "UP") + Edge("down", "up") +
         Edge("up", "down");
}

std::string RepoPath(const std::string& relative) {
  const char* root = std::getenv("JUGGLE_SOURCE_DIR");
  return root != nullptr ? absl::StrCat(root, "/", relative) : relative;
}

TEST(ConfigLoaderTest, ValidInlineGraphLoads) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(WithGraph(ValidBody()), kFile);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->graph->num_nodes(), 2);
  EXPECT_EQ(loaded->graph->num_edges(), 2);
  EXPECT_EQ(loaded->config_path, kFile);
}

TEST(ConfigLoaderTest, UnknownFieldIsATextFormatErrorAtItsLine) {
  const std::string text =
      WithGraph(Node("down", "DOWN", "initial: true colour: \"red\"") + Node("up", "UP") +
                Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), StartsWith(LineOf(text, "colour")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("Message type \"juggle.config.NodeSpec\" has no field named \"colour\""));
}

TEST(ConfigLoaderTest, EdgeFromUnknownNodeNamesTheFromField) {
  const std::string text = WithGraph(ValidBody() + Edge("nowhere", "up"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "from: \"nowhere\""), ": edge[2].from: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("unknown node 'nowhere'"));
}

TEST(ConfigLoaderTest, EdgeToUnknownNodeNamesTheToField) {
  const std::string text = WithGraph(ValidBody() + Edge("up", "nowhere"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "to: \"nowhere\""), ": edge[2].to: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("unknown node 'nowhere'"));
}

TEST(ConfigLoaderTest, EdgeToAMissingNodeListsTheNodesThatExist) {
  // A typo of an existing node: the message lists the real names to pick from.
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Edge("down", "upp") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "to: \"upp\""), ": edge[0].to: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("unknown node 'upp' (nodes: down, up)"));
}

TEST(ConfigLoaderTest, NodeWithoutOutgoingEdgeIsReportedAtItsName) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Node("lonely", "DOWN") + Edge("down", "up") +
                                     Edge("up", "down") + Edge("up", "lonely"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "name: \"lonely\""), ": node[2].name: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("node 'lonely' has no outgoing edge"));
}

TEST(ConfigLoaderTest, ZeroEdgeWeightIsRejectedAtTheWeightField) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Edge("down", "up") + Edge("up", "down", "weight: 0"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "weight: 0"), ": edge[1].weight: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("edge weight must be > 0, got 0"));
}

TEST(ConfigLoaderTest, NegativeEdgeWeightIsRejectedAtTheWeightField) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Edge("down", "up", "weight: -2.5") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "weight: -2.5"), ": edge[0].weight: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("edge weight must be > 0, got -2.5"));
}

TEST(ConfigLoaderTest, ApexHeightBelowContactHeightIsRejected) {
  const std::string text =
      WithGraph(Node("down", "DOWN", "initial: true") +
                Node("up", "UP", "", "contact_height: 0.5 apex_height: 0.4") +
                Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "apex_height: 0.4"), ": node[1].apex_height: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("node 'up': apex_height 0.4 must exceed contact_height 0.5"));
}

TEST(ConfigLoaderTest, ApexHeightEqualToContactHeightIsRejected) {
  const std::string text =
      WithGraph(Node("down", "DOWN", "initial: true", "contact_height: 1.6 apex_height: 1.6") +
                Node("up", "UP") + Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "apex_height: 1.6"), ": node[0].apex_height: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("node 'down': apex_height 1.6 must exceed contact_height 1.6"));
}

TEST(ConfigLoaderTest, MissingApexHeightIsRejectedAtTheNode) {
  // No apex at all: the field is absent, so the message points at the node.
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") +
                                     Node("up", "UP", "", "contact_height: 0.5") +
                                     Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "node {", 1), ": node[1].apex_height: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("must exceed contact_height 0.5"));
}

TEST(ConfigLoaderTest, ApexRangeMinimumAtOrBelowContactHeightIsRejectedAtMin) {
  const std::string text = WithGraph(
      Node("down", "DOWN", "initial: true") +
      Node("up", "UP", "", "contact_height: 0.5 apex_height_range { min: 0.5 max: 2.0 }") +
      Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "min: 0.5"), ": node[1].apex_height_range.min: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("apex height 0.5 must exceed contact_height 0.5"));
}

TEST(ConfigLoaderTest, MissingStageIsReportedAtTheNode) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "") +
                                     Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  // The stage field is absent, so the location is the node's own.
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "node {", 1), ": node[1].stage: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("node 'up' needs a stage (DOWN, UP or STALL)"));
}

TEST(ConfigLoaderTest, DuplicateNodeNameIsReportedAtTheSecondName) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Node("down", "DOWN") + Edge("down", "up") +
                                     Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "name: \"down\"", 1), ": node[2].name: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("duplicate node name 'down'"));
}

TEST(ConfigLoaderTest, DuplicateEdgeIsReportedAtTheSecondEdge) {
  const std::string text = WithGraph(ValidBody() + Edge("up", "down", "weight: 2"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "edge {", 2), ": edge[2]: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("duplicate edge up -> down"));
}

TEST(ConfigLoaderTest, NodeUnreachableFromEveryInitialNodeIsReportedAtItsName) {
  // island_down <-> island_up have edges but no initial node leads to them.
  const std::string text = WithGraph(ValidBody() + Node("island_down", "DOWN") +
                                     Node("island_up", "UP") + Edge("island_down", "island_up") +
                                     Edge("island_up", "island_down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "name: \"island_down\""), ": node[2].name: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("node 'island_down' is unreachable from every initial node"));
}

TEST(ConfigLoaderTest, InitialNodeThatIsNotDownIsRejectedAtInitial) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") +
                                     Node("up", "UP", "initial: true") + Edge("down", "up") +
                                     Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "initial: true", 1), ": node[1].initial: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("node 'up' is not a DOWN node and cannot start an episode"));
}

TEST(ConfigLoaderTest, InitialStallNodeIsRejectedAtInitial) {
  const std::string text = WithGraph(
      Node("down", "DOWN", "initial: true") +
      Node("stall", "STALL", "initial: true stall { body: \"right_ankle\" }") +
      Node("up", "UP") + Edge("down", "stall") + Edge("stall", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "initial: true", 1), ": node[1].initial: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("node 'stall' is not a DOWN node"));
}

TEST(ConfigLoaderTest, GraphWithoutInitialNodeIsRejected) {
  const std::string text = WithGraph(Node("down", "DOWN") + Node("up", "UP") +
                                     Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "node {"), ": node: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("no node is marked 'initial: true'"));
}

TEST(ConfigLoaderTest, UpToUpEdgeIsStageInconsistent) {
  const std::string text = WithGraph(ValidBody() + Node("up2", "UP") + Edge("up", "up2") +
                                     Edge("up2", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "edge {", 2), ": edge[2]: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("edge up -> up2 joins UP to UP; allowed: DOWN->UP|STALL, UP->DOWN, "
                        "STALL->STALL|UP"));
}

TEST(ConfigLoaderTest, GraphAndGraphFileBothSetIsRejectedAtGraphFile) {
  const std::string text = WithGraph(ValidBody()) + "graph_file: \"graphs/right_foot.textproto\"\n";
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "graph_file"), ": graph_file: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("exactly one of 'graph' (inline) or 'graph_file' must be set"));
}

TEST(ConfigLoaderTest, NeitherGraphNorGraphFileIsRejectedNamingTheGraphField) {
  // Nothing to point at: the message names the file and the missing field.
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig("name: \"t\"\nseed: 3\n", kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            "test.textproto: graph: exactly one of 'graph' (inline) or 'graph_file' must be set");
}

TEST(ConfigLoaderTest, MissingGraphFileIsNotFoundAtTheGraphFileField) {
  const std::string text = "name: \"t\"\ngraph_file: \"graphs/no_such_graph.textproto\"\n";
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, "some/dir/test.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()), StartsWith("some/dir/test.textproto:2:1: graph_file: "));
  // Relative to the config's folder.
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("some/dir/graphs/no_such_graph.textproto: cannot open file"));
}

TEST(ConfigLoaderTest, MissingConfigFileIsNotFound) {
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig("no/such/config.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(loaded.status().message(), "no/such/config.textproto: cannot open file");
}

// Writes `text` to a fresh file under the test's temp dir; returns its path.
std::string WriteTemp(const std::string& name, const std::string& text) {
  std::string dir = ::testing::TempDir();
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const std::string path = absl::StrCat(dir, "/", name);
  std::ofstream(path) << text;
  return path;
}

TEST(ConfigLoaderTest, StartStatesFileIsInlinedIntoTheTossConfig) {
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

TEST(ConfigLoaderTest, StartStateWithoutFourJointsIsAnErrorNamingTheState) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: THROW\n  start_state { angle: [0, 1, -2, 0] speed: [0, 0, 0, 0] }\n"
      "  start_state { angle: [1, -2, 0] speed: [0, 0, 0] }\n}\n",
      "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:3"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("start state 1 has 3 angles"));
}

TEST(ConfigLoaderTest, MissingStartStatesFileIsNotFoundNamingTheField) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: CATCH\n  start_states_file: \"no_such_states.textproto\"\n}\n",
      "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:3"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("no_such_states.textproto"));
}

TEST(ConfigLoaderTest, KeepingNoCheckpointsIsAnErrorNamingTheField) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: CATCH\n}\nservice {\n  keep_checkpoints: 0\n}\n", "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:5"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("keep_checkpoints"));
}

TEST(ConfigLoaderTest, LoopPolicyFilesAreInlinedForTheWorkers) {
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

TEST(ConfigLoaderTest, MissingLoopPolicyFileIsNotFoundNamingTheLineAndTheExportCommand) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(
      "toss {\n  task: THROW\n  loop {\n    pattern: \"3\"\n"
      "    catch_policy_file: \"no_such.jglpolicy\"\n  }\n}\n",
      "c.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("c.textproto:5"));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("juggle export-policy"));
}

TEST(ConfigLoaderTest, LoopWithoutAThrowPartnerIsAnErrorNamingTheField) {
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

TEST(ConfigLoaderTest, LoopPolicyFileThatIsNotAnExportIsAnErrorNamingFileAndLine) {
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

TEST(ConfigLoaderTest, ErrorInAGraphFileNamesTheGraphFileAndItsLine) {
  const std::string graph = ValidBody() + Edge("down", "up", "weight: 0");
  const std::string graph_path = WriteTemp("bad_graph.textproto", graph);
  const std::string config_path = WriteTemp(
      "uses_bad_graph.textproto", "name: \"t\"\ngraph_file: \"bad_graph.textproto\"\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  // Loc() renders "test.textproto:L:C"; the graph file's name replaces it.
  const std::string loc = Loc(graph, "weight: 0", 0);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(graph_path, loc.substr(loc.find(':')), ": edge[2]")));
}

TEST(ConfigLoaderTest, GraphFileResolvesAgainstTheConfigFolder) {
  const std::string graph_path = WriteTemp("good_graph.textproto", ValidBody());
  const std::string config_path = WriteTemp(
      "uses_good_graph.textproto", "name: \"t\"\ngraph_file: \"good_graph.textproto\"\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->graph->num_nodes(), 2);
  EXPECT_EQ(loaded->graph_locator.file(), graph_path);
  EXPECT_TRUE(loaded->run.has_graph());  // resolved into run.graph
}

TEST(ConfigLoaderTest, ErrorInsideTheEnvSectionNamesItsField) {
  const std::string text = WithGraph(ValidBody()) + "env {\n  substeps: 0\n}\n";
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            absl::StrCat(Loc(text, "substeps"), ": substeps: must be >= 1"));
}

// ---- The shipped configs ----------------------------------------------------------------

struct ShippedConfig {
  const char* file;
  const char* name;
  int nodes;
  int edges;
  int initial;
};

class ShippedConfigTest : public ::testing::TestWithParam<ShippedConfig> {};

TEST_P(ShippedConfigTest, LoadsWithTheExpectedGraphSize) {
  const ShippedConfig& c = GetParam();
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(RepoPath(c.file));
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->run.name(), c.name);
  EXPECT_EQ(loaded->graph->num_nodes(), c.nodes);
  EXPECT_EQ(loaded->graph->num_edges(), c.edges);
  EXPECT_EQ(static_cast<int>(loaded->graph->initial_nodes().size()), c.initial);
  EXPECT_TRUE(loaded->run.has_graph_file());
}

INSTANTIATE_TEST_SUITE_P(
    AllShipped, ShippedConfigTest,
    ::testing::Values(ShippedConfig{"configs/right_foot.textproto", "right_foot", 2, 2, 1},
                      ShippedConfig{"configs/foot_and_atw.textproto", "foot_and_atw", 4, 6, 2},
                      ShippedConfig{"configs/foot_and_head.textproto", "foot_and_head", 4, 6, 2},
                      ShippedConfig{"configs/full.textproto", "full", 23, 62, 8},
                      ShippedConfig{"configs/foot_variable_height.textproto",
                                    "foot_variable_height", 2, 2, 1}),
    [](const ::testing::TestParamInfo<ShippedConfig>& info) { return std::string(info.param.name); });

TEST(ShippedFullGraphTest, HasEveryReleaseNodeInReleaseOrderWithTheRightStage) {
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(RepoPath("configs/full.textproto"));
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  const ControlGraph& g = *loaded->graph;
  using config::DOWN;
  using config::STALL;
  using config::UP;
  const std::vector<std::pair<std::string, config::Stage>> expected = {
      {"left_foot_down", DOWN},     {"left_foot_up", UP},
      {"left_atw_up", UP},          {"left_atw_down", DOWN},
      {"left_foot_stall", STALL},   {"left_foot_stall_exit", STALL},
      {"chest_stall", STALL},       {"chest_up", UP},
      {"chest_down", DOWN},         {"head_down", DOWN},
      {"head_up", UP},              {"head_stall", STALL},
      {"head_stall_exit", STALL},   {"left_knee_down", DOWN},
      {"left_knee_up", UP},         {"right_foot_down", DOWN},
      {"right_foot_up", UP},        {"right_knee_down", DOWN},
      {"right_knee_up", UP},        {"right_atw_down", DOWN},
      {"right_atw_up", UP},         {"right_foot_stall", STALL},
      {"right_foot_stall_exit", STALL}};
  ASSERT_EQ(g.num_nodes(), static_cast<int>(expected.size()));
  for (int i = 0; i < g.num_nodes(); ++i) {
    EXPECT_EQ(g.node(i).name, expected[i].first) << "release node " << i;
    EXPECT_EQ(g.node(i).stage, expected[i].second) << g.node(i).name;
    // Exactly the DOWN nodes start episodes.
    EXPECT_EQ(g.node(i).initial, expected[i].second == DOWN) << g.node(i).name;
  }
}

TEST(ShippedFullGraphTest, StallSelfLoopsWeigh30AndTheOnceDisabledEdgesExist) {
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(RepoPath("configs/full.textproto"));
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  const ControlGraph& g = *loaded->graph;
  auto edge = [&](const std::string& from, const std::string& to) -> std::optional<int> {
    const std::optional<int> a = g.FindNode(from), b = g.FindNode(to);
    if (!a || !b) return std::nullopt;
    return g.FindEdge(*a, *b);
  };
  for (const char* stall : {"left_foot_stall", "right_foot_stall", "head_stall", "chest_stall"}) {
    const std::optional<int> e = edge(stall, stall);
    ASSERT_TRUE(e.has_value()) << stall;
    EXPECT_EQ(g.edge(*e).base_weight, 30.0) << stall;
  }
  // The release's commented-out edges (reference-juggle.md §1.3) and the chest stall's way in
  // and out.
  const std::vector<std::pair<std::string, std::string>> enabled = {
      {"left_foot_down", "left_foot_stall"}, {"left_foot_up", "chest_down"},
      {"chest_up", "left_knee_down"},        {"chest_up", "right_knee_down"},
      {"head_down", "head_stall"},           {"left_knee_up", "chest_down"},
      {"right_foot_down", "right_foot_stall"}, {"right_foot_up", "chest_down"},
      {"right_knee_up", "chest_down"},       {"chest_down", "chest_stall"},
      {"chest_stall", "chest_up"}};
  for (const auto& [from, to] : enabled) {
    EXPECT_TRUE(edge(from, to).has_value()) << from << " -> " << to;
  }
}

}  // namespace
}  // namespace juggle
