// Kick variables declared per node (NodeSpec.kick_variable): resolved to the named joint axes
// at load time, a bad declaration a config error naming the node and the field at its line,
// applied by the plan to exactly those axes, and the shipped header set reproduced by its
// declaration; a graph whose consecutive nodes' variables move different joints needs a kick
// set per cycle.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "common/adaptive_walk.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "planner/planner_config.h"
#include "planner/soccer_juggle/plan.h"
#include "planner/soccer_juggle/task.h"

namespace juggle::planner {
namespace {

using ::juggle::testing::LoadRightFootPlannerWithGraph;
using ::juggle::testing::SoccerSpecWithGraph;

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using ::testing::HasSubstr;

// Two nodes (down <-> up) of `pose`, each with `variables` inside the node.
std::string Graph(const std::string& pose, const std::string& variables,
                  const std::string& contact = "contact_body: \"neck\" contact_height: 1.75 "
                                               "apex_height: 2.0 ball_target { x: 0.08 y: 0 }") {
  auto node = [&](const std::string& name, const std::string& stage, const std::string& extra) {
    return absl::StrCat("node {\n  name: \"", name, "\"\n  stage: ", stage, "\n", extra, "  ",
                        contact, "\n  pose { ", pose, " }\n", variables, "}\n");
  };
  return node("down", "DOWN", "  initial: true\n") + node("up", "UP", "") +
         "edge { from: \"down\" to: \"up\" }\nedge { from: \"up\" to: \"down\" }\n";
}

// The plan's action `steps` control steps (zero action) into the first node, for `kick`'s
// five variables on top of a zero prior.
std::vector<float> KickActionAt(const std::shared_ptr<const JuggleSpec>& spec,
                                const std::vector<double>& kick, int steps) {
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(7));
  env.ResetAt(0, walk);
  const float zero[kNumActions] = {0};
  for (int t = 0; t < steps; ++t) env.Step(zero, walk);
  config::PlannerConfig config;
  config.set_body_knot_steps(0);
  const SoccerPlanLayout layout = MakeSoccerPlanLayout(config, config.soccer_juggle().kick());
  std::vector<float> action(kNumActions);
  SoccerPlanAction(env, layout, kick.data(), PlanClock{}, action.data());
  return action;
}

constexpr char kHeader[] = "head_dip { amplitude: 0.5 }";
// The built-in header set (plan.cc KickReferences) as a declaration.
constexpr char kHeaderSetDeclared[] =
    "  kick_variable { move { joint: \"chest\" axis: \"z\" } }\n"
    "  kick_variable { move { joint: \"neck\" axis: \"z\" } }\n"
    "  kick_variable { move { joint: \"chest\" axis: \"x\" } move { joint: \"neck\" axis: \"x\" } }\n"
    "  kick_variable { move { joint: \"right_knee\" } move { joint: \"left_knee\" } }\n";

TEST(NodeKickVariablesTest, DeclaredJointsResolveToTheirJointsAxesAndGains) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(Graph(
      kHeader, "  kick_variable { move { joint: \"neck\" axis: \"x\" gain: -0.5 } "
               "move { joint: \"left_knee\" } }\n"));
  ASSERT_TRUE(spec.ok()) << spec.status();
  const auto& variables = (*spec)->node_runtime(0).kick_variables;
  ASSERT_EQ(variables.size(), 1u);
  ASSERT_EQ(variables[0].size(), 2u);
  EXPECT_EQ(variables[0][0].joint, soccer_juggle::kNeck);
  EXPECT_EQ(variables[0][0].axis, 0);
  EXPECT_EQ(variables[0][0].gain, -0.5);
  EXPECT_EQ(variables[0][1].joint, soccer_juggle::kLeftKnee);
  EXPECT_EQ(variables[0][1].gain, 1.0);
}

TEST(NodeKickVariablesTest, TheDeclaredHeaderSetActsExactlyAsTheBuiltInOne) {
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> built_in =
      SoccerSpecWithGraph(Graph(kHeader, ""));
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> declared =
      SoccerSpecWithGraph(Graph(kHeader, kHeaderSetDeclared));
  ASSERT_TRUE(built_in.ok()) << built_in.status();
  ASSERT_TRUE(declared.ok()) << declared.status();
  const std::vector<double> kick = {0.02, 0.1, -0.2, 0.15, 0.3};
  const std::vector<float> a = KickActionAt(*built_in, kick, 20);
  const std::vector<float> b = KickActionAt(*declared, kick, 20);
  EXPECT_EQ(a, b);
  double moved = 0;
  for (float x : a) moved += std::abs(x);
  EXPECT_GT(moved, 0.05) << "the kick must move something for the comparison to mean anything";
}

TEST(NodeKickVariablesTest, ADeclaredVariableMovesOnlyItsAxisAndUndeclaredOnesNothing) {
  // A leg swing whose one declared variable is the kicking hip's roll: its amplitudes stay.
  const std::string swing = "leg_swing { side: RIGHT profile: RAISED_COSINE }";
  const std::string foot = "contact_body: \"right_ankle\" contact_height: 0.5 apex_height: 1.4 "
                           "ball_target { x: 0.6 y: -0.1 }";
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(
      Graph(swing, "  kick_variable { move { joint: \"right_hip\" axis: \"x\" } }\n", foot));
  ASSERT_TRUE(spec.ok()) << spec.status();
  google::protobuf::RepeatedPtrField<std::string> names;
  names.Add("right_hip:x");
  const int hip_roll = BodyActionIndices(names)->at(0);

  const std::vector<float> moved = KickActionAt(*spec, {0, 0.2, 0, 0, 0}, 20);
  for (int i = 0; i < kNumActions; ++i) {
    if (i == hip_roll) {
      EXPECT_GT(std::abs(moved[i]), 0.01) << "the declared axis moves";
    } else {
      EXPECT_NEAR(moved[i], 0.0f, 1e-9) << "action " << i << " moved";  // rounding only
    }
  }
  // The variables the node does not declare (and the swing amplitudes they would otherwise
  // change) move nothing.
  const std::vector<float> undeclared = KickActionAt(*spec, {0, 0, 0.3, -0.3, 0.3}, 20);
  for (int i = 0; i < kNumActions; ++i) EXPECT_NEAR(undeclared[i], 0.0f, 1e-9) << "action " << i;
  // The timing still shifts the swing.
  const std::vector<float> timed = KickActionAt(*spec, {0.05, 0, 0, 0, 0}, 20);
  double shift = 0;
  for (float x : timed) shift += std::abs(x);
  EXPECT_GT(shift, 0.01);
}

TEST(NodeKickVariablesTest, ASpeedVariableMovesItsAxisByTheRateEnvelopeZeroAtTheContact) {
  // The knee (a hinge: its action is linear in the angle) declared once with the position
  // envelope sin²(πφ) and once with the speed one −sin(2πφ)/(2π): at every step the two
  // actions stand in the ratio of the envelopes at the env's phase.
  const std::string swing = "leg_swing { side: RIGHT profile: RAISED_COSINE }";
  const std::string foot = "contact_body: \"right_ankle\" contact_height: 0.5 apex_height: 1.4 "
                           "ball_target { x: 0.6 y: -0.1 }";
  auto spec_with = [&](const std::string& envelope) {
    return SoccerSpecWithGraph(Graph(
        swing, absl::StrCat("  kick_variable { move { joint: \"right_knee\" } ", envelope, " }\n"),
        foot));
  };
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> position = spec_with("");
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> speed = spec_with("envelope: SPEED");
  ASSERT_TRUE(position.ok()) << position.status();
  ASSERT_TRUE(speed.ok()) << speed.status();
  EXPECT_FALSE((*position)->node_runtime(0).kick_variables[0][0].speed);
  EXPECT_TRUE((*speed)->node_runtime(0).kick_variables[0][0].speed);
  google::protobuf::RepeatedPtrField<std::string> names;
  names.Add("right_knee");
  const int knee = BodyActionIndices(names)->at(0);
  AdaptiveWalk walk(&(*speed)->graph());
  JuggleEnv env(*speed, Rng(7));
  env.ResetAt(0, walk);
  const float zero[kNumActions] = {0};
  int compared = 0;
  for (int steps : {6, 12, 18}) {
    while (env.steps() < steps) env.Step(zero, walk);
    const double phase = env.cursor().phase;
    ASSERT_GT(phase, 0.05);
    ASSERT_LT(phase, 0.5) << "still before the contact";
    const double ratio = (-std::sin(2 * M_PI * phase) / (2 * M_PI)) / std::pow(std::sin(M_PI * phase), 2);
    const std::vector<float> a_speed = KickActionAt(*speed, {0, 0.3, 0, 0, 0}, steps);
    const std::vector<float> a_position = KickActionAt(*position, {0, 0.3, 0, 0, 0}, steps);
    ASSERT_GT(std::abs(a_position[knee]), 1e-3);
    EXPECT_NEAR(a_speed[knee] / a_position[knee], ratio, 1e-4) << "phase " << phase;
    EXPECT_LT(a_speed[knee] * a_position[knee], 0) << "before the contact the speed envelope "
                                                     "holds the axis back";
    ++compared;
  }
  EXPECT_EQ(compared, 3);
}

struct BadDeclaration {
  std::string variables;
  std::string needle;   // the field the error points at
  std::string message;  // a part of the message
};

class NodeKickVariablesErrorTest : public ::testing::TestWithParam<BadDeclaration> {};

TEST_P(NodeKickVariablesErrorTest, IsAConfigErrorNamingTheNodeAndTheFieldAtItsLine) {
  const std::string graph_text = Graph(kHeader, GetParam().variables);
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(graph_text);
  ASSERT_FALSE(spec.ok());
  EXPECT_EQ(spec.status().code(), absl::StatusCode::kInvalidArgument);
  const std::string graph = ::juggle::testing::WriteTemp("graph.textproto", graph_text);
  const std::string at = ::juggle::testing::Loc(graph, graph_text, GetParam().needle);
  EXPECT_THAT(std::string(spec.status().message()),
              HasSubstr(at.substr(0, at.rfind(':'))));  // file:line
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("node 'down'"));
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr(GetParam().message));
}

INSTANTIATE_TEST_SUITE_P(
    Declarations, NodeKickVariablesErrorTest,
    ::testing::Values(
        BadDeclaration{"  kick_variable { move { joint: \"tail\" axis: \"z\" } }\n", "joint",
                       "'tail' is not a joint the character actuates"},
        BadDeclaration{"  kick_variable { move { joint: \"chest\" } }\n", "joint: \"chest\"",
                       "is a ball joint: name its axis"},
        BadDeclaration{"  kick_variable { move { joint: \"chest\" axis: \"w\" } }\n", "axis",
                       "is a ball joint: name its axis"},
        BadDeclaration{"  kick_variable { move { joint: \"right_knee\" axis: \"z\" } }\n", "axis",
                       "is a hinge: it takes no axis"},
        BadDeclaration{"  kick_variable { }\n", "kick_variable", "moves no joint"},
        BadDeclaration{absl::StrCat(kHeaderSetDeclared,
                                    "  kick_variable { move { joint: \"neck\" axis: \"y\" } }\n"),
                       "kick_variable { move { joint: \"neck\" axis: \"y\"",
                       "declares 5 kick variables; the planner searches at most 4"}));

TEST(NodeKickFeedbackTest, OutsideADownNodeWithALegSwingIsAConfigErrorAtItsLine) {
  const std::string feedback = "  kick_feedback { abduction_per_m: 6 }\n";
  const std::string foot = "contact_body: \"right_ankle\" contact_height: 0.5 apex_height: 1.4";
  const std::string swing = "leg_swing { side: RIGHT hip_amplitude: 1 }";
  std::string up_only = Graph(swing, "", foot);
  up_only.insert(up_only.find("  contact_body", up_only.find("name: \"up\"")), feedback);
  for (const std::string& graph_text : {Graph(kHeader, feedback), up_only}) {
    absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = SoccerSpecWithGraph(graph_text);
    ASSERT_FALSE(spec.ok());
    EXPECT_EQ(spec.status().code(), absl::StatusCode::kInvalidArgument);
    const std::string at = ::juggle::testing::Loc(
        ::juggle::testing::WriteTemp("graph.textproto", graph_text), graph_text, "kick_feedback");
    EXPECT_THAT(std::string(spec.status().message()), HasSubstr(at.substr(0, at.rfind(':'))));
    EXPECT_THAT(std::string(spec.status().message()),
                HasSubstr("kick_feedback acts only in a DOWN node with a leg swing"));
  }
  // In the swing's DOWN node it loads.
  std::string down_only = Graph(swing, "", foot);
  down_only.insert(down_only.find("  contact_body"), feedback);
  EXPECT_TRUE(SoccerSpecWithGraph(down_only).ok()) << SoccerSpecWithGraph(down_only).status();
}

TEST(NodeKickFeedbackTest, TheKneesFromTheFootConfigGivesTheKneeItsOwnGainsAndLoadsForThePlanner) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(::juggle::testing::RepoPath("configs/knees_from_foot_planner.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_TRUE(ValidatePlannerConfig(*config).ok()) << ValidatePlannerConfig(*config);
  const ControlGraph& graph = *config->graph;
  const config::NodeSpec& foot = graph.node(*graph.FindNode("right_foot_down")).spec;
  const config::NodeSpec& knee = graph.node(*graph.FindNode("right_knee_down")).spec;
  EXPECT_FALSE(foot.has_kick_feedback());  // the env's, the foot's gains
  EXPECT_GT(config->run.soccer_juggle().env().kick_feedback().hip_per_m(), 0);
  ASSERT_TRUE(knee.has_kick_feedback());
  EXPECT_EQ(knee.kick_feedback().hip_per_m(), 0);
  EXPECT_GT(knee.kick_feedback().abduction_per_m(), 0);
  EXPECT_TRUE(graph.node(*graph.FindNode("right_foot_down")).spec.initial());
  EXPECT_FALSE(knee.initial());
}

TEST(NodeKickVariablesTest, OneKickSetForNodesWhoseDeclarationsDifferIsRefusedAtCycles) {
  // The header set declared on one node and a neck-only variable on the other.
  std::string graph_text = Graph(kHeader, kHeaderSetDeclared);
  const size_t up = graph_text.find("name: \"up\"");
  graph_text.replace(graph_text.find("  kick_variable", up),
                     std::string(kHeaderSetDeclared).size(),
                     "  kick_variable { move { joint: \"neck\" axis: \"z\" } }\n");
  absl::StatusOr<LoadedConfig> config = LoadRightFootPlannerWithGraph(graph_text);
  ASSERT_TRUE(config.ok()) << config.status();
  const absl::Status status = ValidateSoccerJuggleTask(*config);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("kick.cycles"));
  EXPECT_THAT(std::string(status.message()), HasSubstr("up -> down"));

  // The same declaration on both nodes shares one set.
  absl::StatusOr<LoadedConfig> same =
      LoadRightFootPlannerWithGraph(Graph(kHeader, kHeaderSetDeclared));
  ASSERT_TRUE(same.ok()) << same.status();
  EXPECT_TRUE(ValidateSoccerJuggleTask(*same).ok()) << ValidateSoccerJuggleTask(*same);
}

TEST(NodeKickVariablesTest, AKeyframeNodeWithoutDeclaredVariablesIsRefusedAtItsKeyframes) {
  const std::string keyframes = "keyframes { frame { phase: 0 } frame { phase: 1 } }";
  const std::string foot = "contact_body: \"right_ankle\" contact_height: 0.5 apex_height: 1.4";
  const std::string graph_text = Graph(keyframes, "", foot);
  absl::StatusOr<LoadedConfig> config = LoadRightFootPlannerWithGraph(graph_text);
  ASSERT_TRUE(config.ok()) << config.status();
  const absl::Status status = ValidateSoccerJuggleTask(*config);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  const std::string at = ::juggle::testing::Loc(
      ::juggle::testing::WriteTemp("graph.textproto", graph_text), graph_text, "keyframes");
  EXPECT_THAT(std::string(status.message()), HasSubstr(at.substr(0, at.rfind(':'))));
  EXPECT_THAT(std::string(status.message()), HasSubstr("node 'down' moves by keyframes"));

  absl::StatusOr<LoadedConfig> declared = LoadRightFootPlannerWithGraph(
      Graph(keyframes, "  kick_variable { move { joint: \"right_hip\" axis: \"z\" } }\n", foot));
  ASSERT_TRUE(declared.ok()) << declared.status();
  EXPECT_TRUE(ValidateSoccerJuggleTask(*declared).ok()) << ValidateSoccerJuggleTask(*declared);
}

TEST(NodeKickVariablesTest, AStallNodeIsAcceptedByThePlannerNowThatAStallHasACost) {
  const std::string graph_text =
      "node { name: \"down\" stage: DOWN initial: true contact_body: \"right_ankle\"\n"
      "  contact_height: 0.5 apex_height: 1.4 pose { leg_swing { side: RIGHT } } }\n"
      "node { name: \"hold\"\n  stage: STALL\n  contact_body: \"right_ankle\"\n"
      "  contact_height: 0.5 stall { body: \"right_ankle\" ball_height: 0.62 }\n"
      "  pose { leg_swing { side: RIGHT hold_peak: true } } }\n"
      "node { name: \"up\" stage: UP contact_body: \"right_ankle\"\n"
      "  contact_height: 0.5 apex_height: 1.4 pose { leg_swing { side: RIGHT } } }\n"
      "edge { from: \"down\" to: \"hold\" }\nedge { from: \"hold\" to: \"hold\" weight: 30 }\n"
      "edge { from: \"hold\" to: \"up\" }\nedge { from: \"up\" to: \"down\" }\n";
  absl::StatusOr<LoadedConfig> config = LoadRightFootPlannerWithGraph(graph_text);
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_TRUE(ValidateSoccerJuggleTask(*config).ok()) << ValidateSoccerJuggleTask(*config);
}

}  // namespace
}  // namespace juggle::planner
