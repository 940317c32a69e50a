// The soccer base controller's stance balance in a node without a leg swing (a header): both
// feet stand, and the zero-action character heads for 20 s where without a balance it falls.
#include <cmath>
#include <memory>
#include <vector>

#include "envs/soccer_juggle/base_controller.h"
#include "envs/soccer_juggle/env.h"
#include "google/protobuf/text_format.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

constexpr float kZeroAction[kNumActions] = {0};

// `name`'s config with its graph replaced by `graph` (text format); null (test failed) on error.
std::shared_ptr<const JuggleSpec> SpecWith(const std::string& name, const char* graph) {
  absl::StatusOr<LoadedConfig> loaded = testing::LoadShippedConfig(name);
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  if (!loaded.ok()) return nullptr;
  LoadedConfig config = *loaded;
  config::ControlGraph proto;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(graph, &proto));
  absl::StatusOr<ControlGraph> built = ControlGraph::Build(proto, config.graph_locator);
  EXPECT_TRUE(built.ok()) << built.status();
  if (!built.ok()) return nullptr;
  *config.run.mutable_soccer_juggle()->mutable_graph() = proto;
  config.graph = std::make_shared<const ControlGraph>(*std::move(built));
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = JuggleSpec::Create(config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

constexpr char kHeadersOnly[] = R"pb(
  node { name: "head_down" stage: DOWN initial: true contact_body: "neck" contact_height: 1.75
         apex_height: 2.0 ball_target { x: 0.08 y: 0 } pose { head_dip { amplitude: 0.25 } } }
  node { name: "head_up" stage: UP contact_body: "neck" contact_height: 1.75
         apex_height: 2.0 ball_target { x: 0.08 y: 0 } pose { head_dip { amplitude: 0.25 } } }
  edge { from: "head_down" to: "head_up" }
  edge { from: "head_up" to: "head_down" }
)pb";

// Seconds the zero-action character of `spec` stands, headers only, with the ball out of play
// (at most `seconds`).
double SecondsStanding(const std::shared_ptr<const JuggleSpec>& spec, double seconds) {
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng(11));
  env.ResetAt(*spec->graph().FindNode("head_down"), walk);
  mjData* d = env.data();
  const int steps = static_cast<int>(std::round(seconds / spec->control_dt()));
  for (int i = 0; i < steps; ++i) {
    double* ball = d->qpos + spec->ball_qpos();
    ball[0] = d->qpos[0];
    ball[1] = d->qpos[1];
    ball[2] = 40.0;
    mju_zero(d->qvel + spec->ball_dof(), 6);
    const StepResult r = env.Step(kZeroAction, walk);
    if (r.outcome == Outcome::kTimeLimit) return seconds;
    if (r.outcome != Outcome::kRunning) return i * spec->control_dt();
  }
  return seconds;
}

TEST(SoccerStanceTest, HeadersStandOnBothFeetForTwentySecondsWithZeroAction) {
  std::shared_ptr<const JuggleSpec> spec = SpecWith("right_foot_planner", kHeadersOnly);
  ASSERT_NE(spec, nullptr);
  ASSERT_TRUE(spec->env().has_stance_balance());
  EXPECT_EQ(SecondsStanding(spec, 20.0), 20.0);

  // Without a stance balance the same character tips over within seconds: the balance is what
  // holds it.
  LoadedConfig unbalanced = spec->config();
  unbalanced.run.mutable_soccer_juggle()->mutable_env()->clear_stance_balance();
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> without = JuggleSpec::Create(unbalanced);
  ASSERT_TRUE(without.ok()) << without.status();
  EXPECT_LT(SecondsStanding(*without, 20.0), 5.0);
}

}  // namespace
}  // namespace juggle::soccer_juggle
