// Loading soccer-juggling configs: every bad graph or env section fails with a message that
// names the file, the line (and column) and the offending field; the shipped configs load.
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "google/protobuf/text_format.h"
#include "google/protobuf/util/message_differencer.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kFile[] = "test.textproto";

std::string Loc(const std::string& text, const std::string& needle, int occurrence = 0) {
  return ::juggle::testing::Loc(kFile, text, needle, occurrence);
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

// A RunConfig with the given inline graph body; `extra` goes inside soccer_juggle after it.
std::string WithGraph(const std::string& body, const std::string& extra = "") {
  return absl::StrCat("name: \"t\"\n", "soccer_juggle {\n", "graph {\n", body, "}\n", extra,
                      "}\n");
}

// The smallest valid graph: down <-> up.
std::string ValidBody() {
  return Node("down", "DOWN", "initial: true") + Node("up", "UP") + Edge("down", "up") +
         Edge("up", "down");
}

TEST(SoccerJuggleConfigTest, ValidInlineGraphLoads) {
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(WithGraph(ValidBody()), kFile);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->graph->num_nodes(), 2);
  EXPECT_EQ(loaded->graph->num_edges(), 2);
  EXPECT_EQ(loaded->config_path, kFile);
}

// Removed levers (docs/learning.md, "Removed levers"): their field numbers are reserved and
// their names are not, so an old config that still sets one fails at its line, naming it.
TEST(SoccerJuggleConfigTest, RemovedLeverFieldsFailAtTheirLineNamingTheField) {
  struct Removed {
    std::string setting, field;
  };
  const std::vector<Removed> removed = {
      {"action_mode: PD_TARGET_OFFSET", "action_mode"},
      {"ball_assist { kp: 20 kd: 4 }", "ball_assist"},
      {"start { recorded_start_fraction: 0.3 }", "recorded_start_fraction"},
      {"start { recorded_start_capacity: 64 }", "recorded_start_capacity"},
      {"start { recorded_start_min_juggles: 1 }", "recorded_start_min_juggles"}};
  for (const Removed& r : removed) {
    const std::string text = WithGraph(ValidBody(), absl::StrCat("env {\n", r.setting, "\n}\n"));
    const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
    ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument) << r.field;
    EXPECT_THAT(std::string(loaded.status().message()), StartsWith(LineOf(text, r.field)));
    EXPECT_THAT(std::string(loaded.status().message()),
                HasSubstr(absl::StrCat("has no field named \"", r.field, "\"")));
  }
}

TEST(SoccerJuggleConfigTest, UnknownFieldIsATextFormatErrorAtItsLine) {
  const std::string text =
      WithGraph(Node("down", "DOWN", "initial: true colour: \"red\"") + Node("up", "UP") +
                Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()), StartsWith(LineOf(text, "colour")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("Message type \"juggle.config.NodeSpec\" has no field named \"colour\""));
}

TEST(SoccerJuggleConfigTest, EdgeFromUnknownNodeNamesTheFromField) {
  const std::string text = WithGraph(ValidBody() + Edge("nowhere", "up"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "from: \"nowhere\""), ": edge[2].from: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("unknown node 'nowhere'"));
}

TEST(SoccerJuggleConfigTest, EdgeToUnknownNodeNamesTheToField) {
  const std::string text = WithGraph(ValidBody() + Edge("up", "nowhere"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "to: \"nowhere\""), ": edge[2].to: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("unknown node 'nowhere'"));
}

TEST(SoccerJuggleConfigTest, EdgeToAMissingNodeListsTheNodesThatExist) {
  // A typo of an existing node: the message lists the real names to pick from.
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Edge("down", "upp") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "to: \"upp\""), ": edge[0].to: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("unknown node 'upp' (nodes: down, up)"));
}

TEST(SoccerJuggleConfigTest, NodeWithoutOutgoingEdgeIsReportedAtItsName) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Node("lonely", "DOWN") + Edge("down", "up") +
                                     Edge("up", "down") + Edge("up", "lonely"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "name: \"lonely\""), ": node[2].name: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("node 'lonely' has no outgoing edge"));
}

TEST(SoccerJuggleConfigTest, ZeroEdgeWeightIsRejectedAtTheWeightField) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Edge("down", "up") + Edge("up", "down", "weight: 0"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "weight: 0"), ": edge[1].weight: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("edge weight must be > 0, got 0"));
}

TEST(SoccerJuggleConfigTest, NegativeEdgeWeightIsRejectedAtTheWeightField) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Edge("down", "up", "weight: -2.5") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "weight: -2.5"), ": edge[0].weight: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("edge weight must be > 0, got -2.5"));
}

TEST(SoccerJuggleConfigTest, NonFiniteOrAbsurdApexHeightIsRejectedAtItsLine) {
  for (const std::string value : {"nan", "inf", "-inf", "1e300"}) {
    SCOPED_TRACE(value);
    const std::string text =
        WithGraph(Node("down", "DOWN", "initial: true") +
                  Node("up", "UP", "", "contact_height: 0.5 apex_height: " + value) +
                  Edge("down", "up") + Edge("up", "down"));
    const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
    ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(std::string(loaded.status().message()),
                StartsWith(absl::StrCat(Loc(text, "apex_height: " + value),
                                        ": soccer_juggle.graph.node[1].apex_height: ")));
    EXPECT_THAT(std::string(loaded.status().message()),
                HasSubstr(value == "1e300" ? "is outside [0.05, 20] m" : "is not a finite number"));
  }
}

TEST(SoccerJuggleConfigTest, EnvCountBeyondItsLimitSaysHowMuchMemoryItWouldNeed) {
  const std::string text = WithGraph(ValidBody()) + "sampling { num_envs: 50000000 }\n";
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "num_envs: 50000000"), ": sampling.num_envs: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("50000000 is outside [1, 4096] (50000000 would need about 139698 GiB of memory)"));
}

TEST(SoccerJuggleConfigTest, StanceChangeLeanBeyondItsRangeIsRefusedAtTheField) {
  const std::string text = WithGraph(ValidBody(), "env { stance_change { lean: 0.5 } }\n");
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "lean: 0.5"),
                                      ": soccer_juggle.env.stance_change.lean: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("is outside [0, 0.3] m"));
}

TEST(SoccerJuggleConfigTest, FloatWithoutADeclaredRangeIsStillBounded) {
  const std::string text =
      WithGraph(ValidBody(), "env { reward { w_position: 1e300 } }\n");
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("soccer_juggle.env.reward.w_position: 1e+300 is beyond ±1000000, the bound of "
                        "fields without a declared range"));
}

TEST(SoccerJuggleConfigTest, ApexHeightBelowContactHeightIsRejected) {
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

TEST(SoccerJuggleConfigTest, ApexHeightEqualToContactHeightIsRejected) {
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

TEST(SoccerJuggleConfigTest, MissingApexHeightIsRejectedAtTheNode) {
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

TEST(SoccerJuggleConfigTest, ApexRangeMinimumAtOrBelowContactHeightIsRejectedAtMin) {
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

TEST(SoccerJuggleConfigTest, MissingStageIsReportedAtTheNode) {
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

TEST(SoccerJuggleConfigTest, DuplicateNodeNameIsReportedAtTheSecondName) {
  const std::string text = WithGraph(Node("down", "DOWN", "initial: true") + Node("up", "UP") +
                                     Node("down", "DOWN") + Edge("down", "up") +
                                     Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "name: \"down\"", 1), ": node[2].name: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("duplicate node name 'down'"));
}

TEST(SoccerJuggleConfigTest, DuplicateEdgeIsReportedAtTheSecondEdge) {
  const std::string text = WithGraph(ValidBody() + Edge("up", "down", "weight: 2"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "edge {", 2), ": edge[2]: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("duplicate edge up -> down"));
}

TEST(SoccerJuggleConfigTest, NodeUnreachableFromEveryInitialNodeIsReportedAtItsName) {
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

TEST(SoccerJuggleConfigTest, InitialNodeThatIsNotDownIsRejectedAtInitial) {
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

TEST(SoccerJuggleConfigTest, InitialStallNodeIsRejectedAtInitial) {
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

TEST(SoccerJuggleConfigTest, GraphWithoutInitialNodeIsRejected) {
  const std::string text = WithGraph(Node("down", "DOWN") + Node("up", "UP") +
                                     Edge("down", "up") + Edge("up", "down"));
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "node {"), ": node: ")));
  EXPECT_THAT(std::string(loaded.status().message()), HasSubstr("no node is marked 'initial: true'"));
}

TEST(SoccerJuggleConfigTest, UpToUpEdgeIsStageInconsistent) {
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

TEST(SoccerJuggleConfigTest, GraphAndGraphFileBothSetIsRejectedAtGraphFile) {
  const std::string text =
      WithGraph(ValidBody(), "graph_file: \"graphs/right_foot.textproto\"\n");
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(Loc(text, "graph_file"), ": graph_file: ")));
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("exactly one of 'graph' (inline) or 'graph_file' must be set"));
}

TEST(SoccerJuggleConfigTest, NeitherGraphNorGraphFileIsRejectedNamingTheGraphField) {
  // Nothing to point at: the message names the section and the missing field.
  const absl::StatusOr<LoadedConfig> loaded =
      ParseRunConfig("name: \"t\"\nsoccer_juggle {\n}\n", kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            "test.textproto:2:1: graph: exactly one of 'graph' (inline) or 'graph_file' must be "
            "set");
}

TEST(SoccerJuggleConfigTest, MissingGraphFileIsNotFoundAtTheGraphFileField) {
  const std::string text =
      "name: \"t\"\nsoccer_juggle {\n  graph_file: \"graphs/no_such_graph.textproto\"\n}\n";
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, "some/dir/test.textproto");
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith("some/dir/test.textproto:3:3: graph_file: "));
  // Relative to the config's folder.
  EXPECT_THAT(std::string(loaded.status().message()),
              HasSubstr("some/dir/graphs/no_such_graph.textproto: cannot open file"));
}

TEST(SoccerJuggleConfigTest, ErrorInAGraphFileNamesTheGraphFileAndItsLine) {
  const std::string graph = ValidBody() + Edge("down", "up", "weight: 0");
  const std::string graph_path = WriteTemp("bad_graph.textproto", graph);
  const std::string config_path = WriteTemp(
      "uses_bad_graph.textproto",
      "name: \"t\"\nsoccer_juggle { graph_file: \"bad_graph.textproto\" }\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  // Loc() renders "test.textproto:L:C"; the graph file's name replaces it.
  const std::string loc = Loc(graph, "weight: 0", 0);
  EXPECT_THAT(std::string(loaded.status().message()),
              StartsWith(absl::StrCat(graph_path, loc.substr(loc.find(':')), ": edge[2]")));
}

TEST(SoccerJuggleConfigTest, GraphFileResolvesAgainstTheConfigFolder) {
  const std::string graph_path = WriteTemp("good_graph.textproto", ValidBody());
  const std::string config_path = WriteTemp(
      "uses_good_graph.textproto",
      "name: \"t\"\nsoccer_juggle { graph_file: \"good_graph.textproto\" }\n");
  const absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(config_path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->graph->num_nodes(), 2);
  EXPECT_EQ(loaded->graph_locator.file(), graph_path);
  EXPECT_TRUE(loaded->run.soccer_juggle().has_graph());  // read into the inline graph
  EXPECT_FALSE(loaded->run.soccer_juggle().has_graph_file());
}

TEST(SoccerJuggleConfigTest, ErrorInsideTheEnvSectionNamesItsField) {
  const std::string text = WithGraph(ValidBody(), "env {\n  substeps: 0\n}\n");
  const absl::StatusOr<LoadedConfig> loaded = ParseRunConfig(text, kFile);
  ASSERT_EQ(loaded.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(loaded.status().message(),
            absl::StrCat(Loc(text, "substeps"), ": soccer_juggle.env.substeps: 0 is outside [1, 1000]"));
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
  EXPECT_TRUE(loaded->run.soccer_juggle().has_graph());
}

INSTANTIATE_TEST_SUITE_P(
    AllShipped, ShippedConfigTest,
    ::testing::Values(ShippedConfig{"configs/right_foot.textproto", "right_foot", 2, 2, 1},
                      ShippedConfig{"configs/right_foot_paper.textproto", "right_foot_paper", 2, 2, 1},
                      ShippedConfig{"configs/right_foot_recipe.textproto", "right_foot_recipe", 2, 2, 1},
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
  // The edges the reference implementation left commented out (configs/graphs/full.textproto
  // lists them) and the chest stall's way in and out.
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

// graphs/full_planner.textproto was assembled by hand: each node's section says where it came
// from ("# from graphs/X.textproto", "# the release node (graphs/full.textproto)"). A node taken
// as it is must still equal its source's node of the same name (`initial` aside: the full
// graph's initial nodes are the release's), so that a change to a skill's graph cannot leave
// the full graph behind unnoticed; the edges must be the release's. The
// mirrored nodes and around-the-world's (the release's with declared variables) are not
// compared field by field here.
config::ControlGraph ParseGraphFile(const std::string& relative, std::string* text = nullptr) {
  std::ifstream in(RepoPath(relative));
  std::stringstream buffer;
  buffer << in.rdbuf();
  config::ControlGraph graph;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(buffer.str(), &graph)) << relative;
  if (text != nullptr) *text = buffer.str();
  return graph;
}

const config::NodeSpec* FindNode(const config::ControlGraph& graph, const std::string& name) {
  for (const config::NodeSpec& node : graph.node()) {
    if (node.name() == name) return &node;
  }
  return nullptr;
}

TEST(FullPlannerGraphTest, NodesTakenAsTheyAreEqualTheirSourcesAndTheEdgesAreTheReleases) {
  std::string text;
  const config::ControlGraph full = ParseGraphFile("configs/graphs/full_planner.textproto", &text);
  const config::ControlGraph release = ParseGraphFile("configs/graphs/full.textproto");
  ASSERT_EQ(full.node_size(), release.node_size());
  // Each "# ---- release node N: NAME" section's first "from"/"the release node" line.
  const std::string marker = "# ---- release node ";
  int compared = 0;
  for (size_t at = text.find(marker); at != std::string::npos;) {
    const size_t next = text.find(marker, at + 1);
    const std::string section = text.substr(at, next == std::string::npos ? next : next - at);
    at = next;
    const size_t colon = section.find(": ");
    const std::string name = section.substr(colon + 2, section.find('\n') - colon - 2);
    const config::NodeSpec* node = FindNode(full, name);
    ASSERT_NE(node, nullptr) << name;
    std::string source;
    if (section.find("\n# the release node (graphs/full.textproto)") != std::string::npos) {
      source = "configs/graphs/full.textproto";
    } else if (const size_t from = section.find("\n# from graphs/"); from != std::string::npos) {
      const std::string line = section.substr(from + 8, section.find('\n', from + 1) - from - 8);
      if (line.find("mirrored") != std::string::npos) continue;
      source = "configs/" + line;
    } else {
      continue;  // around-the-world: the release's nodes with declared variables
    }
    const config::ControlGraph source_graph = ParseGraphFile(source);
    const config::NodeSpec* original = FindNode(source_graph, name);
    ASSERT_NE(original, nullptr) << name << " is not in " << source;
    // `initial` is the release's in the full graph, whatever the source graph starts from.
    config::NodeSpec taken = *node, from = *original;
    taken.clear_initial();
    from.clear_initial();
    EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(taken, from))
        << name << " differs from its source " << source << ":\n"
        << taken.DebugString() << "against\n" << from.DebugString();
    ++compared;
  }
  EXPECT_EQ(compared, 15);  // of the 23: 4 mirrored, 4 around-the-world
  ASSERT_EQ(full.edge_size(), release.edge_size());
  auto edges = [](const config::ControlGraph& graph) {
    std::multiset<std::string> all;
    for (const config::EdgeSpec& e : graph.edge()) {
      all.insert(absl::StrCat(e.from(), " -> ", e.to(), " ", e.weight()));
    }
    return all;
  };
  EXPECT_EQ(edges(full), edges(release));
}

}  // namespace
}  // namespace juggle::soccer_juggle
